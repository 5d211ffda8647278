// SPDX-License-Identifier: GPL-3.0-or-later
// coulomb -- proofs/README.md, "coulomb" (Lemma F), with Lemma R.
// Claim (SPEC section 9): on every cone C_i, with Lambda = H (Q_i - I) gamma and
// xi = Q_i gamma + E_T gamma on the tangents, for every tangent j of contact k:
// Lambda in the friction cone, xi_Tj > 0 => Lambda_Tj = -mu Lambda_Nk, xi_Tj < 0 =>
// Lambda_Tj = +mu Lambda_Nk.
// Check: the friction cone at every ray (linear: Lemma R). Then, with f = Lambda_T + mu Lambda_N
// and g = mu Lambda_N - Lambda_T (both >= 0 on C_i), Lemma F: "f > 0 => xi_T <= 0" holds on the
// simplicial cone C_i exactly when f vanishes at every ray or xi_T <= 0 at every ray (the same
// for g and xi_T >= 0). The witness of a failure is a ray r_a with f(r_a) > 0 plus t times a ray
// r_b with xi_T(r_b) > 0, t large enough that xi_T > 0 there (a point of C_i where both hold).
// On dependent columns (proofs/README.md, "Redundant contacts") Lambda = L_i gamma_B, the piece's
// declared impulse (C L_i = H (Q_i - I), checked at the rays), and xi in all d coordinates:
// C^T Q_i gamma_B + E_T C^T gamma_B.
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

namespace {

// The lever of Lemma F: a point s = e_a + t e_b (a = b: e_a) with f > 0 and the wrong sign of xi.
Vector lemma_f_point(const Piece& piece, std::size_t a, std::size_t b, const Vector& xi_at_rays, int wrong) {
    Vector x = piece.R.column(a);
    if (a == b)
        return x;
    // xi(e_a + t e_b) = xi_a + t xi_b with wrong * xi_b > 0: t = |xi_a| / |xi_b| + 1.
    Rational xa = xi_at_rays[a], xb = xi_at_rays[b];
    if (wrong < 0) {
        xa = -xa;
        xb = -xb;
    }
    Rational t = (sign_of(xa) == Sign::negative ? -xa : xa) / xb + Rational(1);
    return x + t * piece.R.column(b);
}

} // namespace

Outcome Prover::coulomb() {
    Outcome o;
    o.method = m_.has_polygons() ? "friction cone and slip signs at rays, copositive polygon forms"
                                 : "friction cone and slip signs at rays";
    const std::size_t normals = m_.normals();
    const Matrix I = Matrix::identity(c_);
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
        const Piece& piece = pieces_[p];
        const Matrix K = m_.redundant() ? *piece.L : m_.H() * (piece.Q - I);
        const Matrix Ct = m_.redundant() ? transpose(m_.C()) : I; // into all d coordinates
        std::vector<Vector> impulse(c_), after(c_), full(c_);
        for (std::size_t a = 0; a < c_; ++a) {
            const Vector r = piece.R.column(a);
            impulse[a] = K * r;
            after[a] = Ct * (piece.Q * r);
            full[a] = Ct * r;
            ++o.checks;
            if (m_.redundant() && m_.C() * impulse[a] != m_.H() * (piece.Q * r - r))
                return refute(o, Json{{"piece", name(p)}, {"gamma", to_json(r)}, {"impulse", to_json(impulse[a])},
                                      {"reason", "the declared impulse does not give the law's velocities (C L r != H (Q - I) r)"}});
            if (!in_friction_cone(impulse[a]))
                return refute(o, Json{{"piece", name(p)}, {"gamma", to_json(r)}, {"impulse", to_json(impulse[a])},
                                      {"reason", "impulse outside the friction cone"}});
        }
        for (std::size_t j = 0; j < m_.tangents().size(); ++j) {
            const Tangent& t = m_.tangents()[j];
            if (!m_.polygons()[t.contact].empty())
                continue; // a friction polygon: the quadratic forms below
            const std::size_t T = normals + j;
            Vector f(c_), g(c_), xi(c_); // at the rays
            for (std::size_t a = 0; a < c_; ++a) {
                const Rational bound = t.mu * impulse[a][t.contact];
                f[a] = impulse[a][T] + bound;
                g[a] = bound - impulse[a][T];
                xi[a] = after[a][T] + t.e_T * full[a][T];
            }
            // wrong = +1: f > 0 (Lambda_T above -mu Lambda_N) needs xi_T <= 0; wrong = -1: g > 0 needs xi_T >= 0.
            for (const int wrong : {1, -1}) {
                const Vector& h = wrong > 0 ? f : g;
                std::optional<std::size_t> pos_h, bad_xi;
                for (std::size_t a = 0; a < c_; ++a) {
                    if (sign_of(h[a]) == Sign::positive && !pos_h)
                        pos_h = a;
                    const Sign sx = sign_of(xi[a]);
                    if (((wrong > 0 && sx == Sign::positive) || (wrong < 0 && sx == Sign::negative)) && !bad_xi)
                        bad_xi = a;
                }
                ++o.checks;
                if (!pos_h || !bad_xi)
                    continue;
                const Vector x = lemma_f_point(piece, *pos_h, *bad_xi, xi, wrong);
                const Vector lambda = K * x;
                const Vector plus = Ct * (piece.Q * x);
                const Rational xi_x = plus[T] + t.e_T * (Ct * x)[T];
                const Rational h_x = wrong > 0 ? lambda[T] + t.mu * lambda[t.contact] : t.mu * lambda[t.contact] - lambda[T];
                ensure(sign_of(h_x) == Sign::positive && sign_of(xi_x) == (wrong > 0 ? Sign::positive : Sign::negative),
                       "coulomb witness");
                return refute(o, Json{{"piece", name(p)},
                                      {"contact", t.contact + 1},
                                      {"tangent", j + 1},
                                      {"gamma", to_json(x)},
                                      {"gamma_plus", to_json(plus)},
                                      {"impulse", to_json(lambda)},
                                      {"xi_T", to_json(xi_x)},
                                      {"reason", wrong > 0 ? "the contact slips with xi_T > 0 but Lambda_T != -mu Lambda_N"
                                                           : "the contact slips with xi_T < 0 but Lambda_T != +mu Lambda_N"}});
            }
        }
    }
    if (m_.has_polygons())
        return polygon_forms(std::move(o));
    return o;
}

// Friction polygons (proofs/README.md, "Polygonal friction cones", Lemma P): with Lambda_T in the
// polygon mu Lambda_N P at every ray (above), Coulomb's law (maximal dissipation) holds on C_i
// exactly when q_j(gamma) = (Lambda_T - mu Lambda_N v_j) . xi_T <= 0 on C_i for every vertex v_j:
// in the rays' coordinates, A_j = -(B_j + B_j^T) / 2 copositive, B_j(a, b) = (Lambda_T(r_a) -
// mu Lambda_N(r_a) v_j) . xi_T(r_b). A negative point z of A_j gives gamma = R z in C_i where
// Lambda_T dissipates less than the friction mu Lambda_N v_j of the polygon.
Outcome Prover::polygon_forms(Outcome o) {
    const std::size_t normals = m_.normals();
    const Matrix I = Matrix::identity(c_);
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
        const Piece& piece = pieces_[p];
        const Matrix K = m_.redundant() ? *piece.L : m_.H() * (piece.Q - I);
        const Matrix Ct = m_.redundant() ? transpose(m_.C()) : I;
        std::vector<Vector> impulse(c_), xi_all(c_);
        for (std::size_t a = 0; a < c_; ++a) {
            const Vector r = piece.R.column(a);
            impulse[a] = K * r;
            xi_all[a] = Ct * (piece.Q * r); // gamma+ in all d coordinates; e_T gamma- added below
            const Vector full = Ct * r;
            for (std::size_t j = 0; j < m_.tangents().size(); ++j)
                xi_all[a][normals + j] += m_.tangents()[j].e_T * full[normals + j];
        }
        for (std::size_t k = 0; k < normals; ++k) {
            const FrictionPolygon& P = m_.polygons()[k];
            if (P.empty())
                continue;
            std::size_t T = 0;
            while (m_.tangents()[T].contact != k)
                ++T;
            const Rational& mu = m_.tangents()[T].mu;
            T += normals;
            for (std::size_t v = 0; v < P.v.size(); ++v) {
                Matrix A(c_, c_);
                for (std::size_t a = 0; a < c_; ++a)
                    for (std::size_t b = 0; b < c_; ++b) {
                        const Rational f0 = impulse[a][T] - mu * impulse[a][k] * P.v[v][0];
                        const Rational f1 = impulse[a][T + 1] - mu * impulse[a][k] * P.v[v][1];
                        const Rational term = f0 * xi_all[b][T] + f1 * xi_all[b][T + 1];
                        A(a, b) -= term / 2;
                        A(b, a) -= term / 2;
                    }
                const auto cop = decide_copositivity(A, limits_.max_faces, limits_.integer_kernels);
                o.checks += cop.method == CopositivityMethod::kkt_enumeration ? cop.faces : 1;
                if (limits_.evidence)
                    o.data["polygon_forms"].push_back(Json{{"piece", name(p)}, {"contact", k + 1}, {"vertex", v + 1},
                                                           {"A", to_json(A)}, {"certificate", certificate_json(cop)}});
                if (!cop.copositive) {
                    const Vector gamma = piece.R * cop.witness;
                    const Vector lambda = K * gamma;
                    const Vector plus = Ct * (piece.Q * gamma);
                    const Vector full = Ct * gamma;
                    Vector xi_T{plus[T] + m_.tangents()[T - normals].e_T * full[T],
                                plus[T + 1] + m_.tangents()[T + 1 - normals].e_T * full[T + 1]};
                    const Rational q = (lambda[T] - mu * lambda[k] * P.v[v][0]) * xi_T[0] +
                                       (lambda[T + 1] - mu * lambda[k] * P.v[v][1]) * xi_T[1];
                    ensure(sign_of(q) == Sign::positive && nonnegative(piece.R_inv * gamma), "coulomb polygon witness");
                    return refute(o, Json{{"piece", name(p)},
                                          {"contact", k + 1},
                                          {"vertex", v + 1},
                                          {"gamma", to_json(gamma)},
                                          {"gamma_plus", to_json(plus)},
                                          {"impulse", to_json(lambda)},
                                          {"xi_T", to_json(xi_T)},
                                          {"reason", "the friction dissipates less than mu Lambda_N v at a vertex v of the "
                                                     "polygon ((Lambda_T - mu Lambda_N v) . xi_T > 0): not Coulomb's law"}});
                }
            }
        }
    }
    return o;
}

} // namespace impactcert::detail
