// SPDX-License-Identifier: GPL-3.0-or-later
// energetic -- proofs/README.md, "energetic", with Lemma Q (quadratic statements on a cone are
// copositivity) and "Exact copositivity".
// Claim: |Q_i x|_H <= |x|_H for x in C_i.
// Check: B = R_i^T (H - Q_i^T H Q_i) R_i copositive, decided exactly (decide_copositivity:
// A >= 0, PSD, PSD plus non-negative, else the complete KKT enumeration of every simplex face).
// A negative minimiser s >= 0 gives the witness gamma = R_i s in C_i with
// |Q_i gamma|_H^2 > |gamma|_H^2.
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

Outcome Prover::energetic() {
    Outcome o;
    o.method = "copositivity of R^T (H - Q^T H Q) R" + by_symmetries();
    // With verified symmetries one piece per orbit (proofs/README.md, "Symmetries").
    for (const std::size_t p : orbit_representatives()) {
        const Piece& pc = pieces_[p];
        const Matrix B = transpose(pc.R) * (m_.H() - transpose(pc.Q) * m_.H() * pc.Q) * pc.R;
        const auto cop = decide_copositivity(B, limits_.max_faces, limits_.integer_kernels);
        o.checks += cop.method == CopositivityMethod::kkt_enumeration ? cop.faces : 1;
        if (limits_.evidence)
            o.data["pieces"].push_back(Json{{"piece", name(p)}, {"B", to_json(B)}, {"certificate", certificate_json(cop)}});
        if (!cop.copositive) {
            const Vector gamma = pc.R * cop.witness;
            const Rational lhs = m_.energy(pc.Q * gamma), rhs = m_.energy(gamma);
            ensure(lhs > rhs && nonnegative(pc.R_inv * gamma), "energetic");
            return refute(o, Json{{"piece", name(p)}, {"gamma", to_json(gamma)},
                                  {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
        }
    }
    return o;
}

} // namespace impactcert::detail
