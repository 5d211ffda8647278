// SPDX-License-Identifier: GPL-3.0-or-later
// matrix.hpp -- small dense exact vectors and matrices.
//
// Contract: sizes are checked (std::logic_error on a mismatch: that is a bug, not bad input);
// every operation is exact. Sizes are small (c <= ~8), so plain row-major storage and
// Gauss-Jordan elimination are the right tools.
#pragma once

#include "exact/rational.hpp"

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace impactcert {

using Vector = std::vector<Rational>;

class Matrix {
  public:
    Matrix() = default;
    Matrix(std::size_t rows, std::size_t cols) : rows_(rows), cols_(cols), a_(rows * cols) {}
    static Matrix identity(std::size_t n);
    static Matrix from_columns(const std::vector<Vector>& columns); // all of one length
    static Matrix from_rows(const std::vector<Vector>& rows);

    std::size_t rows() const { return rows_; }
    std::size_t cols() const { return cols_; }
    Rational& operator()(std::size_t i, std::size_t j) { return a_[i * cols_ + j]; }
    const Rational& operator()(std::size_t i, std::size_t j) const { return a_[i * cols_ + j]; }
    Vector column(std::size_t j) const;
    Vector row(std::size_t i) const;
    bool operator==(const Matrix& o) const;
    bool operator!=(const Matrix& o) const { return !(*this == o); }

  private:
    std::size_t rows_ = 0; // number of rows
    std::size_t cols_ = 0; // number of columns
    std::vector<Rational> a_; // row-major entries
};

Matrix operator*(const Matrix& a, const Matrix& b);
Vector operator*(const Matrix& a, const Vector& x);
Matrix operator+(const Matrix& a, const Matrix& b);
Matrix operator-(const Matrix& a, const Matrix& b);
Matrix operator*(const Rational& s, const Matrix& a);
Matrix transpose(const Matrix& a);

Vector operator+(const Vector& a, const Vector& b);
Vector operator-(const Vector& a, const Vector& b);
Vector operator*(const Rational& s, const Vector& a);
Rational dot(const Vector& a, const Vector& b);
// x^T A y
Rational bilinear(const Vector& x, const Matrix& a, const Vector& y);
Vector unit_vector(std::size_t n, std::size_t k);
bool is_zero(const Vector& v);

// Inverse by Gauss-Jordan with exact pivots; nothing when singular.
std::optional<Matrix> inverse(const Matrix& a);
Rational determinant(const Matrix& a);
// The coefficients a_0 = 1, a_1, ..., a_c of det(xI - A) = x^c + a_1 x^(c-1) + ... + a_c (A
// square), by Newton's identities from the traces of A, A^2, ..., A^c: c products.
std::vector<Rational> characteristic_polynomial(const Matrix& a);
// Solution of a x = b for square non-singular a; nothing when singular.
std::optional<Vector> solve(const Matrix& a, const Vector& b);

// The positive multiple of v != 0 whose entries are coprime integers. Two non-zero vectors span
// the same ray iff their primitive representatives are equal.
Vector primitive_ray(const Vector& v);
// The primitive representative of the line through v != 0 whose first non-zero entry is
// positive: two non-zero vectors span the same line (or hyperplane normal) iff these are equal.
Vector canonical_line(const Vector& v);

// A basis of {x in R^dim : r . x = 0 for every r in rows}, by reduced row echelon form: one
// primitive integer vector per free column, in column order (deterministic). Empty when the rows
// have rank dim.
std::vector<Vector> null_space(const std::vector<Vector>& rows, std::size_t dim);

std::string to_string(const Vector& v); // "(a, b, c)"
std::string short_text(const Vector& v); // "(a, b, c)", each by short_text

// The largest bits of an entry (numerator plus denominator): the growth measure of compact laws.
std::size_t matrix_bits(const Matrix& m);
// The memory of numbers, as budgets count it: 96 bytes per rational and 8 per limb.
std::size_t rational_bytes(const Rational& q);
std::size_t matrix_bytes(const Matrix& m);
std::size_t vector_bytes(const Vector& v);

} // namespace impactcert
