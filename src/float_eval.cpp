#include "float_eval.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace impactcert {

namespace {

// x rounded up a little: a safe upper bound for a non-negative double computed with a few
// roundings (each at most a relative u; a factor 1 + 16u covers them with room).
double up(double x) { return x * (1 + 16 * std::ldexp(1.0, -53)) + std::numeric_limits<double>::denorm_min(); }

} // namespace

double nearest_double(const Rational& q) {
    const double t = mpq_get_d(q.mpq()); // truncation toward zero
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

FloatLaw::FloatLaw(const Model& model) : model_(model), c_(model.contacts()) {
    for (const auto& p : model.pieces()) {
        std::vector<double> r, q;
        for (std::size_t i = 0; i < c_; ++i)
            for (std::size_t j = 0; j < c_; ++j) {
                r.push_back(nearest_double(p.R_inv(i, j)));
                q.push_back(nearest_double(p.Q(i, j)));
            }
        r_inv_.push_back(std::move(r));
        q_.push_back(std::move(q));
    }
    const double u = std::ldexp(1.0, -53), n = static_cast<double>(c_ + 1);
    gamma_c1_ = up(n * u / (1 - n * u));
}

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
    const double tiny = static_cast<double>(c_) * std::numeric_limits<double>::denorm_min();
    // Filtered classification.
    bool found = false;
    for (std::size_t p = 0; p < r_inv_.size() && !found; ++p) {
        bool inside = true, outside = false;
        for (std::size_t k = 0; k < c_; ++k) {
            double t = 0, mag = 0;
            for (std::size_t j = 0; j < c_; ++j) {
                t += r_inv_[p][k * c_ + j] * gamma[j];
                mag += std::fabs(r_inv_[p][k * c_ + j] * gamma[j]);
            }
            const double e = up(gamma_c1_ * mag + tiny);
            if (t < -e)
                outside = true;
            if (!(t > e))
                inside = false;
        }
        if (inside && !outside) {
            r.piece = p;
            found = true;
        }
    }
    if (!found) {
        // Exact fallback: doubles are rationals.
        Vector exact;
        for (double g : gamma)
            exact.emplace_back(g);
        const auto pieces = model_.pieces_containing(exact);
        if (pieces.empty()) {
            r.error = "gamma lies in no cone";
            return r;
        }
        r.piece = pieces.front();
        r.exact_fallback = true;
    }
    // Output and its bound.
    for (std::size_t i = 0; i < c_; ++i) {
        double y = 0, mag = 0;
        for (std::size_t j = 0; j < c_; ++j) {
            y += q_[r.piece][i * c_ + j] * gamma[j];
            mag += std::fabs(q_[r.piece][i * c_ + j] * gamma[j]);
        }
        if (!std::isfinite(y) || !std::isfinite(mag)) {
            r.error = "overflow in the output";
            return r;
        }
        r.value.push_back(y);
        r.bound.push_back(up(gamma_c1_ * mag + tiny));
    }
    r.ok = true;
    return r;
}

} // namespace impactcert
