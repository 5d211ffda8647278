// SPDX-License-Identifier: GPL-3.0-or-later
// symmetries -- proofs/README.md, "Symmetries".
// Claim: for every declared symmetry (P, P'): |P x|_H = |x|_H and |P' x|_H = |x|_H for all x,
// P maps every cone C_i onto a cone C_sigma(i), and Q_sigma(i) P = P' Q_i; hence
// S(P x) = P' S(x) for all x.
// Check: P^T H P = H and P'^T H P' = H exactly (polarisation, as P2); the primitive rays of
// P C_i are, as a set, those of one piece, which is sigma(i); Q_sigma(i) P r = P' Q_i r on the c
// rays r of C_i (a basis). The permutations sigma and the orbits of pieces they generate are
// what the other obligations use (orbit_representatives) once this one is proved.
// Witness: a point x with |P x|_H != |x|_H; or a piece whose image rays are no piece's rays;
// or a ray r of C_i with Q_sigma(i) P r != P' Q_i r.
#include "exact/int_kernel.hpp"
#include "prover/obligations/prover.hpp"

#include <algorithm>
#include <map>
#include <numeric>

namespace impactcert::detail {

namespace {

// x with x^T D x != 0 for a symmetric D != 0; empty when D = 0.
Vector nonzero_direction(const Matrix& D) {
    const std::size_t c = D.rows();
    for (std::size_t k = 0; k < c; ++k)
        if (sign_of(D(k, k)) != Sign::zero)
            return unit_vector(c, k);
    for (std::size_t k = 0; k < c; ++k)
        for (std::size_t l = k + 1; l < c; ++l)
            if (sign_of(D(k, l)) != Sign::zero)
                return unit_vector(c, k) + unit_vector(c, l);
    return {};
}

// Whether A B = C D exactly, in integers: (A.a B.a) C.den D.den = (C.a D.a) A.den B.den.
// False also when a value does not fit (the caller then decides over GMP).
bool commute_int(const intk::IntMatrix& A, const intk::IntMatrix& B, const intk::IntMatrix& C,
                 const intk::IntMatrix& D) {
    intk::IntMatrix left, right;
    if (!intk::multiply(A, B, left) || !intk::multiply(C, D, right))
        return false;
    __extension__ typedef __int128 i128;
    for (std::size_t k = 0; k < left.a.size(); ++k)
        if (static_cast<i128>(left.a[k]) * right.den != static_cast<i128>(right.a[k]) * left.den)
            return false;
    return true;
}

} // namespace

Outcome Prover::decide_symmetries() {
    Outcome o;
    o.method = "P^T H P = H, rays of P C_i, Q_sigma(i) P = P' Q_i";
    const auto& decls = m_.law().symmetries;
    const Matrix& H = m_.H();
    std::map<std::vector<std::size_t>, std::size_t> by_rays;
    std::map<Vector, std::size_t> ray_id;
    for (std::size_t r = 0; r < m_.rays().size(); ++r)
        ray_id.emplace(m_.rays()[r], r);
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
        auto ids = pieces_[p].ray_ids;
        std::sort(ids.begin(), ids.end());
        by_rays.emplace(std::move(ids), p);
    }
    // Integer forms of the rays and matrices, where they fit (int_kernel.hpp).
    std::vector<std::optional<std::vector<intk::i64>>> int_rays;
    std::map<std::vector<intk::i64>, std::size_t> int_ray_id;
    for (std::size_t r = 0; r < m_.rays().size(); ++r) {
        int_rays.push_back(intk::to_int_vector(m_.rays()[r]));
        if (int_rays.back())
            int_ray_id.emplace(*int_rays.back(), r);
    }
    std::vector<std::optional<intk::IntMatrix>> Q_int;
    for (const auto& pc : pieces_)
        Q_int.push_back(intk::to_int(pc.Q));
    SymmetryData data;
    for (std::size_t g = 0; g < decls.size(); ++g) {
        const SymmetryDecl& sym = decls[g];
        Json evidence = Json{{"symmetry", sym.name}};
        for (const char* which : {"P", "P_prime"}) {
            const Matrix& P = std::string(which) == "P" ? sym.P : sym.P_prime;
            const Matrix PtHP = transpose(P) * H * P;
            ++o.checks;
            evidence[std::string(which) == "P" ? "PtHP" : "P_primetHP_prime"] = to_json(PtHP);
            const Vector x = nonzero_direction(PtHP - H);
            if (x.empty())
                continue;
            const Rational lhs = m_.energy(P * x), rhs = m_.energy(x);
            ensure(lhs != rhs, "symmetries: isometry");
            return refute(o, Json{{"symmetry", sym.name}, {"matrix", which}, {"gamma", to_json(x)},
                                  {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
        }
        std::vector<std::size_t> sigma(pieces_.size());
        const auto P_int = intk::to_int(sym.P), Pp_int = intk::to_int(sym.P_prime);
        std::vector<intk::i64> image_int(c_);
        for (std::size_t p = 0; p < pieces_.size(); ++p) {
            const Piece& pc = pieces_[p];
            std::vector<Vector> image;
            std::vector<std::size_t> ids;
            bool known = true;
            for (std::size_t k = 0; k < c_; ++k) {
                // int64 where P and the ray fit (the same primitive ray as over GMP).
                const auto& r = int_rays[pc.ray_ids[k]];
                if (P_int && r && intk::apply(*P_int, r->data(), image_int.data())) {
                    intk::make_primitive(image_int);
                    auto it = int_ray_id.find(image_int);
                    if (it != int_ray_id.end()) {
                        ids.push_back(it->second);
                        continue;
                    }
                    image.push_back(intk::to_vector(image_int));
                } else {
                    image.push_back(primitive_ray(sym.P * pc.R.column(k)));
                }
                auto it = ray_id.find(image.back());
                known = known && it != ray_id.end();
                ids.push_back(known ? it->second : 0);
            }
            std::sort(ids.begin(), ids.end());
            auto found = known ? by_rays.find(ids) : by_rays.end();
            ++o.checks;
            if (found == by_rays.end()) {
                image.clear();
                for (std::size_t k = 0; k < c_; ++k)
                    image.push_back(primitive_ray(sym.P * pc.R.column(k)));
                Json rays = Json::array();
                for (const auto& r : image)
                    rays.push_back(to_json(r));
                return refute(o, Json{{"symmetry", sym.name}, {"piece", name(p)}, {"image_rays", rays}});
            }
            const std::size_t q = found->second;
            sigma[p] = q;
            if (P_int && Pp_int && Q_int[p] && Q_int[q] && commute_int(*Q_int[q], *P_int, *Pp_int, *Q_int[p]))
                continue; // Q_q P = P' Q_p as matrices: on every ray
            for (std::size_t k = 0; k < c_; ++k) {
                const Vector r = pc.R.column(k);
                const Vector lhs = pieces_[q].Q * (sym.P * r), rhs = sym.P_prime * (pc.Q * r);
                if (lhs == rhs)
                    continue;
                return refute(o, Json{{"symmetry", sym.name}, {"piece", name(p)}, {"image_piece", name(q)},
                                      {"gamma", to_json(r)}, {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
            }
        }
        if (limits_.evidence) {
            Json perm = Json::array();
            for (auto q : sigma)
                perm.push_back(q);
            evidence["permutation"] = std::move(perm);
            o.data["symmetries"].push_back(std::move(evidence));
        }
        data.sigma.push_back(std::move(sigma));
    }
    // Orbits: union of the generators' cycles; each orbit is represented by its least piece.
    std::vector<std::size_t> parent(pieces_.size());
    std::iota(parent.begin(), parent.end(), std::size_t{0});
    auto find = [&](std::size_t x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const auto& sigma : data.sigma)
        for (std::size_t p = 0; p < sigma.size(); ++p) {
            const std::size_t a = find(p), b = find(sigma[p]);
            if (a != b)
                parent[std::max(a, b)] = std::min(a, b);
        }
    for (std::size_t p = 0; p < pieces_.size(); ++p)
        if (find(p) == p)
            data.representatives.push_back(p);
    // P' a non-negative monomial matrix: one non-zero entry, positive, in each row and column.
    data.orthant_preserving = std::all_of(decls.begin(), decls.end(), [&](const SymmetryDecl& sym) {
        for (std::size_t r = 0; r < c_; ++r) {
            std::size_t in_row = 0, in_column = 0;
            for (std::size_t k = 0; k < c_; ++k) {
                if (sign_of(sym.P_prime(r, k)) == Sign::negative || sign_of(sym.P_prime(k, r)) == Sign::negative)
                    return false;
                in_row += sign_of(sym.P_prime(r, k)) != Sign::zero ? 1 : 0;
                in_column += sign_of(sym.P_prime(k, r)) != Sign::zero ? 1 : 0;
            }
            if (in_row != 1 || in_column != 1)
                return false;
        }
        return true;
    });
    o.method += ": " + std::to_string(decls.size()) + " symmetries, " + std::to_string(data.representatives.size()) +
                " orbits of pieces";
    if (limits_.evidence)
        o.data["orbit_representatives"] = names_of(data.representatives);
    symmetry_data_ = std::move(data);
    return o;
}

const Outcome& Prover::symmetries_outcome() {
    if (!symmetries_)
        symmetries_ = decide_symmetries();
    return *symmetries_;
}

const SymmetryData* Prover::symmetry() {
    if (!m_.applies("symmetries"))
        return nullptr;
    return symmetries_outcome().proved ? &*symmetry_data_ : nullptr;
}

std::string Prover::by_symmetries() {
    const SymmetryData* s = symmetry();
    return s ? " (" + std::to_string(s->representatives.size()) + " orbit representatives, by the symmetries)" : "";
}

std::vector<std::size_t> Prover::orthant_representatives() {
    const SymmetryData* s = symmetry();
    if (s && s->orthant_preserving)
        return s->representatives;
    std::vector<std::size_t> all(pieces_.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    return all;
}

std::vector<std::size_t> Prover::orbit_representatives() {
    if (const SymmetryData* s = symmetry())
        return s->representatives;
    std::vector<std::size_t> all(pieces_.size());
    std::iota(all.begin(), all.end(), std::size_t{0});
    return all;
}

} // namespace impactcert::detail
