// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/consistency.hpp"
#include "fuzz/consistency_dependent.hpp"

#include "base/errors.hpp"
#include "exact/exact_double.hpp"
#include "base/parallel.hpp"
#include "base/splitmix.hpp"

#include <gmp.h>

#include <algorithm>
#include <set>
#include <atomic>
#include <cfenv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>

namespace impactcert::fuzz {

const char* property_id(Property p) {
    switch (p) {
    case Property::kinematic: return "kinematic";
    case Property::kinetic: return "kinetic";
    case Property::friction_cone: return "friction_cone";
    case Property::coulomb: return "coulomb";
    case Property::restitution: return "restitution";
    case Property::momentum: return "momentum";
    case Property::energy: return "energy";
    case Property::nonexpansive: return "nonexpansive";
    case Property::continuity: return "continuity";
    case Property::at_rest: return "at-rest";
    case Property::nondeterministic: return "nondeterministic";
    case Property::non_finite: return "non_finite";
    case Property::reference: return "reference";
    case Property::count: break;
    }
    return "?";
}

const char* property_title(Property p) {
    switch (p) {
    case Property::kinematic: return "negative contact velocity (kinematic)";
    case Property::kinetic: return "pulling impulse (kinetic)";
    case Property::friction_cone: return "friction beyond mu Lambda_N (friction cone)";
    case Property::coulomb: return "friction not opposing the slip (coulomb)";
    case Property::restitution: return "restitution not applied (restitution)";
    case Property::momentum: return "change outside the range of M^-1 W (momentum)";
    case Property::energy: return "energy gain";
    case Property::nonexpansive: return "expansion of a pair (nonexpansive)";
    case Property::continuity: return "jump between close inputs (continuity)";
    case Property::at_rest: return "motion from rest (at-rest)";
    case Property::nondeterministic: return "the same input answered differently (nondeterministic)";
    case Property::non_finite: return "non-finite output";
    case Property::reference: return "answer off the reference law (reference)";
    case Property::count: break;
    }
    return "?";
}

std::uint64_t ConsistencySummary::violations() const {
    std::uint64_t v = crashed + hung + malformed + refused;
    for (const auto& p : properties)
        v += p.count;
    return v;
}

std::optional<Rational> exact_of(double x) { return exact_of_double(x); }

std::pair<double, double> parse_range(const std::string& text) {
    const auto dots = text.find("..");
    if (dots == std::string::npos)
        throw InputError("--range: expected LO..HI, got \"" + text + "\"");
    auto number = [&](const std::string& s) {
        char* end = nullptr;
        const double d = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(d))
            throw InputError("--range: \"" + s + "\" is not a finite number");
        return d;
    };
    const double lo = number(text.substr(0, dots)), hi = number(text.substr(dots + 2));
    if (!(lo > 0 && lo <= hi))
        throw InputError("--range: expected 0 < LO <= HI, got " + text);
    if (hi > 1e150)
        throw InputError("--range: HI above 1e150 (outputs' squares must stay far from overflow in any engine): " + text);
    return {lo, hi};
}

// An upper bound u >= sqrt(x) (x >= 0), a rational within a relative 2^-60 of it.
Rational sqrt_up(const Rational& x) {
    if (sign_of(x) == Sign::zero)
        return Rational(0);
    // sqrt(p/q) = sqrt(p q 4^k) / (q 2^k); floor of the integer square root, plus one.
    mpz_t num, den, t;
    mpz_init(num);
    mpz_init(den);
    mpz_init(t);
    mpz_mul(t, mpq_numref(x.mpq()), mpq_denref(x.mpq()));
    mpz_mul_2exp(t, t, 128);
    mpz_sqrt(num, t);
    mpz_add_ui(num, num, 1);
    mpz_mul_2exp(den, mpq_denref(x.mpq()), 64);
    Rational r;
    mpq_set_num(r.mpq(), num);
    mpq_set_den(r.mpq(), den);
    mpq_canonicalize(r.mpq());
    mpz_clear(num);
    mpz_clear(den);
    mpz_clear(t);
    return r;
}

namespace {


double unit(std::uint64_t& st) { return static_cast<double>(splitmix(st) >> 11) * 0x1p-53; }

// Log-uniform magnitude in [lo, hi].
double magnitude(std::uint64_t& st, double lo, double hi) {
    const double v = std::exp(std::log(lo) + unit(st) * (std::log(hi) - std::log(lo)));
    return std::clamp(v, lo, hi);
}


double approx(const Rational& x) { return mpq_get_d(x.mpq()); }

// a / b as a double for ordering and display; b = 0 (an input at rest, in a replay) is infinite.
double ratio(const Rational& a, const Rational& b) {
    if (sign_of(b) == Sign::zero)
        return sign_of(a) == Sign::zero ? 0.0 : INFINITY;
    return approx(a / b);
}

// Text of an exact value: a decimal of 17 significant digits, "~" in front when rounded (the exact
// rationals are in --json).
std::string exact_text(const Rational& x) { return readable_text(x); }

std::string decimal_text(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

std::string percent(double f) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%+.3g%%", 100 * f);
    return buf;
}

} // namespace

ConsistencyChecker::ConsistencyChecker(const Mechanics& m, bool velocities, double max_rel_error,
                                       std::vector<Rational> restitution, Cone cone)
    : m_(m), velocities_(velocities), R_(max_rel_error), e_(std::move(restitution)), cone_(cone) {
    if (!e_.empty() && e_.size() != m.normals)
        throw std::logic_error("ConsistencyChecker: one restitution per normal contact");
    // The allowance for underflow (proofs/README.md, "Consistency ... near underflow"): an output
    // component may be off by one subnormal ulp, 2^-1074, whatever its scale; in the metric X of
    // the input space that is at most sqrt(d trace X) 2^-1074 (|v|_X^2 <= lambda_max |v|^2).
    const Matrix& X = velocities ? m.M : m.H;
    Rational trace;
    for (std::size_t i = 0; i < X.rows(); ++i)
        trace += X(i, i);
    Rational ulp(1);
    mpq_div_2exp(ulp.mpq(), ulp.mpq(), 1074); // 2^-1074 exactly, in one step (samples build a checker each)
    A_ = sqrt_up(Rational(static_cast<long>(X.rows())) * trace) * ulp;
}

std::size_t ConsistencyChecker::dim() const { return velocities_ ? m_.balls() : m_.contacts(); }

bool ConsistencyChecker::approaching(const double* x) const {
    Vector v(dim());
    for (std::size_t i = 0; i < v.size(); ++i) {
        auto r = exact_of(x[i]);
        if (!r)
            return false;
        v[i] = *r;
    }
    const Vector gamma = velocities_ ? transpose(m_.W) * v : v;
    return std::any_of(gamma.begin(), gamma.begin() + static_cast<std::ptrdiff_t>(m_.normals),
                       [](const Rational& g) { return sign_of(g) == Sign::negative; });
}

std::uint64_t ConsistencyChecker::approach_pattern(const double* x, Vector* gamma) const {
    Vector v(dim());
    for (std::size_t i = 0; i < v.size(); ++i) {
        auto r = exact_of(x[i]);
        if (!r)
            return 0;
        v[i] = *r;
    }
    Vector g = velocities_ ? transpose(m_.W) * v : v;
    std::uint64_t bits = 0;
    for (std::size_t k = 0; k < m_.normals && k < 64; ++k)
        if (sign_of(g[k]) == Sign::negative)
            bits |= std::uint64_t{1} << k;
    if (gamma)
        *gamma = std::move(g);
    return bits;
}

std::vector<Finding> ConsistencyChecker::check(const double* xd, const double* yd) const {
    const std::size_t d = dim();
    Vector x(d), y(d);
    for (std::size_t i = 0; i < d; ++i) {
        x[i] = *exact_of(xd[i]); // inputs are finite by construction (the caller checks)
        auto r = exact_of(yd[i]);
        if (!r) {
            Finding f;
            f.property = Property::non_finite;
            f.score = 1;
            f.detail = "output component " + std::to_string(i + 1) + " is not finite";
            f.input.assign(xd, xd + d);
            f.output.assign(yd, yd + d);
            return {std::move(f)};
        }
        y[i] = *r;
    }
    std::vector<Finding> out = check_exact(x, y, false);
    for (auto& f : out) {
        f.input.assign(xd, xd + d);
        f.output.assign(yd, yd + d);
    }
    return out;
}

std::vector<Finding> ConsistencyChecker::check_exact(const Vector& x, const Vector& y, bool no_tolerance) const {
    const std::size_t d = dim(), c = m_.normals;
    std::vector<Finding> out;
    using Figures = std::initializer_list<std::pair<std::string, Rational>>;
    auto finding = [&](Property p, double score, std::string detail, Figures figures) {
        Finding f;
        f.property = p;
        f.score = score;
        f.detail = std::move(detail);
        for (const auto& [name, value] : figures)
            f.exact.emplace_back(name, to_string(value));
        out.push_back(std::move(f));
    };
    const Matrix& X = velocities_ ? m_.M : m_.H;
    const Rational R = no_tolerance ? Rational(0) : *exact_of(R_);
    const Rational allow = no_tolerance ? Rational(0) : A_; // the underflow allowance, or none
    const Rational s2 = bilinear(x, X, x);
    // (R s + A)^2 <= R^2 s^2 + A (2 R s_up + A): the tolerance with the underflow allowance A.
    const Rational s_up = sqrt_up(s2);
    const Rational tol2 = R * R * s2 + allow * (Rational(2) * R * s_up + allow);
    const Vector gm = velocities_ ? transpose(m_.W) * x : x;
    const Vector gp = velocities_ ? transpose(m_.W) * y : y;
    // Dependent columns (proofs/README.md, "Consistency on dependent columns"): no unique impulse;
    // kinetic, the friction cone and Coulomb by linear programs below, momentum by W_B.
    const bool dependent = m_.redundant();
    const Vector lambda = dependent ? Vector() : m_.H * (gp - gm);
    // kinematic: the worst contact
    {
        std::optional<std::size_t> worst;
        double worst_score = 0;
        for (std::size_t k = 0; k < c; ++k) {
            if (sign_of(gp[k]) != Sign::negative)
                continue;
            const double score = ratio(gp[k] * gp[k], m_.G(k, k) * s2);
            if (gp[k] * gp[k] > tol2 * m_.G(k, k) && (!worst || score > worst_score)) {
                worst = k;
                worst_score = score;
            }
        }
        if (worst)
            finding(Property::kinematic, std::sqrt(worst_score),
                    "gamma+_" + std::to_string(*worst + 1) + " = " + exact_text(gp[*worst]) + " < 0 (gamma-_" +
                        std::to_string(*worst + 1) + " = " + exact_text(gm[*worst]) + ")",
                    {{"gamma+_" + std::to_string(*worst + 1), gp[*worst]}, {"gamma-_" + std::to_string(*worst + 1), gm[*worst]}});
    }
    // restitution with friction (Newton's law with Coulomb friction, proofs/README.md): an
    // approaching contact k that pushes, Lambda_N,k > (R s + A) sqrt(H_kk), pushes in every
    // consistent answer within R s + A, whose xi_N,k = gamma+_k + e_k gamma-_k is then 0; so
    // xi_N,k^2 > (R s + A)^2 G_kk is a violation. The worst contact is reported.
    if (!e_.empty() && m_.has_friction() && !dependent) {
        std::optional<std::size_t> worst;
        double worst_score = 0;
        for (std::size_t k = 0; k < c; ++k) {
            if (sign_of(gm[k]) != Sign::negative || sign_of(lambda[k]) != Sign::positive ||
                !(lambda[k] * lambda[k] > tol2 * m_.H(k, k)))
                continue;
            const Rational xi = gp[k] + e_[k] * gm[k];
            const double score = ratio(xi * xi, m_.G(k, k) * s2);
            if (xi * xi > tol2 * m_.G(k, k) && (!worst || score > worst_score)) {
                worst = k;
                worst_score = score;
            }
        }
        if (worst) {
            const std::size_t k = *worst;
            finding(Property::restitution, std::sqrt(worst_score),
                    "gamma+_" + std::to_string(k + 1) + " = " + exact_text(gp[k]) + ", not -e gamma-_" +
                        std::to_string(k + 1) + " = " + exact_text(-(e_[k] * gm[k])) + " (e = " + to_string(e_[k]) +
                        "; contact " + std::to_string(k + 1) + " approaches and pushes, Lambda_" + std::to_string(k + 1) +
                        " = " + exact_text(lambda[k]) + ": Newton's law with friction leaves it at -e gamma-)",
                    {{"gamma+_" + std::to_string(k + 1), gp[k]},
                     {"gamma-_" + std::to_string(k + 1), gm[k]},
                     {"Lambda_" + std::to_string(k + 1), lambda[k]},
                     {"e", e_[k]}});
        }
    }
    // restitution: exactly one normal contact k approaches, and the single impact at k leaves every
    // other normal contact not approaching; then every law gives gamma+_k = -e_k gamma-_k.
    if (!e_.empty() && !m_.has_friction()) {
        std::optional<std::size_t> only;
        std::size_t approaching = 0;
        for (std::size_t k = 0; k < c; ++k)
            if (sign_of(gm[k]) == Sign::negative) {
                ++approaching;
                only = k;
            }
        if (approaching == 1) {
            const std::size_t k = *only;
            const Rational impulse = (Rational(1) + e_[k]) * gm[k] / m_.G(k, k);
            bool single = true;
            for (std::size_t j = 0; j < c && single; ++j)
                single = j == k || sign_of(gm[j] - m_.G(j, k) * impulse) != Sign::negative;
            const Rational dev = gp[k] + e_[k] * gm[k];
            if (single && dev * dev > tol2 * m_.G(k, k))
                finding(Property::restitution, std::sqrt(ratio(dev * dev, m_.G(k, k) * s2)),
                        "gamma+_" + std::to_string(k + 1) + " = " + exact_text(gp[k]) + ", not -e gamma-_" +
                            std::to_string(k + 1) + " = " + exact_text(-(e_[k] * gm[k])) + " (e = " + to_string(e_[k]) +
                            "; contact " + std::to_string(k + 1) + " alone approaches, gamma- = " + exact_text(gm[k]) + ")",
                        {{"gamma+_" + std::to_string(k + 1), gp[k]}, {"gamma-_" + std::to_string(k + 1), gm[k]}, {"e", e_[k]}});
        }
    }
    // kinetic
    if (!dependent) {
        std::optional<std::size_t> worst;
        double worst_score = 0;
        for (std::size_t k = 0; k < c; ++k) {
            if (sign_of(lambda[k]) != Sign::negative)
                continue;
            const double score = ratio(lambda[k] * lambda[k], m_.H(k, k) * s2);
            if (lambda[k] * lambda[k] > tol2 * m_.H(k, k) && (!worst || score > worst_score)) {
                worst = k;
                worst_score = score;
            }
        }
        if (worst)
            finding(Property::kinetic, std::sqrt(worst_score),
                    "Lambda_" + std::to_string(*worst + 1) + " = " + exact_text(lambda[*worst]) +
                        " < 0: the contact pulls (Lambda = H (gamma+ - gamma-))",
                    {{"Lambda_" + std::to_string(*worst + 1), lambda[*worst]}});
    }
    // Dependent columns: is there an impulse of each kind whose change of velocity comes within
    // the tolerance of the answer's (projected onto the range of M^-1 W: momentum below)?
    Vector r_dependent;
    if (dependent) {
        const std::size_t n = m_.balls(), rank = m_.basis.size();
        Matrix W_B(n, rank);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t k = 0; k < rank; ++k)
                W_B(i, k) = m_.W(i, m_.basis[k]);
        const Vector du = y - x;
        const Vector du_p = m_.M_inv * (W_B * (m_.H_B * (transpose(W_B) * du)));
        r_dependent = du - du_p;
        const Rational tol = R * s_up + allow;
        const DependentFit fit(m_);
        const bool friction = m_.has_friction();
        auto score_of = [&](const Rational& t) { return sign_of(s2) == Sign::positive ? std::sqrt(ratio(t * t, s2)) : 0; };
        const Rational tk = fit.least(du_p, gm, DependentFit::Kind::kinetic);
        const Rational t = tk > tol || !friction ? tk : fit.least(du_p, gm, DependentFit::Kind::cone);
        if (tk > tol) {
            finding(Property::kinetic, score_of(tk),
                    "no impulse with Lambda_N >= 0 moves the velocities within " + exact_text(tk) +
                        " of the answer (per velocity, scaled by sqrt((M^-1)_ii); the tolerance is " + exact_text(tol) + ")",
                    {{"t", tk}, {"tolerance", tol}});
        } else if (t > tol) {
            finding(Property::friction_cone, score_of(t),
                    "no impulse in the friction cone moves the velocities within " + exact_text(t) +
                        " of the answer (per velocity, scaled by sqrt((M^-1)_ii); the tolerance is " + exact_text(tol) + ")",
                    {{"t", t}, {"tolerance", tol}});
        } else if (friction) {
            const Rational tc = fit.least_coulomb(du_p, gm, tol);
            if (tc > tol)
                finding(Property::coulomb, score_of(tc),
                        "no impulse that opposes the slip (in any mode of Coulomb's law) moves the velocities within " +
                            exact_text(tc) + " of the answer (the tolerance is " + exact_text(tol) + ")",
                        {{"t", tc}, {"tolerance", tol}});
        }
    }
    // Friction (SPEC section 9), per tangent j of contact k, with the tolerances of proofs/README.md
    // ("Consistency with friction"): the friction cone, then Coulomb's law.
    if (m_.has_friction() && !dependent && cone_ == Cone::circular)
        circular_friction(lambda, gm, gp, R * s_up + allow, s2, out);
    if (m_.has_friction() && !dependent && cone_ == Cone::box) {
        const Rational tol = R * s_up + allow;
        std::optional<std::size_t> worst_cone, worst_slip;
        double cone_score = 0, slip_score = 0;
        std::string cone_detail, slip_detail;
        for (std::size_t j = 0; j < m_.tangents.size(); ++j) {
            const Tangent& t = m_.tangents[j];
            if (t.contact < m_.polygons.size() && !m_.polygons[t.contact].empty())
                continue; // a friction polygon: polygon_friction below
            const std::size_t T = m_.normals + j, N = t.contact;
            const Rational lt = lambda[T], ln = lambda[N];
            const Rational tau_h = tol * (sqrt_up(m_.H(T, T)) + t.mu * sqrt_up(m_.H(N, N)));
            const Rational abs_lt = sign_of(lt) == Sign::negative ? -lt : lt;
            const Rational over = abs_lt - t.mu * ln;
            if (over > tau_h) {
                const double score = ratio(over * over, m_.H(T, T) * s2);
                if (!worst_cone || score > cone_score) {
                    worst_cone = j;
                    cone_score = score;
                    cone_detail = "|Lambda_T" + std::to_string(j + 1) + "| = " + exact_text(abs_lt) + " > mu Lambda_N" +
                                  std::to_string(N + 1) + " = " + exact_text(t.mu * ln) + " (contact " +
                                  std::to_string(N + 1) + ", mu = " + to_string(t.mu) + ")";
                }
            }
            const Rational xi = gp[T] + t.e_T * gm[T];
            const Rational tau_x = tol * sqrt_up(m_.G(T, T));
            for (const int dir : {1, -1}) {
                // dir +1: slip forward (xi_T > 0) needs Lambda_T = -mu Lambda_N; -1 the other way.
                const Rational slip = dir > 0 ? xi : -xi;
                const Rational off = (dir > 0 ? lt : -lt) + t.mu * ln; // 0 at the opposing bound
                if (slip > tau_x && off > tau_h) {
                    const double score = ratio(off * off, m_.H(T, T) * s2);
                    if (!worst_slip || score > slip_score) {
                        worst_slip = j;
                        slip_score = score;
                        slip_detail = "xi_T" + std::to_string(j + 1) + " = " + exact_text(xi) + (dir > 0 ? " > 0" : " < 0") +
                                      " (the contact slips) but Lambda_T" + std::to_string(j + 1) + " = " + exact_text(lt) +
                                      (dir > 0 ? " != -mu Lambda_N = " : " != +mu Lambda_N = ") +
                                      exact_text(Rational(-dir) * t.mu * ln) + " (contact " + std::to_string(N + 1) + ")";
                    }
                }
            }
        }
        if (worst_cone)
            finding(Property::friction_cone, std::sqrt(cone_score), cone_detail, {});
        if (worst_slip)
            finding(Property::coulomb, std::sqrt(slip_score), slip_detail, {});
        if (m_.has_polygons())
            polygon_friction(lambda, gm, gp, tol, s2, out);
    }
    // momentum: the part of the velocity change outside the range of M^-1 W
    if (velocities_) {
        const Vector r = dependent ? r_dependent : (y - x) - m_.M_inv * (m_.W * lambda);
        const Rational r2 = bilinear(r, m_.M, r);
        if (r2 > tol2) {
            std::string detail = "|r|_M^2 = " + exact_text(r2) + " with |u-|_M^2 = " + exact_text(s2) +
                                 " (r = du - M^-1 W Lambda, not made of contact impulses)";
            // Total momentum only where it is conserved by any impulses and means one thing: every
            // contact pushes two coordinates by +-1 (internal, no wall or fixed ground), every
            // coordinate is touched by a contact (no mixing with a rotation or a second axis), and
            // no friction.
            bool chain_like = m_.diagonal && !m_.has_friction();
            std::vector<bool> touched(d, false);
            for (std::size_t k = 0; chain_like && k < m_.W.cols(); ++k) {
                int plus = 0, minus = 0;
                for (std::size_t i = 0; i < d; ++i) {
                    const Rational& w = m_.W(i, k);
                    if (w == Rational(1))
                        ++plus;
                    else if (w == Rational(-1))
                        ++minus;
                    else if (sign_of(w) != Sign::zero)
                        chain_like = false;
                    if (sign_of(w) != Sign::zero)
                        touched[i] = true;
                }
                chain_like = chain_like && plus == 1 && minus == 1;
            }
            for (std::size_t i = 0; i < d; ++i)
                chain_like = chain_like && touched[i];
            if (chain_like) {
                Rational pm, pp;
                for (std::size_t i = 0; i < d; ++i) {
                    pm += m_.M(i, i) * x[i];
                    pp += m_.M(i, i) * y[i];
                }
                detail += "; total momentum p- = " + exact_text(pm) + ", p+ = " + exact_text(pp);
            }
            finding(Property::momentum, std::sqrt(ratio(r2, s2)), detail, {{"|r|_M^2", r2}, {"|u-|_M^2", s2}});
        }
    }
    // energy
    {
        const Rational t2 = bilinear(y, X, y);
        const Rational one_r = Rational(1) + R;
        // |y| > (1 + R) s + A, squared with s_up >= s on the cross term
        if (t2 > one_r * one_r * s2 + allow * (Rational(2) * one_r * s_up + allow)) {
            const Rational half(1, 2);
            const std::string part = velocities_ ? "" : " (contact part)";
            finding(Property::energy, ratio(t2 - s2, s2),
                    percent(ratio(t2 - s2, s2)) + ": T-" + part + " = " + exact_text(half * s2) + ", T+" + part + " = " +
                        exact_text(half * t2),
                    {{"T-" + part, half * s2}, {"T+" + part, half * t2}});
        }
    }
    // Where the velocity change is not made of contact impulses (momentum), Lambda is the
    // projection of that change onto the contacts' range: the kinetic, cone and Coulomb findings
    // at this input describe the projection, not impulses the implementation applied.
    bool momentum = false;
    for (const auto& f : out)
        momentum = momentum || f.property == Property::momentum;
    if (momentum)
        for (auto& f : out)
            if (f.property == Property::kinetic || f.property == Property::friction_cone || f.property == Property::coulomb ||
                (f.property == Property::restitution && m_.has_friction())) {
                f.projection = true;
                f.detail += " [Lambda projected: the velocity change is not made of contact impulses here (momentum)]";
            }
    return out;
}

// The law's exact answer at x nearest y in the metric of the input space (the law may have several
// values on a boundary), with its squared distance; nothing where x lies in no cone of the law.
// Shared by the reference property and the law/solver classification.
static std::optional<Vector> nearest_law_answer(const Model& law, const Mechanics& m, bool velocities, const Vector& x,
                                         const Vector& y, Rational& d2_out) {
    const Vector gamma = velocities ? law.contact_velocities(x) : x; // the law's coordinates (W_B^T u)
    const Matrix& X = velocities ? m.M : m.H;
    std::optional<Vector> best;
    for (const Vector& g : law.values_at(gamma)) {
        const Vector ystar = velocities ? law.post_impact_velocities(x, gamma, g) : g;
        const Vector diff = y - ystar;
        const Rational d2 = bilinear(diff, X, diff);
        if (!best || d2 < d2_out) {
            best = ystar;
            d2_out = d2;
        }
    }
    return best;
}

std::optional<Finding> ConsistencyChecker::reference(const double* xd, const double* yd, const Model& law) const {
    const std::size_t d = dim();
    Vector x(d), y(d);
    for (std::size_t i = 0; i < d; ++i) {
        const auto xi = exact_of(xd[i]), yi = exact_of(yd[i]);
        if (!xi || !yi)
            return std::nullopt; // a non-finite output is its own finding (non_finite)
        x[i] = *xi;
        y[i] = *yi;
    }
    const Matrix& X = velocities_ ? m_.M : m_.H;
    Rational best_d2;
    const std::optional<Vector> best = nearest_law_answer(law, m_, velocities_, x, y, best_d2);
    if (!best)
        return std::nullopt; // x lies in no cone of the law
    // (R s + A)^2 <= R^2 s^2 + A (2 R s_up + A), as in check_exact: beyond this bound, beyond the
    // tolerance.
    const Rational R = *exact_of(R_);
    const Rational s2 = bilinear(x, X, x);
    const Rational tol2 = R * R * s2 + A_ * (Rational(2) * R * sqrt_up(s2) + A_);
    if (!(best_d2 > tol2))
        return std::nullopt;
    Finding f;
    f.property = Property::reference;
    f.input.assign(xd, xd + d);
    f.output.assign(yd, yd + d);
    f.off = sign_of(s2) == Sign::positive ? std::sqrt(ratio(best_d2, s2)) : 0;
    f.score = f.off;
    std::string exact;
    for (std::size_t i = 0; i < d; ++i)
        exact += (i ? ", " : "") + exact_text((*best)[i]);
    char off[48];
    std::snprintf(off, sizeof off, "%.3g", f.off);
    f.detail = std::string(off) + " off the exact law (relative, |y - y*| / |x|); the law answers (" + exact + ")";
    for (std::size_t i = 0; i < d; ++i)
        f.exact.emplace_back("y*_" + std::to_string(i + 1), to_string((*best)[i]));
    f.exact.emplace_back("|y - y*|^2", to_string(best_d2));
    f.exact.emplace_back("|x|^2", to_string(s2));
    return f;
}

Finding ConsistencyChecker::nondeterministic(const double* x, const double* y1, const std::vector<double>& y2) const {
    const std::size_t d = dim();
    Finding f;
    f.property = Property::nondeterministic;
    f.score = 1;
    f.input.assign(x, x + d);
    f.output.assign(y1, y1 + d);
    f.output_b = y2;
    std::string a, b;
    for (std::size_t i = 0; i < d; ++i) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%s%.17g", i ? ", " : "", y1[i]);
        a += buf;
        std::snprintf(buf, sizeof buf, "%s%.17g", i ? ", " : "", i < y2.size() ? y2[i] : NAN);
        b += buf;
    }
    f.detail = "answered (" + a + "), then (" + b + ")";
    return f;
}

std::optional<Finding> ConsistencyChecker::at_rest(const double* yd) const {
    const std::size_t d = dim();
    Finding f;
    f.property = Property::at_rest;
    f.input.assign(d, 0.0);
    f.output.assign(yd, yd + d);
    Vector y(d);
    for (std::size_t i = 0; i < d; ++i) {
        const auto r = exact_of(yd[i]);
        if (!r) {
            f.score = 1;
            f.detail = "the input at rest is answered with a non-finite component " + std::to_string(i + 1);
            return f;
        }
        y[i] = *r;
    }
    const Matrix& X = velocities_ ? m_.M : m_.H;
    const Rational e2 = bilinear(y, X, y);
    if (!(e2 > A_ * A_))
        return std::nullopt;
    f.score = ratio(e2, Rational(1));
    f.detail = std::string("the input at rest is answered with motion: ") + (velocities_ ? "T+" : "T+ (contact part)") +
               " = " + exact_text(Rational(1, 2) * e2) + " from T- = 0 (energy from nothing)";
    f.exact.emplace_back(velocities_ ? "T+" : "T+ (contact part)", to_string(Rational(1, 2) * e2));
    return f;
}

namespace {

// `f` replaces the finding in `slot` when there is none or its score is higher (the worst per property).
void keep_worst(std::optional<Finding>& slot, Finding f) {
    if (!slot || f.score > slot->score)
        slot = std::move(f);
}

// A finding of property p with its score, detail and exact figures.
Finding make_finding(Property p, double score, std::string detail, std::vector<std::pair<std::string, std::string>> exact) {
    Finding f;
    f.property = p;
    f.score = score;
    f.detail = std::move(detail);
    f.exact = std::move(exact);
    return f;
}

// The sign of P + Q sqrt(S), S >= 0, exactly.
Sign sign_with_root(const Rational& P, const Rational& Q, const Rational& S) {
    const Sign p = sign_of(P), q = sign_of(S) == Sign::zero ? Sign::zero : sign_of(Q);
    if (q == Sign::zero || p == q)
        return p == Sign::zero ? q : p;
    if (p == Sign::zero)
        return q;
    // Opposite signs: the larger magnitude wins (P^2 against Q^2 S).
    const Rational a = P * P, b = Q * Q * S;
    return a == b ? Sign::zero : a > b ? p : q;
}

} // namespace

// The circular cone (proofs/README.md, "Consistency with a circular friction cone"), per rough
// contact N with tangents T (one mu, one e_T): with t = R s + A and an answer within t of one of
// Coulomb's law (Lambda*, xi*), |Delta Lambda_T| <= t sqrt(lambda_max H_TT) <= t sqrt(tr H_TT),
// |Delta Lambda_N| <= t sqrt(H_NN) and |Delta xi_T| <= t sqrt(tr G_TT) (Cauchy-Schwarz in the
// metric), so the bounds below are never passed by such an answer.
void ConsistencyChecker::circular_friction(const Vector& lambda, const Vector& gm, const Vector& gp, const Rational& tol,
                                           const Rational& s2, std::vector<Finding>& out) const {
    std::optional<Finding> cone, slip;
    std::vector<bool> done(m_.tangents.size(), false);
    auto vector_text = [](const std::vector<Rational>& v) {
        std::string t = "(";
        for (std::size_t i = 0; i < v.size(); ++i)
            t += (i ? ", " : "") + exact_text(v[i]);
        return t + ")";
    };
    for (std::size_t j0 = 0; j0 < m_.tangents.size(); ++j0) {
        if (done[j0])
            continue;
        const std::size_t N = m_.tangents[j0].contact;
        const Rational& mu = m_.tangents[j0].mu;
        const Rational& e_T = m_.tangents[j0].e_T;
        Rational lt2, trH, trG, xi2, dot;
        std::vector<Rational> lt, xi;
        for (std::size_t j = j0; j < m_.tangents.size(); ++j) {
            if (m_.tangents[j].contact != N)
                continue;
            done[j] = true;
            const std::size_t T = m_.normals + j;
            lt.push_back(lambda[T]);
            xi.push_back(gp[T] + e_T * gm[T]);
            lt2 += lt.back() * lt.back();
            xi2 += xi.back() * xi.back();
            dot += lt.back() * xi.back();
            trH += m_.H(T, T);
            trG += m_.G(T, T);
        }
        const Rational ln = lambda[N];
        const Rational hn = sqrt_up(m_.H(N, N));
        const Rational tau_h = tol * (sqrt_up(trH) + mu * hn);
        const std::string where = " (contact " + std::to_string(N + 1) + ", mu = " + to_string(mu) + ")";
        // friction_cone: |Lambda_T| > mu Lambda_N + tau_h.
        const Rational bound = mu * ln + tau_h;
        if (sign_of(bound) == Sign::negative || lt2 > bound * bound) {
            const double over = std::sqrt(approx(lt2)) - approx(mu * ln);
            const double score = s2 > Rational(0) ? over / std::sqrt(approx(trH * s2)) : INFINITY;
            keep_worst(cone, make_finding(Property::friction_cone, score,
                                          "|Lambda_T| = |" + vector_text(lt) + "| > mu Lambda_N" + std::to_string(N + 1) +
                                              " = " + exact_text(mu * ln) + where,
                                          {{"|Lambda_T|^2", to_string(lt2)}, {"mu Lambda_N", to_string(mu * ln)}}));
        }
        // coulomb, two conditions that every answer of Coulomb's law meets (sliding: Lambda_T =
        // -mu Lambda_N xi_T / |xi_T|; sticking: xi_T = 0), each with its bound:
        //  - rho = Lambda_T . xi_T + mu Lambda_N |xi_T| = 0 (too little friction, or along the slip):
        //    (dot - C) + (mu Lambda_N - tau_h) |xi_T| > 0, C = 2 mu Lambda_N^up t sqrt tr G_TT;
        //  - |Lambda_T ^ xi_T| = 0 (friction not along the slip; Lagrange: |a ^ b|^2 = |a|^2 |b|^2 -
        //    (a . b)^2): |Lambda_T ^ xi_T| > a |xi_T| + b, a = t sqrt tr H_TT, b = mu Lambda_N^up t sqrt tr G_TT,
        //    squared: (wedge2 - a^2 |xi|^2 - b^2) - 2 a b |xi_T| > 0.
        // (First order in an error of size and of direction; Lambda_N^up = max(Lambda_N + t sqrt H_NN, 0).)
        Rational ln_up = ln + tol * hn;
        if (sign_of(ln_up) == Sign::negative)
            ln_up = Rational(0);
        const Rational gt = sqrt_up(trG), ht = sqrt_up(trH);
        const Rational C = Rational(2) * mu * ln_up * tol * gt;
        const bool too_little = sign_with_root(dot - C, mu * ln - tau_h, xi2) == Sign::positive;
        const Rational wedge2 = lt2 * xi2 - dot * dot;
        const Rational a = tol * ht, b = mu * ln_up * tol * gt;
        const bool aside = !too_little && sign_with_root(wedge2 - a * a * xi2 - b * b, Rational(-2) * a * b, xi2) == Sign::positive;
        if (too_little || aside) {
            const double xi_norm = std::sqrt(approx(xi2));
            const double rho = approx(dot) + approx(mu * ln) * xi_norm;
            const double off = too_little ? rho / xi_norm : std::sqrt(std::max(0.0, approx(wedge2))) / xi_norm;
            const double score = s2 > Rational(0) ? off / std::sqrt(approx(trH * s2)) : INFINITY;
            keep_worst(slip, make_finding(Property::coulomb, score,
                                          "xi_T = " + vector_text(xi) + " but Lambda_T = " + vector_text(lt) +
                                              " is not -mu Lambda_N xi_T / |xi_T| (mu Lambda_N = " + exact_text(mu * ln) +
                                              "): " +
                                              (too_little ? "Lambda_T . xi_T + mu Lambda_N |xi_T| = ~" + decimal_text(rho) + " > 0"
                                                          : "|Lambda_T ^ xi_T| / |xi_T| = ~" + decimal_text(off) +
                                                                " (not along the slip)") +
                                              where,
                                          {{"Lambda_T . xi_T", to_string(dot)},
                                           {"mu Lambda_N", to_string(mu * ln)},
                                           {"|xi_T|^2", to_string(xi2)},
                                           {"|Lambda_T|^2", to_string(lt2)}}));
        }
    }
    if (cone)
        out.push_back(std::move(*cone));
    if (slip)
        out.push_back(std::move(*slip));
}

// Friction polygons (proofs/README.md, "Polygonal friction cones": consistency), per contact N
// with a polygon (facets a_j, vertices v_j; tangents T1, T2), with t = R s + A:
//   friction_cone  a_j . Lambda_T - mu Lambda_N > t (sqrt(a_j^T H_TT a_j) + mu sqrt H_NN) for some j;
//   coulomb     q_j = (Lambda_T - mu Lambda_N v_j) . xi_T > t sqrt(tr H_TT) |xi_T| + mu L rho t g
//               + mu t sqrt(H_NN) |v_j . xi_T| + mu L |v_j| t g for some vertex j (g = sqrt tr G_TT,
//               rho = max |v_i|, L = max(Lambda_N + t sqrt H_NN, 0)): every answer of the law has
//               q_j <= 0, and each term bounds what an answer within t can change; every root is
//               replaced by a rational above it.
void ConsistencyChecker::polygon_friction(const Vector& lambda, const Vector& gm, const Vector& gp, const Rational& tol,
                                          const Rational& s2, std::vector<Finding>& out) const {
    std::optional<Finding> cone, slip;
    for (std::size_t N = 0; N < m_.polygons.size(); ++N) {
        const FrictionPolygon& P = m_.polygons[N];
        if (P.empty())
            continue;
        std::size_t j0 = 0;
        while (m_.tangents[j0].contact != N)
            ++j0;
        const std::size_t T1 = m_.normals + j0, T2 = T1 + 1;
        const Rational& mu = m_.tangents[j0].mu;
        const Vector lt{lambda[T1], lambda[T2]};
        const Vector xi{gp[T1] + m_.tangents[j0].e_T * gm[T1], gp[T2] + m_.tangents[j0 + 1].e_T * gm[T2]};
        const Rational ln = lambda[N];
        const Rational hn = sqrt_up(m_.H(N, N));
        const std::string where = " (contact " + std::to_string(N + 1) + ", mu = " + to_string(mu) + ")";
        const double scale = s2 > Rational(0) ? std::sqrt(approx((m_.H(T1, T1) + m_.H(T2, T2)) * s2)) : 0;
        for (std::size_t j = 0; j < P.a.size(); ++j) {
            const Vector& a = P.a[j];
            const Rational over = dot(a, lt) - mu * ln;
            const Rational aHa = a[0] * a[0] * m_.H(T1, T1) + Rational(2) * a[0] * a[1] * m_.H(T1, T2) + a[1] * a[1] * m_.H(T2, T2);
            if (over > tol * (sqrt_up(aHa) + mu * hn)) {
                const double score = scale > 0 ? approx(over) / scale : INFINITY;
                keep_worst(cone, make_finding(Property::friction_cone, score,
                                              "a_" + std::to_string(j + 1) + " . Lambda_T = " + exact_text(dot(a, lt)) +
                                                  " > mu Lambda_N" + std::to_string(N + 1) + " = " + exact_text(mu * ln) +
                                                  " (facet " + std::to_string(j + 1) + " of the friction polygon)" + where,
                                              {{"a . Lambda_T", to_string(dot(a, lt))}, {"mu Lambda_N", to_string(mu * ln)}}));
            }
        }
        Rational ln_up = ln + tol * hn;
        if (sign_of(ln_up) == Sign::negative)
            ln_up = Rational(0);
        const Rational g = sqrt_up(m_.G(T1, T1) + m_.G(T2, T2));
        const Rational h = sqrt_up(m_.H(T1, T1) + m_.H(T2, T2));
        const Rational xi_up = sqrt_up(dot(xi, xi));
        Rational radius;
        for (const Vector& v : P.v)
            radius = std::max(radius, sqrt_up(dot(v, v)));
        for (std::size_t j = 0; j < P.v.size(); ++j) {
            const Vector& v = P.v[j];
            const Rational q = (lt[0] - mu * ln * v[0]) * xi[0] + (lt[1] - mu * ln * v[1]) * xi[1];
            const Rational vxi = dot(v, xi);
            const Rational bound = tol * h * xi_up + mu * ln_up * radius * tol * g +
                                   mu * tol * hn * (sign_of(vxi) == Sign::negative ? -vxi : vxi) +
                                   mu * ln_up * sqrt_up(dot(v, v)) * tol * g;
            if (q > bound) {
                const double score = scale > 0 && xi_up > Rational(0) ? approx(q / xi_up) / scale : INFINITY;
                keep_worst(slip, make_finding(Property::coulomb, score,
                                              "xi_T = (" + exact_text(xi[0]) + ", " + exact_text(xi[1]) + ") but Lambda_T = (" +
                                                  exact_text(lt[0]) + ", " + exact_text(lt[1]) +
                                                  ") dissipates less than mu Lambda_N v_" + std::to_string(j + 1) + " = (" +
                                                  exact_text(mu * ln * v[0]) + ", " + exact_text(mu * ln * v[1]) +
                                                  "): (Lambda_T - mu Lambda_N v) . xi_T = " + exact_text(q) + " > 0 (vertex " +
                                                  std::to_string(j + 1) + " of the friction polygon)" + where,
                                              {{"(Lambda_T - mu Lambda_N v) . xi_T", to_string(q)}, {"bound", to_string(bound)}}));
            }
        }
    }
    if (cone)
        out.push_back(std::move(*cone));
    if (slip)
        out.push_back(std::move(*slip));
}

std::vector<Finding> ConsistencyChecker::check_pair(const double* ad, const double* yad, const double* bd,
                                                    const double* ybd, bool nonexpansive, bool continuity) const {
    const std::size_t d = dim();
    std::vector<Finding> out;
    Vector a(d), b(d), ya(d), yb(d);
    for (std::size_t i = 0; i < d; ++i) {
        auto p = exact_of(yad[i]), q = exact_of(ybd[i]);
        if (!p || !q)
            return out; // reported by check() of the points
        a[i] = *exact_of(ad[i]);
        b[i] = *exact_of(bd[i]);
        ya[i] = *p;
        yb[i] = *q;
    }
    const Matrix& X = velocities_ ? m_.M : m_.H;
    const Rational R = *exact_of(R_);
    const Vector dy = ya - yb, dx = a - b;
    const Rational A = bilinear(dy, X, dy), B = bilinear(dx, X, dx);
    // T >= R (|a| + |b|), rational; then |dy| > L |dx| + T  <=>  A - L^2 B - T^2 > 0 and
    // (A - L^2 B - T^2)^2 > 4 T^2 L^2 B (both sides of the root comparison are non-negative).
    const Rational T = R * (sqrt_up(bilinear(a, X, a)) + sqrt_up(bilinear(b, X, b))) + Rational(2) * A_;
    auto exceeds = [&](const Rational& L) {
        const Rational lb = L * L * B;
        const Rational gap = A - lb - T * T;
        return sign_of(gap) == Sign::positive && gap * gap > Rational(4) * T * T * lb;
    };
    auto make = [&](Property p, const std::string& bound) {
        Finding f;
        f.property = p;
        f.score = std::sqrt(ratio(A, B));
        char ratio[48];
        std::snprintf(ratio, sizeof ratio, "%.6g", f.score);
        f.detail = "|S(a) - S(b)|^2 = " + exact_text(A) + " > (" + bound + ")^2, |a - b|^2 = " + exact_text(B) +
                   " (ratio " + ratio + ")";
        f.input.assign(ad, ad + d);
        f.input_b.assign(bd, bd + d);
        f.output.assign(yad, yad + d);
        f.output_b.assign(ybd, ybd + d);
        out.push_back(std::move(f));
    };
    if (nonexpansive && exceeds(Rational(1)))
        make(Property::nonexpansive, "|a - b| + R (|a| + |b|)");
    if (continuity && exceeds(Rational(1024)))
        make(Property::continuity, "1024 |a - b| + R (|a| + |b|)");
    return out;
}

namespace {
// The families of structured_input, in order; each is a count and a maker of its j-th member.
struct Family {
    std::size_t (*count)(std::size_t d);
    void (*make)(std::size_t d, std::size_t j, std::vector<int>& v);
};
const Family kFamilies[] = {
    {[](std::size_t d) { return 2 * d; }, // one moving component
     [](std::size_t, std::size_t j, std::vector<int>& v) { v[j / 2] = j % 2 ? -1 : 1; }},
    {[](std::size_t d) { return 16 * (d * (d - 1) / 2); }, // two: every pair, values +-1, +-2
     [](std::size_t d, std::size_t j, std::vector<int>& v) {
         static const int values[] = {1, -1, 2, -2};
         std::size_t p = j / 16, a = 0;
         while (p >= d - 1 - a) { // the p-th pair (a, b), a < b, in lexicographic order
             p -= d - 1 - a;
             ++a;
         }
         v[a] = values[(j % 16) / 4];
         v[a + 1 + p] = values[j % 4];
     }},
    {[](std::size_t d) { return d * (d + 1) / 2 * d; }, // ties: a run [i, i + len) at 1, one other at -1
     [](std::size_t d, std::size_t j, std::vector<int>& v) {
         std::size_t run = j / d, other = j % d, i = 0;
         while (run >= d - i) { // the run-th (start, length) pair
             run -= d - i;
             ++i;
         }
         for (std::size_t t = i; t <= i + run; ++t)
             v[t] = 1;
         if (other < i || other > i + run)
             v[other] = -1;
     }},
    {[](std::size_t) -> std::size_t { return 3; }, // everything approaching (a chain's contacts close)
     [](std::size_t d, std::size_t j, std::vector<int>& v) {
         for (std::size_t t = 0; t < d; ++t) {
             const int ramp = static_cast<int>(d - 1 - t);
             v[t] = j == 0 ? ramp : j == 1 ? 2 * ramp - static_cast<int>(d - 1) : -static_cast<int>(t);
         }
     }},
    {[](std::size_t d) -> std::size_t { return d >= 3 ? (d - 2) * 343 : 0; }, // small integers on three neighbours
     [](std::size_t, std::size_t j, std::vector<int>& v) {
         const std::size_t at = j / 343, code = j % 343;
         v[at] = static_cast<int>(code / 49) - 3;
         v[at + 1] = static_cast<int>(code / 7 % 7) - 3;
         v[at + 2] = static_cast<int>(code % 7) - 3;
     }},
};
} // namespace

std::size_t structured_count(std::size_t d) {
    std::size_t n = 0;
    for (const Family& f : kFamilies)
        n += d ? f.count(d) : 0;
    return n;
}

void structured_input(std::size_t d, std::size_t k, std::vector<int>& out) {
    out.assign(d, 0);
    for (const Family& f : kFamilies) {
        const std::size_t n = d ? f.count(d) : 0;
        if (k < n) {
            f.make(d, k, out);
            return;
        }
        k -= n;
    }
}

void consistency_sample(const Mechanics& m, const ConsistencyOptions& o, std::uint64_t index, double* a, double* b,
                        bool& pair, bool& close) {
    const std::size_t d = o.velocities ? m.balls() : m.contacts();
    const ConsistencyChecker checker(m, o.velocities, 0);
    std::uint64_t st = o.seed * 0x9E3779B97F4A7C15ULL ^ (index + 0x632BE59BD9B4E019ULL);
    bool structured = false;
    if (index % 2 == 0 && index / 2 < structured_count(d)) {
        // The unit: the power of two nearest the range's geometric middle, lowered until 3 units
        // fit under HI and raised to at least LO (entries beyond the range are clamped below).
        double unit_s = std::ldexp(1.0, static_cast<int>(std::lround(std::log2(std::sqrt(o.range_lo) * std::sqrt(o.range_hi)))));
        while (3 * unit_s > o.range_hi && unit_s / 2 >= o.range_lo)
            unit_s /= 2;
        while (unit_s < o.range_lo) // every non-zero entry at least LO (those above HI are clamped)
            unit_s *= 2;
        std::vector<int> v;
        structured_input(d, static_cast<std::size_t>(index / 2), v);
        for (std::size_t i = 0; i < d; ++i)
            a[i] = std::clamp(v[i] * unit_s, -o.range_hi, o.range_hi);
        structured = checker.approaching(a); // one that approaches nowhere: a random sample instead
    }
    for (int attempt = 0; !structured; ++attempt) {
        const std::uint64_t kind = below(st, 4);
        const double scale = magnitude(st, o.range_lo, o.range_hi);
        for (std::size_t i = 0; i < d; ++i) {
            double v = 0;
            switch (kind) {
            case 0: { // small integers times a power of two: the classical experiments and their ties, exactly
                const int k = static_cast<int>(below(st, 7)) - 3;
                double p2 = std::ldexp(1.0, std::ilogb(scale));
                if (p2 < o.range_lo)
                    p2 *= 2;
                v = k * p2;
                if (std::fabs(v) > o.range_hi)
                    v = (k < 0 ? -1 : 1) * p2;
                break;
            }
            case 1: // uniform at one scale
                v = (2 * unit(st) - 1) * scale;
                break;
            case 2: // independent magnitudes over the whole range
                v = (splitmix(st) & 1 ? 1 : -1) * magnitude(st, o.range_lo, o.range_hi);
                break;
            default: { // zeros, repeated values (contacts at rest, balls moving together) and near-ties
                const std::uint64_t r = below(st, 4);
                if (r == 0)
                    v = 0;
                else if (i > 0 && r == 1)
                    v = a[i - 1];
                else if (i > 0 && r == 2 && a[i - 1] != 0) {
                    // 1 to 2^20 ulps from the previous component, either way: the orderings and
                    // thresholds that exact ties hide.
                    const double ulp = std::ldexp(1.0, std::ilogb(a[i - 1]) - 52);
                    const double k = std::ldexp(1.0, static_cast<int>(below(st, 21)));
                    v = a[i - 1] + (below(st, 2) == 0 ? k : -k) * ulp;
                } else
                    v = (2 * unit(st) - 1) * scale;
                break;
            }
            }
            if (v != 0 && std::fabs(v) < o.range_lo)
                v = 0;
            a[i] = std::clamp(v, -o.range_hi, o.range_hi);
        }
        if (checker.approaching(a) || attempt == 1000)
            break;
    }
    pair = o.nonexpansive || o.continuity;
    close = false;
    if (!pair)
        return;
    close = o.continuity && (!o.nonexpansive || below(st, 2) == 0);
    const int exponent = close ? 20 + static_cast<int>(below(st, 20)) : 2 + static_cast<int>(below(st, 18));
    double big = 0;
    for (std::size_t i = 0; i < d; ++i)
        big = std::max(big, std::fabs(a[i]));
    for (std::size_t i = 0; i < d; ++i) {
        const double delta = (2 * unit(st) - 1) * std::ldexp(big, -exponent);
        double v = a[i] + delta;
        if (v != 0 && std::fabs(v) < o.range_lo)
            v = 0;
        b[i] = std::clamp(v, -o.range_hi, o.range_hi);
    }
}

namespace {

std::string replay_text(const std::string& prefix, const Finding& f) {
    // The prefix ends with "--" (so that negative numbers are points): --pair goes before it.
    std::string s = prefix;
    if (!f.input_b.empty()) {
        if (s.size() >= 3 && s.compare(s.size() - 3, 3, " --") == 0)
            s.insert(s.size() - 3, " --pair");
        else
            s += " --pair";
    }
    for (double x : f.input)
        s += " " + hex(x);
    for (double x : f.input_b)
        s += " " + hex(x);
    return s;
}

struct Partial {
    ConsistencySummary sum;
    std::vector<Finding> examples;
    std::set<std::uint64_t> patterns; // coverage (ConsistencySummary)
    std::set<int> decades;
    std::vector<char> reference_hit;
};

// Law-level or solver-level (ConsistencyOptions::reference): the reference law's exact answer at
// the finding's input (the value nearest the implementation's where the law has several) is
// checked for the same property with no tolerance at all.
void classify(Finding& f, const Model* reference, const ConsistencyChecker& checker, const Mechanics& m,
              bool velocities) {
    if (!reference)
        return;
    switch (f.property) {
    case Property::nonexpansive:
    case Property::continuity:
        return; // pairs: not classified
    case Property::reference:
        return; // the distance to the law itself: not classified
    case Property::at_rest:
    case Property::nondeterministic:
    case Property::non_finite:
        f.level = 2; // a law maps rest to rest, is a function and is finite: the implementation's own
        return;
    default:
        break;
    }
    const std::size_t d = f.input.size();
    Vector x(d), y(d);
    for (std::size_t i = 0; i < d; ++i) {
        x[i] = *exact_of(f.input[i]);
        y[i] = *exact_of(f.output[i]);
    }
    const Matrix& X = velocities ? m.M : m.H;
    Rational best_d2;
    const std::optional<Vector> best = nearest_law_answer(*reference, m, velocities, x, y, best_d2);
    if (!best)
        return; // outside every cone of the reference law
    bool law = false;
    for (const auto& g : checker.check_exact(x, *best, true))
        law = law || g.property == f.property;
    f.level = law ? 1 : 2;
    const Rational s2 = bilinear(x, X, x);
    f.off = sign_of(s2) == Sign::positive ? std::sqrt(ratio(best_d2, s2)) : 0;
}

void record(Partial& p, Finding f, std::size_t keep) {
    auto& slot = p.sum.properties[static_cast<std::size_t>(f.property)];
    ++slot.count;
    slot.projections += f.projection ? 1 : 0;
    slot.law += f.level == 1 ? 1 : 0;
    slot.solver += f.level == 2 ? 1 : 0;
    if (f.level == 2 && (!slot.worst_solver || f.off > slot.worst_solver->off ||
                         (f.off == slot.worst_solver->off && f.index < slot.worst_solver->index)))
        slot.worst_solver = f;
    if (!slot.worst || f.score > slot.worst->score || (f.score == slot.worst->score && f.index < slot.worst->index))
        slot.worst = f;
    if (p.examples.size() < keep)
        p.examples.push_back(std::move(f));
}

} // namespace

ConsistencySummary run_consistency(const Mechanics& m, const ConsistencyOptions& o, const Implementation& impl,
                                   const std::function<void(std::uint64_t)>& progress) {
    const std::size_t d = o.velocities ? m.balls() : m.contacts();
    if (d > kMaxDim)
        throw InputError("fuzz: at most " + std::to_string(kMaxDim) + " input components, the system has " +
                         std::to_string(d));
    const ConsistencyChecker checker(m, o.velocities, o.max_rel_error, o.restitution, o.cone);
    // Every finding is classified (law-level or solver-level) when a reference law is given.
    auto note = [&](Partial& part, Finding f) {
        classify(f, o.reference, checker, m, o.velocities);
        record(part, std::move(f), o.keep);
    };
    // Every property of one answer, the distance to the reference law included.
    auto checked = [&](const double* x, const double* y) {
        auto findings = checker.check(x, y);
        if (o.reference)
            if (auto f = checker.reference(x, y, *o.reference))
                findings.push_back(std::move(*f));
        return findings;
    };
    // A nondeterministic answer's replay: the input twice, in one run of the implementation.
    auto twice = [&](const Finding& f) {
        std::string s = o.replay_prefix;
        for (int rep = 0; rep < 2; ++rep)
            for (double x : f.input)
                s += " " + hex(x);
        return s;
    };
    // An implementation's failure at input x (answer y): counted, or, when it answered x
    // differently twice, its own finding. False when it answered (status ok).
    auto failure = [&](Partial& part, ImplStatus st, const double* x, const double* y, std::uint64_t index,
                       const Implementation& im, std::size_t point) {
        switch (st) {
        case ImplStatus::ok: return false;
        case ImplStatus::crashed: ++part.sum.crashed; break;
        case ImplStatus::hung: ++part.sum.hung; break;
        case ImplStatus::malformed: ++part.sum.malformed; break;
        case ImplStatus::refused: ++part.sum.refused; break;
        case ImplStatus::skipped: break;
        case ImplStatus::nondeterministic: {
            const std::vector<double> second = im.repeated_answer(point);
            Finding f = checker.nondeterministic(x, y, second);
            f.index = index;
            f.replay = twice(f);
            note(part, std::move(f));
            // Not a reason to stop checking: each of the differing answers is checked as given.
            for (const double* answer : {y, second.size() == d ? second.data() : nullptr}) {
                if (!answer)
                    continue;
                for (auto& g : checked(x, answer)) {
                    g.index = index;
                    g.replay = twice(g);
                    note(part, std::move(g));
                }
            }
            break;
        }
        }
        return true;
    };
    // Coverage of a checked input: its pattern of approaching contacts, its decade, and the
    // reference law's pieces that contain it (exactly; for references of at most kCoveragePieces
    // pieces, a scan of them per sample). Presentation only: no verdict uses it.
    auto cover = [&](Partial& part, const double* x) {
        Vector gamma;
        part.patterns.insert(checker.approach_pattern(x, &gamma));
        double top = 0;
        for (std::size_t i = 0; i < d; ++i)
            top = std::max(top, std::fabs(x[i]));
        if (top > 0)
            part.decades.insert(static_cast<int>(std::floor(std::log10(top))));
        if (o.reference && o.reference->redundant() && gamma.size() == o.reference->C().cols()) {
            Vector basis; // the law's coordinates: gamma at the basis columns (C's are unit vectors there)
            for (const std::size_t k : o.reference->basis())
                basis.push_back(gamma[k]);
            gamma = std::move(basis);
        }
        if (o.reference && o.reference->pieces().size() <= kCoveragePieces && gamma.size() == o.reference->contacts()) {
            part.reference_hit.resize(o.reference->pieces().size(), 0);
            for (const auto p : o.reference->pieces_containing(gamma))
                part.reference_hit[p] = 1;
        }
    };
    const unsigned jobs = std::max(1u, o.jobs);
    const std::size_t block = std::max<std::size_t>(1, impl.batch_samples());
    // (samples + block - 1) / block would wrap for samples near 2^64 (reliability round four, 5)
    const std::uint64_t blocks = o.samples / block + (o.samples % block != 0 ? 1 : 0);
    std::atomic<std::uint64_t> next{0}, done{0};
    std::atomic<bool> stop{false};
    std::vector<Partial> partials(jobs);
    std::vector<std::unique_ptr<Implementation>> impls;
    for (unsigned j = 0; j < jobs; ++j) {
        impls.push_back(impl.clone());
        impls.back()->set_stop_flag(&stop);
    }
    // The probe: the input at rest, once, before the samples (its answer must be at rest).
    {
        std::vector<double> zero(d, 0.0), y(d, 0.0);
        ImplStatus st = ImplStatus::ok;
        impls[0]->eval(zero.data(), y.data(), nullptr, 1, &st);
        Partial& part = partials[0];
        if (st == ImplStatus::crashed || st == ImplStatus::hung || st == ImplStatus::malformed) {
            // No answer at rest: the finding at-rest, with its replay (not a reason to stop).
            Finding f;
            f.property = Property::at_rest;
            f.score = 1;
            f.input = zero;
            f.detail = st == ImplStatus::crashed ? "the implementation crashed (its process ended) on the input at rest"
                       : st == ImplStatus::hung  ? "no answer to the input at rest within the timeout"
                                                 : "the answer to the input at rest is not " + std::to_string(d) + " numbers";
            f.replay = replay_text(o.replay_prefix, f);
            note(part, std::move(f));
        } else if (!failure(part, st, zero.data(), y.data(), 0, *impls[0], 0)) {
            if (auto f = checker.at_rest(y.data())) {
                f->replay = replay_text(o.replay_prefix, *f);
                note(part, std::move(*f));
            }
        }
    }
    const auto start = std::chrono::steady_clock::now();
    auto worker = [&](unsigned j) {
        std::fesetround(FE_TONEAREST);
        Partial& part = partials[j];
        std::vector<double> in, out;
        std::vector<ImplStatus> status;
        std::vector<std::uint64_t> indices;
        std::vector<char> has_pair;
        while (!stop.load(std::memory_order_relaxed)) {
            const std::uint64_t b = next.fetch_add(1);
            if (b >= blocks)
                break;
            const std::uint64_t first = b * block, last = std::min<std::uint64_t>(o.samples, first + block);
            in.clear();
            indices.clear();
            has_pair.clear();
            std::vector<double> pa(d), pb(d);
            for (std::uint64_t i = first; i < last; ++i) {
                bool pair = false, close = false;
                consistency_sample(m, o, i, pa.data(), pb.data(), pair, close);
                if (!checker.approaching(pa.data())) {
                    ++part.sum.skipped;
                    continue;
                }
                indices.push_back(i);
                has_pair.push_back(pair);
                in.insert(in.end(), pa.begin(), pa.end());
                if (pair)
                    in.insert(in.end(), pb.begin(), pb.end());
            }
            const std::size_t points = in.size() / d;
            out.assign(in.size(), 0.0);
            status.assign(points, ImplStatus::ok);
            if (points)
                impls[j]->eval(in.data(), out.data(), nullptr, points, status.data());
            std::size_t p = 0;
            for (std::size_t s = 0; s < indices.size(); ++s) {
                const std::size_t pa_i = p++;
                const std::size_t pb_i = has_pair[s] ? p++ : pa_i;
                auto failed = [&](std::size_t q) {
                    return failure(part, status[q], &in[q * d], &out[q * d], indices[s], *impls[j], q);
                };
                if (status[pa_i] == ImplStatus::skipped)
                    continue;
                ++part.sum.samples;
                cover(part, &in[pa_i * d]);
                if (failed(pa_i))
                    continue;
                for (auto& f : checked(&in[pa_i * d], &out[pa_i * d])) {
                    f.index = indices[s];
                    f.replay = replay_text(o.replay_prefix, f);
                    note(part, std::move(f));
                }
                if (!has_pair[s] || failed(pb_i))
                    continue;
                ++part.sum.pairs;
                // The second point's answer is checked like the first's (a NaN there, an energy gain).
                for (auto& f : checked(&in[pb_i * d], &out[pb_i * d])) {
                    f.index = indices[s];
                    f.replay = replay_text(o.replay_prefix, f);
                    note(part, std::move(f));
                }
                for (auto& f : checker.check_pair(&in[pa_i * d], &out[pa_i * d], &in[pb_i * d], &out[pb_i * d],
                                                  o.nonexpansive, o.continuity)) {
                    f.index = indices[s];
                    f.replay = replay_text(o.replay_prefix, f);
                    note(part, std::move(f));
                }
            }
            done.fetch_add(last - first);
        }
    };
    // The watcher first (the time limit needs it), then the workers: those that cannot start
    // leave their blocks to the others (parallel.hpp). A worker's exception stops them all and is
    // rethrown after the joins.
    std::vector<std::exception_ptr> errors(jobs); // before any thread starts
    std::vector<std::thread> threads;
    threads.reserve(jobs); // before the watcher starts: a failure here leaves no thread to join
    std::thread watcher = start_required_thread([&] {
        while (done.load() < o.samples && !stop.load()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (o.seconds > 0 && secs >= o.seconds)
                stop = true;
            if (progress)
                progress(done.load());
            if (next.load() >= blocks)
                break;
        }
    });
    auto guarded = [&](unsigned j) {
        try {
            worker(j);
        } catch (...) {
            errors[j] = std::current_exception();
            stop = true;
        }
    };
    for (unsigned j = 1; j < jobs; ++j)
        start_thread(threads, [&guarded, j] { guarded(j); });
    guarded(0);
    for (auto& t : threads)
        t.join();
    stop = true;
    watcher.join();
    for (const auto& e : errors)
        if (e)
            std::rethrow_exception(e);

    ConsistencySummary sum;
    sum.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<Finding> examples;
    for (auto& part : partials) {
        sum.samples += part.sum.samples;
        sum.pairs += part.sum.pairs;
        sum.skipped += part.sum.skipped;
        sum.crashed += part.sum.crashed;
        sum.hung += part.sum.hung;
        sum.malformed += part.sum.malformed;
        sum.refused += part.sum.refused;
        for (std::size_t p = 0; p < kProperties; ++p) {
            auto& into = sum.properties[p];
            const auto& from = part.sum.properties[p];
            into.count += from.count;
            into.projections += from.projections;
            into.law += from.law;
            into.solver += from.solver;
            if (from.worst_solver && (!into.worst_solver || from.worst_solver->off > into.worst_solver->off ||
                                      (from.worst_solver->off == into.worst_solver->off &&
                                       from.worst_solver->index < into.worst_solver->index)))
                into.worst_solver = from.worst_solver;
            if (from.worst && (!into.worst || from.worst->score > into.worst->score ||
                               (from.worst->score == into.worst->score && from.worst->index < into.worst->index)))
                into.worst = from.worst;
        }
        for (auto& f : part.examples)
            examples.push_back(std::move(f));
    }
    std::stable_sort(examples.begin(), examples.end(), [](const Finding& a, const Finding& b) { return a.index < b.index; });
    if (examples.size() > o.keep)
        examples.resize(o.keep);
    sum.examples = std::move(examples);
    std::set<std::uint64_t> patterns;
    std::set<int> decades;
    std::vector<char> hit(o.reference && o.reference->pieces().size() <= kCoveragePieces ? o.reference->pieces().size() : 0, 0);
    for (const auto& part : partials) {
        patterns.insert(part.patterns.begin(), part.patterns.end());
        decades.insert(part.decades.begin(), part.decades.end());
        for (std::size_t p = 0; p < part.reference_hit.size() && p < hit.size(); ++p)
            hit[p] = hit[p] || part.reference_hit[p];
    }
    patterns.erase(0); // an input with no approaching contact is skipped, never checked
    sum.patterns_hit = patterns.size();
    sum.patterns = m.normals <= 20 ? (std::uint64_t{1} << m.normals) - 1 : 0;
    sum.decades = decades.size();
    if (!decades.empty()) {
        sum.decade_lo = *decades.begin();
        sum.decade_hi = *decades.rbegin();
    }
    // Only pieces with an approaching input count: a cone with every ray's normal components
    // >= 0 holds no input the run may check.
    for (std::size_t p = 0; p < hit.size(); ++p) {
        const Piece& piece = o.reference->pieces()[p];
        bool approaches = false;
        for (std::size_t r = 0; r < piece.R.cols() && !approaches; ++r) {
            const Vector ray = o.reference->redundant() ? transpose(o.reference->C()) * piece.R.column(r) : piece.R.column(r);
            for (std::size_t k = 0; k < m.normals && !approaches; ++k)
                approaches = sign_of(ray[k]) == Sign::negative;
        }
        if (approaches) {
            ++sum.reference_pieces;
            sum.reference_pieces_hit += hit[p] ? 1 : 0;
        }
    }
    return sum;
}

} // namespace impactcert::fuzz
