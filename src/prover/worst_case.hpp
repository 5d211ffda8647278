// SPDX-License-Identifier: GPL-3.0-or-later
// worst_case.hpp -- the exact worst case of a cone-wise linear law (proofs/README.md, "The exact
// worst case of a law"): the supremum of T+/T- over the law's cones, and for a continuous law
// that tiles the space its Lipschitz constant in the metric H (given squared), each an algebraic
// number with a certified rational enclosure and the input that attains it.
//
// Contract:
//   - Energy ratio, per piece i with P = R^T Q^T H Q R and N = R^T H R: sup over z >= 0, z != 0
//     of z^T P z / z^T N z. The certificate of a piece: a face J (rays), the polynomial
//     p_J(x) = det(P_JJ - x N_JJ), an interval [lower, upper] with
//       lower = the ratio at `point` (a rational input in the cone): sup >= lower;
//       upper: upper N - P copositive (the copositivity evidence): sup <= upper;
//       every face polynomial p_K (K any face) has in [lower, upper] no root other than the one
//       root of p_J there: the supremum, a root of some p_K (Lemma W), is that root.
//   - Lipschitz constant squared, per piece: the largest root of det(Q^T H Q - x H); the interval
//     [lower, upper] holds exactly one root and none lies above it; lower is the ratio at
//     `direction`.
//   - The law's value is the largest piece value: each other piece's upper end is at most the top
//     piece's lower end, or its root equals the top one (a common root of the two polynomials
//     in both intervals).
//   - Refinement doubles the bits of the intervals from 64 up to 4096; a law whose values cannot
//     be separated by then, or whose faces exceed `max_faces`, is undecided (limit named).
#pragma once

#include "exact/copositivity.hpp"
#include "base/json.hpp"
#include "model/law.hpp"
#include "exact/upoly.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

struct AlgebraicValue {
    UPoly poly;                    // square-free, monic; the value is its only root in [lo, hi]
    Rational lo, hi;
    std::optional<Rational> exact; // when the value is rational (and found so)
};

struct PieceBound {
    std::size_t piece = 0;
    std::vector<std::size_t> face; // energy: the rays of the face (0-based); Lipschitz: empty
    UPoly poly;                    // p_J, as computed from the law (not made monic)
    Rational lower, upper;
    Vector point;                  // energy: a point of the cone (gamma-); Lipschitz: a direction
    CopositivityResult upper_evidence; // energy only
};

struct LawBound {
    bool decided = false;
    std::string limit; // when undecided: the option that stopped it
    std::vector<PieceBound> pieces;
    std::size_t top = 0; // index into pieces of the piece that attains the value
    AlgebraicValue value;
};

struct WorstCase {
    LawBound energy;
    std::optional<LawBound> lipschitz; // only for a continuous law whose cones tile the space
};

struct WorstCaseOptions {
    std::size_t max_faces = Limits{}.max_faces; // faces of all pieces together
    bool integer_kernels = true;
};

LawBound energy_supremum(const Model& model, const WorstCaseOptions& options);
LawBound lipschitz_squared(const Model& model, const WorstCaseOptions& options);
WorstCase worst_case(const Model& model, bool continuous_tiling, const WorstCaseOptions& options);

// The value in text: "4/3" when rational, else "~1.2345678901234567 (root of x^2 - ... in [a, b])".
std::string value_text(const AlgebraicValue& v);
// Decimal enclosure of the value with 17 significant digits (rounded outward from [lo, hi] refined).
std::string value_decimal(const AlgebraicValue& v);

Json to_json(const WorstCase& w, const Model& model);
Json to_json(const AlgebraicValue& v); // exact (when rational), polynomial, interval, decimal

} // namespace impactcert
