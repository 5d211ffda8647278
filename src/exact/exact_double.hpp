// SPDX-License-Identifier: GPL-3.0-or-later
// exact_double.hpp -- the one way from a double to the exact path.
//
// Contract: a finite double is a dyadic rational and converts exactly. A NaN or an infinity has
// no exact value: exact_of_double returns nothing, set_exact throws std::logic_error (a caller
// that let one through has a bug; GMP itself would raise SIGFPE). Every conversion from double
// in impactcert goes through here (grep mpq_set_d: only this file).
#pragma once

#include "exact/rational.hpp"

#include <gmp.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace impactcert {

inline std::optional<Rational> exact_of_double(double x) {
    if (!std::isfinite(x))
        return std::nullopt;
    Rational r;
    mpq_set_d(r.mpq(), x);
    return r;
}

inline void set_exact(mpq_t out, double x, const char* where) {
    if (!std::isfinite(x))
        throw std::logic_error(std::string(where) + ": a non-finite double reached an exact conversion");
    mpq_set_d(out, x);
}

inline Rational exact_double(double x, const char* where) {
    Rational r;
    set_exact(r.mpq(), x, where);
    return r;
}

} // namespace impactcert
