// SPDX-License-Identifier: GPL-3.0-or-later
// P2 -- proofs/README.md, "P2 (energy conservation)".
// Claim: |Q_i x|_H = |x|_H for all x and every piece.
// Check: Q_i^T H Q_i = H exactly, one per piece: |Q x|_H^2 - |x|_H^2 = x^T D x with
// D = Q^T H Q - H symmetric, which vanishes for all x iff D = 0 (polarisation).
// Witness when D != 0: x = e_k if D_kk != 0, else e_k + e_l with D_kl != 0.
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

Outcome Prover::p2() {
    Outcome o;
    o.method = "Q^T H Q = H" + by_symmetries();
    const Matrix& H = m_.H();
    // With verified symmetries one piece per orbit (proofs/README.md, "Symmetries").
    for (const std::size_t p : orbit_representatives()) {
        const Matrix& Q = pieces_[p].Q;
        const Matrix QtHQ = transpose(Q) * H * Q;
        const Matrix D = QtHQ - H;
        ++o.checks;
        if (limits_.evidence)
            o.data["QtHQ"].push_back(Json{{"piece", name(p)}, {"matrix", to_json(QtHQ)}});
        if (D == Matrix(c_, c_))
            continue;
        // A symmetric D != 0 has x^T D x != 0 at some e_k or e_k + e_l.
        Vector x;
        for (std::size_t k = 0; k < c_ && x.empty(); ++k)
            if (sign_of(D(k, k)) != Sign::zero)
                x = unit_vector(c_, k);
        for (std::size_t k = 0; k < c_ && x.empty(); ++k)
            for (std::size_t l = k + 1; l < c_ && x.empty(); ++l)
                if (sign_of(D(k, l)) != Sign::zero)
                    x = unit_vector(c_, k) + unit_vector(c_, l);
        const Rational lhs = m_.energy(Q * x), rhs = m_.energy(x);
        ensure(lhs != rhs, "P2");
        return refute(o, Json{{"piece", name(p)}, {"gamma", to_json(x)},
                              {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
    }
    return o;
}

} // namespace impactcert::detail
