// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/law.hpp"

#include "exact/int_kernel.hpp"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <set>

namespace impactcert {

std::vector<const char*> obligation_ids(bool friction) {
    if (friction)
        return {kFrictionObligationIds.begin(), kFrictionObligationIds.end()};
    return {kObligationIds.begin(), kObligationIds.end()};
}

bool is_obligation_id(const std::string& id) {
    return std::find(kFrictionObligationIds.begin(), kFrictionObligationIds.end(), id) != kFrictionObligationIds.end();
}

namespace {

void check_square(const Matrix& m, std::size_t c, const std::string& path) {
    if (m.rows() != c || m.cols() != c)
        input_error(path, "expected a " + std::to_string(c) + "x" + std::to_string(c) +
                              " matrix, got " + std::to_string(m.rows()) + "x" +
                              std::to_string(m.cols()));
}

} // namespace

void Model::add_piece(const std::string& name, const Matrix& Q, const std::vector<Vector>& primitive_rays,
                      const std::string& path) {
    Piece piece;
    piece.name = name;
    piece.Q = Q;
    piece.R = Matrix::from_columns(primitive_rays);
    // R is integral (primitive rays): its inverse by fraction-free elimination in int64 where
    // it fits, else over GMP; the same exact matrix either way.
    std::optional<Matrix> r_inv;
    if (const auto R_int = intk::to_int(piece.R); R_int && R_int->den == 1)
        if (const auto inv = intk::inverse(*R_int))
            r_inv = intk::to_matrix(*inv);
    if (!r_inv)
        r_inv = inverse(piece.R);
    if (!r_inv)
        input_error(path + ".rays", "linearly dependent rays (the cone is not full-dimensional)");
    piece.R_inv = *r_inv;
    for (const auto& r : primitive_rays) {
        auto [it, added] = ray_index_.emplace(r, rays_.size());
        piece.ray_ids.push_back(it->second);
        if (added)
            rays_.push_back(r);
    }
    pieces_.push_back(std::move(piece));
}

Model::Model(Law law, std::size_t max_pieces, std::size_t max_memory_mb) : law_(std::move(law)) {
    if (law_.name.empty())
        input_error("$.name", "empty law name");

    // Masses and contacts (system.hpp: the same rules as a system file).
    {
        Mechanics mech = make_mechanics(law_.masses, law_.M, law_.W, law_.friction, Dependent::allow);
        normals_ = mech.normals;
        tangents_ = std::move(mech.tangents);
        polygons_ = std::move(mech.polygons);
        M_ = std::move(mech.M);
        M_inv_ = std::move(mech.M_inv);
        if (mech.redundant()) {
            // The law lives on gamma_B = W_B^T u (proofs/README.md, "Redundant contacts").
            basis_ = mech.basis;
            C_ = mech.C;
            full_W_ = mech.W;
            W_ = Matrix(M_.rows(), basis_.size());
            for (std::size_t i = 0; i < W_.rows(); ++i)
                for (std::size_t k = 0; k < basis_.size(); ++k)
                    W_(i, k) = mech.W(i, basis_[k]);
            G_ = std::move(mech.G_B);
            H_ = std::move(mech.H_B);
        } else {
            W_ = std::move(mech.W);
            G_ = std::move(mech.G);
            H_ = std::move(mech.H);
        }
    }
    if (redundant()) {
        if (law_.claims)
            for (std::size_t i = 0; i < law_.claims->size(); ++i)
                if ((*law_.claims)[i] == "P3")
                    input_error(idx("$.claims", i), "P3 does not apply on dependent contact columns (no orthant of a basis)");
        if (!law_.symmetries.empty())
            input_error("$.symmetries", "a law on dependent contact columns declares no symmetries (not supported)");
        if (!law_.single_impacts.empty())
            input_error("$.single_impacts", "a law on dependent contact columns declares no single impacts (not supported)");
    }
    const std::size_t n = M_.rows(), c = W_.cols();

    // Pieces.
    if (law_.pieces.empty())
        input_error("$.pieces", "no pieces");
    std::set<std::string> names;
    for (std::size_t p = 0; p < law_.pieces.size(); ++p) {
        const PieceDecl& decl = law_.pieces[p];
        const std::string path = idx("$.pieces", p);
        if (decl.name.empty())
            input_error(path + ".name", "empty piece name");
        if (!names.insert(decl.name).second)
            input_error(path + ".name", "duplicate piece name " + in_quotes(decl.name));
        check_square(decl.Q, c, path + ".Q");

        std::vector<Vector> rays;
        if (decl.rays) {
            rays = *decl.rays;
            if (rays.size() != c)
                input_error(path + ".rays", "expected " + std::to_string(c) + " rays, got " +
                                                std::to_string(rays.size()));
            for (std::size_t k = 0; k < c; ++k) {
                if (rays[k].size() != c)
                    input_error(idx(path + ".rays", k), "expected " + std::to_string(c) +
                                                            " components, got " +
                                                            std::to_string(rays[k].size()));
                if (is_zero(rays[k]))
                    input_error(idx(path + ".rays", k), "zero ray");
                for (std::size_t l = 0; l < k; ++l)
                    if (primitive_ray(rays[l]) == primitive_ray(rays[k]))
                        input_error(idx(path + ".rays", k),
                                    "repeats ray " + std::to_string(l) + " (same direction)");
            }
        } else {
            auto q_inv = inverse(decl.Q);
            if (!q_inv)
                input_error(path + ".Q", "singular matrix, and no rays given (the cone is spanned "
                                         "by the columns of Q^-1)");
            for (std::size_t k = 0; k < c; ++k)
                rays.push_back(q_inv->column(k));
        }

        std::vector<Vector> primitive;
        for (const auto& r : rays)
            primitive.push_back(primitive_ray(r));
        add_piece(decl.name, decl.Q, primitive, path);
        if (redundant()) {
            const std::size_t d = C_.cols();
            if (!decl.impulses)
                input_error(path, "missing \"impulses\": W's " + std::to_string(d) + " columns have rank " +
                                      std::to_string(c) + ", so each piece gives its impulses (" + std::to_string(d) +
                                      " x " + std::to_string(c) + ")");
            if (decl.impulses->rows() != d || decl.impulses->cols() != c)
                input_error(path + ".impulses", "expected " + std::to_string(d) + " x " + std::to_string(c) + ", got " +
                                                    std::to_string(decl.impulses->rows()) + " x " +
                                                    std::to_string(decl.impulses->cols()));
            pieces_.back().L = decl.impulses;
        } else if (decl.impulses) {
            input_error(path + ".impulses", "only a law on dependent contact columns gives impulses (W has full column rank)");
        }
    }

    // Symmetries: invertible, named once; with representatives only, the closure.
    std::set<std::string> symmetry_names;
    for (std::size_t g = 0; g < law_.symmetries.size(); ++g) {
        const SymmetryDecl& sym = law_.symmetries[g];
        const std::string path = idx("$.symmetries", g);
        if (sym.name.empty())
            input_error(path + ".name", "empty symmetry name");
        if (!symmetry_names.insert(sym.name).second)
            input_error(path + ".name", "duplicate symmetry name " + in_quotes(sym.name));
        check_square(sym.P, c, path + ".P");
        check_square(sym.P_prime, c, path + ".P_prime");
        auto P_inv = inverse(sym.P);
        if (!P_inv)
            input_error(path + ".P", "singular matrix (a symmetry maps the cones one to one)");
        P_inv_.push_back(*P_inv);
    }
    if (law_.representatives_only) {
        if (law_.symmetries.empty())
            input_error("$.pieces_listed", "orbit representatives need \"symmetries\"");
        validate_compact_symmetries(law_, H_);
        std::map<std::vector<std::size_t>, std::size_t> by_rays;
        auto key_of = [](std::vector<std::size_t> ids) {
            std::sort(ids.begin(), ids.end());
            return ids;
        };
        for (std::size_t p = 0; p < pieces_.size(); ++p)
            by_rays.emplace(key_of(pieces_[p].ray_ids), p);
        // Budgets of the expansion (18.2): bytes of the generated numbers, and their growth.
        const std::size_t max_bytes = max_memory_mb > (SIZE_MAX >> 20) ? SIZE_MAX : max_memory_mb << 20;
        std::size_t listed_bits = 0, bytes = 0;
        for (const auto& p : pieces_) {
            listed_bits = std::max({listed_bits, matrix_bits(p.Q), matrix_bits(p.R)});
            bytes += matrix_bytes(p.Q) + matrix_bytes(p.R) + matrix_bytes(p.R_inv);
        }
        for (std::size_t g = 0; g < law_.symmetries.size(); ++g)
            listed_bits = std::max({listed_bits, matrix_bits(law_.symmetries[g].P), matrix_bits(law_.symmetries[g].P_prime),
                                    matrix_bits(P_inv_[g])});
        const std::size_t max_bits = 16 * listed_bits + 1024;
        // Images of rays in int64 where P (over a common denominator) and the rays fit,
        // else over GMP; the same primitive rays either way.
        std::vector<std::optional<intk::IntMatrix>> P_int, P_prime_int, P_inv_int;
        for (std::size_t g = 0; g < law_.symmetries.size(); ++g) {
            P_int.push_back(intk::to_int(law_.symmetries[g].P));
            P_prime_int.push_back(intk::to_int(law_.symmetries[g].P_prime));
            P_inv_int.push_back(intk::to_int(P_inv_[g]));
        }
        // Q' = P' Q P^-1, in int64 over common denominators where it fits, else over GMP.
        auto image_matrix = [&](std::size_t g, const Matrix& Q) {
            if (P_prime_int[g] && P_inv_int[g])
                if (const auto Q_int = intk::to_int(Q)) {
                    intk::IntMatrix t, u;
                    if (intk::multiply(*P_prime_int[g], *Q_int, t) && intk::multiply(t, *P_inv_int[g], u))
                        return intk::to_matrix(u);
                }
            return Matrix(law_.symmetries[g].P_prime * Q * P_inv_[g]);
        };
        std::map<std::vector<intk::i64>, std::size_t> int_ray_index;
        std::vector<std::optional<std::vector<intk::i64>>> int_rays;
        auto int_ray = [&](std::size_t id) -> const std::optional<std::vector<intk::i64>>& {
            while (int_rays.size() <= id) {
                int_rays.push_back(intk::to_int_vector(rays_[int_rays.size()]));
                if (int_rays.back())
                    int_ray_index.emplace(*int_rays.back(), int_rays.size() - 1);
            }
            return int_rays[id];
        };
        std::vector<intk::i64> image_int(c);
        for (std::size_t p = 0; p < pieces_.size(); ++p)
            for (std::size_t g = 0; g < law_.symmetries.size(); ++g) {
                const SymmetryDecl& sym = law_.symmetries[g];
                std::vector<Vector> image;
                std::vector<std::size_t> ids;
                for (std::size_t k = 0; k < c; ++k) {
                    int_ray(rays_.size() - 1); // every known ray indexed (before r: no reallocation after)
                    const auto& r = int_rays[pieces_[p].ray_ids[k]];
                    if (P_int[g] && r && intk::apply(*P_int[g], r->data(), image_int.data())) {
                        intk::make_primitive(image_int);
                        auto it = int_ray_index.find(image_int);
                        if (it != int_ray_index.end()) {
                            image.push_back(rays_[it->second]);
                            ids.push_back(it->second);
                            continue;
                        }
                        image.push_back(intk::to_vector(image_int));
                    } else {
                        image.push_back(primitive_ray(sym.P * pieces_[p].R.column(k)));
                    }
                    auto it = ray_index_.find(image.back());
                    ids.push_back(it == ray_index_.end() ? rays_.size() + k : it->second);
                }
                if (by_rays.count(key_of(ids)))
                    continue;
                if (pieces_.size() >= max_pieces)
                    input_error("$.symmetries", "the symmetries generate more than " + std::to_string(max_pieces) +
                                                    " pieces (raise it with --max-pieces)");
                const std::string name = pieces_[p].name + "." + sym.name;
                // Names grow with the depth of the breadth-first search: a group of infinite
                // order (a rational rotation) is stopped here long before memory runs out.
                if (name.size() > kMaxGeneratedName)
                    input_error("$.symmetries", "generated piece name longer than " + std::to_string(kMaxGeneratedName) +
                                                    " characters (a symmetry of infinite order?)");
                if (!names.insert(name).second)
                    input_error(idx("$.symmetries", g) + ".name",
                                "generated piece name " + in_quotes(name) + " is taken");
                const Matrix Q = image_matrix(g, pieces_[p].Q);
                const std::size_t grown = std::max(matrix_bits(Q), matrix_bits(Matrix::from_columns(image)));
                if (grown > max_bits)
                    input_error("$.symmetries", "generated piece " + in_quotes(name.substr(0, 60)) + " has an entry of " +
                                                    std::to_string(grown) + " bits, more than 16 times those of the "
                                                    "listed data: the numbers grow (a symmetry of infinite order?)");
                const std::size_t rays_before = rays_.size();
                add_piece(name, Q, image, "$.symmetries");
                // The piece's matrices, its name (twice: the piece and the set of names), the map
                // entries, and each new ray twice (the table and its index).
                bytes += matrix_bytes(pieces_.back().Q) + matrix_bytes(pieces_.back().R) + matrix_bytes(pieces_.back().R_inv) +
                         2 * name.size() + 512;
                for (std::size_t r = rays_before; r < rays_.size(); ++r)
                    bytes += 2 * (matrix_bytes(Matrix::from_columns({rays_[r]})) + 64);
                if (bytes > max_bytes)
                    input_error("$.symmetries", "the generated pieces need more than " + std::to_string(max_memory_mb) +
                                                    " MB (" + std::to_string(pieces_.size()) +
                                                    " pieces so far; raise it with --max-memory)");
                by_rays.emplace(key_of(pieces_.back().ray_ids), pieces_.size() - 1);
            }
    }

    validate_declarations(law_, n, c, [&](const std::string& name) { return names.count(name) > 0; });
    r_inv_int_.reserve(pieces_.size());
    for (const auto& piece : pieces_)
        r_inv_int_.push_back(intk::to_int(piece.R_inv));
}

std::size_t Model::piece_index(const std::string& name) const {
    for (std::size_t p = 0; p < pieces_.size(); ++p)
        if (pieces_[p].name == name)
            return p;
    throw std::out_of_range("no piece named " + name);
}

namespace {
// The sign of row r of a (numerators) times g, exactly; nothing when a sum leaves 128 bits.
std::optional<Sign> row_sign(const intk::IntMatrix& a, std::size_t r, const std::vector<intk::i64>& g) {
    intk::i128 s = 0;
    for (std::size_t j = 0; j < a.cols; ++j)
        if (__builtin_add_overflow(s, static_cast<intk::i128>(a(r, j)) * g[j], &s))
            return std::nullopt;
    return s > 0 ? Sign::positive : s < 0 ? Sign::negative : Sign::zero;
}
} // namespace

// gamma in the closed (interior: open) cone of piece p: every coordinate R_inv gamma >= 0 (> 0),
// decided row by row, stopping at the first that fails. In int64 rows over a common denominator
// when both fit (a positive scaling of R_inv and of gamma keeps every sign), else over GMP.
bool Model::in_cone(std::size_t p, const Vector& gamma, const std::optional<std::vector<intk::i64>>& g,
                    bool interior) const {
    const auto& a = r_inv_int_[p];
    const std::size_t c = gamma.size();
    for (std::size_t r = 0; r < c; ++r) {
        std::optional<Sign> s;
        if (a && g)
            s = row_sign(*a, r, *g);
        if (!s) {
            Rational sum = 0;
            for (std::size_t j = 0; j < c; ++j)
                sum += pieces_[p].R_inv(r, j) * gamma[j];
            s = sign_of(sum);
        }
        if (*s == Sign::negative || (interior && *s == Sign::zero))
            return false;
    }
    return true;
}

void Model::require_contacts(const Vector& gamma) const {
    if (gamma.size() != contacts())
        throw std::logic_error("a point of " + std::to_string(gamma.size()) + " contact velocities for a law of " +
                               std::to_string(contacts()) + " contacts");
}

std::optional<std::vector<intk::i64>> Model::scaled(const Vector& gamma) { return intk::to_int_scaled(gamma); }

std::vector<std::size_t> Model::pieces_containing(const Vector& gamma) const {
    require_contacts(gamma);
    std::vector<std::size_t> out;
    const auto g = scaled(gamma);
    for (std::size_t p = 0; p < pieces_.size(); ++p)
        if (in_cone(p, gamma, g, false))
            out.push_back(p);
    return out;
}

std::vector<Vector> Model::values_at(const Vector& gamma) const {
    std::vector<Vector> out;
    for (auto p : pieces_containing(gamma)) {
        Vector v = pieces_[p].Q * gamma;
        if (std::find(out.begin(), out.end(), v) == out.end())
            out.push_back(std::move(v));
    }
    return out;
}

bool Model::in_interior(std::size_t p, const Vector& gamma) const {
    if (p >= pieces_.size())
        throw std::out_of_range("in_interior: no piece " + std::to_string(p));
    require_contacts(gamma);
    return in_cone(p, gamma, scaled(gamma), true);
}

std::pair<Vector, Vector> interior_pair_along(const Piece& piece, const Vector& x) {
    const Vector centre = piece.R * Vector(piece.R.cols(), Rational(1));
    Rational spread = 1;
    for (const auto& coeff : piece.R_inv * x)
        spread = std::max(spread, abs_of(coeff) + 1);
    const Rational eps = Rational(1) / (2 * spread);
    return {centre + eps * x, centre};
}

bool law_applies(const Law& law, const std::string& id) {
    if (id == "identities")
        return !law.identities.empty();
    if (id == "single-impacts")
        return !law.single_impacts.empty();
    if (id == "outcomes")
        return !law.outcomes.empty();
    if (id == "symmetries")
        return !law.symmetries.empty();
    if (id == "coulomb")
        return !law.friction.empty();
    if (id == "P3") // the images of rays in the orthant: no sign for a tangential velocity
        return law.friction.empty();
    return is_obligation_id(id);
}

bool law_claims(const Law& law, const std::string& id) {
    if (!law.claims)
        return law_applies(law, id);
    return std::find(law.claims->begin(), law.claims->end(), id) != law.claims->end();
}

void validate_compact_symmetries(const Law& law, const Matrix& H) {
    // Generating pieces is only meaningful (and only bounded) for H-isometries of finite order.
    for (std::size_t g = 0; g < law.symmetries.size(); ++g) {
        const SymmetryDecl& sym = law.symmetries[g];
        if (transpose(sym.P) * H * sym.P != H)
            input_error(idx("$.symmetries", g) + ".P", "not an H-isometry (P^T H P != H): a compact law's "
                                                       "symmetries must be");
        if (transpose(sym.P_prime) * H * sym.P_prime != H)
            input_error(idx("$.symmetries", g) + ".P_prime", "not an H-isometry (P'^T H P' != H): a compact "
                                                             "law's symmetries must be");
        if (sym.P.rows() <= kMaxOrderCheckContacts) {
            const std::vector<Rational> a = characteristic_polynomial(sym.P);
            for (std::size_t k = 1; k < a.size(); ++k)
                if (a[k].denominator() != 1)
                    input_error(idx("$.symmetries", g) + ".P",
                                "of infinite order: the coefficient of x^" + std::to_string(a.size() - 1 - k) +
                                    " in det(xI - P) is " + to_string(a[k]) +
                                    ", not an integer, so the powers of P never return to I and generate pieces "
                                    "without end (proofs/README.md, Lemma S0)");
        }
    }
}

void validate_declarations(const Law& law, std::size_t n, std::size_t c,
                           const std::function<bool(const std::string&)>& piece_exists) {
    auto require_piece = [&](const std::string& name, const std::string& path) {
        if (!piece_exists(name))
            input_error(path, "unknown piece " + in_quotes(name));
    };
    for (std::size_t i = 0; i < law.identities.size(); ++i) {
        const auto& id = law.identities[i];
        const std::string path = idx("$.identities", i);
        require_piece(id.lhs, path + ".lhs");
        if (id.product.empty())
            input_error(path + ".product", "empty product");
        for (std::size_t k = 0; k < id.product.size(); ++k)
            require_piece(id.product[k], idx(path + ".product", k));
    }
    for (std::size_t i = 0; i < law.single_impacts.size(); ++i) {
        const auto& si = law.single_impacts[i];
        const std::string path = idx("$.single_impacts", i);
        require_piece(si.piece, path + ".piece");
        if (si.contact < 1 || static_cast<std::size_t>(si.contact) > c)
            input_error(path + ".contact", "contact must be in 1.." + std::to_string(c) + ", got " +
                                               std::to_string(si.contact));
        // With friction the columns after the normals are tangents: a two-body impact is declared
        // at a normal (frictional single impacts with their mode are not supported).
        std::size_t tangents = 0;
        for (const auto& f : law.friction)
            tangents += f.tangents.size();
        if (tangents > 0 && static_cast<std::size_t>(si.contact) > c - tangents)
            input_error(path + ".contact", "contact " + std::to_string(si.contact) + " is a friction tangent: single impacts "
                                           "are declared at the normals 1.." + std::to_string(c - tangents));
        if (sign_of(si.restitution) == Sign::negative || si.restitution > Rational(1))
            input_error(path + ".restitution",
                        "restitution must be in [0, 1], got " + to_string(si.restitution));
    }
    std::set<std::string> outcome_names;
    for (std::size_t i = 0; i < law.outcomes.size(); ++i) {
        const auto& o = law.outcomes[i];
        const std::string path = idx("$.outcomes", i);
        if (!outcome_names.insert(o.name).second)
            input_error(path + ".name", "duplicate outcome name " + in_quotes(o.name));
        if (o.u_minus.size() != n)
            input_error(path + ".u_minus", "expected " + std::to_string(n) + " ball velocities, got " +
                                               std::to_string(o.u_minus.size()));
        if (o.u_plus.size() != n)
            input_error(path + ".u_plus", "expected " + std::to_string(n) + " ball velocities, got " +
                                              std::to_string(o.u_plus.size()));
    }
    validate_claims(law);
}

void validate_claims(const Law& law) {
    if (!law.claims)
        return;
    if (law.claims->empty())
        input_error("$.claims", "no obligation claimed (omit \"claims\" to claim every one that applies)");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < law.claims->size(); ++i) {
        const std::string& id = (*law.claims)[i];
        const std::string path = idx("$.claims", i);
        if (!is_obligation_id(id))
            input_error(path, "unknown obligation " + in_quotes(id));
        if (!seen.insert(id).second)
            input_error(path, "obligation " + in_quotes(id) + " claimed twice");
        if (!law_applies(law, id))
            input_error(path, in_quotes(id) + (id == "P3" ? " is claimed but does not apply to a law with friction"
                                               : id == "coulomb" ? " is claimed but the law has no friction"
                                                                 : " is claimed but the law declares nothing for it"));
    }
}

void Model::require_independent_columns(const std::string& who) const {
    if (redundant())
        throw InputError(who + " does not read laws on dependent contact columns (rank " + std::to_string(basis_.size()) +
                         " of " + std::to_string(C_.cols()) + ") yet; verify, certify, report and impactcert-check do");
}

// P3 (onto the orthant) has no meaning on a basis of dependent columns.
bool Model::applies(const std::string& id) const { return !(redundant() && id == "P3") && law_applies(law_, id); }

bool Model::claimed(const std::string& id) const { return !(redundant() && id == "P3") && law_claims(law_, id); }

Vector Model::post_impact_velocities(const Vector& u_minus, const Vector& gamma_minus,
                                     const Vector& gamma_plus) const {
    const Vector impulse = H_ * (gamma_plus - gamma_minus);
    return u_minus + M_inv_ * (W_ * impulse);
}

Matrix Model::single_impact(std::size_t k, const Rational& e) const {
    const std::size_t c = contacts();
    Matrix Q = Matrix::identity(c);
    const Rational f = (Rational(1) + e) / G_(k, k);
    for (std::size_t i = 0; i < c; ++i)
        Q(i, k) -= f * G_(i, k);
    return Q;
}

} // namespace impactcert
