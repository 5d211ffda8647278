// SPDX-License-Identifier: GPL-3.0-or-later
// The classical simultaneous impact laws, derived exactly (SPEC section 8; derive.hpp).
//
// Newton-type: gamma+ = gamma- + G Lambda, 0 <= Lambda _|_ gamma+ + E rho(gamma-) >= 0. With
// q = D gamma- (D = I + E on the contacts where restitution applies, 1 elsewhere) this is the
// LCP w = q + G Lambda, 0 <= Lambda _|_ w >= 0. G is positive definite (a P-matrix), so for every
// q there is exactly one solution, and the complementary cones {q : Lambda_J = -G_JJ^-1 q_J >= 0,
// w_k >= 0 outside J} cover the space with disjoint interiors. On each, everything is linear in
// gamma-: Lambda_J = -G_JJ^-1 D_J gamma-, gamma+ = (I - G_:J G_JJ^-1 D_J) gamma-. With restitution
// on approaching contacts only, D depends on the orthant of gamma-, so the regions are the
// orthants cut by the complementary cones (proofs/README.md, "Classical laws").
// Poisson-type: the compression LCP (q = gamma-) and, on each of its regions, the expansion LCP
// (q' = gamma_c + G E Lambda_c), both linear in gamma- on the region: regions are pairs of
// active sets.
#include "derive/derive.hpp"

#include "derive/derive_regions.hpp"
#include "base/errors.hpp"

namespace impactcert {

using namespace derive_detail;

RestitutionOn parse_restitution_on(const std::string& text) {
    if (text == "all")
        return RestitutionOn::all;
    if (text == "approaching")
        return RestitutionOn::approaching;
    throw InputError("--restitution-on: expected all or approaching, got \"" + text + "\"");
}

namespace {

std::vector<std::size_t> members(std::size_t mask, std::size_t c) {
    std::vector<std::size_t> out;
    for (std::size_t k = 0; k < c; ++k)
        if (mask & (std::size_t{1} << k))
            out.push_back(k);
    return out;
}

std::string set_text(const std::vector<std::size_t>& set) {
    if (set.empty())
        return "0";
    std::string s;
    for (auto k : set)
        s += std::to_string(k + 1);
    return s;
}

// The LCP w = A gamma + G Lambda, 0 <= Lambda _|_ w >= 0, on the active set J (Lambda zero
// outside J, w zero on J), as linear maps of gamma: Lambda = L gamma (c x c, rows outside J
// zero), w = (A + G L) gamma. The region is {L_J gamma >= 0, w_k >= 0 outside J}.
struct Active {
    Matrix L, w;
    std::vector<Vector> constraints;
};

Active on_active_set(const Matrix& G, const Matrix& A, const std::vector<std::size_t>& J) {
    const std::size_t c = G.rows();
    Active out;
    out.L = Matrix(c, c);
    if (!J.empty()) {
        Matrix GJJ(J.size(), J.size());
        for (std::size_t i = 0; i < J.size(); ++i)
            for (std::size_t l = 0; l < J.size(); ++l)
                GJJ(i, l) = G(J[i], J[l]);
        const auto inv = inverse(GJJ); // a principal submatrix of a positive definite G
        if (!inv)
            throw std::logic_error("classical law: singular principal submatrix of G");
        for (std::size_t i = 0; i < J.size(); ++i)
            for (std::size_t col = 0; col < c; ++col) {
                Rational x;
                for (std::size_t l = 0; l < J.size(); ++l)
                    x -= (*inv)(i, l) * A(J[l], col);
                out.L(J[i], col) = x;
            }
    }
    out.w = A + G * out.L;
    std::vector<bool> in(c, false);
    for (auto k : J)
        in[k] = true;
    for (std::size_t k = 0; k < c; ++k)
        out.constraints.push_back(in[k] ? out.L.row(k) : out.w.row(k));
    return out;
}

Matrix diagonal(const Vector& d) {
    Matrix D(d.size(), d.size());
    for (std::size_t k = 0; k < d.size(); ++k)
        D(k, k) = d[k];
    return D;
}

Mechanics validated(const ClassicalOptions& o, bool poisson) {
    const Mechanics m = make_mechanics(o);
    const std::size_t c = m.contacts();
    const std::size_t limit = poisson ? kMaxPoissonContacts
                              : o.on == RestitutionOn::approaching ? kMaxApproachingContacts
                                                                   : kMaxNewtonContacts;
    const std::string kind = poisson ? "the Poisson law" : o.on == RestitutionOn::approaching ? "the Newton law with restitution on approaching contacts" : "the Newton law";
    if (c > limit)
        throw InputError("derive: at most " + std::to_string(limit) + " contacts for " + kind + " (" + std::to_string(c) +
                         " given): its regions are enumerated over active sets, 2^c or 4^c of them");
    if (o.restitution.size() != c)
        throw InputError("--restitution: expected one value or " + std::to_string(c) + " (one per contact), got " +
                         std::to_string(o.restitution.size()));
    for (std::size_t k = 0; k < c; ++k)
        if (sign_of(o.restitution[k]) == Sign::negative || o.restitution[k] > Rational(1))
            throw InputError("--restitution: contact " + std::to_string(k + 1) + " must be in [0, 1], got " +
                             to_string(o.restitution[k]));
    check_bits(m.G, o.max_bits, "G = W^T M^-1 W");
    return m;
}

Law head(const ClassicalOptions& o, const std::string& kind) {
    Law law;
    const bool plain_chain = !o.M && !o.W;
    law.name = kind + "-" + (plain_chain ? std::to_string(o.masses.size()) + "-balls" : o.name);
    law.masses = o.masses;
    law.M = o.M;
    law.W = o.W;
    law.velocity_names = o.velocity_names;
    law.contact_names = o.contact_names;
    return law;
}

// Single impacts: the first piece whose matrix is the two-body impact at contact k.
void declare_single_impacts(Law& law, const Matrix& G, const std::vector<Rational>& e) {
    for (std::size_t k = 0; k < G.rows(); ++k) {
        const Matrix Qk = two_body_impact(G, k, e[k]);
        for (const auto& p : law.pieces)
            if (p.Q == Qk) {
                law.single_impacts.push_back(SingleImpactDecl{p.name, static_cast<int>(k + 1), e[k]});
                break;
            }
    }
}

// The pieces from the regions, the single impacts, and the outcomes by the independent
// simulation in ball velocities (or the ones given).
void finish(Law& law, std::vector<Region>& regions, const Mechanics& mech, const ClassicalOptions& o,
            const std::function<Vector(const Vector&)>& simulate) {
    RegionBudget budget(o.max_memory_mb);
    for (const auto& r : regions)
        budget.add(RegionBudget::bytes_of(r), "regions");
    add_region_pieces(regions, mech.contacts(), law, {}, &budget);
    declare_single_impacts(law, mech.G, o.restitution);
    declare_outcomes(law, o.outcomes_override, [&](const Vector& u) -> std::optional<Vector> { return simulate(u); });
}

} // namespace

Law derive_newton(const ClassicalOptions& o) {
    const Mechanics mech = validated(o, false);
    const std::size_t c = mech.contacts();
    const PplScope ppl;
    const Matrix I = Matrix::identity(c);
    std::vector<Region> regions;
    const bool approaching = o.on == RestitutionOn::approaching;
    const std::size_t orthants = approaching ? (std::size_t{1} << c) : 1;
    for (std::size_t sigma = 0; sigma < orthants; ++sigma) {
        // sigma: the contacts that approach (gamma_k <= 0); restitution applies there only.
        std::vector<Vector> orthant;
        Vector d(c, Rational(1));
        for (std::size_t k = 0; k < c; ++k) {
            const bool applies = !approaching || (sigma & (std::size_t{1} << k));
            if (applies)
                d[k] += o.restitution[k];
            if (approaching)
                orthant.push_back((sigma & (std::size_t{1} << k)) ? Rational(-1) * unit_vector(c, k) : unit_vector(c, k));
        }
        const Matrix D = diagonal(d);
        for (std::size_t mask = 0; mask < (std::size_t{1} << c); ++mask) {
            const auto J = members(mask, c);
            const Active a = on_active_set(mech.G, D, J);
            std::vector<Vector> constraints = orthant;
            constraints.insert(constraints.end(), a.constraints.begin(), a.constraints.end());
            PPL::C_Polyhedron cell = cone_of(c, constraints);
            if (!full_dimensional(cell, c))
                continue;
            std::vector<std::size_t> R; // contacts of J where restitution applies
            for (auto k : J)
                if (!approaching || (sigma & (std::size_t{1} << k)))
                    R.push_back(k);
            std::string name = J.empty() ? "free" : "J" + set_text(J);
            std::vector<std::size_t> key = J;
            if (!J.empty() && R != J) {
                name += "/e" + set_text(R);
                key.push_back(c);
                key.insert(key.end(), R.begin(), R.end());
            }
            Matrix map = I + mech.G * a.L;
            check_bits(map, o.max_bits, "the map of " + name);
            regions.push_back({cell, std::move(map), key, name});
        }
    }
    Law law = head(o, approaching ? "newton-approaching" : "newton");
    law.description = std::string("Newton-type simultaneous impact law (restitution on ") +
                      (approaching ? "approaching contacts only, plain non-penetration on the others: what the "
                                     "sequential-impulse and LCP solvers of physics engines compute"
                                   : "every contact: the classical inequality law") +
                      ") of " + system_text(o) + ", restitution " + list_text(o.restitution) +
                      "; derived by impactcert derive newton. Pieces are named by the contacts that carry an impulse "
                      "(J13: contacts 1 and 3; free: none); /e1 lists the contacts of J where restitution applies "
                      "when not all of them (/e0: none); parts of a triangulated region by .1, .2, ...";
    finish(law, regions, mech, o, [&](const Vector& u) { return simulate_newton(mech, o.restitution, o.on, u); });
    return law;
}

Law derive_poisson(const ClassicalOptions& o) {
    const Mechanics mech = validated(o, true);
    const std::size_t c = mech.contacts();
    const PplScope ppl;
    const Matrix I = Matrix::identity(c);
    Vector e = o.restitution;
    const Matrix E = diagonal(e);
    std::vector<Region> regions;
    for (std::size_t jmask = 0; jmask < (std::size_t{1} << c); ++jmask) {
        const auto J = members(jmask, c);
        const Active comp = on_active_set(mech.G, I, J); // gamma_c = comp.w gamma-, Lambda_c = comp.L gamma-
        PPL::C_Polyhedron compression = cone_of(c, comp.constraints);
        if (!full_dimensional(compression, c))
            continue;
        const Matrix q = comp.w + mech.G * E * comp.L; // gamma_c + G E Lambda_c
        for (std::size_t kmask = 0; kmask < (std::size_t{1} << c); ++kmask) {
            const auto K = members(kmask, c);
            const Active exp = on_active_set(mech.G, q, K); // gamma+ = exp.w gamma-
            PPL::C_Polyhedron cell = compression;
            for (const auto& a : exp.constraints)
                if (!is_zero(a))
                    cell.add_constraint(nonneg(a));
            if (!full_dimensional(cell, c))
                continue;
            std::vector<std::size_t> key = J;
            key.push_back(c);
            key.insert(key.end(), K.begin(), K.end());
            const std::string name = J.empty() && K.empty() ? "free" : "C" + set_text(J) + "/E" + set_text(K);
            check_bits(exp.w, o.max_bits, "the map of " + name);
            regions.push_back({cell, exp.w, key, name});
        }
    }
    // Restitution 0 makes the expansion LCP degenerate (q_J = 0 where compression ended): several
    // expansion sets give one cell and one map. Overlaps are removed before the pieces are written.
    remove_overlaps(regions, c);
    Law law = head(o, "poisson");
    law.description = "Poisson-type simultaneous impact law (compression, then expansion with Lambda_e >= E Lambda_c) of " +
                      system_text(o) + ", restitution " + list_text(o.restitution) +
                      "; derived by impactcert derive poisson. Pieces are named by the active sets of the compression "
                      "and expansion phases (C12/E1: contacts 1 and 2 compress, contact 1 carries an extra impulse in "
                      "expansion; 0: none; free: no impact); parts of a triangulated region by .1, .2, ...";
    finish(law, regions, mech, o, [&](const Vector& u) { return simulate_poisson(mech, o.restitution, u); });
    return law;
}

// ---- Independent solutions in ball velocities.

namespace {

// The LCP in ball velocities: find u and Lambda >= 0 with M u = M u0 + W Lambda and
// 0 <= Lambda _|_ W^T u + s >= 0, by enumerating active sets J: the square system
// [M, -W_J; W_J^T, 0] [u; Lambda_J] = [M u0; -s_J] is non-singular (M positive definite, W_J of
// full column rank); the first J whose solution satisfies the inequalities is the solution.
std::pair<Vector, Vector> ball_lcp(const Mechanics& m, const Vector& u0, const Vector& s) {
    const std::size_t n = m.balls(), c = m.contacts();
    const Vector Mu0 = m.M * u0;
    for (std::size_t mask = 0; mask < (std::size_t{1} << c); ++mask) {
        const auto J = members(mask, c);
        const std::size_t N = n + J.size();
        Matrix A(N, N);
        Vector b(N);
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t j = 0; j < n; ++j)
                A(i, j) = m.M(i, j);
            for (std::size_t l = 0; l < J.size(); ++l)
                A(i, n + l) = -m.W(i, J[l]);
            b[i] = Mu0[i];
        }
        for (std::size_t l = 0; l < J.size(); ++l) {
            for (std::size_t j = 0; j < n; ++j)
                A(n + l, j) = m.W(j, J[l]);
            b[n + l] = -s[J[l]];
        }
        const auto x = solve(A, b);
        if (!x)
            continue;
        Vector u(x->begin(), x->begin() + static_cast<std::ptrdiff_t>(n));
        Vector lambda(c);
        bool ok = true;
        for (std::size_t l = 0; l < J.size(); ++l) {
            lambda[J[l]] = (*x)[n + l];
            ok = ok && sign_of(lambda[J[l]]) != Sign::negative;
        }
        std::vector<bool> in(c, false);
        for (auto k : J)
            in[k] = true;
        for (std::size_t k = 0; k < c && ok; ++k)
            if (!in[k])
                ok = sign_of(dot(m.W.column(k), u) + s[k]) != Sign::negative;
        if (ok)
            return {u, lambda};
    }
    throw std::logic_error("ball_lcp: no active set solves the LCP (G is not positive definite?)");
}

} // namespace

Vector simulate_newton(const Mechanics& m, const std::vector<Rational>& e, RestitutionOn on, const Vector& u_minus) {
    const std::size_t c = m.contacts();
    Vector s(c);
    for (std::size_t k = 0; k < c; ++k) {
        const Rational gamma = dot(m.W.column(k), u_minus);
        const bool applies = on == RestitutionOn::all || sign_of(gamma) == Sign::negative;
        if (applies)
            s[k] = e[k] * gamma;
    }
    return ball_lcp(m, u_minus, s).first;
}

Vector simulate_poisson(const Mechanics& m, const std::vector<Rational>& e, const Vector& u_minus) {
    const std::size_t c = m.contacts();
    const auto [uc, lambda_c] = ball_lcp(m, u_minus, Vector(c));
    Vector impulse(c);
    for (std::size_t k = 0; k < c; ++k)
        impulse[k] = e[k] * lambda_c[k];
    const Vector u0 = uc + m.M_inv * (m.W * impulse);
    return ball_lcp(m, u0, Vector(c)).first;
}

} // namespace impactcert
