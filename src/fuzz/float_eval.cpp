// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/float_eval.hpp"

#include "exact/exact_double.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace impactcert {

namespace {

// Non-negative a + b and a * b rounded up: the next double above the round-to-nearest result
// is >= the exact value (the exact value lies within half a gap of the nearest double).
double add_up(double a, double b) { return std::nextafter(a + b, INFINITY); }
double mul_up(double a, double b) { return std::nextafter(a * b, INFINITY); }

// Sets r to q * 2^k exactly.
void times_pow2(Rational& r, const Rational& q, long k) {
    if (k >= 0)
        mpq_mul_2exp(r.mpq(), q.mpq(), static_cast<unsigned long>(k));
    else
        mpq_div_2exp(r.mpq(), q.mpq(), static_cast<unsigned long>(-k));
}

// The nearest double to a q with |q| < 2^-1022 (the subnormal range): round q 2^1074 to the
// nearest integer m (ties to even), then m 2^-1074 is exact.
double nearest_subnormal(const Rational& q) {
    Rational scaled;
    times_pow2(scaled, abs_of(q), 1074);
    mpz_t m, rem;
    mpz_init(m);
    mpz_init(rem);
    mpz_fdiv_qr(m, rem, mpq_numref(scaled.mpq()), mpq_denref(scaled.mpq()));
    mpz_mul_2exp(rem, rem, 1); // compare rem / den with 1/2
    const int half = mpz_cmp(rem, mpq_denref(scaled.mpq()));
    if (half > 0 || (half == 0 && mpz_odd_p(m)))
        mpz_add_ui(m, m, 1);
    const double d = std::ldexp(static_cast<double>(mpz_get_ui(m)), -1074); // m <= 2^52: exact
    mpz_clear(m);
    mpz_clear(rem);
    return sign_of(q) == Sign::negative ? -d : d;
}

} // namespace

double nearest_double(const Rational& q) {
    // Half an ulp above the largest double, 2^1024 - 2^970: from there on (the tie included, the
    // largest double's last bit being odd) round to nearest overflows.
    static const Rational overflow = Rational(std::numeric_limits<double>::max()) + Rational(std::ldexp(1.0, 970));
    static const Rational smallest_normal(std::numeric_limits<double>::min());
    const Rational a = abs_of(q);
    if (a >= overflow)
        return sign_of(q) == Sign::negative ? -INFINITY : INFINITY;
    if (a < smallest_normal)
        return nearest_subnormal(q);
    const double t = mpq_get_d(q.mpq()); // truncation toward zero: a normal double, exact path
    double best = t;
    Rational best_err = abs_of(Rational(t) - q);
    for (double c : {std::nextafter(t, -INFINITY), std::nextafter(t, INFINITY)}) {
        if (!std::isfinite(c))
            continue;
        const Rational err = abs_of(Rational(c) - q);
        std::uint64_t cb, bb;
        std::memcpy(&cb, &c, 8);
        std::memcpy(&bb, &best, 8);
        if (err < best_err || (err == best_err && (cb & 1) == 0 && (bb & 1) == 1)) {
            best = c;
            best_err = err;
        }
    }
    return best;
}

double upper_double(const Rational& q) {
    const double d = nearest_double(q);
    if (d == INFINITY)
        return d;
    if (d == -INFINITY)
        return -std::numeric_limits<double>::max(); // q < -(2^1024 - 2^970)
    return exact_double(d, "float law") < q ? std::nextafter(d, INFINITY) : d;
}

FloatLaw::FloatLaw(const Model& model) : model_(model), c_(model.contacts()) {
    // Entry and a bound on its conversion error.
    auto convert = [](const Rational& x, std::vector<double>& to, std::vector<double>& err) {
        const double d = nearest_double(x);
        to.push_back(d);
        err.push_back(std::isfinite(d) ? upper_double(abs_of(exact_double(d, "float law") - x)) : INFINITY);
    };
    for (const auto& p : model.pieces()) {
        std::vector<double> r, r_err, q, q_err;
        for (std::size_t i = 0; i < c_; ++i)
            for (std::size_t j = 0; j < c_; ++j) {
                convert(p.R_inv(i, j), r, r_err);
                convert(p.Q(i, j), q, q_err);
            }
        r_inv_.push_back(std::move(r));
        r_inv_err_.push_back(std::move(r_err));
        q_.push_back(std::move(q));
        q_err_.push_back(std::move(q_err));
    }
    const double cu = static_cast<double>(c_) * std::ldexp(1.0, -53); // exact, as is 1 - cu
    gamma_c_ = std::nextafter(cu / (1 - cu), INFINITY);
}

namespace {

struct Row {
    double value; // fl(sum_j a_j gamma_j)
    double bound; // e (see the header), rounded up; may be non-finite
};

Row row_of(const double* a, const double* delta, const std::vector<double>& gamma, double gamma_c) {
    const std::size_t c = gamma.size();
    double t = 0, mag = 0, conversion = 0;
    for (std::size_t j = 0; j < c; ++j) {
        if (gamma[j] == 0)
            continue;
        const double g = std::fabs(gamma[j]);
        t += a[j] * gamma[j];
        mag = add_up(mag, mul_up(std::fabs(a[j]), g));
        if (delta[j] != 0)
            conversion = add_up(conversion, mul_up(delta[j], g));
    }
    const double tiny = static_cast<double>(c) * std::numeric_limits<double>::denorm_min(); // c 2^-1074, exact
    return {t, add_up(add_up(mul_up(gamma_c, mag), tiny), conversion)};
}

} // namespace

FloatLaw::Result FloatLaw::eval(const std::vector<double>& gamma) const {
    Result r;
    if (gamma.size() != c_) {
        r.error = "expected " + std::to_string(c_) + " components";
        return r;
    }
    for (double g : gamma)
        if (!std::isfinite(g)) {
            r.error = "non-finite input";
            return r;
        }
    Vector exact; // gamma as rationals, built when needed
    auto exact_gamma = [&]() -> const Vector& {
        if (exact.empty())
            for (double g : gamma)
                exact.emplace_back(g);
        return exact;
    };
    // Filtered classification.
    bool found = false;
    for (std::size_t p = 0; p < r_inv_.size() && !found; ++p) {
        bool inside = true;
        for (std::size_t k = 0; k < c_ && inside; ++k) {
            const Row t = row_of(&r_inv_[p][k * c_], &r_inv_err_[p][k * c_], gamma, gamma_c_);
            inside = std::isfinite(t.value) && std::isfinite(t.bound) && t.value > t.bound;
        }
        if (inside) {
            r.piece = p;
            found = true;
        }
    }
    if (!found) {
        // Exact fallback: doubles are rationals.
        const auto pieces = model_.pieces_containing(exact_gamma());
        if (pieces.empty()) {
            r.error = "gamma lies in no cone";
            return r;
        }
        r.piece = pieces.front();
        r.exact_fallback = true;
    }
    // Output and its bound.
    for (std::size_t i = 0; i < c_; ++i) {
        Row y = row_of(&q_[r.piece][i * c_], &q_err_[r.piece][i * c_], gamma, gamma_c_);
        if (!std::isfinite(y.value) || !std::isfinite(y.bound)) {
            // Exact: the row in rationals, rounded to nearest.
            const Matrix& Q = model_.pieces()[r.piece].Q;
            Rational v = 0;
            for (std::size_t j = 0; j < c_; ++j)
                v += Q(i, j) * exact_gamma()[j];
            y.value = nearest_double(v);
            if (!std::isfinite(y.value)) {
                r.error = "overflow in the output";
                r.value.clear();
                r.bound.clear();
                return r;
            }
            y.bound = upper_double(abs_of(exact_double(y.value, "float law") - v));
            r.exact_output = true;
        }
        r.value.push_back(y.value);
        r.bound.push_back(y.bound);
    }
    r.ok = true;
    return r;
}

} // namespace impactcert
