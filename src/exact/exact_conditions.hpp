// SPDX-License-Identifier: GPL-3.0-or-later
// exact_conditions.hpp -- where continuity (P1) holds in the parameters of a sweep, exactly.
//
// Contract (proofs/README.md, "Where continuity holds"): for a sweep of a three-ball chain (two
// contacts) under the most-negative rule, with one or two parameters among the masses and
// restitutions, the derived law is continuous at a parameter point p (off the cell walls below)
// exactly when J(p) = 0, J the jump at the tie gamma- = (-1, -1): the gamma+ of the process forced
// to start with contact 1 minus the one forced to start with contact 2. In a *cell* -- the set of p
// where both continuations have fixed words and pass no boundary (no zero component, no tie, a
// strictly positive end), a finite set of strict polynomial sign conditions -- J is a vector of
// rational functions of p; its numerators' greatest common divisor g is the curve (two parameters)
// or the points (one parameter) of continuity in that cell, and J = 0 identically makes the cell
// continuous as a whole. When g is constant but neither numerator is, continuity holds at most at
// isolated common zeros: the cell is listed (`isolated`) with the probe points where both vanish. Polynomials are CGAL's (Polynomial<Polynomial<Gmpq>>), roots are
// isolated by CGAL's algebraic kernel (Descartes' rule, exact), and every crossing reported is
// a root of g on the line whose every cell condition was decided exactly at the algebraic root.
// Cells are found at the grid points and at `subdivisions` points between grid values.
#pragma once

#include "exact/rational.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace impactcert {

struct ConditionParameter {
    std::string name;
    std::vector<Rational> values; // the grid (increasing or decreasing)
};

struct ConditionFamily {
    std::vector<std::string> masses;      // numbers or parameter names, three items
    std::vector<std::string> restitution; // one item or two
    std::vector<ConditionParameter> parameters; // one or two
    std::size_t max_impacts = 100;
    std::size_t subdivisions = 4;   // drawing lines and cell probes per grid interval
    std::size_t max_word = 24;      // cells whose continuations are longer are not computed
};

struct Crossing {
    std::size_t varies = 0;   // the root is a value of this parameter; the other one (if any) ...
    Rational at;              // ... is fixed at this value (a grid or drawing line)
    Rational lo, hi;          // exactly one root of g on the line lies in [lo, hi]
    std::optional<Rational> exact; // the root, when it is rational (lo = hi = exact)
    bool grid_line = false;   // at a grid value (else a drawing line); with `along`: a grid point
    bool along = false;       // the whole line lies on the curve here; `exact` is one of its probe points
};

struct PolynomialTerm {
    std::size_t ex = 0, ey = 0; // powers of the first and second parameter
    Rational coefficient;       // an integer (g is primitive)
};

struct ConditionCurve {
    std::vector<PolynomialTerm> terms; // g
    std::string word_a, word_b;   // the words after the tie, forced 1 and forced 2 (first letter included)
    std::string polynomial;       // g in the parameter names, integer coefficients, primitive
    bool whole_cell = false;      // J vanishes identically: the cell is continuous as a whole
    // The two components of J are coprime (no common curve): continuity only at their isolated
    // common zeros, which are not computed; the probe points (grid points and the points between
    // them) of this cell where both vanish are listed.
    bool isolated = false;
    std::vector<std::vector<Rational>> points; // with `isolated`: exact common zeros among the probes
    std::size_t degree = 0;       // total degree of g
    std::vector<Crossing> crossings;
};

struct ConditionsResult {
    bool computed = false;
    std::string why_not;          // when not computed
    std::vector<ConditionCurve> curves; // one per cell where g is not a non-zero constant
    std::size_t cells = 0;        // cells found
    std::size_t cells_not_computed = 0; // cells beyond max_word
    std::size_t subdivisions = 0;       // used (fewer than asked on large grids)
};

// InputError for a family this does not cover is not thrown: `computed` is false with the reason.
ConditionsResult continuity_conditions(const ConditionFamily& family);

// g at the given parameter values (one per parameter), exactly.
Rational evaluate_condition(const ConditionCurve& curve, const std::vector<Rational>& at);
// The words of the two continuations at the tie at a parameter point, or nothing when the point is
// on a cell wall (a boundary on either path) or a continuation exceeds max_impacts.
std::optional<std::pair<std::string, std::string>> tie_words(const ConditionFamily& family,
                                                             const std::vector<Rational>& at);

} // namespace impactcert
