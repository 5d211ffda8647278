// SPDX-License-Identifier: GPL-3.0-or-later
// nonexpansive-lemma -- proofs/README.md, "nonexpansive-lemma", with Lemma P (PSD certificate).
// Claim: the statement of nonexpansive, by a second, independent route.
// Check: S a function (the fan's decision), P1, and H - Q_i^T H Q_i PSD for every piece by exact
// LDL^T. Then S is continuous and linear on each cone, and the triangle inequality along the
// segment from a to b gives |S(b) - S(a)|_H <= |b - a|_H. Each failure is a true witness: the
// domain witness, P1's discontinuity ("via": "P1"), or for a piece that is not PSD along x the
// interior pair R 1 + eps x, R 1 with eps = 1 / (2 max(1, max_k |(R^-1 x)_k| + 1)).
#include "prover/obligations/prover.hpp"

#include <algorithm>

namespace impactcert::detail {

Outcome Prover::nonexpansive_lemma() {
    Outcome o;
    o.method = "fan + P1 + H - Q^T H Q PSD per piece";
    if (auto w = domain_witness())
        return refute(o, std::move(*w));
    const Outcome continuity = p1();
    o.checks += continuity.checks;
    if (!continuity.proved) {
        Json w = continuity.counterexample;
        w["via"] = "P1";
        return refute(o, std::move(w));
    }
    // With verified symmetries one piece per orbit (proofs/README.md, "Symmetries").
    o.method += by_symmetries();
    for (const std::size_t p : orbit_representatives()) {
        const Piece& pc = pieces_[p];
        const Matrix B = m_.H() - transpose(pc.Q) * m_.H() * pc.Q;
        const auto ldl = ldl_psd(B);
        ++o.checks;
        if (ldl.psd) {
            if (limits_.evidence)
                o.data["pieces"].push_back(Json{{"piece", name(p)}, {"matrix", to_json(B)},
                                                {"L", to_json(ldl.L)}, {"D", to_json(ldl.D)}});
            continue;
        }
        // Two interior points of the same cone, a - b along the expanding direction.
        const auto [a, b] = interior_pair_along(pc, ldl.witness);
        return refute(o, pair_witness(p, p, a, b));
    }
    return o;
}

} // namespace impactcert::detail
