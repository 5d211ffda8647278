// kinetic -- proofs/README.md, "kinetic", with Lemma R (rays suffice for linear statements).
// Claim: the impulse Lambda = H (Q_i - I) gamma >= 0 for gamma in C_i (Lambda = H (gamma+ -
// gamma-) by the impact equations, SPEC section 1).
// Check: H (Q_i - I) r >= 0 for every ray r of every cone; Lemma R with L = H (Q_i - I). A ray
// with a negative impulse is the witness.
#include "prover.hpp"

namespace impactcert::detail {

Outcome Prover::kinetic() {
    Outcome o;
    o.method = "impulses at rays";
    const Matrix I = Matrix::identity(c_);
    for (std::size_t p = 0; p < pieces_.size(); ++p) {
        const Matrix K = m_.H() * (pieces_[p].Q - I);
        for (std::size_t a = 0; a < c_; ++a) {
            const Vector r = pieces_[p].R.column(a);
            const Vector impulse = K * r;
            ++o.checks;
            if (limits_.evidence)
                o.data["impulses"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"impulse", to_json(impulse)}});
            if (!nonnegative(impulse))
                return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                      {"impulse", to_json(impulse)}});
        }
    }
    return o;
}

} // namespace impactcert::detail
