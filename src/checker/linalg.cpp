// SPDX-License-Identifier: GPL-3.0-or-later
// The checker's exact linear algebra (linalg.hpp): Gauss-Jordan elimination over the rationals.
#include "linalg.hpp"

#include <algorithm>
#include <utility>

namespace impactcert_check::detail {

Mat zeros(std::size_t r, std::size_t c) { return Mat(r, Vec(c, Q(0))); }
Mat eye(std::size_t n) {
    Mat m = zeros(n, n);
    for (std::size_t i = 0; i < n; ++i)
        m[i][i] = 1;
    return m;
}
// Products of integer-valued entries (den = 1, the common case: cradle laws, symmetries, rays)
// are summed as integers (mpz_addmul), exactly the same values without a gcd per term; any
// fraction in a row or column takes the rational sum.
namespace {
bool integral(const Q& x) { return mpz_cmp_ui(x.get_den_mpz_t(), 1) == 0; }
} // namespace

Mat mul(const Mat& a, const Mat& b) {
    const std::size_t rows = a.size(), inner = b.size(), cols = b[0].size();
    Mat c = zeros(rows, cols);
    std::vector<char> col_int(cols, 1);
    for (std::size_t k = 0; k < inner; ++k)
        for (std::size_t j = 0; j < cols; ++j)
            col_int[j] = col_int[j] && integral(b[k][j]);
    mpz_class acc;
    for (std::size_t i = 0; i < rows; ++i) {
        const bool row_int = std::all_of(a[i].begin(), a[i].end(), integral);
        for (std::size_t j = 0; j < cols; ++j) {
            if (row_int && col_int[j]) {
                acc = 0;
                for (std::size_t k = 0; k < inner; ++k)
                    if (sgn(a[i][k]) != 0 && sgn(b[k][j]) != 0)
                        mpz_addmul(acc.get_mpz_t(), a[i][k].get_num_mpz_t(), b[k][j].get_num_mpz_t());
                c[i][j] = acc;
                continue;
            }
            for (std::size_t k = 0; k < inner; ++k)
                if (sgn(a[i][k]) != 0 && sgn(b[k][j]) != 0) // exact: a zero term adds nothing
                    c[i][j] += a[i][k] * b[k][j];
        }
    }
    return c;
}
Vec mul(const Mat& a, const Vec& x) {
    const bool x_int = std::all_of(x.begin(), x.end(), integral);
    Vec y(a.size(), Q(0));
    mpz_class acc;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (x_int && std::all_of(a[i].begin(), a[i].end(), integral)) {
            acc = 0;
            for (std::size_t k = 0; k < x.size(); ++k)
                if (sgn(a[i][k]) != 0 && sgn(x[k]) != 0)
                    mpz_addmul(acc.get_mpz_t(), a[i][k].get_num_mpz_t(), x[k].get_num_mpz_t());
            y[i] = acc;
            continue;
        }
        for (std::size_t k = 0; k < x.size(); ++k)
            if (sgn(a[i][k]) != 0 && sgn(x[k]) != 0)
                y[i] += a[i][k] * x[k];
    }
    return y;
}
Mat tr(const Mat& a) {
    Mat t = zeros(a[0].size(), a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < a[0].size(); ++j)
            t[j][i] = a[i][j];
    return t;
}
Mat sub(Mat a, const Mat& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < a[0].size(); ++j)
            a[i][j] -= b[i][j];
    return a;
}
Vec sub(Vec a, const Vec& b) {
    for (std::size_t i = 0; i < a.size(); ++i)
        a[i] -= b[i];
    return a;
}
Q dot(const Vec& a, const Vec& b) {
    Q s = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
        s += a[i] * b[i];
    return s;
}
Q form(const Mat& a, const Vec& x) { return dot(x, mul(a, x)); }
Vec col(const Mat& a, std::size_t j) {
    Vec v;
    for (const auto& row : a)
        v.push_back(row[j]);
    return v;
}
Mat from_cols(const std::vector<Vec>& cols) {
    Mat m = zeros(cols[0].size(), cols.size());
    for (std::size_t j = 0; j < cols.size(); ++j)
        for (std::size_t i = 0; i < cols[0].size(); ++i)
            m[i][j] = cols[j][i];
    return m;
}
bool nonneg(const Vec& v) {
    return std::all_of(v.begin(), v.end(), [](const Q& x) { return sgn(x) >= 0; });
}
bool positive(const Vec& v) {
    return std::all_of(v.begin(), v.end(), [](const Q& x) { return sgn(x) > 0; });
}

// Solves a x = b (square); false when singular.
bool solve(Mat a, Vec b, Vec& x) {
    const std::size_t n = a.size();
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t p = c;
        while (p < n && sgn(a[p][c]) == 0)
            ++p;
        if (p == n)
            return false;
        std::swap(a[p], a[c]);
        std::swap(b[p], b[c]);
        for (std::size_t r = 0; r < n; ++r) {
            if (r == c || sgn(a[r][c]) == 0)
                continue;
            const Q f = a[r][c] / a[c][c];
            for (std::size_t k = c; k < n; ++k)
                a[r][k] -= f * a[c][k];
            b[r] -= f * b[c];
        }
    }
    x.assign(n, Q(0));
    for (std::size_t i = 0; i < n; ++i)
        x[i] = b[i] / a[i][i];
    return true;
}

bool invert(const Mat& a, Mat& inv) {
    const std::size_t n = a.size();
    std::vector<Vec> cols;
    for (std::size_t j = 0; j < n; ++j) {
        Vec e(n, Q(0)), x;
        e[j] = 1;
        if (!solve(a, e, x))
            return false;
        cols.push_back(x);
    }
    inv = from_cols(cols);
    return true;
}

Q det(Mat a) {
    const std::size_t n = a.size();
    Q d = 1;
    for (std::size_t c = 0; c < n; ++c) {
        std::size_t p = c;
        while (p < n && sgn(a[p][c]) == 0)
            ++p;
        if (p == n)
            return 0;
        if (p != c) {
            std::swap(a[p], a[c]);
            d = -d;
        }
        d *= a[c][c];
        for (std::size_t r = c + 1; r < n; ++r) {
            const Q f = a[r][c] / a[c][c];
            for (std::size_t k = c; k < n; ++k)
                a[r][k] -= f * a[c][k];
        }
    }
    return d;
}

Vec primitive(const Vec& v) {
    mpz_class l = 1, g = 0;
    for (const auto& x : v)
        l = lcm(l, x.get_den());
    Vec out;
    for (const auto& x : v) {
        out.push_back(Q(x * l));
        g = gcd(g, out.back().get_num());
    }
    if (g == 0)
        return out; // the zero vector: no ray
    for (auto& x : out)
        x /= g;
    return out;
}

// The primitive vector of the line through v != 0 whose first non-zero entry is positive.
Vec canonical_line(const Vec& v) {
    Vec p = primitive(v);
    for (const auto& x : p)
        if (sgn(x) != 0) {
            if (sgn(x) < 0)
                for (auto& y : p)
                    y = -y;
            break;
        }
    return p;
}

// A basis of {x : r . x = 0 for every row r} (Gaussian elimination, then one vector per column
// without a pivot).
std::vector<Vec> kernel(std::vector<Vec> rows, std::size_t dim) {
    std::vector<std::size_t> pivots;
    std::size_t r = 0;
    for (std::size_t col = 0; col < dim && r < rows.size(); ++col) {
        std::size_t p = r;
        while (p < rows.size() && sgn(rows[p][col]) == 0)
            ++p;
        if (p == rows.size())
            continue;
        std::swap(rows[p], rows[r]);
        const Q lead = rows[r][col];
        for (auto& x : rows[r])
            x /= lead;
        for (std::size_t i = 0; i < rows.size(); ++i)
            if (i != r && sgn(rows[i][col]) != 0) {
                const Q f = rows[i][col];
                for (std::size_t k = 0; k < dim; ++k)
                    rows[i][k] -= f * rows[r][k];
            }
        pivots.push_back(col);
        ++r;
    }
    std::vector<Vec> out;
    for (std::size_t f = 0; f < dim; ++f) {
        if (std::find(pivots.begin(), pivots.end(), f) != pivots.end())
            continue;
        Vec x(dim, Q(0));
        x[f] = 1;
        for (std::size_t k = 0; k < pivots.size(); ++k)
            x[pivots[k]] = -rows[k][f];
        out.push_back(x);
    }
    return out;
}

} // namespace impactcert_check::detail
