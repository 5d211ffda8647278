// SPDX-License-Identifier: GPL-3.0-or-later
// Consistency of a black-box map on dependent contact columns (proofs/README.md, "Consistency on
// dependent columns"): the impulses are not unique, so kinetic, the friction cone and Coulomb's
// law ask whether *some* impulse Lambda of the right kind moves the velocities close to the
// answer. Each is the least t >= 0 of a linear program in (Lambda, t), exact (PPL's MIP_Problem
// over GMP): M^-1 W Lambda within t w_i of the answer's change in every coordinate i, with
// w_i >= sqrt((M^-1)_ii), so that the ball of radius t in the metric M lies inside the box.
#include "fuzz/consistency_dependent.hpp"

#include "derive/derive_regions.hpp" // PplScope, PPL

#include <mutex>

namespace impactcert::fuzz {

namespace {

namespace PPL = Parma_Polyhedra_Library;
using derive_detail::PplScope;

// The affine constraint a . z + b (>= 0, or == 0) with integer coefficients (a positive multiple).
PPL::Linear_Expression affine(const Vector& a, const Rational& b) {
    mpz_class den = 1;
    auto lcm_with = [&](const Rational& q) {
        const mpz_class d(mpq_denref(q.mpq()));
        den = lcm(den, d);
    };
    for (const auto& x : a)
        lcm_with(x);
    lcm_with(b);
    PPL::Linear_Expression e;
    for (std::size_t k = 0; k < a.size(); ++k)
        if (sign_of(a[k]) != Sign::zero) {
            const mpz_class num(mpq_numref(a[k].mpq())), d(mpq_denref(a[k].mpq()));
            e += PPL::Coefficient(num * (den / d)) * PPL::Variable(static_cast<PPL::dimension_type>(k));
        }
    const mpz_class num(mpq_numref(b.mpq())), d(mpq_denref(b.mpq()));
    e += PPL::Coefficient(num * (den / d));
    return e;
}

std::mutex& ppl_lock() {
    static std::mutex m; // PPL is used from one thread at a time
    return m;
}

} // namespace

DependentFit::DependentFit(const Mechanics& m) : m_(m), d_(m.contacts()), n_(m.balls()) {
    V_ = m.M_inv * m.W;
    for (std::size_t i = 0; i < n_; ++i)
        w_.push_back(sqrt_up(m.M_inv(i, i)));
}

Rational DependentFit::least(const Vector& du, const Vector& gamma_minus, Kind kind, const std::string& modes) const {
    // Variables: Lambda_0 .. Lambda_{d-1}, then t (index d). PPL initialised, its rounding mode
    // set, and one thread in it at a time, from the first expression on.
    const std::lock_guard<std::mutex> lock(ppl_lock());
    const PplScope scope;
    const std::size_t t = d_;
    PPL::Constraint_System cs;
    auto row = [&](Vector a, const Rational& b) { return affine(a, b); };
    for (std::size_t i = 0; i < n_; ++i) {
        Vector a(d_ + 1);
        for (std::size_t k = 0; k < d_; ++k)
            a[k] = V_(i, k);
        // t w_i - (V Lambda)_i + du_i >= 0 and t w_i + (V Lambda)_i - du_i >= 0
        Vector lo = Rational(-1) * a, hi = a;
        lo[t] = w_[i];
        hi[t] = w_[i];
        cs.insert(row(lo, du[i]) >= 0);
        cs.insert(row(hi, -du[i]) >= 0);
    }
    cs.insert(PPL::Variable(static_cast<PPL::dimension_type>(t)) >= 0);
    auto unit = [&](std::size_t k, const Rational& s) {
        Vector a(d_ + 1);
        a[k] = s;
        return a;
    };
    for (std::size_t k = 0; k < m_.normals; ++k)
        cs.insert(row(unit(k, Rational(1)), Rational(0)) >= 0);
    if (kind != Kind::kinetic)
        for (std::size_t j = 0; j < m_.tangents.size(); ++j) {
            const Tangent& tg = m_.tangents[j];
            const std::size_t T = m_.normals + j;
            Vector up = unit(tg.contact, tg.mu), down = unit(tg.contact, tg.mu);
            up[T] = Rational(-1);
            down[T] = Rational(1);
            cs.insert(row(up, Rational(0)) >= 0); // mu Lambda_N - Lambda_T >= 0
            cs.insert(row(down, Rational(0)) >= 0);
            if (kind != Kind::coulomb)
                continue;
            // xi_T = (1 + e_T) gamma_T- + (G Lambda)_T at the candidate answer
            Vector xi(d_ + 1);
            for (std::size_t k = 0; k < d_; ++k)
                xi[k] = m_.G(T, k);
            const Rational xi0 = (Rational(1) + tg.e_T) * gamma_minus[T];
            const char mode = modes.at(j);
            if (mode == 's') {
                cs.insert(row(xi, xi0) == 0);
            } else if (mode == 'f') { // Lambda_T = -mu Lambda_N, xi_T >= 0
                cs.insert(row(down, Rational(0)) == 0);
                cs.insert(row(xi, xi0) >= 0);
            } else { // 'b': Lambda_T = +mu Lambda_N, xi_T <= 0
                cs.insert(row(up, Rational(0)) == 0);
                cs.insert(row(Rational(-1) * xi, -xi0) >= 0);
            }
        }
    PPL::MIP_Problem lp(static_cast<PPL::dimension_type>(d_ + 1), cs,
                        PPL::Linear_Expression(PPL::Variable(static_cast<PPL::dimension_type>(t))),
                        PPL::MINIMIZATION);
    if (lp.solve() != PPL::OPTIMIZED_MIP_PROBLEM)
        return Rational(-1); // infeasible (a Coulomb mode whose slip signs no impulse meets)
    PPL::Coefficient num, den;
    lp.optimal_value(num, den);
    Rational out(CGAL::Gmpz(mpz_class(num).get_mpz_t()));
    out /= Rational(CGAL::Gmpz(mpz_class(den).get_mpz_t()));
    return out;
}

Rational DependentFit::least_coulomb(const Vector& du, const Vector& gamma_minus, const Rational& enough) const {
    const std::size_t tangents = m_.tangents.size();
    // First the modes of the answer's own slip signs (xi_T at u- + du), the likeliest to fit.
    std::string own(tangents, 's');
    for (std::size_t j = 0; j < tangents; ++j) {
        const std::size_t T = m_.normals + j;
        Rational xi = (Rational(1) + m_.tangents[j].e_T) * gamma_minus[T];
        for (std::size_t i = 0; i < n_; ++i)
            xi += m_.W(i, T) * du[i];
        own[j] = sign_of(xi) == Sign::positive ? 'f' : sign_of(xi) == Sign::negative ? 'b' : 's';
    }
    std::optional<Rational> best;
    if (const Rational t = least(du, gamma_minus, Kind::coulomb, own); sign_of(t) != Sign::negative) {
        if (t <= enough)
            return t;
        best = t;
    }
    std::string modes(tangents, 's');
    while (true) {
        const Rational t = modes == own ? Rational(-1) : least(du, gamma_minus, Kind::coulomb, modes);
        if (sign_of(t) != Sign::negative && (!best || t < *best))
            best = t;
        if (best && *best <= enough)
            return *best; // within the tolerance: the least is not needed
        std::size_t j = 0;
        for (; j < tangents; ++j) {
            if (modes[j] == 's') {
                modes[j] = 'f';
                break;
            }
            if (modes[j] == 'f') {
                modes[j] = 'b';
                break;
            }
            modes[j] = 's';
        }
        if (j == tangents)
            break;
    }
    if (!best) // Lambda = 0 in the mode of the slip signs of gamma- itself is always feasible
        throw std::logic_error("consistency: no Coulomb mode is feasible at any distance");
    return *best;
}

} // namespace impactcert::fuzz
