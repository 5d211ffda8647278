// SPDX-License-Identifier: GPL-3.0-or-later
// int_kernel.hpp -- small exact integer linear algebra in int64, for the fast paths of the
// exact core (proofs/README.md, "Integer kernels").
//
// Contract: every function either returns the exact result or reports overflow (nothing /
// false); callers then take the GMP path, so a result never depends on which path ran.
// An IntMatrix stands for the rational matrix a / den (den > 0). No floating point.
#pragma once

#include "exact/matrix.hpp"

#include <cstddef>
#include <cstdint>
#include <gmp.h>
#include <optional>
#include <vector>

namespace impactcert::intk {

using i64 = std::int64_t;
__extension__ typedef __int128 i128; // GCC and Clang: exact products of two int64

// Whether x is an int64 of the symmetric range (-2^63 excluded: every value has a magnitude).
inline bool fits(i128 x) { return x > -static_cast<i128>(INT64_MAX) - 1 && x <= INT64_MAX; }

// A GMP integer as int64 of the symmetric range, when it fits.
std::optional<i64> to_i64(mpz_srcptr z);

struct IntMatrix {
    std::size_t rows = 0, cols = 0;
    std::vector<i64> a; // row-major numerators
    i64 den = 1;        // common positive denominator
    i64 operator()(std::size_t r, std::size_t c) const { return a[r * cols + c]; }
};

// m as integers over the least common denominator of its entries; nothing when a numerator
// or the denominator does not fit int64.
std::optional<IntMatrix> to_int(const Matrix& m);

// An integer vector (every denominator 1) as int64; nothing when it is not integral or does
// not fit.
std::optional<std::vector<i64>> to_int_vector(const Vector& v);

// v times the least common denominator of its entries (a positive scale: every sign and the
// direction kept), as int64; nothing when an entry does not fit.
std::optional<std::vector<i64>> to_int_scaled(const Vector& v);

// out = A.a x (numerators only: the value is out / A.den). False on overflow.
bool apply(const IntMatrix& A, const i64* x, i64* out);

// out = A B with out.den = A.den B.den (not reduced). False on overflow.
bool multiply(const IntMatrix& A, const IntMatrix& B, IntMatrix& out);

// Divides v by the gcd of its entries (the primitive vector of its direction, v != 0).
void make_primitive(std::vector<i64>& v);

// The sign of det of the n x n matrix a (row-major; destroyed), by fraction-free elimination
// with row pivoting; nothing on overflow.
std::optional<int> det_sign(std::vector<i64>& a, std::size_t n);

// Fraction-free Gauss-Jordan elimination (proofs/README.md, "Integer kernels", Lemma K3) of
// the n x w matrix m (row-major, w >= n; row exchanges allowed): on `solved` the left n x n
// block is det I, with det != 0 the last pivot, and the other columns are det times the
// solutions (a^-1 b for m = [a | b]). `singular`: a has no inverse. `overflow`: a value left
// int64 (m is then garbage; callers take the GMP path).
enum class Elimination { solved, singular, overflow };
Elimination gauss_jordan(std::vector<i64>& m, std::size_t n, std::size_t w, i64& det);

// a^-1 for an integer a (den 1) as numerators over den = |det a|; nothing when a is singular
// or a value leaves int64.
std::optional<IntMatrix> inverse(const IntMatrix& a);

Vector to_vector(const std::vector<i64>& v);
Matrix to_matrix(const IntMatrix& m); // the rationals a / den, canonical

} // namespace impactcert::intk
