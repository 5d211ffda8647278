// SPDX-License-Identifier: GPL-3.0-or-later
// consistency_dependent.hpp -- kinetic, the friction cone and Coulomb's law of a black-box answer
// on dependent contact columns (proofs/README.md, "Consistency on dependent columns").
//
// Contract:
//   - DependentFit(m): m with dependent columns (m.redundant()), in ball velocities.
//   - least(du, gamma-, kind, modes): the least t >= 0 such that some impulse Lambda of the kind
//     (kinetic: Lambda_N >= 0; cone: the friction cone; coulomb: the cone and, per tangent, the
//     mode modes[j] of Coulomb's law, 's' xi_T = 0, 'f' Lambda_T = -mu Lambda_N with xi_T >= 0,
//     'b' the other way, xi_T at the answer u- + M^-1 W Lambda) gives |(M^-1 W Lambda - du)_i| <=
//     t w_i in every coordinate, w_i >= sqrt((M^-1)_ii): a ball of radius t in the metric M lies
//     in that box. -1 where no Lambda of the kind exists at all. Exact (PPL, one thread at a time).
//   - least_coulomb: the least over every mode, or the first one found <= enough (the answer's
//     own slip signs tried first).
//   - sqrt_up(x): a rational u >= sqrt(x) within a relative 2^-60 (shared with consistency.cpp).
#pragma once

#include "model/system.hpp"

#include <string>
#include <vector>

namespace impactcert::fuzz {

Rational sqrt_up(const Rational& x);

class DependentFit {
  public:
    enum class Kind { kinetic, cone, coulomb };
    explicit DependentFit(const Mechanics& m);
    Rational least(const Vector& du, const Vector& gamma_minus, Kind kind, const std::string& modes = "") const;
    Rational least_coulomb(const Vector& du, const Vector& gamma_minus, const Rational& enough) const;

  private:
    const Mechanics& m_;
    std::size_t d_, n_;
    Matrix V_;              // M^-1 W (n x d)
    std::vector<Rational> w_; // sqrt_up((M^-1)_ii)
};

} // namespace impactcert::fuzz
