// SPDX-License-Identifier: GPL-3.0-or-later
// P3 -- proofs/README.md, "P3 (each cone onto the orthant)".
// Claim: Q_i maps C_i onto the closed positive orthant.
// Check: for every ray r of C_i, Q_i r = lambda e_k with lambda > 0, and the c rays of a cone
// reach c distinct axes (then Q_i R_i = E Lambda, E a permutation, Lambda positive diagonal).
// Conversely Q_i maps the extreme rays of C_i onto the positive axes bijectively, so a ray
// whose image is off every positive axis, or two rays on one axis, refute P3.
#include "prover/obligations/prover.hpp"

#include <string>
#include <vector>

namespace impactcert::detail {

Outcome Prover::p3() {
    Outcome o;
    o.method = "images of rays";
    // With verified symmetries whose P' keep the orthant, one piece per orbit (proofs/README.md,
    // "Symmetries": Q_sigma(i) P r = P' Q_i r).
    const auto ps = orthant_representatives();
    if (ps.size() < pieces_.size())
        o.method += by_symmetries();
    for (const std::size_t p : ps) {
        std::vector<bool> hit(c_, false);
        for (std::size_t a = 0; a < c_; ++a) {
            const Vector r = pieces_[p].R.column(a);
            const Vector img = pieces_[p].Q * r;
            ++o.checks;
            if (limits_.evidence)
                o.data["images"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"image", to_json(img)}});
            std::size_t nonzero = 0, axis = 0;
            for (std::size_t k = 0; k < c_; ++k)
                if (sign_of(img[k]) != Sign::zero) {
                    ++nonzero;
                    axis = k;
                }
            std::string reason;
            if (nonzero != 1 || sign_of(img[axis]) != Sign::positive)
                reason = "the image of the ray is not on a positive axis";
            else if (hit[axis])
                reason = "two rays map to the same axis";
            if (!reason.empty())
                return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                      {"image", to_json(img)}, {"reason", reason}});
            hit[axis] = true;
        }
    }
    return o;
}

} // namespace impactcert::detail
