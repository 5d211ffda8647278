// SPDX-License-Identifier: GPL-3.0-or-later
// kinetic -- proofs/README.md, "kinetic", with Lemma R (rays suffice for linear statements).
// Claim: the impulse Lambda = H (Q_i - I) gamma >= 0 for gamma in C_i (Lambda = H (gamma+ -
// gamma-) by the impact equations, SPEC section 1).
// Check: H (Q_i - I) r >= 0 for every ray r of every cone; Lemma R with L = H (Q_i - I). A ray
// with a negative impulse is the witness.
// With friction (SPEC section 9): Lambda in the friction cone, Lambda_N >= 0 and
// mu_k Lambda_Nk -+ Lambda_Tj >= 0 for every tangent j of contact k: linear inequalities in
// Lambda, so again the rays suffice (Lemma R); the witness is a ray outside the cone.
// On dependent columns (proofs/README.md, "Redundant contacts", Lemma V) the impulse is the
// piece's declared Lambda = L gamma_B, which must move the velocities as the law does:
// C L r = H (Q_i - I) r at every ray (then on R^c: the rays are a basis); a ray where it does
// not is the witness.
#include "exact/int_kernel.hpp"
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

namespace {

bool impulses_nonnegative_int(const intk::IntMatrix& H, const Piece& piece, std::vector<intk::i64>& t,
                              std::vector<intk::i64>& impulse) {
    const auto Q = intk::to_int(piece.Q);
    if (!Q)
        return false;
    const std::size_t c = t.size();
    for (std::size_t a = 0; a < c; ++a) {
        const auto r = intk::to_int_vector(piece.R.column(a));
        if (!r || !intk::apply(*Q, r->data(), t.data()))
            return false;
        for (std::size_t k = 0; k < c; ++k) // t = Qn r - dQ r
            if (__builtin_mul_overflow((*r)[k], Q->den, &impulse[k]) || __builtin_sub_overflow(t[k], impulse[k], &t[k]))
                return false;
        if (!intk::apply(H, t.data(), impulse.data()))
            return false;
        for (auto x : impulse)
            if (x < 0)
                return false;
    }
    return true;
}

} // namespace

bool Prover::in_friction_cone(const Vector& impulse) const {
    for (std::size_t k = 0; k < m_.normals(); ++k)
        if (sign_of(impulse[k]) == Sign::negative)
            return false;
    for (std::size_t j = 0; j < m_.tangents().size(); ++j) {
        const Tangent& t = m_.tangents()[j];
        const Rational bound = t.mu * impulse[t.contact];
        if (!m_.polygons()[t.contact].empty()) {
            // A friction polygon: a . Lambda_T <= mu Lambda_N for every facet (at the contact's first tangent).
            if (j > 0 && m_.tangents()[j - 1].contact == t.contact)
                continue;
            const std::size_t T = m_.normals() + j;
            for (const Vector& a : m_.polygons()[t.contact].a)
                if (sign_of(bound - a[0] * impulse[T] - a[1] * impulse[T + 1]) == Sign::negative)
                    return false;
            continue;
        }
        const Rational& lt = impulse[m_.normals() + j];
        if (sign_of(bound - lt) == Sign::negative || sign_of(bound + lt) == Sign::negative)
            return false;
    }
    return true;
}

Outcome Prover::kinetic() {
    Outcome o;
    o.method = "impulses at rays";
    const Matrix I = Matrix::identity(c_);
    // Without evidence, the signs first in int64 (int_kernel.hpp): Hn (Qn r - dQ r) has the
    // signs of H (Q - I) r; any piece that is not all non-negative, or does not fit, over GMP.
    const bool friction = m_.has_friction();
    if (friction)
        o.method = "impulses at rays in the friction cone";
    const auto H_int = limits_.evidence || !limits_.integer_kernels || friction || m_.redundant()
                           ? std::nullopt
                           : intk::to_int(m_.H());
    std::vector<intk::i64> t(c_), impulse_int(c_);
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
        if (H_int && impulses_nonnegative_int(*H_int, pieces_[p], t, impulse_int)) {
            o.checks += c_;
            continue;
        }
        const Matrix K = m_.H() * (pieces_[p].Q - I);
        for (std::size_t a = 0; a < c_; ++a) {
            const Vector r = pieces_[p].R.column(a);
            const Vector impulse = m_.redundant() ? *pieces_[p].L * r : K * r;
            ++o.checks;
            if (limits_.evidence)
                o.data["impulses"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"impulse", to_json(impulse)}});
            if ((friction ? !in_friction_cone(impulse) : !nonnegative(impulse)) ||
                (m_.redundant() && m_.C() * impulse != K * r))
                return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                      {"impulse", to_json(impulse)}});
        }
    }
    return o;
}

} // namespace impactcert::detail
