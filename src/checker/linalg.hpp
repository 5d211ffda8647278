// SPDX-License-Identifier: GPL-3.0-or-later
// linalg.hpp -- the checker's own exact linear algebra, over GMP rationals (gmpxx).
//
// Contract: Vec and Mat (row-major, rows of equal length) hold mpq_class; every operation is
// exact. Shapes are the caller's: nothing is checked here (the reader checks every shape
// before a matrix is used). Shares no code with the prover's matrix.hpp.
#pragma once

#include <gmpxx.h>

#include <cstddef>
#include <vector>

namespace impactcert_check::detail {

using Q = mpq_class;
using Vec = std::vector<Q>;
using Mat = std::vector<Vec>; // row-major, rows of equal length

Mat zeros(std::size_t r, std::size_t c);
Mat eye(std::size_t n);
Mat mul(const Mat& a, const Mat& b);
Vec mul(const Mat& a, const Vec& x);
Mat tr(const Mat& a);
Mat sub(Mat a, const Mat& b);
Vec sub(Vec a, const Vec& b);
Q dot(const Vec& a, const Vec& b);
Q form(const Mat& a, const Vec& x); // x^T a x
Vec col(const Mat& a, std::size_t j);
Mat from_cols(const std::vector<Vec>& cols);
bool nonneg(const Vec& v);
bool positive(const Vec& v);

bool solve(Mat a, Vec b, Vec& x); // a x = b (square); false when singular
bool invert(const Mat& a, Mat& inv);
Q det(Mat a);

// The primitive integer vector of the ray through v (the zero vector stays zero).
Vec primitive(const Vec& v);
Vec canonical_line(const Vec& v);
std::vector<Vec> kernel(std::vector<Vec> rows, std::size_t dim);

} // namespace impactcert_check::detail
