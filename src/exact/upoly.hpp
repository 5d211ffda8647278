// SPDX-License-Identifier: GPL-3.0-or-later
// upoly.hpp -- univariate polynomials over the rationals, exactly: the determinant of a pencil,
// gcd, square-free part, and real roots counted and isolated by Sturm sequences (proofs/README.md,
// "The exact worst case of a law").
//
// Contract: a UPoly is its coefficients from the constant term up, with no zero leading
// coefficient (the zero polynomial is empty). Every operation is exact; no floating point.
//   - pencil_determinant(P, N): det(P - x N) for square P, N of one size, by evaluating the
//     determinant at x = 0..k and interpolating (degree at most k).
//   - count_roots(p, lo, hi): the number of distinct real roots of p in the closed interval
//     [lo, hi] (lo <= hi), p not zero. count_roots_above(p, lo): in (lo, +infinity).
//   - isolate(p): disjoint intervals [a, b], one around each distinct real root, in increasing
//     order (a == b when the root is that rational); refine(p, iv, width) narrows one to at most
//     `width` wide, keeping its root inside.
#pragma once

#include "base/json.hpp"
#include "exact/matrix.hpp"
#include "exact/rational.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

struct UPoly {
    std::vector<Rational> c; // c[i] multiplies x^i; the last one is not zero
    int degree() const { return static_cast<int>(c.size()) - 1; }
    bool zero() const { return c.empty(); }
};

struct RootInterval {
    Rational lo, hi; // lo <= hi; the root is in [lo, hi] and is the only one there
};

UPoly make_poly(std::vector<Rational> coefficients); // trims zero leading coefficients
Rational evaluate(const UPoly& p, const Rational& x);
UPoly derivative(const UPoly& p);
// a = q b + r with deg r < deg b (b not zero).
void divide(const UPoly& a, const UPoly& b, UPoly& q, UPoly& r);
UPoly monic(const UPoly& p);
UPoly gcd(const UPoly& a, const UPoly& b); // monic; gcd(0, 0) = 0
UPoly square_free(const UPoly& p);         // p / gcd(p, p'), monic

UPoly pencil_determinant(const Matrix& P, const Matrix& N);

std::size_t count_roots(const UPoly& p, const Rational& lo, const Rational& hi);
std::size_t count_roots_above(const UPoly& p, const Rational& lo);
std::vector<RootInterval> isolate(const UPoly& p);
// Halves [lo, hi] until hi - lo <= width (or the root is found exactly: lo == hi).
RootInterval refine(const UPoly& p, RootInterval iv, const Rational& width);
// The rational root in [lo, hi] when the root isolated there is rational and has a denominator
// of at most `max_den_bits` bits (tried by continued fractions of the midpoint); nothing otherwise.
std::optional<Rational> rational_root(const UPoly& p, const RootInterval& iv, std::size_t max_den_bits);

Json to_json(const UPoly& p);

} // namespace impactcert
