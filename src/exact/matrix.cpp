// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/matrix.hpp"

#include <algorithm>

#include <stdexcept>
#include <utility>

namespace impactcert {

namespace {
void require(bool ok, const char* what) {
    if (!ok)
        throw std::logic_error(std::string("matrix size mismatch: ") + what);
}
} // namespace

Matrix Matrix::identity(std::size_t n) {
    Matrix m(n, n);
    for (std::size_t i = 0; i < n; ++i)
        m(i, i) = 1;
    return m;
}

Matrix Matrix::from_columns(const std::vector<Vector>& columns) {
    require(!columns.empty(), "from_columns of nothing");
    Matrix m(columns.front().size(), columns.size());
    for (std::size_t j = 0; j < columns.size(); ++j) {
        require(columns[j].size() == m.rows(), "from_columns");
        for (std::size_t i = 0; i < m.rows(); ++i)
            m(i, j) = columns[j][i];
    }
    return m;
}

Matrix Matrix::from_rows(const std::vector<Vector>& rows) {
    require(!rows.empty(), "from_rows of nothing");
    Matrix m(rows.size(), rows.front().size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        require(rows[i].size() == m.cols(), "from_rows");
        for (std::size_t j = 0; j < m.cols(); ++j)
            m(i, j) = rows[i][j];
    }
    return m;
}

Vector Matrix::column(std::size_t j) const {
    Vector v(rows_);
    for (std::size_t i = 0; i < rows_; ++i)
        v[i] = (*this)(i, j);
    return v;
}

Vector Matrix::row(std::size_t i) const {
    return Vector(a_.begin() + static_cast<std::ptrdiff_t>(i * cols_),
                  a_.begin() + static_cast<std::ptrdiff_t>((i + 1) * cols_));
}

bool Matrix::operator==(const Matrix& o) const {
    return rows_ == o.rows_ && cols_ == o.cols_ && a_ == o.a_;
}

Matrix operator*(const Matrix& a, const Matrix& b) {
    require(a.cols() == b.rows(), "product");
    Matrix c(a.rows(), b.cols());
    for (std::size_t i = 0; i < a.rows(); ++i)
        for (std::size_t j = 0; j < b.cols(); ++j) {
            Rational s = 0;
            for (std::size_t k = 0; k < a.cols(); ++k)
                if (sign_of(a(i, k)) != Sign::zero && sign_of(b(k, j)) != Sign::zero) // exact: skip zero terms
                    s += a(i, k) * b(k, j);
            c(i, j) = s;
        }
    return c;
}

Vector operator*(const Matrix& a, const Vector& x) {
    require(a.cols() == x.size(), "matrix-vector product");
    Vector y(a.rows());
    for (std::size_t i = 0; i < a.rows(); ++i) {
        Rational s = 0;
        for (std::size_t k = 0; k < a.cols(); ++k)
            if (sign_of(a(i, k)) != Sign::zero && sign_of(x[k]) != Sign::zero) // exact: skip zero terms
                s += a(i, k) * x[k];
        y[i] = s;
    }
    return y;
}

Matrix operator+(const Matrix& a, const Matrix& b) {
    require(a.rows() == b.rows() && a.cols() == b.cols(), "sum");
    Matrix c(a.rows(), a.cols());
    for (std::size_t i = 0; i < a.rows(); ++i)
        for (std::size_t j = 0; j < a.cols(); ++j)
            c(i, j) = a(i, j) + b(i, j);
    return c;
}

Matrix operator-(const Matrix& a, const Matrix& b) {
    require(a.rows() == b.rows() && a.cols() == b.cols(), "difference");
    Matrix c(a.rows(), a.cols());
    for (std::size_t i = 0; i < a.rows(); ++i)
        for (std::size_t j = 0; j < a.cols(); ++j)
            c(i, j) = a(i, j) - b(i, j);
    return c;
}

Matrix operator*(const Rational& s, const Matrix& a) {
    Matrix c(a.rows(), a.cols());
    for (std::size_t i = 0; i < a.rows(); ++i)
        for (std::size_t j = 0; j < a.cols(); ++j)
            c(i, j) = s * a(i, j);
    return c;
}

Matrix transpose(const Matrix& a) {
    Matrix t(a.cols(), a.rows());
    for (std::size_t i = 0; i < a.rows(); ++i)
        for (std::size_t j = 0; j < a.cols(); ++j)
            t(j, i) = a(i, j);
    return t;
}

Vector operator+(const Vector& a, const Vector& b) {
    require(a.size() == b.size(), "vector sum");
    Vector c(a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        c[i] = a[i] + b[i];
    return c;
}

Vector operator-(const Vector& a, const Vector& b) {
    require(a.size() == b.size(), "vector difference");
    Vector c(a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        c[i] = a[i] - b[i];
    return c;
}

Vector operator*(const Rational& s, const Vector& a) {
    Vector c(a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        c[i] = s * a[i];
    return c;
}

Rational dot(const Vector& a, const Vector& b) {
    require(a.size() == b.size(), "dot");
    Rational s = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        s += a[i] * b[i];
    return s;
}

Rational bilinear(const Vector& x, const Matrix& a, const Vector& y) { return dot(x, a * y); }

Vector unit_vector(std::size_t n, std::size_t k) {
    Vector e(n, Rational(0));
    e.at(k) = 1;
    return e;
}

bool is_zero(const Vector& v) {
    for (const auto& x : v)
        if (sign_of(x) != Sign::zero)
            return false;
    return true;
}

namespace {
// Reduces [a | b] to [I | a^-1 b] in place; false when a is singular.
bool gauss_jordan(Matrix& a, Matrix& b) {
    const std::size_t n = a.rows();
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t pivot = col;
        while (pivot < n && sign_of(a(pivot, col)) == Sign::zero)
            ++pivot;
        if (pivot == n)
            return false;
        if (pivot != col) {
            for (std::size_t j = 0; j < n; ++j)
                std::swap(a(pivot, j), a(col, j));
            for (std::size_t j = 0; j < b.cols(); ++j)
                std::swap(b(pivot, j), b(col, j));
        }
        const Rational inv = Rational(1) / a(col, col);
        for (std::size_t j = 0; j < n; ++j)
            a(col, j) *= inv;
        for (std::size_t j = 0; j < b.cols(); ++j)
            b(col, j) *= inv;
        for (std::size_t i = 0; i < n; ++i) {
            if (i == col || sign_of(a(i, col)) == Sign::zero)
                continue;
            const Rational f = a(i, col);
            for (std::size_t j = 0; j < n; ++j)
                a(i, j) -= f * a(col, j);
            for (std::size_t j = 0; j < b.cols(); ++j)
                b(i, j) -= f * b(col, j);
        }
    }
    return true;
}
} // namespace

std::optional<Matrix> inverse(const Matrix& a) {
    require(a.rows() == a.cols(), "inverse of a non-square matrix");
    Matrix work = a, result = Matrix::identity(a.rows());
    if (!gauss_jordan(work, result))
        return std::nullopt;
    return result;
}

std::optional<Vector> solve(const Matrix& a, const Vector& b) {
    require(a.rows() == a.cols() && a.rows() == b.size(), "solve");
    Matrix work = a, rhs(b.size(), 1);
    for (std::size_t i = 0; i < b.size(); ++i)
        rhs(i, 0) = b[i];
    if (!gauss_jordan(work, rhs))
        return std::nullopt;
    return rhs.column(0);
}

std::vector<Rational> characteristic_polynomial(const Matrix& a) {
    // With e_k the elementary symmetric functions of the eigenvalues and p_j = tr(A^j):
    // k e_k = sum_{i=1..k} (-1)^(i-1) e_(k-i) p_i, and a_k = (-1)^k e_k.
    const std::size_t c = a.rows();
    std::vector<Rational> e{Rational(1)}, p{Rational(0)}, out{Rational(1)};
    Matrix power = a;
    for (std::size_t k = 1; k <= c; ++k) {
        if (k > 1)
            power = power * a;
        Rational trace = 0;
        for (std::size_t i = 0; i < c; ++i)
            trace += power(i, i);
        p.push_back(trace);
        Rational sum = 0;
        for (std::size_t i = 1; i <= k; ++i)
            sum += (i % 2 == 1 ? e[k - i] : -e[k - i]) * p[i];
        e.push_back(sum / Rational(static_cast<long>(k)));
        out.push_back(k % 2 == 1 ? -e.back() : e.back());
    }
    return out;
}

Rational determinant(const Matrix& a) {
    require(a.rows() == a.cols(), "determinant of a non-square matrix");
    Matrix m = a;
    const std::size_t n = m.rows();
    Rational det = 1;
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t pivot = col;
        while (pivot < n && sign_of(m(pivot, col)) == Sign::zero)
            ++pivot;
        if (pivot == n)
            return 0;
        if (pivot != col) {
            for (std::size_t j = 0; j < n; ++j)
                std::swap(m(pivot, j), m(col, j));
            det = -det;
        }
        det *= m(col, col);
        for (std::size_t i = col + 1; i < n; ++i) {
            if (sign_of(m(i, col)) == Sign::zero)
                continue;
            const Rational f = m(i, col) / m(col, col);
            for (std::size_t j = col; j < n; ++j)
                m(i, j) -= f * m(col, j);
        }
    }
    return det;
}

Vector primitive_ray(const Vector& v) {
    require(!is_zero(v), "primitive_ray of the zero vector");
    mpz_t scale, g;
    mpz_init_set_ui(scale, 1);
    mpz_init_set_ui(g, 0);
    for (const auto& x : v)
        mpz_lcm(scale, scale, mpq_denref(x.mpq()));
    Vector out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) {
        mpq_t t;
        mpq_init(t);
        mpq_set_z(t, scale);
        mpq_mul(t, t, v[i].mpq()); // an integer now
        out[i] = Rational(t);
        mpz_gcd(g, g, mpq_numref(t));
        mpq_clear(t);
    }
    for (auto& x : out) {
        mpq_t t;
        mpq_init(t);
        mpq_set_z(t, g);
        mpq_div(t, x.mpq(), t);
        x = Rational(t);
        mpq_clear(t);
    }
    mpz_clear(scale);
    mpz_clear(g);
    return out;
}

Vector canonical_line(const Vector& v) {
    Vector p = primitive_ray(v);
    for (const auto& x : p) {
        const Sign s = sign_of(x);
        if (s == Sign::zero)
            continue;
        if (s == Sign::negative)
            for (auto& y : p)
                y = -y;
        break;
    }
    return p;
}

std::vector<Vector> null_space(const std::vector<Vector>& rows, std::size_t dim) {
    std::vector<Vector> m = rows;
    std::vector<std::size_t> pivot_cols;
    std::size_t r = 0;
    for (std::size_t col = 0; col < dim && r < m.size(); ++col) {
        std::size_t p = r;
        while (p < m.size() && sign_of(m[p][col]) == Sign::zero)
            ++p;
        if (p == m.size())
            continue;
        std::swap(m[p], m[r]);
        const Rational inv = Rational(1) / m[r][col];
        for (auto& x : m[r])
            x *= inv;
        for (std::size_t i = 0; i < m.size(); ++i) {
            if (i == r || sign_of(m[i][col]) == Sign::zero)
                continue;
            const Rational f = m[i][col];
            for (std::size_t j = 0; j < dim; ++j)
                m[i][j] -= f * m[r][j];
        }
        pivot_cols.push_back(col);
        ++r;
    }
    std::vector<Vector> basis;
    for (std::size_t free = 0; free < dim; ++free) {
        if (std::find(pivot_cols.begin(), pivot_cols.end(), free) != pivot_cols.end())
            continue;
        Vector x(dim);
        x[free] = 1;
        for (std::size_t k = 0; k < pivot_cols.size(); ++k)
            x[pivot_cols[k]] = -m[k][free];
        basis.push_back(primitive_ray(x));
    }
    return basis;
}

std::string to_string(const Vector& v) {
    std::string s = "(";
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? ", " : "") + to_string(v[i]);
    return s + ")";
}

std::size_t matrix_bits(const Matrix& m) {
    std::size_t bits = 0;
    for (std::size_t i = 0; i < m.rows(); ++i)
        for (std::size_t j = 0; j < m.cols(); ++j)
            bits = std::max(bits, mpz_sizeinbase(mpq_numref(m(i, j).mpq()), 2) + mpz_sizeinbase(mpq_denref(m(i, j).mpq()), 2));
    return bits;
}

std::size_t rational_bytes(const Rational& q) {
    return 96 + 8 * (mpz_size(mpq_numref(q.mpq())) + mpz_size(mpq_denref(q.mpq())));
}

std::size_t matrix_bytes(const Matrix& m) {
    std::size_t bytes = 0;
    for (std::size_t i = 0; i < m.rows(); ++i)
        for (std::size_t j = 0; j < m.cols(); ++j)
            bytes += rational_bytes(m(i, j));
    return bytes;
}

std::size_t vector_bytes(const Vector& v) {
    std::size_t bytes = 0;
    for (const auto& x : v)
        bytes += rational_bytes(x);
    return bytes;
}

std::string short_text(const Vector& v) {
    std::string s = "(";
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? ", " : "") + short_text(v[i]);
    return s + ")";
}

} // namespace impactcert
