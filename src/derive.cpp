#include "derive.hpp"

#include "errors.hpp"

// PPL initialises itself in every program that links it unless told not to; impactcert starts
// often (it is a CI gate), and only `derive` needs PPL, so it is initialised on first use.
#define PPL_NO_AUTOMATIC_INITIALIZATION
#include <ppl.hh>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

namespace impactcert {

namespace PPL = Parma_Polyhedra_Library;

ImpactRule parse_rule(const std::string& text) {
    if (text == "most-negative")
        return ImpactRule::most_negative;
    if (text == "left-first")
        return ImpactRule::left_first;
    if (text == "right-first")
        return ImpactRule::right_first;
    throw InputError("--rule: unknown rule \"" + text + "\" (most-negative, left-first or right-first)");
}

const char* to_string(ImpactRule rule) {
    switch (rule) {
    case ImpactRule::most_negative: return "most-negative";
    case ImpactRule::left_first: return "left-first";
    case ImpactRule::right_first: return "right-first";
    }
    return "?";
}

namespace {

// The contact the rule picks among the approaching ones (gamma_k < 0), or nothing.
std::optional<std::size_t> pick(ImpactRule rule, const Vector& gamma) {
    std::optional<std::size_t> k;
    for (std::size_t i = 0; i < gamma.size(); ++i) {
        if (sign_of(gamma[i]) != Sign::negative)
            continue;
        if (!k || rule == ImpactRule::right_first ||
            (rule == ImpactRule::most_negative && gamma[i] < gamma[*k]))
            k = i;
        if (rule == ImpactRule::left_first)
            break;
    }
    return k;
}

// Chain contacts: G = W^T M^-1 W with W[k][k] = -1, W[k+1][k] = 1.
Matrix chain_G(const std::vector<Rational>& m) {
    const std::size_t c = m.size() - 1;
    Matrix G(c, c);
    for (std::size_t k = 0; k < c; ++k) {
        G(k, k) = Rational(1) / m[k] + Rational(1) / m[k + 1];
        if (k + 1 < c) {
            G(k, k + 1) = -(Rational(1) / m[k + 1]);
            G(k + 1, k) = G(k, k + 1);
        }
    }
    return G;
}

Matrix impact(const Matrix& G, std::size_t k, const Rational& e) {
    Matrix Q = Matrix::identity(G.rows());
    const Rational f = (Rational(1) + e) / G(k, k);
    for (std::size_t i = 0; i < G.rows(); ++i)
        Q(i, k) -= f * G(i, k);
    return Q;
}

void validate(const DeriveOptions& o) {
    if (o.masses.size() < 2)
        throw InputError("--masses: a chain needs at least two balls, got " + std::to_string(o.masses.size()));
    for (std::size_t i = 0; i < o.masses.size(); ++i)
        if (sign_of(o.masses[i]) != Sign::positive)
            throw InputError("--masses: mass " + std::to_string(i + 1) + " must be positive, got " + to_string(o.masses[i]));
    if (o.restitution.size() != o.masses.size() - 1)
        throw InputError("--restitution: expected one value or " + std::to_string(o.masses.size() - 1) +
                         " (one per contact), got " + std::to_string(o.restitution.size()));
    for (std::size_t k = 0; k < o.restitution.size(); ++k)
        if (sign_of(o.restitution[k]) == Sign::negative || o.restitution[k] > Rational(1))
            throw InputError("--restitution: contact " + std::to_string(k + 1) + " must be in [0, 1], got " +
                             to_string(o.restitution[k]));
    if (o.max_impacts == 0)
        throw InputError("--max-impacts: must be at least 1");
}

// ---- PPL bridge: integer linear forms a . x >= 0 on R^c.

PPL::Linear_Expression form(const Vector& a) {
    const Vector p = primitive_ray(a); // a positive multiple with integer entries
    PPL::Linear_Expression e;
    for (std::size_t k = 0; k < p.size(); ++k)
        if (sign_of(p[k]) != Sign::zero)
            e += PPL::Coefficient(mpz_class(mpq_numref(p[k].mpq()))) * PPL::Variable(static_cast<PPL::dimension_type>(k));
    return e;
}

// The coefficients of a PPL generator or constraint on the c space dimensions.
template <class Row>
Vector vector_of(const Row& g, std::size_t c) {
    Vector v(c);
    for (std::size_t k = 0; k < c; ++k) {
        const mpz_class z(g.coefficient(PPL::Variable(static_cast<PPL::dimension_type>(k))));
        v[k] = Rational(CGAL::Gmpz(z.get_mpz_t()));
    }
    return v;
}

struct Cone {
    std::vector<Vector> rays;        // extreme rays, primitive, sorted
    std::vector<Vector> constraints; // facet normals a (a . x >= 0)
    bool has_lines = false;
};

Cone describe(const PPL::C_Polyhedron& P, std::size_t c) {
    Cone out;
    std::set<Vector> rays;
    for (const auto& g : P.minimized_generators()) {
        if (g.is_line())
            out.has_lines = true;
        else if (g.is_ray())
            rays.insert(primitive_ray(vector_of(g, c)));
    }
    out.rays.assign(rays.begin(), rays.end());
    for (const auto& k : P.minimized_constraints())
        if (k.is_inequality())
            out.constraints.push_back(vector_of(k, c));
    return out;
}

std::size_t rank_of(const std::vector<Vector>& vs, std::size_t c) {
    if (vs.empty())
        return 0;
    return c - null_space(vs, c).size();
}

// Pulling triangulation of the face `face` (indices into rays, of dimension dim): the first ray
// of the face coned over the triangulations of the face's facets that do not contain it.
void triangulate(const std::vector<Vector>& rays, const std::vector<std::size_t>& face, std::size_t dim,
                 const std::vector<Vector>& constraints, std::size_t c,
                 std::vector<std::vector<std::size_t>>& out) {
    if (face.size() == dim) {
        out.push_back(face);
        return;
    }
    const std::size_t apex = face.front();
    std::set<std::vector<std::size_t>> facets;
    for (const auto& a : constraints) {
        if (sign_of(dot(a, rays[apex])) == Sign::zero)
            continue;
        std::vector<std::size_t> on;
        std::vector<Vector> vs;
        for (auto r : face)
            if (sign_of(dot(a, rays[r])) == Sign::zero) {
                on.push_back(r);
                vs.push_back(rays[r]);
            }
        if (rank_of(vs, c) == dim - 1)
            facets.insert(on);
    }
    for (const auto& f : facets) {
        std::vector<std::vector<std::size_t>> sub;
        triangulate(rays, f, dim - 1, constraints, c, sub);
        for (auto& s : sub) {
            s.insert(s.begin(), apex);
            out.push_back(std::move(s));
        }
    }
}

std::string word_name(const std::vector<std::size_t>& word, std::size_t c) {
    if (word.empty())
        return "none";
    std::string s;
    for (std::size_t i = 0; i < word.size(); ++i) {
        if (c > 9 && i > 0)
            s += "-";
        s += std::to_string(word[i] + 1);
    }
    return s;
}

std::string list_text(const std::vector<Rational>& xs) {
    std::string s;
    for (std::size_t i = 0; i < xs.size(); ++i)
        s += (i ? "," : "") + to_string(xs[i]);
    return s;
}

struct Region {
    PPL::C_Polyhedron cone;
    Matrix M;                       // gamma+ = M gamma- on the region
    std::vector<std::size_t> word;  // contacts, 0-based, in order of application
};

} // namespace

std::pair<std::vector<std::size_t>, bool> sequential_word(const std::vector<Rational>& masses,
                                                          const std::vector<Rational>& restitution,
                                                          ImpactRule rule, const Vector& gamma,
                                                          std::size_t limit) {
    const Matrix G = chain_G(masses);
    Vector g = gamma;
    std::vector<std::size_t> word;
    while (auto k = pick(rule, g)) {
        if (word.size() == limit)
            return {word, false};
        word.push_back(*k);
        g = impact(G, *k, restitution[*k]) * g;
    }
    return {word, true};
}

std::optional<Vector> simulate_balls(const std::vector<Rational>& m, const std::vector<Rational>& restitution,
                                     ImpactRule rule, Vector u, std::size_t limit) {
    for (std::size_t step = 0;; ++step) {
        Vector gamma(u.size() - 1);
        for (std::size_t k = 0; k + 1 < u.size(); ++k)
            gamma[k] = u[k + 1] - u[k];
        const auto k = pick(rule, gamma);
        if (!k)
            return u;
        if (step == limit)
            return std::nullopt;
        // Two balls i = k, j = k+1: the relative velocity u_i - u_j reverses with factor e; the
        // momentum m_i u_i + m_j u_j is kept.
        const std::size_t i = *k, j = *k + 1;
        const Rational closing = u[i] - u[j];
        const Rational e = restitution[i];
        const Rational total = m[i] + m[j];
        u[i] -= (Rational(1) + e) * m[j] / total * closing;
        u[j] += (Rational(1) + e) * m[i] / total * closing;
    }
}

// PPL switches the FPU to rounding upward when it is initialised and expects that mode while it
// works (for its inexact coefficient types, unused here); the rest of impactcert (the float law,
// the fuzzer's error-free transformations) needs round-to-nearest. So the mode PPL wants is set
// only while derive_sequential runs, and the caller's mode is restored on every way out.
struct PplRounding {
    PplRounding() { PPL::set_rounding_for_PPL(); }
    ~PplRounding() { PPL::restore_pre_PPL_rounding(); }
    PplRounding(const PplRounding&) = delete;
    PplRounding& operator=(const PplRounding&) = delete;
};

DeriveResult derive_sequential(const DeriveOptions& options) {
    validate(options);
    static const bool ppl_ready = [] {
        PPL::initialize(); // saves the caller's rounding mode, sets PPL's
        PPL::restore_pre_PPL_rounding();
        return true;
    }();
    (void)ppl_ready;
    const PplRounding rounding;
    const std::size_t n = options.masses.size(), c = n - 1;
    const Matrix G = chain_G(options.masses);
    std::vector<Matrix> Qk;
    for (std::size_t k = 0; k < c; ++k)
        Qk.push_back(impact(G, k, options.restitution[k]));
    const auto dim = static_cast<PPL::dimension_type>(c);

    DeriveResult result;
    std::vector<Region> regions;
    std::vector<Region> work;
    work.push_back({PPL::C_Polyhedron(dim, PPL::UNIVERSE), Matrix::identity(c), {}});
    while (!work.empty()) {
        Region node = std::move(work.back());
        work.pop_back();
        // Branches: no contact approaches (the word ends), or contact k is the one the rule picks.
        for (std::size_t branch = 0; branch <= c; ++branch) {
            PPL::C_Polyhedron cell = node.cone;
            auto add = [&](const Vector& a) {
                if (!is_zero(a))
                    cell.add_constraint(form(a) >= 0);
                else
                    return; // 0 >= 0 holds everywhere
            };
            if (branch == c) {
                for (std::size_t j = 0; j < c; ++j)
                    add(node.M.row(j));
            } else {
                const std::size_t k = branch;
                // A contact whose velocity is 0 for every gamma- (after a plastic impact) never
                // approaches; a tie that holds everywhere goes to the lowest index.
                if (is_zero(node.M.row(k)))
                    continue;
                bool never = false;
                for (std::size_t j = 0; j < k; ++j)
                    never = never || (options.rule == ImpactRule::most_negative && node.M.row(j) == node.M.row(k));
                if (never)
                    continue;
                add(Rational(-1) * node.M.row(k)); // gamma_k <= 0
                for (std::size_t j = 0; j < c; ++j) {
                    if (j == k)
                        continue;
                    if (options.rule == ImpactRule::most_negative)
                        add(node.M.row(j) - node.M.row(k)); // gamma_k <= gamma_j
                    else if ((options.rule == ImpactRule::left_first && j < k) ||
                             (options.rule == ImpactRule::right_first && j > k))
                        add(node.M.row(j)); // gamma_j >= 0
                }
            }
            if (cell.affine_dimension() != dim)
                continue;
            if (branch == c) {
                regions.push_back({cell, node.M, node.word});
                continue;
            }
            if (node.word.size() == options.max_impacts) {
                // A gamma- inside the cell: the sum of its generators.
                const Cone d = describe(cell, c);
                Vector x(c);
                for (const auto& r : d.rays)
                    x = x + r;
                auto word = node.word;
                word.push_back(branch);
                const auto sim = sequential_word(options.masses, options.restitution, options.rule, x, options.max_impacts);
                if (sim.second || is_zero(x))
                    throw std::logic_error("derive: the non-finite witness does not exceed the bound");
                result.not_finite = x;
                result.word = word_name(word, c);
                return result;
            }
            auto word = node.word;
            word.push_back(branch);
            work.push_back({cell, Qk[branch] * node.M, word});
        }
    }
    result.regions = regions.size();
    std::sort(regions.begin(), regions.end(), [](const Region& a, const Region& b) {
        return a.word.size() != b.word.size() ? a.word.size() < b.word.size() : a.word < b.word;
    });
    for (const auto& region : regions)
        result.max_word = std::max(result.max_word, region.word.size());
    // Regions of different words with the same matrix (the braid relation Q1 Q2 Q1 = Q2 Q1 Q2
    // makes "121" and "212" one map) are merged where their union is convex: the union must
    // cover its convex hull (an exact test of PPL). The merged piece keeps the first word.
    auto convex_union = [&](const PPL::C_Polyhedron& a, const PPL::C_Polyhedron& b) -> std::optional<PPL::C_Polyhedron> {
        PPL::C_Polyhedron hull = a;
        hull.poly_hull_assign(b);
        PPL::Pointset_Powerset<PPL::C_Polyhedron> parts(dim, PPL::EMPTY);
        parts.add_disjunct(a);
        parts.add_disjunct(b);
        if (parts.geometrically_covers(PPL::Pointset_Powerset<PPL::C_Polyhedron>(hull)))
            return hull;
        return std::nullopt;
    };
    // Group by matrix, then merge within each group until no pair has a convex union.
    std::map<std::string, std::vector<Region>> groups;
    std::vector<std::string> order;
    for (auto& region : regions) {
        std::string key;
        for (std::size_t i = 0; i < c; ++i)
            key += to_string(region.M.row(i)) + ";";
        if (!groups.count(key))
            order.push_back(key);
        groups[key].push_back(std::move(region));
    }
    std::vector<Region> merged;
    for (const auto& key : order) {
        auto& group = groups[key];
        for (bool changed = true; changed;) {
            changed = false;
            for (std::size_t a = 0; a < group.size() && !changed; ++a)
                for (std::size_t b = a + 1; b < group.size() && !changed; ++b)
                    if (auto hull = convex_union(group[a].cone, group[b].cone)) {
                        group[a].cone = *hull;
                        group.erase(group.begin() + static_cast<std::ptrdiff_t>(b));
                        changed = true;
                    }
        }
        for (auto& r : group)
            merged.push_back(std::move(r));
    }
    std::sort(merged.begin(), merged.end(), [](const Region& a, const Region& b) {
        return a.word.size() != b.word.size() ? a.word.size() < b.word.size() : a.word < b.word;
    });
    regions = std::move(merged);

    Law law;
    law.name = "sequential-" + std::to_string(n) + "-balls";
    law.description = "Sequential impact law of a chain of " + std::to_string(n) + " balls, masses " +
                      list_text(options.masses) + ", restitution " + list_text(options.restitution) +
                      ", rule " + to_string(options.rule) +
                      "; derived by impactcert derive sequential. Pieces are named by their words (contacts in "
                      "order of application; regions of several words with one matrix and a convex union are "
                      "merged under the first word); parts of a triangulated region by .1, .2, ...";
    law.masses = options.masses;
    std::map<std::size_t, std::string> letter_piece; // contact -> a piece of the one-letter word
    std::vector<std::pair<std::string, std::vector<std::size_t>>> named;
    for (const auto& region : regions) {
        std::vector<PPL::C_Polyhedron> pointed;
        if (describe(region.cone, c).has_lines) {
            // Not pointed: split by the orthants first.
            for (std::size_t mask = 0; mask < (std::size_t{1} << c); ++mask) {
                PPL::C_Polyhedron part = region.cone;
                for (std::size_t k = 0; k < c; ++k) {
                    Vector e = unit_vector(c, k);
                    if (mask & (std::size_t{1} << k))
                        e = Rational(-1) * e;
                    part.add_constraint(form(e) >= 0);
                }
                if (part.affine_dimension() == dim)
                    pointed.push_back(part);
            }
        } else {
            pointed.push_back(region.cone);
        }
        std::vector<std::vector<Vector>> simplices;
        for (const auto& part : pointed) {
            const Cone d = describe(part, c);
            std::vector<std::size_t> all(d.rays.size());
            for (std::size_t i = 0; i < all.size(); ++i)
                all[i] = i;
            std::vector<std::vector<std::size_t>> tri;
            triangulate(d.rays, all, c, d.constraints, c, tri);
            for (const auto& t : tri) {
                std::vector<Vector> rs;
                for (auto i : t)
                    rs.push_back(d.rays[i]);
                simplices.push_back(rs);
            }
        }
        const std::string base = word_name(region.word, c);
        for (std::size_t s = 0; s < simplices.size(); ++s) {
            PieceDecl piece;
            piece.name = simplices.size() == 1 ? base : base + "." + std::to_string(s + 1);
            piece.Q = region.M;
            piece.rays = simplices[s];
            law.pieces.push_back(piece);
            named.emplace_back(piece.name, region.word);
            if (region.word.size() == 1 && !letter_piece.count(region.word[0]))
                letter_piece[region.word[0]] = piece.name;
        }
    }
    for (const auto& [k, name] : letter_piece)
        law.single_impacts.push_back(SingleImpactDecl{name, static_cast<int>(k + 1), options.restitution[k]});
    for (const auto& [name, word] : named) {
        if (word.size() < 2)
            continue;
        IdentityDecl id;
        id.lhs = name;
        bool complete = true;
        for (auto it = word.rbegin(); it != word.rend(); ++it) {
            if (!letter_piece.count(*it))
                complete = false;
            else
                id.product.push_back(letter_piece[*it]);
        }
        if (complete)
            law.identities.push_back(id);
    }
    // Classical outcomes, by the ball-velocity simulation, where every piece containing gamma-
    // agrees with it.
    const Model model(law);
    std::vector<std::pair<std::string, Vector>> experiments;
    auto ball_vector = [&](std::initializer_list<std::pair<std::size_t, int>> entries) {
        Vector u(n);
        for (const auto& [i, v] : entries)
            u[i] = v;
        return u;
    };
    experiments.push_back({"one ball in from the left", ball_vector({{0, 1}})});
    experiments.push_back({"two balls in from the left", ball_vector({{0, 1}, {1, 1}})});
    experiments.push_back({"one ball from each side", ball_vector({{0, 1}, {n - 1, -1}})});
    experiments.push_back({"one ball in from the right", ball_vector({{n - 1, -1}})});
    Vector ones(n, Rational(1));
    experiments.push_back({"all moving together", ones});
    for (const auto& [name, u] : experiments) {
        const auto u_plus = simulate_balls(options.masses, options.restitution, options.rule, u, options.max_impacts);
        if (!u_plus)
            continue;
        const Vector gamma = model.contact_velocities(u);
        const auto pieces = model.pieces_containing(gamma);
        bool agree = !pieces.empty();
        for (auto p : pieces)
            agree = agree && model.post_impact_velocities(u, gamma, model.pieces()[p].Q * gamma) == *u_plus;
        if (agree)
            law.outcomes.push_back(OutcomeDecl{name, u, *u_plus});
    }
    result.law = std::move(law);
    return result;
}

} // namespace impactcert
