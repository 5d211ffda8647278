// SPDX-License-Identifier: GPL-3.0-or-later
// eft.hpp -- exact arithmetic on doubles by error-free transformations, for the fuzzer's
// reference (a floating-point module on purpose: it is exact without GMP, and fast).
//
// Contract (the arguments are in proofs/README.md, "The fuzzer's exact reference"):
//   - two_sum(a, b): s + e == a + b exactly, s = fl(a + b), for finite a, b whose sum does not
//     overflow (Knuth). two_prod(a, b): p + e == a b exactly, p = fl(a b), by one FMA, when
//     |a b| >= 2^-969 (then e is a multiple of 2^-1074 and does not underflow) and no overflow.
//   - Expansion: a sum of doubles held as components that are non-overlapping, increasing in
//     magnitude, with zeros removed (Shewchuk). add() adds one double exactly (GROW-EXPANSION
//     with zero elimination keeps those properties); the sign of the value is the sign of the
//     largest (last) component, and the value is zero exactly when there is no component.
//   - IntRow: a linear form sum_j a_j x_j / d with integers |a_j| < 2^53 and 0 < d < 2^53 held
//     exactly as doubles. sign() and nearest() decide, for doubles x scaled into the safe range
//     (every non-zero |x_j| in [2^-969, 2^964)), the exact sign and the double nearest to the
//     value times 2^-k (ties to even, subnormals and overflow to infinity included), or report
//     that they cannot (then the caller uses GMP).
//   - Nothing here depends on the rounding of anything but IEEE binary64 round-to-nearest; do not
//     compile with -ffast-math (it would rewrite two_sum into 0).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace impactcert::eft {

inline void two_sum(double a, double b, double& s, double& e) {
    s = a + b;
    const double bv = s - a;
    e = (a - (s - bv)) + (b - bv);
}

inline void two_prod(double a, double b, double& p, double& e) {
    p = a * b;
    e = std::fma(a, b, -p);
}

// Largest number of components an Expansion holds: a row of up to kMaxTerms products (two
// components each) plus the six of a rounding test.
inline constexpr std::size_t kMaxTerms = 32;

struct Expansion {
    double c[2 * kMaxTerms + 8];
    std::size_t n = 0;

    void add(double b) {
        double q = b;
        std::size_t k = 0;
        for (std::size_t i = 0; i < n; ++i) {
            double s, e;
            two_sum(q, c[i], s, e);
            q = s;
            if (e != 0)
                c[k++] = e;
        }
        if (q != 0)
            c[k++] = q;
        n = k;
    }
    void add_product(double a, double b) {
        double p, e;
        two_prod(a, b, p, e);
        add(e);
        add(p);
    }
    int sign() const { return n == 0 ? 0 : c[n - 1] > 0 ? 1 : -1; }
    // An approximation of the value (components summed from the smallest).
    double estimate() const {
        double s = 0;
        for (std::size_t i = 0; i < n; ++i)
            s += c[i];
        return s;
    }
};

inline std::uint64_t bits_of(double x) {
    std::uint64_t b;
    std::memcpy(&b, &x, sizeof b);
    return b;
}

// x 2^k rounded once to nearest, like std::ldexp, without a library call in the common case: a
// product with an exact power of two is correctly rounded by IEEE multiplication.
inline double ldexp_fast(double x, int k) {
    if (k >= -1022 && k <= 1023) {
        double p;
        const std::uint64_t b = static_cast<std::uint64_t>(k + 1023) << 52;
        std::memcpy(&p, &b, sizeof p);
        return x * p;
    }
    return std::ldexp(x, k);
}

// The smallest positive normal double, and the lower end of the safe range of scaled inputs.
inline constexpr double kMinNormal = std::numeric_limits<double>::min();
inline constexpr double kSafeLow = 0x1p-969;

struct IntRow {
    double a[kMaxTerms] = {}; // integers, |a_j| < 2^53
    double d = 1;             // integer, 0 < d < 2^53
    std::size_t m = 0;        // number of terms
    // Rows that need neither scaling nor expansions (set by prepare()): `terms` non-zero entries
    // at i0, i1, with d = 1 and every entry +-1 when terms == 2. Then the value is 0, +-x_i0 or
    // a_i0 x_i0 (one IEEE product) or +-x_i0 +- x_i1 (one IEEE sum), each correctly rounded by
    // IEEE arithmetic itself, overflow to infinity included; and a rounded sum or product is zero
    // exactly when the exact one is, with the same sign. Otherwise terms = -1.
    int terms = -1;
    std::size_t i0 = 0, i1 = 0;

    bool unit = false; // every entry is 0 or +-1: products are exact without scaling

    // The sign for a unit row from unscaled x by a floating-point filter alone: 2 when it cannot
    // tell (near zero, or an overflow). |t - exact| <= gamma_m sum |x_j| (products are exact,
    // sums never add an underflow error).
    int unit_sign(const double* x) const {
        double t = 0, s = 0;
        for (std::size_t j = 0; j < m; ++j) {
            t += a[j] * x[j];
            s += std::fabs(a[j] * x[j]);
        }
        const double bound = static_cast<double>(m + 2) * 0x1p-52 * s;
        if (!(s <= std::numeric_limits<double>::max()))
            return 2;
        return t > bound ? 1 : t < -bound ? -1 : 2;
    }

    void prepare() {
        int count = 0;
        bool units = true;
        for (std::size_t j = 0; j < m; ++j)
            if (a[j] != 0) {
                (count == 0 ? i0 : i1) = j;
                ++count;
                units = units && std::fabs(a[j]) == 1;
            }
        terms = -1;
        if (d == 1 && (count <= 1 || (count == 2 && units)))
            terms = count;
        unit = units;
    }
    // The exact value times d (the numerator) as an expansion, for scaled x (see above).
    void numerator(const double* x, Expansion& e) const {
        e.n = 0;
        for (std::size_t j = 0; j < m; ++j)
            if (a[j] != 0 && x[j] != 0)
                e.add_product(a[j], x[j]);
    }

    // Exact sign of sum_j a_j x_j for scaled x: a floating-point filter, then the expansion.
    int sign(const double* x) const {
        double t = 0, s = 0;
        for (std::size_t j = 0; j < m; ++j) {
            const double p = a[j] * x[j];
            t += p;
            s += std::fabs(p);
        }
        // |t - exact| <= gamma_m sum_j |a_j x_j| (no underflow: every product is 0 or >= 2^-969
        // in magnitude); (m + 2) 2^-52 s exceeds it with room for the rounding of s itself.
        const double bound = static_cast<double>(m + 2) * 0x1p-52 * s;
        if (t > bound)
            return 1;
        if (t < -bound)
            return -1;
        Expansion e;
        numerator(x, e);
        return e.sign();
    }

    // The double nearest to X = 2^-k (sum_j a_j x_j) / d, ties to even (+-inf from 2^1024 - 2^970
    // on, as IEEE rounding gives), for scaled x; `exact` tells whether it equals X. Returns false
    // (leaving the outputs alone) when a scaled quantity of the rounding test would leave the
    // range where the expansions are exact, or the candidate search does not settle: the caller
    // then decides with GMP.
    bool nearest(const double* x, int k, double& out, bool& exact) const {
        Expansion num;
        numerator(x, num);
        if (num.n == 0) {
            out = 0;
            exact = true;
            return true;
        }
        if (d == 1 && num.n == 1) { // a double exactly: only the scaling back can round
            const double v = ldexp_fast(num.c[0], -k);
            if (std::fabs(v) >= kMinNormal && std::isfinite(v)) {
                out = v;
                exact = true;
                return true;
            }
        }
        constexpr double kMax = std::numeric_limits<double>::max();
        const double kMaxGap = 0x1p971; // the gap above the largest double, to 2^1024
        double v = ldexp_fast(num.estimate() / d, -k);
        if (std::isnan(v))
            return false;
        for (int step = 0; step < 4; ++step) {
            if (std::isinf(v))
                v = std::copysign(kMax, v);
            // The neighbours and the gaps to them (exact: differences of adjacent doubles); beyond
            // the largest double the next "double" is 2^1024, where rounding gives infinity.
            const double up = std::nextafter(v, INFINITY), down = std::nextafter(v, -INFINITY);
            const double gu = std::isinf(up) ? kMaxGap : up - v;
            const double gd = std::isinf(down) ? kMaxGap : v - down;
            // In scaled units: v' = v 2^k and the half gaps (powers of two).
            const double vs = ldexp_fast(v, k);
            const double hu = ldexp_fast(gu, k - 1), hd = ldexp_fast(gd, k - 1);
            if (!((vs == 0 || std::fabs(vs) >= kSafeLow) && hu >= kSafeLow && hd >= kSafeLow) ||
                !std::isfinite(vs) || !std::isfinite(hu) || !std::isfinite(hd))
                return false;
            // sign(X - v), sign(X - (v + hu)) and sign(X - (v - hd)), as signs of num - d (...).
            Expansion mid = num;
            if (vs != 0)
                mid.add_product(-d, vs);
            Expansion above = mid, below = mid;
            above.add_product(-d, hu);
            below.add_product(d, hd);
            const int sa = above.sign(), sb = below.sign();
            // Beyond a midpoint: move to that neighbour (and stop there on a tie, which goes to
            // the even neighbour, or at infinity); exactly on it with v odd: the neighbour.
            const bool odd = (bits_of(v) & 1) == 1;
            const int side = sa > 0 || (sa == 0 && odd) ? 1 : sb < 0 || (sb == 0 && odd) ? -1 : 0;
            if (side != 0) {
                const double next = side > 0 ? up : down;
                if (std::isinf(next) || (side > 0 ? sa : sb) == 0) {
                    out = next;
                    exact = false;
                    return true;
                }
                v = next;
                continue;
            }
            out = v;
            exact = mid.sign() == 0;
            return true;
        }
        return false;
    }
};

// The scaling of a point into the safe range: a power of two 2^k with every non-zero
// |x_j| 2^k in [2^-969, 2^964) (then products with integers below 2^53 and their sums stay in the
// normal range), preferring max_j |x_j| 2^k in [1, 2). False when the components span more than
// about 1930 binades or x is not finite. On success x_scaled[j] = x[j] 2^k exactly (normal, or 0).
inline bool scale_into_safe_range(const double* x, std::size_t m, double* x_scaled, int& k) {
    double big = 0, small = INFINITY;
    for (std::size_t j = 0; j < m; ++j) {
        if (!std::isfinite(x[j]))
            return false;
        const double a = std::fabs(x[j]);
        big = std::fmax(big, a);
        if (a != 0)
            small = std::fmin(small, a);
    }
    if (big == 0) {
        k = 0;
        for (std::size_t j = 0; j < m; ++j)
            x_scaled[j] = x[j];
        return true;
    }
    const int emax = std::ilogb(big), emin = std::ilogb(small);
    k = -emax;
    if (emin + k < -969)
        k = -969 - emin;
    if (emax + k > 963)
        return false;
    for (std::size_t j = 0; j < m; ++j)
        x_scaled[j] = ldexp_fast(x[j], k); // >= 2^-969 after scaling, or 0: exact
    return true;
}

} // namespace impactcert::eft
