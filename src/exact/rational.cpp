// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/rational.hpp"

#include "base/errors.hpp"

#include <cctype>

namespace impactcert {

Sign sign_of(const Rational& x) {
    const int s = mpq_sgn(x.mpq());
    return s < 0 ? Sign::negative : (s > 0 ? Sign::positive : Sign::zero);
}

Rational abs_of(const Rational& x) { return sign_of(x) == Sign::negative ? -x : x; }

namespace {

constexpr long kMaxDecimalExponent = 100000;

bool all_digits(std::string_view s, bool hex = false) {
    if (s.empty())
        return false;
    for (char c : s)
        if (!(hex ? std::isxdigit(static_cast<unsigned char>(c))
                  : std::isdigit(static_cast<unsigned char>(c))))
            return false;
    return true;
}

Rational integer_from_digits(std::string_view digits, int base) {
    Rational r;
    mpz_set_str(mpq_numref(r.mpq()), std::string(digits).c_str(), base);
    mpz_set_ui(mpq_denref(r.mpq()), 1);
    return r;
}

Rational power_of(unsigned long base, unsigned long exponent) {
    Rational r;
    mpz_ui_pow_ui(mpq_numref(r.mpq()), base, exponent);
    mpz_set_ui(mpq_denref(r.mpq()), 1);
    return r;
}

void set_why(std::string* why, const char* text) {
    if (why)
        *why = text;
}

// Strips a leading sign; returns true when it was '-'.
bool take_sign(std::string_view& s) {
    if (!s.empty() && (s.front() == '+' || s.front() == '-')) {
        const bool negative = s.front() == '-';
        s.remove_prefix(1);
        return negative;
    }
    return false;
}

std::optional<Rational> parse_hex_float(std::string_view s, bool negative, std::string* why) {
    // s is what follows "0x".
    std::string_view mantissa = s, exponent_text;
    if (auto p = s.find_first_of("pP"); p != std::string_view::npos) {
        mantissa = s.substr(0, p);
        exponent_text = s.substr(p + 1);
        if (exponent_text.empty()) {
            set_why(why, "hexadecimal literal has an empty exponent");
            return std::nullopt;
        }
    }
    std::string_view int_part = mantissa, frac_part;
    if (auto d = mantissa.find('.'); d != std::string_view::npos) {
        int_part = mantissa.substr(0, d);
        frac_part = mantissa.substr(d + 1);
    }
    if ((int_part.empty() && frac_part.empty()) || (!int_part.empty() && !all_digits(int_part, true)) ||
        (!frac_part.empty() && !all_digits(frac_part, true))) {
        set_why(why, "malformed hexadecimal mantissa");
        return std::nullopt;
    }
    long exponent = 0;
    if (!exponent_text.empty()) {
        std::string_view e = exponent_text;
        const bool e_negative = take_sign(e);
        if (!all_digits(e) || e.size() > 6) {
            set_why(why, "malformed hexadecimal exponent");
            return std::nullopt;
        }
        exponent = std::stol(std::string(e));
        if (e_negative)
            exponent = -exponent;
    }
    const std::string digits = std::string(int_part) + std::string(frac_part);
    Rational value = integer_from_digits(digits, 16);
    exponent -= 4 * static_cast<long>(frac_part.size());
    if (exponent >= 0)
        value *= power_of(2, static_cast<unsigned long>(exponent));
    else
        value /= power_of(2, static_cast<unsigned long>(-exponent));
    return negative ? -value : value;
}

} // namespace

std::optional<Rational> parse_rational(std::string_view text, std::string* why) {
    std::string_view s = text;
    const bool negative = take_sign(s);
    Rational value;
    if (auto slash = s.find('/'); slash != std::string_view::npos) {
        const auto num = s.substr(0, slash), den = s.substr(slash + 1);
        if (!all_digits(num) || !all_digits(den)) {
            set_why(why, "not a rational (expected digits/digits)");
            return std::nullopt;
        }
        const Rational d = integer_from_digits(den, 10);
        if (sign_of(d) == Sign::zero) {
            set_why(why, "zero denominator");
            return std::nullopt;
        }
        value = integer_from_digits(num, 10) / d;
    } else if (auto dot = s.find('.'); dot != std::string_view::npos) {
        const auto int_part = s.substr(0, dot), frac_part = s.substr(dot + 1);
        if (!all_digits(int_part) || !all_digits(frac_part)) {
            set_why(why, "not a decimal (expected digits.digits)");
            return std::nullopt;
        }
        value = integer_from_digits(std::string(int_part) + std::string(frac_part), 10) /
                power_of(10, frac_part.size());
    } else {
        if (!all_digits(s)) {
            set_why(why, "not a rational (expected [+-]digits, digits/digits or digits.digits)");
            return std::nullopt;
        }
        value = integer_from_digits(s, 10);
    }
    return negative ? -value : value;
}

std::optional<Rational> parse_cli_number(std::string_view text, std::string* why) {
    std::string_view s = text;
    const bool negative = take_sign(s);
    if (s.size() >= 2 && s[0] == '0' && (s[1] == 'x' || s[1] == 'X'))
        return parse_hex_float(s.substr(2), negative, why);
    const auto e = s.find_first_of("eE");
    if (e == std::string_view::npos)
        return parse_rational(text, why);
    // [+-]digits[.digits](e|E)[+-]digits: the mantissa times an exact power of ten.
    const std::string_view mantissa_text = text.substr(0, text.size() - s.size() + e);
    std::string_view exponent_text = s.substr(e + 1);
    if (mantissa_text.find('/') != std::string_view::npos) {
        set_why(why, "an exponent applies to integers and decimals only, not to digits/digits");
        return std::nullopt;
    }
    const bool exponent_negative = take_sign(exponent_text);
    if (!all_digits(exponent_text)) {
        set_why(why, "malformed decimal exponent (expected e[+-]digits)");
        return std::nullopt;
    }
    while (exponent_text.size() > 1 && exponent_text.front() == '0')
        exponent_text.remove_prefix(1);
    // 10^100000 has 100,001 digits and takes milliseconds; 1e999999999 would take GMP hours.
    if (exponent_text.size() > 6 || std::stol(std::string(exponent_text)) > kMaxDecimalExponent) {
        set_why(why, "decimal exponent out of range (|exponent| <= 100000)");
        return std::nullopt;
    }
    const auto exponent = static_cast<unsigned long>(std::stol(std::string(exponent_text)));
    auto mantissa = parse_rational(mantissa_text, why);
    if (!mantissa)
        return std::nullopt;
    if (exponent_negative)
        return *mantissa / power_of(10, exponent);
    return *mantissa * power_of(10, exponent);
}

std::string to_string(const Rational& x) {
    // mpq_get_str writes "p" or "p/q" for a canonical mpq.
    char* raw = mpq_get_str(nullptr, 10, x.mpq());
    std::string out(raw);
    void (*free_fn)(void*, size_t);
    mp_get_memory_functions(nullptr, nullptr, &free_fn);
    free_fn(raw, out.size() + 1);
    return out;
}

std::string readable_text(const Rational& x, int digits) {
    if (digits < 1)
        digits = 1;
    if (mpq_sgn(x.mpq()) == 0)
        return "0";
    mpz_t p, q, n, r, ten, lo, hi;
    mpz_inits(p, q, n, r, ten, lo, hi, nullptr);
    mpz_abs(p, mpq_numref(x.mpq()));
    mpz_set(q, mpq_denref(x.mpq()));
    mpz_ui_pow_ui(lo, 10, static_cast<unsigned long>(digits - 1));
    mpz_ui_pow_ui(hi, 10, static_cast<unsigned long>(digits));
    // k such that 10^(digits-1) <= floor(|x| 10^k) < 10^digits; the estimate from the lengths is
    // off by at most one either way.
    long k = static_cast<long>(digits) - 1 -
             (static_cast<long>(mpz_sizeinbase(p, 10)) - static_cast<long>(mpz_sizeinbase(q, 10)));
    auto scaled = [&](long kk) { // n = floor(p 10^kk / q), r = the remainder (times the scale)
        mpz_t a, b;
        mpz_inits(a, b, nullptr);
        mpz_set(a, p);
        mpz_set(b, q);
        mpz_ui_pow_ui(ten, 10, static_cast<unsigned long>(kk >= 0 ? kk : -kk));
        mpz_mul(kk >= 0 ? a : b, kk >= 0 ? a : b, ten);
        mpz_fdiv_qr(n, r, a, b);
        mpz_set(q, b); // the divisor r is measured against, restored below
        mpz_clears(a, b, nullptr);
    };
    const mpz_srcptr den = mpq_denref(x.mpq());
    for (int guard = 0; guard < 8; ++guard) {
        mpz_set(q, den);
        scaled(k);
        if (mpz_cmp(n, hi) >= 0)
            --k;
        else if (mpz_cmp(n, lo) < 0)
            ++k;
        else
            break;
    }
    // Round to nearest, ties away from zero: 2r >= divisor.
    mpz_mul_2exp(r, r, 1);
    const bool exact = mpz_sgn(r) == 0;
    if (mpz_cmp(r, q) >= 0) {
        mpz_add_ui(n, n, 1);
        if (mpz_cmp(n, hi) == 0) { // 99..9 rounded up to 10..0
            mpz_divexact_ui(n, n, 10);
            --k;
        }
    }
    char* raw = mpz_get_str(nullptr, 10, n);
    std::string d(raw);
    void (*free_fn)(void*, size_t);
    mp_get_memory_functions(nullptr, nullptr, &free_fn);
    free_fn(raw, d.size() + 1);
    mpz_clears(p, q, n, r, ten, lo, hi, nullptr);
    const long exp10 = static_cast<long>(digits) - 1 - k; // value = d[0].d[1..] 10^exp10
    while (d.size() > 1 && d.back() == '0')
        d.pop_back();
    std::string out;
    if (exp10 >= -5 && exp10 < digits) {
        if (exp10 >= 0) {
            const auto int_len = static_cast<std::size_t>(exp10 + 1);
            if (d.size() <= int_len)
                out = d + std::string(int_len - d.size(), '0');
            else
                out = d.substr(0, int_len) + "." + d.substr(int_len);
        } else {
            out = "0." + std::string(static_cast<std::size_t>(-exp10 - 1), '0') + d;
        }
    } else {
        out = d.substr(0, 1) + (d.size() > 1 ? "." + d.substr(1) : "") + "e" + (exp10 < 0 ? "-" : "+") +
              std::to_string(exp10 < 0 ? -exp10 : exp10);
    }
    return (exact ? "" : "~") + std::string(mpq_sgn(x.mpq()) < 0 ? "-" : "") + out;
}

std::string short_text(const Rational& x) {
    std::string s = to_string(x);
    if (s.size() <= 40)
        return s;
    // mpf has an exponent range far beyond double's: an approximation of any rational.
    mpf_t f;
    mpf_init2(f, 64);
    mpf_set_q(f, x.mpq());
    char buf[64];
    gmp_snprintf(buf, sizeof buf, "~%.6Fe", f);
    mpf_clear(f);
    return std::string(buf) + " [" + std::to_string(s.size()) + " characters exact]";
}

std::vector<Rational> parse_number_list(const std::string& option, const std::string& text) {
    std::vector<Rational> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        std::string why;
        const auto x = parse_cli_number(item, &why);
        if (!x)
            throw InputError(option + ": \"" + item + "\" is not a number" + (why.empty() ? "" : " (" + why + ")"));
        out.push_back(*x);
        if (comma == std::string::npos)
            return out;
        start = comma + 1;
    }
}

} // namespace impactcert
