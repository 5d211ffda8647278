// SPDX-License-Identifier: GPL-3.0-or-later
// sweep_grid.cpp -- the grid points of `sweep --vary` (sweep.hpp, grid_values).
//
// Not on the exact path (tests/no_floating_point.cmake): the points are exact rationals, and
// doubles only choose which ones -- logarithms of LO and HI from their exponents, and the
// mantissas of the geometric points -- so no verdict depends on them.
#include "sweep/sweep.hpp"

#include "base/errors.hpp"

#include <gmpxx.h>

#include <cmath>

namespace impactcert {

namespace {

// log2 of a positive rational as a double: the binary exponent from the bit lengths (exact, any
// size), the rest from a quotient in [1/4, 4).
double log2_of(const Rational& q) {
    const long k = static_cast<long>(mpz_sizeinbase(mpq_numref(q.mpq()), 2)) -
                   static_cast<long>(mpz_sizeinbase(mpq_denref(q.mpq()), 2));
    Rational scaled;
    if (k >= 0)
        mpq_div_2exp(scaled.mpq(), q.mpq(), static_cast<mp_bitcnt_t>(k));
    else
        mpq_mul_2exp(scaled.mpq(), q.mpq(), static_cast<mp_bitcnt_t>(-k));
    return static_cast<double>(k) + std::log2(mpq_get_d(scaled.mpq()));
}

Rational power_of_ten(long e) {
    mpz_class p;
    mpz_ui_pow_ui(p.get_mpz_t(), 10, static_cast<unsigned long>(e < 0 ? -e : e));
    const Rational r{CGAL::Gmpz(p.get_mpz_t())};
    return e < 0 ? Rational(1) / r : r;
}

} // namespace

std::vector<Rational> grid_values(const SweepParameter& p) {
    std::vector<Rational> values;
    const std::size_t count = p.count;
    if (!p.log || count <= 2 || p.lo == p.hi) {
        for (std::size_t i = 0; i < count; ++i)
            values.push_back(count == 1 || i == 0 ? p.lo
                             : i + 1 == count   ? p.hi
                                                : p.lo + (p.hi - p.lo) * Rational(static_cast<int>(i)) /
                                                             Rational(static_cast<int>(count - 1)));
        return values;
    }
    const double a = log2_of(p.lo), b = log2_of(p.hi), log10_2 = std::log10(2.0);
    const bool up = p.lo < p.hi;
    for (int digits = 3; digits <= 15; ++digits) {
        values.assign(1, p.lo);
        bool ok = true;
        for (std::size_t i = 1; i + 1 < count && ok; ++i) {
            const double t = static_cast<double>(i) / static_cast<double>(count - 1);
            const double l10 = ((1 - t) * a + t * b) * log10_2;
            const double e10 = std::floor(l10);
            const double mant = std::nearbyint(std::pow(10.0, l10 - e10 + digits - 1)); // in [10^(d-1), 10^d]
            const Rational v = Rational(static_cast<long>(mant)) * power_of_ten(static_cast<long>(e10) - digits + 1);
            ok = up ? values.back() < v && v < p.hi : p.hi < v && v < values.back();
            values.push_back(v);
        }
        if (ok) {
            values.push_back(p.hi);
            return values;
        }
    }
    throw InputError("--vary " + p.name + ": " + std::to_string(count) + " log-spaced points between LO and HI are not distinct at 15 significant digits (fewer points, or a wider range)");
}

} // namespace impactcert
