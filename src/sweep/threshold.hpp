// SPDX-License-Identifier: GPL-3.0-or-later
// threshold.hpp -- where a verdict changes along the one parameter of a sweep (`sweep
// --thresholds`; proofs/README.md, "Thresholds along a parameter").
//
// Contract: find_thresholds(spec, results) takes run_sweep's results (one parameter, grid order)
// and each pair of neighbouring grid points where
//   - the derivation gives a law at one and none at the other (column "derive"), or
//   - an obligation is proved at one and refuted at the other,
// and narrows that interval by exact bisection until it is at most 10^-D wide (D =
// spec.threshold_digits): each midpoint is the decimal with the fewest digits within an eighth of
// the interval's width of its middle; the law is derived there and only that obligation decided.
// The entry gives the enclosure [lo, hi], the verdicts at both ends (laws derived and decided
// there: the change is proved to lie in [lo, hi]), or, where a midpoint gave a third answer
// (undecided, no law), the interval reached and why it stopped. More than one change between the
// same two grid points is not excluded: the bisection finds one.
// For `energetic`, the boundary's polynomial too: at the refuted end, the exact worst case
// (worst_case.hpp) names the piece and the face J where T+/T- is largest; the energy balance of
// that face, f(p) = det(P_JJ - N_JJ) / det(-N_JJ) (P = R^T Q^T H Q R, N = R^T H R: independent
// of the rays' lengths), is a rational function of the parameter wherever the piece keeps its
// form, and vanishes at the threshold. It is interpolated exactly through the laws derived at
// 25 points of [lo, hi] (numerator and denominator of the least degree k that fits 2k + 1 of them)
// and must equal them at all the others; its numerator, with integer coefficients, must then have
// exactly one root in [lo, hi] (Sturm), given with a certified decimal. Otherwise the entry says
// why there is no polynomial, and the enclosure stands alone.
#pragma once

#include "base/json.hpp"
#include "sweep/sweep.hpp"

#include <vector>

namespace impactcert {

inline constexpr std::size_t kThresholdSamples = 25;

Json find_thresholds(const SweepSpec& spec, const std::vector<Json>& results,
                     const std::function<void(const std::string&)>& progress = {});

} // namespace impactcert
