// SPDX-License-Identifier: GPL-3.0-or-later
// kinematic -- proofs/README.md, "kinematic", with Lemma R (rays suffice for linear
// statements) and the fan.
// Claim: gamma+ >= 0 for every gamma- in R^c; with friction (SPEC section 9) gamma_N+ >= 0 (the
// normals: a tangential velocity has no sign). On dependent columns (proofs/README.md, "Redundant
// contacts") every normal of all of W: (C^T gamma_B+)_k >= 0, the image in all d coordinates.
// Check: Q_i r >= 0 for every ray r of every cone (Lemma R: then Q_i x >= 0 on C_i), together
// with the fan: every gamma- lies in some cone. The witness is a ray with a negative image,
// else the domain witness: a point where S is undefined or two-valued (proofs/README.md,
// "S as a function").
#include "prover/obligations/prover.hpp"

namespace impactcert::detail {

Outcome Prover::kinematic() {
    Outcome o;
    o.method = "images of rays >= 0, with fan";
    // With verified symmetries whose P' keep the orthant, one piece per orbit (proofs/README.md,
    // "Symmetries": Q_sigma(i) P r = P' Q_i r).
    // With friction, every piece (a symmetry's P' need not keep the normals apart from the tangents).
    const bool friction = m_.has_friction() || m_.redundant();
    std::vector<std::size_t> ps;
    if (friction) {
        o.method = "images of rays: normals >= 0, with fan";
        for (std::size_t p = 0; p < pieces_.size(); ++p)
            ps.push_back(p);
    } else {
        ps = orthant_representatives();
        if (ps.size() < pieces_.size())
            o.method += by_symmetries();
    }
    const std::size_t normals = m_.normals();
    for (const std::size_t p : ps)
        for (std::size_t a = 0; a < c_; ++a) {
            const Vector r = pieces_[p].R.column(a);
            const Vector img = m_.redundant() ? transpose(m_.C()) * (pieces_[p].Q * r) : pieces_[p].Q * r;
            ++o.checks;
            if (limits_.evidence)
                o.data["images"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"image", to_json(img)}});
            bool ok = true;
            for (std::size_t k = 0; k < normals; ++k)
                ok = ok && sign_of(img[k]) != Sign::negative;
            if (!ok)
                return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                      {"image", to_json(img)}});
        }
    if (auto w = domain_witness())
        return refute(o, std::move(*w));
    return o;
}

} // namespace impactcert::detail
