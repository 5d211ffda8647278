// float_eval.hpp -- any law file evaluated in double, with a stated error bound.
//
// Contract: FloatLaw(model) converts R^-1 and Q to double once (round to nearest). eval(gamma):
//   - classification is filtered: the cone coordinates t = R^-1 gamma are computed in double
//     with a rigorous error bound e_k = gamma_{c+1} * sum_j |R^-1_kj gamma_j| + c * 2^-1074
//     (gamma_n = n u / (1 - n u), u = 2^-53, rounded up). A cone is taken when every
//     t_k > e_k and rejected when some t_k < -e_k; if no cone is decided that way, gamma is
//     classified exactly (its double components are rationals; R^-1 is exact). The first piece
//     that contains gamma is used (on a shared face of a continuous law they agree).
//   - the output y = Q gamma in double satisfies |y_i - (Q gamma)_i| <= bound_i with
//     bound_i = gamma_{c+1} * sum_j |Q_ij gamma_j| + c * 2^-1074 (Q's rounding included), the
//     bound itself rounded up.
//   - non-finite input is rejected, an overflowing output is reported (ok = false), never
//     returned silently.
#pragma once

#include "law.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace impactcert {

// The double nearest to q (ties to even), by exact comparison of the truncation and its two
// neighbours. q must lie within the finite double range.
double nearest_double(const Rational& q);

class FloatLaw {
  public:
    explicit FloatLaw(const Model& model);

    struct Result {
        bool ok = false;            // false: non-finite input, overflow, or gamma in no cone
        std::string error;          // why, when !ok
        std::size_t piece = 0;      // the piece used
        bool exact_fallback = false; // classification needed exact arithmetic
        std::vector<double> value;  // gamma+
        std::vector<double> bound;  // |value_i - exact_i| <= bound_i
    };

    Result eval(const std::vector<double>& gamma) const;

  private:
    const Model& model_;
    std::size_t c_;
    std::vector<std::vector<double>> r_inv_; // per piece, row-major c x c
    std::vector<std::vector<double>> q_;     // per piece, row-major c x c
    double gamma_c1_;                        // gamma_{c+1}, rounded up
};

} // namespace impactcert
