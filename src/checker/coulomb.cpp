// SPDX-License-Identifier: GPL-3.0-or-later
// The checker's own decision of `coulomb` (SPEC section 9; proofs/README.md, "coulomb", Lemma F),
// in its own arithmetic: no evidence is trusted, everything is recomputed from the law.
#include "checker.hpp"

namespace impactcert_check::detail {

std::optional<Checker::CoulombFailure> Checker::first_coulomb_failure() const {
    const std::size_t c = law_.c, N = law_.normals;
    for (std::size_t p = 0; p < P(); ++p) {
        const Piece& piece = pc(p);
        std::vector<Vec> lambda(c), after(c), all(c); // after, all: in all d coordinates
        for (std::size_t a = 0; a < c; ++a) {
            after[a] = law_.all_coordinates(mul(piece.Q_, piece.rays[a]));
            all[a] = law_.all_coordinates(piece.rays[a]);
            lambda[a] = law_.impulse_at(p, piece.rays[a]);
            if (!law_.impulse_consistent(p, piece.rays[a]) || !law_.impulse_admissible(lambda[a]))
                return CoulombFailure{p, 0, 0, piece.rays[a]};
        }
        for (std::size_t j = 0; j < law_.tangents.size(); ++j) {
            const Tangent& t = law_.tangents[j];
            for (const int kind : {1, -1}) {
                // h: Lambda_T + mu Lambda_N (kind +1) or mu Lambda_N - Lambda_T (kind -1), >= 0 here.
                std::optional<std::size_t> first_h, first_xi;
                Vec xi(c);
                for (std::size_t a = 0; a < c; ++a) {
                    const Q h = kind * lambda[a][N + j] + t.mu * lambda[a][t.contact];
                    xi[a] = after[a][N + j] + t.e_T * all[a][N + j];
                    if (sgn(h) > 0 && !first_h)
                        first_h = a;
                    if (kind * sgn(xi[a]) > 0 && !first_xi)
                        first_xi = a;
                }
                if (!first_h || !first_xi)
                    continue;
                Vec g = piece.rays[*first_h];
                if (*first_xi != *first_h) {
                    Q xa = kind * xi[*first_h], xb = kind * xi[*first_xi];
                    Q scale = (sgn(xa) < 0 ? Q(-xa) : xa) / xb + 1;
                    for (std::size_t i = 0; i < c; ++i)
                        g[i] += scale * piece.rays[*first_xi][i];
                }
                return CoulombFailure{p, j, kind, g};
            }
        }
    }
    return std::nullopt;
}

void Checker::check_coulomb_witness(const Json& w, const std::string& wp) {
    const auto failure = first_coulomb_failure();
    require(failure.has_value(), wp, "Coulomb's law holds on every cone");
    const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
    const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
    require(g.size() == law_.c && law_.in_cone(p, g), at(wp, "gamma"), "is not in the piece's cone");
    const Vec plus = law_.all_coordinates(mul(pc(p).Q_, g));
    const Vec lambda = law_.impulse_at(p, g);
    const Vec all = law_.all_coordinates(g);
    expect_vec(w, wp, "impulse", lambda, law_.redundant ? "L gamma" : "H (Q - I) gamma");
    str(field(w, wp, "reason"), at(wp, "reason"));
    if (failure->kind == 0) {
        expect_keys(w, wp, {"piece", "gamma", "impulse", "reason"});
        require(!law_.impulse_admissible(lambda) || !law_.impulse_consistent(p, g), at(wp, "impulse"),
                "is in the friction cone");
    } else {
        expect_keys(w, wp, {"piece", "contact", "tangent", "gamma", "gamma_plus", "impulse", "xi_T", "reason"});
        expect_vec(w, wp, "gamma_plus", plus, law_.redundant ? "C^T Q gamma" : "Q gamma");
        const std::size_t j = natural(field(w, wp, "tangent"), at(wp, "tangent"));
        require(j >= 1 && j <= law_.tangents.size(), at(wp, "tangent"), "no such tangent");
        const Tangent& t = law_.tangents[j - 1];
        require(natural(field(w, wp, "contact"), at(wp, "contact")) == t.contact + 1, at(wp, "contact"),
                "is not the tangent's contact");
        const std::size_t T = law_.normals + j - 1;
        const Q xi = plus[T] + t.e_T * all[T];
        require(rat(field(w, wp, "xi_T"), at(wp, "xi_T")) == xi, at(wp, "xi_T"), "is not gamma_T+ + e_T gamma_T-");
        const int kind = sgn(xi) > 0 ? 1 : -1;
        require(sgn(xi) != 0 && sgn(kind * lambda[T] + t.mu * lambda[t.contact]) > 0, wp,
                "friction opposes the slip there (Coulomb's law holds at gamma)");
        require(j - 1 == failure->tangent && kind == failure->kind, at(wp, "tangent"),
                "is not the first failure of Coulomb's law");
    }
    require(p == failure->piece && g == failure->gamma, at(wp, "gamma"),
            "is not the first failure of Coulomb's law (Lemma F's point)");
}

} // namespace impactcert_check::detail
