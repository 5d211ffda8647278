// nonexpansive -- proofs/README.md, "nonexpansive (pairwise)", with "Exact copositivity" and
// "S as a function".
// Claim: |S(a) - S(b)|_H <= |a - b|_H for all a, b in R^c.
// Check: S is a function (else the domain witness refutes it first), then for every ordered
// pair (i, j), i = j included, with a = R_i s, b = R_j t, z = (s, t) >= 0:
// A = B1^T H B1 - B2^T H B2 (B1 = [R_i, -R_j], B2 = [Q_i R_i, -Q_j R_j]) is copositive.
// Witness: a negative z moved into the open orthant (interior_witness), so that gamma_a and
// gamma_b are interior to their cones.
#include "prover.hpp"

#include <cstddef>
#include <optional>
#include <string>

namespace impactcert::detail {

Json Prover::pair_witness(std::size_t i, std::size_t j, const Vector& gamma_a, const Vector& gamma_b) {
    const Rational lhs = m_.energy(pieces_[i].Q * gamma_a - pieces_[j].Q * gamma_b);
    const Rational rhs = m_.energy(gamma_a - gamma_b);
    ensure(lhs > rhs, "nonexpansive lhs > rhs");
    ensure(m_.in_interior(i, gamma_a) && m_.in_interior(j, gamma_b), "nonexpansive interiors");
    return Json{{"piece_a", name(i)},         {"piece_b", name(j)},
                {"gamma_a", to_json(gamma_a)}, {"gamma_b", to_json(gamma_b)},
                {"lhs", to_json(lhs)},         {"rhs", to_json(rhs)}};
}

Outcome Prover::nonexpansive() {
    Outcome o;
    o.method = "S a function, then copositive pair forms";
    // Where S is undefined or two-valued on an open set it is not non-expansive: that
    // witness comes first, and spares the pair forms. A fan beyond its limit leaves the
    // pairs to decide a refutation.
    std::optional<LimitExceeded> fan_limit;
    try {
        if (auto w = domain_witness())
            return refute(o, std::move(*w));
    } catch (const LimitExceeded& e) {
        fan_limit = e;
    }
    std::size_t by_method[4] = {0, 0, 0, 0};
    auto method_summary = [&] {
        return "copositive pair forms: " + std::to_string(by_method[0]) + " A>=0, " +
               std::to_string(by_method[1]) + " PSD, " + std::to_string(by_method[2]) + " PSD+N, " +
               std::to_string(by_method[3]) + " KKT";
    };
    const Matrix& H = m_.H();
    for (std::size_t i = 0; i < pieces_.size(); ++i)
        for (std::size_t j = 0; j < pieces_.size(); ++j) {
            if (j == 0 && i % 16 == 0)
                report_progress("nonexpansive", i * pieces_.size(), pieces_.size() * pieces_.size());
            // z = (s, t): a = R_i s, b = R_j t;  a - b = B1 z,  S(a) - S(b) = B2 z.
            Matrix B1(c_, 2 * c_), B2(c_, 2 * c_);
            const Matrix QRi = pieces_[i].Q * pieces_[i].R, QRj = pieces_[j].Q * pieces_[j].R;
            for (std::size_t r = 0; r < c_; ++r)
                for (std::size_t k = 0; k < c_; ++k) {
                    B1(r, k) = pieces_[i].R(r, k);
                    B1(r, c_ + k) = -pieces_[j].R(r, k);
                    B2(r, k) = QRi(r, k);
                    B2(r, c_ + k) = -QRj(r, k);
                }
            const Matrix A = transpose(B1) * H * B1 - transpose(B2) * H * B2;
            const auto cop = decide_copositivity(A, limits_.max_faces);
            o.checks += cop.method == CopositivityMethod::kkt_enumeration ? cop.faces : 1;
            ++by_method[static_cast<int>(cop.method)];
            o.method = method_summary();
            o.data["pairs"].push_back(Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"A", to_json(A)},
                                           {"certificate", certificate_json(cop)}});
            if (cop.copositive)
                continue;
            const Vector z = interior_witness(A, cop.witness);
            const Vector s(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(c_));
            const Vector t(z.begin() + static_cast<std::ptrdiff_t>(c_), z.end());
            return refute(o, pair_witness(i, j, pieces_[i].R * s, pieces_[j].R * t));
        }
    if (fan_limit)
        throw *fan_limit;
    return o;
}

} // namespace impactcert::detail
