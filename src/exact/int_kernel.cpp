// SPDX-License-Identifier: GPL-3.0-or-later
// int_kernel.cpp -- see int_kernel.hpp. GMP only to convert; int64 and __int128 with overflow
// checks to compute.
#include "exact/int_kernel.hpp"

#include <gmp.h>

#include <limits>
#include <numeric>
#include <stdexcept>

namespace impactcert::intk {

std::optional<i64> to_i64(mpz_srcptr z) {
    if (!mpz_fits_slong_p(z) || mpz_cmp_si(z, std::numeric_limits<long>::min()) == 0)
        return std::nullopt;
    static_assert(sizeof(long) == sizeof(i64), "long is 64 bits on the supported platforms");
    return static_cast<i64>(mpz_get_si(z));
}


std::optional<IntMatrix> to_int(const Matrix& m) {
    IntMatrix out;
    out.rows = m.rows();
    out.cols = m.cols();
    out.a.resize(out.rows * out.cols);
    mpz_t d, t;
    mpz_inits(d, t, nullptr);
    mpz_set_ui(d, 1);
    for (std::size_t r = 0; r < out.rows; ++r)
        for (std::size_t c = 0; c < out.cols; ++c)
            mpz_lcm(d, d, mpq_denref(m(r, c).mpq()));
    bool ok = true;
    if (auto den = to_i64(d))
        out.den = *den;
    else
        ok = false;
    for (std::size_t r = 0; r < out.rows && ok; ++r)
        for (std::size_t c = 0; c < out.cols && ok; ++c) {
            mpz_divexact(t, d, mpq_denref(m(r, c).mpq()));
            mpz_mul(t, t, mpq_numref(m(r, c).mpq()));
            const auto v = to_i64(t);
            ok = v.has_value();
            if (ok)
                out.a[r * out.cols + c] = *v;
        }
    mpz_clears(d, t, nullptr);
    if (!ok)
        return std::nullopt;
    return out;
}

std::optional<std::vector<i64>> to_int_vector(const Vector& v) {
    std::vector<i64> out(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) {
        if (mpz_cmp_ui(mpq_denref(v[k].mpq()), 1) != 0)
            return std::nullopt;
        const auto x = to_i64(mpq_numref(v[k].mpq()));
        if (!x)
            return std::nullopt;
        out[k] = *x;
    }
    return out;
}

std::optional<std::vector<i64>> to_int_scaled(const Vector& v) {
    auto m = to_int(Matrix::from_columns({v}));
    if (!m)
        return std::nullopt;
    return std::move(m->a);
}

bool apply(const IntMatrix& A, const i64* x, i64* out) {
    for (std::size_t r = 0; r < A.rows; ++r) {
        i128 s = 0;
        for (std::size_t c = 0; c < A.cols; ++c)
            if (__builtin_add_overflow(s, static_cast<i128>(A.a[r * A.cols + c]) * x[c], &s))
                return false;
        if (!fits(s))
            return false;
        out[r] = static_cast<i64>(s);
    }
    return true;
}

bool multiply(const IntMatrix& A, const IntMatrix& B, IntMatrix& out) {
    if (A.cols != B.rows)
        throw std::logic_error("intk::multiply: shapes");
    out.rows = A.rows;
    out.cols = B.cols;
    out.a.assign(out.rows * out.cols, 0);
    const i128 den = static_cast<i128>(A.den) * B.den;
    if (!fits(den))
        return false;
    out.den = static_cast<i64>(den);
    for (std::size_t r = 0; r < A.rows; ++r)
        for (std::size_t c = 0; c < B.cols; ++c) {
            i128 s = 0;
            for (std::size_t k = 0; k < A.cols; ++k)
                if (__builtin_add_overflow(s, static_cast<i128>(A.a[r * A.cols + k]) * B.a[k * B.cols + c], &s))
                    return false;
            if (!fits(s))
                return false;
            out.a[r * out.cols + c] = static_cast<i64>(s);
        }
    return true;
}

void make_primitive(std::vector<i64>& v) {
    i64 g = 0;
    for (i64 x : v)
        g = std::gcd(g, x); // |x| <= 2^63 - 1: every value here was checked to fit
    if (g > 1)
        for (auto& x : v)
            x /= g;
}

std::optional<int> det_sign(std::vector<i64>& a, std::size_t n) {
    // Bareiss: after step k the trailing block holds (k+1) x (k+1) minors; a row swap flips
    // the sign.
    int sign = 1;
    i64 prev = 1;
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t pivot = k;
        while (pivot < n && a[pivot * n + k] == 0)
            ++pivot;
        if (pivot == n)
            return 0;
        if (pivot != k) {
            for (std::size_t c = 0; c < n; ++c)
                std::swap(a[k * n + c], a[pivot * n + c]);
            sign = -sign;
        }
        const i64 p = a[k * n + k];
        for (std::size_t r = k + 1; r < n; ++r) {
            const i128 ark = a[r * n + k];
            for (std::size_t c = k + 1; c < n; ++c) {
                i128 t;
                if (__builtin_sub_overflow(static_cast<i128>(p) * a[r * n + c], ark * a[k * n + c], &t))
                    return std::nullopt;
                if (t % prev != 0)
                    throw std::logic_error("fraction-free determinant: inexact division");
                t /= prev;
                if (!fits(t))
                    return std::nullopt;
                a[r * n + c] = static_cast<i64>(t);
            }
            a[r * n + k] = 0;
        }
        prev = p;
    }
    const i64 d = a[(n - 1) * n + (n - 1)];
    return d > 0 ? sign : d < 0 ? -sign : 0;
}

Elimination gauss_jordan(std::vector<i64>& m, std::size_t n, std::size_t w, i64& det) {
    i64 prev = 1;
    for (std::size_t col = 0; col < n; ++col) {
        std::size_t pivot = col;
        while (pivot < n && m[pivot * w + col] == 0)
            ++pivot;
        if (pivot == n)
            return Elimination::singular;
        if (pivot != col)
            for (std::size_t j = 0; j < w; ++j)
                std::swap(m[pivot * w + j], m[col * w + j]);
        const i64 p = m[col * w + col];
        for (std::size_t r = 0; r < n; ++r) {
            if (r == col)
                continue;
            const i64 f = m[r * w + col];
            for (std::size_t j = 0; j < w; ++j) {
                // |p m_rj|, |f m_colj| < 2^126 (symmetric int64 range): the difference fits i128.
                const i128 t = static_cast<i128>(p) * m[r * w + j] - static_cast<i128>(f) * m[col * w + j];
                if (t % prev != 0 || !fits(t / prev))
                    return Elimination::overflow;
                m[r * w + j] = static_cast<i64>(t / prev);
            }
        }
        prev = p;
    }
    det = prev;
    return Elimination::solved;
}

std::optional<IntMatrix> inverse(const IntMatrix& a) {
    if (a.rows != a.cols || a.den != 1)
        throw std::logic_error("intk::inverse: a square integer matrix");
    const std::size_t n = a.rows, w = 2 * n;
    std::vector<i64> m(n * w, 0);
    for (std::size_t r = 0; r < n; ++r) {
        for (std::size_t c = 0; c < n; ++c)
            m[r * w + c] = a(r, c);
        m[r * w + n + r] = 1;
    }
    i64 det = 0;
    if (gauss_jordan(m, n, w, det) != Elimination::solved)
        return std::nullopt;
    IntMatrix out;
    out.rows = out.cols = n;
    out.a.resize(n * n);
    const i64 s = det > 0 ? 1 : -1; // fits: |det| <= INT64_MAX
    for (std::size_t r = 0; r < n; ++r)
        for (std::size_t c = 0; c < n; ++c)
            out.a[r * n + c] = s * m[r * w + n + c];
    out.den = s * det;
    return out;
}

Matrix to_matrix(const IntMatrix& m) {
    Matrix out(m.rows, m.cols);
    const Rational den(static_cast<long>(m.den));
    for (std::size_t r = 0; r < m.rows; ++r)
        for (std::size_t c = 0; c < m.cols; ++c)
            if (m(r, c) != 0)
                out(r, c) = m.den == 1 ? Rational(static_cast<long>(m(r, c))) : Rational(static_cast<long>(m(r, c))) / den;
    return out;
}

Vector to_vector(const std::vector<i64>& v) {
    Vector out;
    out.reserve(v.size());
    for (i64 x : v)
        out.emplace_back(static_cast<long>(x));
    return out;
}

} // namespace impactcert::intk
