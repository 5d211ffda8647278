// SPDX-License-Identifier: GPL-3.0-or-later
// rational.hpp -- the exact number type of impactcert.
//
// Contract: every value on the exact path is a `Rational` (CGAL's GMP rational, CGAL::Gmpq).
// Nothing here converts from or to floating point; text is the only way in and out:
//   - parse_rational:     the law-file grammar  [+-]?digits("/"digits | "."digits)?
//   - parse_cli_number:   the command-line grammar, which adds hex floats (0x1.8p-3) and decimal
//                         exponents (1e300, 2.5e-3 = 1/400), both read exactly; |exponent| <= 100000
//   - to_string:          canonical "p" or "p/q" (q > 1, lowest terms)
// Signs are three-way (`Sign`), never a bool that hides zero.
#pragma once

#include <CGAL/Gmpq.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace impactcert {

using Rational = CGAL::Gmpq;

enum class Sign { negative = -1, zero = 0, positive = 1 };

Sign sign_of(const Rational& x);
Rational abs_of(const Rational& x);

// Law-file grammar. Returns nothing when `text` does not match it or the denominator is zero;
// `why` (if given) receives a short reason.
std::optional<Rational> parse_rational(std::string_view text, std::string* why = nullptr);

// Command-line grammar: the law-file grammar plus hex floats "[+-]0x<hex>[.<hex>][p[+-]<dec>]",
// converted exactly (a hex float is a dyadic rational), plus a decimal exponent on integers
// and decimals "[+-]digits[.digits](e|E)[+-]digits", exact (1e300 is 10^300). An exponent of
// magnitude above 100000 is an input error (its power of ten would be absurdly long to form).
std::optional<Rational> parse_cli_number(std::string_view text, std::string* why = nullptr);

// A comma-separated list in the command-line grammar (an option's value: "1,2,1"); InputError
// "OPTION: "x" is not a number (why)" at the first item that is not one.
std::vector<Rational> parse_number_list(const std::string& option, const std::string& text);

// Canonical text: "0", "-7", "3/4", "-7/12".
std::string to_string(const Rational& x);

// Readable text: the value rounded to `digits` significant decimal digits (to nearest, ties away
// from zero), in fixed notation for exponents -5..digits-1 and "d.ddde+X" otherwise, trailing
// zeros dropped; "~" in front when the rounding changed the value ("0.75", "~0.33333333333333333",
// "1e+100000"). Computed in integers: no double, any exponent.
std::string readable_text(const Rational& x, int digits = 17);

// An exact value for a one-line message: itself when at most 40 characters, else
// "~1.234567e+1000 [3011 characters exact]" (GMP's mpf, no double).
std::string short_text(const Rational& x);

} // namespace impactcert
