// SPDX-License-Identifier: GPL-3.0-or-later
// float_eval.hpp -- any law file evaluated in double, with a stated error bound.
//
// Contract: FloatLaw(model) converts every entry of R^-1 and Q to the nearest double (an entry
// beyond the double range becomes +-inf, one below it 0 or a subnormal: never a crash) and keeps
// for each entry delta >= its exact conversion error (a double rounded up; inf for an infinite
// entry). Let u = 2^-53 and gamma_c = c u / (1 - c u).
//   - Rows. For a row a of R^-1 or Q and finite input gamma, t = fl(sum_j fl(a_j) gamma_j)
//     (recursive sum in j order, zero components skipped: they contribute exactly 0) satisfies
//         |t - sum_j a_j gamma_j| <= e = gamma_c sum_j |fl(a_j) gamma_j| + c 2^-1074 + sum_j delta_j |gamma_j|.
//     Why: a product is fl(x y) = x y (1 + eps) + eta, |eps| <= u, |eta| <= 2^-1075 (underflow);
//     a sum is (x + y)(1 + d), |d| <= u, with no absolute term (IEEE sums that underflow are
//     exact). So t = sum_j p_j (1 + theta_j), |theta_j| <= gamma_{c-1}, and
//     |t - sum_j fl(a_j) gamma_j| <= gamma_c sum_j |fl(a_j) gamma_j| + (1 + gamma_{c-1}) c 2^-1075;
//     the last sum of e is the conversion error of the entries. An overflow anywhere makes t or
//     e non-finite. e is computed with every operation rounded up (the next double above the
//     round-to-nearest result), so the computed e is >= the exact expression. A non-finite t or
//     e decides nothing.
//   - Classification: the cone coordinates t_k are the rows of R^-1. A piece is taken when
//     every t_k > e_k (the first such piece); if no piece is decided that way, gamma is
//     classified exactly (its double components are rationals; R^-1 is exact) and the first
//     piece whose closed cone contains gamma is used. The piece used always contains gamma.
//   - Output: y_i is row i of Q with bound_i = e_i, so |y_i - (Q gamma)_i| <= bound_i. When y_i
//     or e_i is not finite (an entry beyond the double range, or an overflow in double), the
//     row is computed exactly, y_i is its nearest double and bound_i >= the exact rounding
//     error (exact_output = true); only when an exact output lies beyond the double range is
//     the evaluation refused ("overflow in the output").
//   - Refusals (ok = false, `error` says why): wrong dimension, non-finite input, gamma in no
//     cone, overflow in the output. Nothing wrong is ever returned with ok = true.
#pragma once

#include "model/law.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace impactcert {

// The double nearest to q (ties to even), by exact comparison. Beyond the double range
// (|q| >= 2^1024 - 2^970, half an ulp above the largest double) the result is +-inf, as IEEE
// round to nearest gives; below it, the nearest subnormal or zero.
double nearest_double(const Rational& q);
// The least double >= q (+inf when q is beyond the largest double).
double upper_double(const Rational& q);

class FloatLaw {
  public:
    explicit FloatLaw(const Model& model);

    struct Result {
        bool ok = false;             // false: see `error`
        std::string error;           // why, when !ok
        std::size_t piece = 0;       // the piece used
        bool exact_fallback = false; // classification needed exact arithmetic
        bool exact_output = false;   // some output component was computed exactly (double overflowed)
        std::vector<double> value;   // gamma+
        std::vector<double> bound;   // |value_i - exact_i| <= bound_i
    };

    Result eval(const std::vector<double>& gamma) const;

  private:
    const Model& model_;
    std::size_t c_;
    std::vector<std::vector<double>> r_inv_, r_inv_err_; // per piece, row-major c x c
    std::vector<std::vector<double>> q_, q_err_;         // per piece, row-major c x c
    double gamma_c_;                                     // gamma_c, rounded up
};

} // namespace impactcert
