// SPDX-License-Identifier: GPL-3.0-or-later
// single-impacts -- proofs/README.md, "single-impacts".
// Claim: a declared piece equals the two-ball impact at contact k with restitution e.
// Derivation (from M and W only): only Lambda_k acts, gamma+ = gamma- + lambda G e_k, and
// gamma+_k = -e gamma-_k fixes lambda, so Q^(k)(e) = I - (1+e) G e_k e_k^T / G_kk
// (Model::single_impact). Check: Q_piece = Q^(k)(e) exactly, one per declaration; a failure
// reports the unit vector of the first differing column.
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

Outcome Prover::single_impacts() {
    Outcome o;
    o.method = "Q^(k)(e) = I - (1+e) G e_k e_k^T / G_kk";
    const auto& decls = m_.law().single_impacts;
    for (const auto& d : decls) {
        const Matrix& Q = pieces_[m_.piece_index(d.piece)].Q;
        const Matrix impact = m_.single_impact(static_cast<std::size_t>(d.contact - 1), d.restitution);
        ++o.checks;
        o.data["impacts"].push_back(Json{{"piece", d.piece}, {"contact", d.contact},
                                         {"restitution", to_json(d.restitution)}, {"impact", to_json(impact)}});
        if (Q == impact)
            continue;
        std::size_t col = 0;
        while (Q.column(col) == impact.column(col))
            ++col;
        const Vector e = unit_vector(c_, col);
        return refute(o, Json{{"piece", d.piece}, {"contact", d.contact},
                              {"restitution", to_json(d.restitution)}, {"gamma", to_json(e)},
                              {"piece_image", to_json(Q * e)},
                              {"impact_image", to_json(impact * e)}});
    }
    return o;
}

} // namespace impactcert::detail
