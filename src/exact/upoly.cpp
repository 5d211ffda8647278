// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/upoly.hpp"

#include "base/json.hpp"

#include <stdexcept>
#include <utility>

namespace impactcert {

UPoly make_poly(std::vector<Rational> coefficients) {
    while (!coefficients.empty() && sign_of(coefficients.back()) == Sign::zero)
        coefficients.pop_back();
    return UPoly{std::move(coefficients)};
}

Rational evaluate(const UPoly& p, const Rational& x) {
    Rational v(0);
    for (std::size_t i = p.c.size(); i-- > 0;)
        v = v * x + p.c[i];
    return v;
}

UPoly derivative(const UPoly& p) {
    std::vector<Rational> d;
    for (std::size_t i = 1; i < p.c.size(); ++i)
        d.push_back(Rational(static_cast<long>(i)) * p.c[i]);
    return make_poly(std::move(d));
}

void divide(const UPoly& a, const UPoly& b, UPoly& q, UPoly& r) {
    if (b.zero())
        throw std::logic_error("polynomial division by zero");
    std::vector<Rational> rem = a.c, quo(a.c.size() >= b.c.size() ? a.c.size() - b.c.size() + 1 : 0, Rational(0));
    const Rational& lead = b.c.back();
    for (std::size_t k = quo.size(); k-- > 0;) {
        const Rational t = rem[k + b.c.size() - 1] / lead;
        quo[k] = t;
        if (sign_of(t) == Sign::zero)
            continue;
        for (std::size_t j = 0; j < b.c.size(); ++j)
            rem[k + j] -= t * b.c[j];
    }
    rem.resize(std::min(rem.size(), b.c.size() - 1));
    q = make_poly(std::move(quo));
    r = make_poly(std::move(rem));
}

UPoly monic(const UPoly& p) {
    if (p.zero())
        return p;
    UPoly m = p;
    const Rational lead = p.c.back();
    for (auto& x : m.c)
        x /= lead;
    return m;
}

UPoly gcd(const UPoly& a, const UPoly& b) {
    UPoly x = a, y = b, q, r;
    while (!y.zero()) {
        divide(x, y, q, r);
        x = std::move(y);
        y = std::move(r);
    }
    return monic(x);
}

UPoly square_free(const UPoly& p) {
    if (p.degree() < 1)
        return monic(p);
    UPoly q, r;
    divide(p, gcd(p, derivative(p)), q, r);
    return monic(q);
}

UPoly pencil_determinant(const Matrix& P, const Matrix& N) {
    const std::size_t k = P.rows();
    // Values at x = 0..k, then Newton's divided differences on the integer nodes, then the
    // Newton form expanded into coefficients.
    std::vector<Rational> dd;
    for (std::size_t t = 0; t <= k; ++t)
        dd.push_back(determinant(P - Rational(static_cast<long>(t)) * N));
    for (std::size_t level = 1; level <= k; ++level)
        for (std::size_t t = k; t >= level; --t)
            dd[t] = (dd[t] - dd[t - 1]) / Rational(static_cast<long>(level));
    std::vector<Rational> coeff(1, dd[k]);
    for (std::size_t t = k; t-- > 0;) {
        // coeff = coeff * (x - t) + dd[t]
        std::vector<Rational> next(coeff.size() + 1, Rational(0));
        for (std::size_t i = 0; i < coeff.size(); ++i) {
            next[i + 1] += coeff[i];
            next[i] -= Rational(static_cast<long>(t)) * coeff[i];
        }
        next[0] += dd[t];
        coeff = std::move(next);
    }
    return make_poly(std::move(coeff));
}

namespace {

std::vector<UPoly> sturm_sequence(const UPoly& p) {
    std::vector<UPoly> s{square_free(p)};
    s.push_back(derivative(s[0]));
    while (!s.back().zero()) {
        UPoly q, r;
        divide(s[s.size() - 2], s.back(), q, r);
        for (auto& x : r.c)
            x = -x;
        s.push_back(std::move(r));
    }
    s.pop_back();
    return s;
}

int sign_int(const Rational& x) { return static_cast<int>(sign_of(x)); }

std::size_t changes(const std::vector<int>& signs) {
    std::size_t n = 0;
    int last = 0;
    for (int s : signs) {
        if (s == 0)
            continue;
        if (last != 0 && s != last)
            ++n;
        last = s;
    }
    return n;
}

std::size_t variations_at(const std::vector<UPoly>& s, const Rational& x) {
    std::vector<int> signs;
    for (const auto& p : s)
        signs.push_back(sign_int(evaluate(p, x)));
    return changes(signs);
}

std::size_t variations_at_infinity(const std::vector<UPoly>& s, bool positive) {
    std::vector<int> signs;
    for (const auto& p : s) {
        int v = p.zero() ? 0 : sign_int(p.c.back());
        if (!positive && p.degree() % 2 == 1)
            v = -v;
        signs.push_back(v);
    }
    return changes(signs);
}

} // namespace

namespace {
// Sturm's theorem for the square-free part q (the same distinct roots): the number of distinct
// roots in (a, b] is V(a) - V(b) when q(a) != 0; a root at lo is counted separately. `s` is
// sturm_sequence(p), built once by the callers that count many times (isolate).
std::size_t count_with(const std::vector<UPoly>& s, const Rational& lo, const Rational& hi) {
    if (hi < lo)
        return 0;
    const bool at_lo = sign_of(evaluate(s[0], lo)) == Sign::zero;
    if (lo == hi)
        return at_lo ? 1 : 0;
    const std::size_t va = variations_at(s, lo), vb = variations_at(s, hi);
    // At a root a of q the sign of q is skipped: V(a) = V(a+), so V(a) - V(b) counts (a, b].
    return (va - vb) + (at_lo ? 1 : 0);
}
} // namespace

std::size_t count_roots(const UPoly& p, const Rational& lo, const Rational& hi) {
    if (p.zero())
        throw std::logic_error("roots of the zero polynomial");
    return count_with(sturm_sequence(p), lo, hi);
}

std::size_t count_roots_above(const UPoly& p, const Rational& lo) {
    const auto s = sturm_sequence(p);
    return variations_at(s, lo) - variations_at_infinity(s, true);
}

namespace {

// Every real root lies in [-B, B], B = 1 + max |c_i / c_n| (Cauchy).
Rational cauchy_bound(const UPoly& p) {
    Rational b(0);
    for (std::size_t i = 0; i + 1 < p.c.size(); ++i)
        b = std::max(b, abs_of(p.c[i] / p.c.back()));
    return b + Rational(1);
}

// q square-free, s its Sturm sequence; n = number of roots of q in [lo, hi]; lo and hi are not
// roots unless lo == hi.
void isolate_in(const UPoly& q, const std::vector<UPoly>& s, const Rational& lo, const Rational& hi, std::size_t n,
                std::vector<RootInterval>& out) {
    if (n == 0)
        return;
    if (n == 1) {
        out.push_back({lo, hi});
        return;
    }
    const Rational mid = (lo + hi) / Rational(2);
    if (sign_of(evaluate(q, mid)) == Sign::zero) {
        // Keep the intervals open around the rational root: shrink both sides off it.
        Rational step = (hi - lo) / Rational(4);
        while (count_with(s, mid - step, mid + step) > 1)
            step /= Rational(2);
        const Rational left_hi = mid - step, right_lo = mid + step;
        isolate_in(q, s, lo, left_hi, count_with(s, lo, left_hi), out);
        out.push_back({mid, mid});
        isolate_in(q, s, right_lo, hi, count_with(s, right_lo, hi), out);
        return;
    }
    const std::size_t left = count_with(s, lo, mid);
    isolate_in(q, s, lo, mid, left, out);
    isolate_in(q, s, mid, hi, n - left, out);
}

} // namespace

std::vector<RootInterval> isolate(const UPoly& p) {
    std::vector<RootInterval> out;
    if (p.degree() < 1)
        return out;
    const UPoly q = square_free(p);
    const auto s = sturm_sequence(q);
    const Rational b = cauchy_bound(q);
    isolate_in(q, s, -b, b, count_with(s, -b, b), out);
    // Roots at the ends of an interval shared by two neighbours cannot occur (an end that is a
    // root is split off at a midpoint above), so the intervals are disjoint but may touch at
    // ends that are not roots.
    return out;
}

RootInterval refine(const UPoly& p, RootInterval iv, const Rational& width) {
    const UPoly q = square_free(p);
    if (iv.lo == iv.hi)
        return iv;
    if (sign_of(evaluate(q, iv.lo)) == Sign::zero)
        return {iv.lo, iv.lo};
    if (sign_of(evaluate(q, iv.hi)) == Sign::zero)
        return {iv.hi, iv.hi};
    // One root inside, none at the ends: q changes sign exactly once in between.
    const Sign s_lo = sign_of(evaluate(q, iv.lo));
    while (iv.hi - iv.lo > width) {
        const Rational mid = (iv.lo + iv.hi) / Rational(2);
        const Sign s = sign_of(evaluate(q, mid));
        if (s == Sign::zero)
            return {mid, mid};
        (s == s_lo ? iv.lo : iv.hi) = mid;
    }
    return iv;
}

std::optional<Rational> rational_root(const UPoly& p, const RootInterval& iv, std::size_t max_den_bits) {
    if (iv.lo == iv.hi)
        return iv.lo;
    // The continued-fraction convergents h/k of the midpoint; a convergent inside [lo, hi] that
    // is a root of p is the root (the only one there).
    Rational x = (iv.lo + iv.hi) / Rational(2);
    mpz_t a, h0, h1, k0, k1, t;
    mpz_inits(a, h0, h1, k0, k1, t, nullptr);
    mpz_set_ui(h0, 0);
    mpz_set_ui(h1, 1);
    mpz_set_ui(k0, 1);
    mpz_set_ui(k1, 0);
    std::optional<Rational> found;
    for (int step = 0; step < 400; ++step) {
        mpz_fdiv_q(a, mpq_numref(x.mpq()), mpq_denref(x.mpq()));
        mpz_mul(t, a, h1); // h2 = a h1 + h0
        mpz_add(t, t, h0);
        mpz_set(h0, h1);
        mpz_set(h1, t);
        mpz_mul(t, a, k1); // k2 = a k1 + k0
        mpz_add(t, t, k0);
        mpz_set(k0, k1);
        mpz_set(k1, t);
        if (mpz_sizeinbase(k1, 2) > max_den_bits)
            break;
        Rational conv;
        mpq_set_num(conv.mpq(), h1);
        mpq_set_den(conv.mpq(), k1);
        mpq_canonicalize(conv.mpq());
        if (iv.lo <= conv && conv <= iv.hi && sign_of(evaluate(p, conv)) == Sign::zero) {
            found = conv;
            break;
        }
        Rational whole;
        mpq_set_z(whole.mpq(), a);
        const Rational frac = x - whole;
        if (sign_of(frac) == Sign::zero)
            break;
        x = Rational(1) / frac;
    }
    mpz_clears(a, h0, h1, k0, k1, t, nullptr);
    return found;
}

Json to_json(const UPoly& p) {
    Json j = Json::array();
    for (const auto& x : p.c)
        j.push_back(to_json(x));
    return j;
}

} // namespace impactcert
