// SPDX-License-Identifier: GPL-3.0-or-later
// outcomes -- proofs/README.md, "outcomes".
// Claim: each declared experiment u- maps to the declared u+.
// Check, exactly in ball velocities: gamma- = W^T u-, and for every piece whose cone contains
// gamma- (every one on a boundary), gamma+ = Q gamma-, Lambda = H (gamma+ - gamma-),
// u+ = u- + M^-1 W Lambda, compared with the declaration. A gamma- in no cone refutes it.
#include "prover/obligations/prover.hpp"

#include <cstddef>
#include <optional>

namespace impactcert::detail {

Outcome Prover::outcomes() {
    Outcome o;
    o.method = "exact impacts in ball velocities";
    for (const auto& decl : m_.law().outcomes) {
        const Vector gamma = m_.contact_velocities(decl.u_minus);
        const auto containing = m_.pieces_containing(gamma);
        if (containing.empty())
            return refute(o, Json{{"outcome", decl.name}, {"u_minus", to_json(decl.u_minus)},
                                  {"gamma_minus", to_json(gamma)},
                                  {"reason", "gamma- lies in no cone"}});
        // On a boundary every piece containing gamma- must give the declared u+.
        Json by_piece = Json::array();
        std::optional<std::size_t> wrong;
        for (auto p : containing) {
            const Vector u_plus =
                m_.post_impact_velocities(decl.u_minus, gamma, pieces_[p].Q * gamma);
            ++o.checks;
            by_piece.push_back(Json{{"piece", name(p)}, {"u_plus", to_json(u_plus)}});
            if (u_plus != decl.u_plus && !wrong)
                wrong = by_piece.size() - 1;
        }
        if (limits_.evidence)
            o.data["outcomes"].push_back(Json{{"outcome", decl.name}, {"gamma_minus", to_json(gamma)},
                                              {"pieces", by_piece}});
        if (wrong)
            return refute(o, Json{{"outcome", decl.name}, {"u_minus", to_json(decl.u_minus)},
                                  {"u_plus_declared", to_json(decl.u_plus)},
                                  {"piece", by_piece[*wrong]["piece"]},
                                  {"u_plus", by_piece[*wrong]["u_plus"]},
                                  {"pieces_at_gamma", by_piece}});
    }
    return o;
}

} // namespace impactcert::detail
