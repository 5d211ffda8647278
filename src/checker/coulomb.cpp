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
            if (!law_.polygons[t.contact].a.empty())
                continue; // a friction polygon: its forms (check_polygon_forms)
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

std::vector<Checker::PolygonForm> Checker::polygon_forms() const {
    std::vector<PolygonForm> out;
    for (std::size_t p = 0; p < P(); ++p)
        for (std::size_t k = 0; k < law_.normals; ++k)
            for (std::size_t v = 0; v < law_.polygons[k].v.size(); ++v)
                out.push_back(PolygonForm{p, k, v});
    return out;
}

Mat Checker::polygon_form(const PolygonForm& f) const {
    const std::size_t c = law_.c, N = law_.normals;
    const Piece& piece = pc(f.piece);
    std::size_t j = 0;
    while (law_.tangents[j].contact != f.contact)
        ++j;
    const std::size_t T1 = N + j, T2 = N + j + 1;
    const Q& mu = law_.tangents[j].mu;
    const Vec& v = law_.polygons[f.contact].v[f.vertex];
    std::vector<Vec> fr(c), xi(c); // (Lambda_T - mu Lambda_N v) and xi_T at the rays
    for (std::size_t a = 0; a < c; ++a) {
        const Vec lambda = law_.impulse_at(f.piece, piece.rays[a]);
        const Vec after = law_.all_coordinates(mul(piece.Q_, piece.rays[a]));
        const Vec all = law_.all_coordinates(piece.rays[a]);
        fr[a] = Vec{lambda[T1] - mu * lambda[f.contact] * v[0], lambda[T2] - mu * lambda[f.contact] * v[1]};
        xi[a] = Vec{after[T1] + law_.tangents[j].e_T * all[T1], after[T2] + law_.tangents[j + 1].e_T * all[T2]};
    }
    Mat A(c, Vec(c, Q(0)));
    for (std::size_t a = 0; a < c; ++a)
        for (std::size_t b = 0; b < c; ++b)
            A[a][b] = -(fr[a][0] * xi[b][0] + fr[a][1] * xi[b][1] + fr[b][0] * xi[a][0] + fr[b][1] * xi[a][1]) / 2;
    return A;
}

void Checker::check_coulomb_witness(const Json& w, const std::string& wp) {
    const auto failure = first_coulomb_failure();
    if (!failure && law_.has_polygons()) {
        // The first polygon form that is not copositive: its canonical point.
        const Json& entry = last_entry("coulomb", "polygon_forms");
        expect_keys(w, wp, {"piece", "contact", "vertex", "gamma", "gamma_plus", "impulse", "xi_T", "reason"});
        require(w.at("piece") == entry.at("piece") && w.at("contact") == entry.at("contact") &&
                    w.at("vertex") == entry.at("vertex"),
                wp, "is not the first polygon form that fails");
        const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
        const std::size_t k = natural(field(w, wp, "contact"), at(wp, "contact")) - 1;
        const std::size_t v = natural(field(w, wp, "vertex"), at(wp, "vertex")) - 1;
        require(k < law_.normals && v < law_.polygons[k].v.size(), at(wp, "vertex"), "no such vertex");
        const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        const Vec canonical = mul(pc(p).R, kkt_minimiser(entry.at("certificate"), wp, law_.c));
        require(g == canonical, at(wp, "gamma"), "is not the canonical witness");
        const Vec plus = law_.all_coordinates(mul(pc(p).Q_, g));
        const Vec all = law_.all_coordinates(g);
        const Vec lambda = law_.impulse_at(p, g);
        expect_vec(w, wp, "gamma_plus", plus, law_.redundant ? "C^T Q gamma" : "Q gamma");
        expect_vec(w, wp, "impulse", lambda, law_.redundant ? "L gamma" : "H (Q - I) gamma");
        str(field(w, wp, "reason"), at(wp, "reason"));
        std::size_t j = 0;
        while (law_.tangents[j].contact != k)
            ++j;
        const std::size_t T = law_.normals + j;
        const Vec xi{plus[T] + law_.tangents[j].e_T * all[T], plus[T + 1] + law_.tangents[j + 1].e_T * all[T + 1]};
        expect_vec(w, wp, "xi_T", xi, "gamma_T+ + e_T gamma_T-");
        const Q& mu = law_.tangents[j].mu;
        const Vec& vx = law_.polygons[k].v[v];
        const Q q = (lambda[T] - mu * lambda[k] * vx[0]) * xi[0] + (lambda[T + 1] - mu * lambda[k] * vx[1]) * xi[1];
        require(law_.in_cone(p, g) && sgn(q) > 0, wp, "the friction dissipates at least as much as at the vertex there");
        return;
    }
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
