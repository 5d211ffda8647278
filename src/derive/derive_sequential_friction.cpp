// SPDX-License-Identifier: GPL-3.0-or-later
// The sequential impact law with Coulomb friction (SPEC section 9; derive.hpp), derived exactly.
//
// While some normal contact approaches (gamma_Nk < 0), the rule of section 7 picks one, compared
// on the normals only, and the one-contact Newton law with friction acts at it: with J its normal
// and its tangents, Lambda_J solves xi_N = (1 + e_k) gamma_N + (G Lambda)_N = 0 and, per tangent,
// stick (xi_T = (1 + e_T) gamma_T + (G Lambda)_T = 0, |Lambda_T| <= mu Lambda_N), slip forward
// (Lambda_T = -mu Lambda_N, xi_T >= 0) or slip backward (Lambda_T = +mu Lambda_N, xi_T <= 0), with
// Lambda_N >= 0 (open is impossible: the contact approaches). Each mode with an invertible system
// gives Lambda_J = L gamma and the step gamma <- (I + G_:J L) gamma on a polyhedral cone of the
// current gamma; a word is a sequence of (contact, modes) and its region the conjunction of the
// rule's and the modes' conditions along it, as for the frictionless law. The written law is
// single-valued exactly when the regions tile R^d: derive decides it with the fan of the law it
// writes (proofs/README.md, "Friction"), and otherwise exits 1 with the fan's point.
#include "derive/derive.hpp"

#include "derive/derive_regions.hpp"
#include "base/errors.hpp"
#include "prover/obligations.hpp"

namespace impactcert {

using namespace derive_detail;

namespace {

// One mode of the one-contact law at normal k: the step's map and its conditions (linear forms in
// the current gamma that must be >= 0).
struct Step {
    std::string letters; // one per tangent: s, f, b
    Matrix map;
    std::vector<Vector> conditions;
};

std::vector<Step> contact_steps(const Mechanics& m, std::size_t k, const Rational& e) {
    const std::size_t d = m.contacts(), N = m.normals;
    std::vector<std::size_t> tangents; // indices into m.tangents
    for (std::size_t j = 0; j < m.tangents.size(); ++j)
        if (m.tangents[j].contact == k)
            tangents.push_back(j);
    std::vector<std::size_t> J{k};
    for (auto j : tangents)
        J.push_back(N + j);
    const std::size_t r = J.size();
    std::vector<std::string> words{""};
    for (std::size_t t = 0; t < tangents.size(); ++t) {
        std::vector<std::string> next;
        for (const auto& w : words)
            for (const char* l : {"s", "f", "b"})
                next.push_back(w + l);
        words = next;
    }
    std::vector<Step> out;
    for (const auto& w : words) {
        // A Lambda_J + B gamma = 0, rows: the normal's xi, then each tangent's equation.
        Matrix A(r, r), B(r, d);
        for (std::size_t c = 0; c < r; ++c)
            A(0, c) = m.G(k, J[c]);
        B(0, k) = Rational(1) + e;
        for (std::size_t t = 0; t < tangents.size(); ++t) {
            const std::size_t row = t + 1, T = N + tangents[t];
            const Rational& mu = m.tangents[tangents[t]].mu;
            if (w[t] == 's') {
                for (std::size_t c = 0; c < r; ++c)
                    A(row, c) = m.G(T, J[c]);
                B(row, T) = Rational(1) + m.tangents[tangents[t]].e_T;
            } else {
                A(row, row) = 1;
                A(row, 0) = w[t] == 'f' ? mu : -mu;
            }
        }
        const auto A_inv = inverse(A);
        if (!A_inv)
            continue; // its solutions lie in a lower-dimensional set of gamma
        const Matrix L = Rational(-1) * (*A_inv * B); // r x d
        Step step;
        step.letters = w;
        step.map = Matrix::identity(d);
        for (std::size_t i = 0; i < d; ++i)
            for (std::size_t c = 0; c < r; ++c)
                for (std::size_t col = 0; col < d; ++col)
                    step.map(i, col) += m.G(i, J[c]) * L(c, col);
        step.conditions.push_back(L.row(0)); // Lambda_N >= 0
        for (std::size_t t = 0; t < tangents.size(); ++t) {
            const std::size_t T = N + tangents[t];
            const Rational& mu = m.tangents[tangents[t]].mu;
            if (w[t] == 's') {
                step.conditions.push_back(mu * L.row(0) - L.row(t + 1));
                step.conditions.push_back(mu * L.row(0) + L.row(t + 1));
            } else {
                // xi_T = (1 + e_T) gamma_T + (G Lambda)_T = e_T gamma_T + (map gamma)_T
                Vector xi = step.map.row(T);
                xi[T] += m.tangents[tangents[t]].e_T;
                step.conditions.push_back(w[t] == 'f' ? xi : Rational(-1) * xi);
            }
        }
        out.push_back(std::move(step));
    }
    return out;
}

std::string letter(std::size_t k, const std::string& modes, std::size_t normals) {
    return (normals > 9 ? "-" : "") + std::to_string(k + 1) + modes;
}

} // namespace

std::optional<Vector> simulate_sequential_friction(const Mechanics& m, const std::vector<Rational>& restitution,
                                                   ImpactRule rule, Vector u, std::size_t limit) {
    // In body velocities, without G: the one-contact law of the picked contact by its modes.
    const std::size_t N = m.normals;
    std::vector<Mechanics> one(N);
    for (std::size_t k = 0; k < N; ++k) {
        Mechanics& s = one[k];
        s.M = m.M;
        s.M_inv = m.M_inv;
        s.diagonal = m.diagonal;
        s.normals = 1;
        std::vector<Vector> cols{m.W.column(k)};
        for (std::size_t j = 0; j < m.tangents.size(); ++j)
            if (m.tangents[j].contact == k) {
                cols.push_back(m.W.column(N + j));
                s.tangents.push_back(Tangent{0, m.tangents[j].mu, m.tangents[j].e_T});
            }
        s.W = Matrix::from_columns(cols);
        s.G = transpose(s.W) * s.M_inv * s.W; // the one-contact system's own (simulate_newton_friction reads W and M)
    }
    for (std::size_t step = 0;; ++step) {
        Vector gamma(N);
        for (std::size_t k = 0; k < N; ++k)
            gamma[k] = dot(m.W.column(k), u);
        std::optional<std::size_t> k;
        for (std::size_t i = 0; i < N; ++i) {
            if (sign_of(gamma[i]) != Sign::negative)
                continue;
            if (!k || rule == ImpactRule::right_first || (rule == ImpactRule::most_negative && gamma[i] < gamma[*k]))
                k = i;
            if (rule == ImpactRule::left_first)
                break;
        }
        if (!k)
            return u;
        if (step == limit)
            return std::nullopt;
        const auto next = simulate_newton_friction(one[*k], {restitution[*k]}, RestitutionOn::all, u);
        if (!next)
            return std::nullopt;
        u = *next;
    }
}

DeriveResult derive_sequential_friction(const DeriveOptions& options, const Mechanics& mech) {
    const std::size_t d = mech.contacts(), N = mech.normals;
    const PplScope ppl;
    std::vector<std::vector<Step>> steps(N);
    for (std::size_t k = 0; k < N; ++k) {
        steps[k] = contact_steps(mech, k, options.restitution[k]);
        for (const auto& s : steps[k])
            check_bits(s.map, options.max_bits, "the impact matrix of contact " + std::to_string(k + 1) + s.letters);
    }
    DeriveResult result;
    std::vector<Region> regions;
    std::vector<Region> work;
    // key: the word as (contact, mode index) pairs flattened; name kept in Region::name.
    work.push_back({cone_of(d, {}), Matrix::identity(d), {}, ""});
    RegionBudget budget(options.max_memory_mb); // the regions found and the cells waiting
    budget.add(RegionBudget::bytes_of(work.back()), "regions");
    std::size_t nodes = 0;
    while (!work.empty()) {
        if (options.progress && ++nodes % 1024 == 0)
            options.progress("regions", regions.size(), 0);
        Region node = std::move(work.back());
        work.pop_back();
        budget.remove(RegionBudget::bytes_of(node));
        for (std::size_t branch = 0; branch <= N; ++branch) {
            PPL::C_Polyhedron cell = node.cone;
            auto add = [&](PPL::C_Polyhedron& p, const Vector& a) {
                if (!is_zero(a))
                    p.add_constraint(nonneg(a));
            };
            if (branch == N) {
                for (std::size_t j = 0; j < N; ++j)
                    add(cell, node.M.row(j));
                if (!full_dimensional(cell, d))
                    continue;
                regions.push_back({cell, node.M, node.key, node.name.empty() ? "none" : node.name});
                budget.add(RegionBudget::bytes_of(regions.back()), "regions");
                continue;
            }
            const std::size_t k = branch;
            if (is_zero(node.M.row(k)))
                continue;
            bool never = false;
            for (std::size_t j = 0; j < k; ++j)
                never = never || (options.rule == ImpactRule::most_negative && node.M.row(j) == node.M.row(k));
            if (never)
                continue;
            add(cell, Rational(-1) * node.M.row(k));
            for (std::size_t j = 0; j < N; ++j) {
                if (j == k)
                    continue;
                if (options.rule == ImpactRule::most_negative)
                    add(cell, node.M.row(j) - node.M.row(k));
                else if ((options.rule == ImpactRule::left_first && j < k) ||
                         (options.rule == ImpactRule::right_first && j > k))
                    add(cell, node.M.row(j));
            }
            if (!full_dimensional(cell, d))
                continue;
            for (std::size_t s = 0; s < steps[k].size(); ++s) {
                const Step& step = steps[k][s];
                PPL::C_Polyhedron sub = cell;
                for (const auto& c : step.conditions)
                    add(sub, transpose(node.M) * c); // c . (M gamma-) >= 0
                if (!full_dimensional(sub, d))
                    continue;
                const std::string name = node.name + letter(k, step.letters, N);
                if (node.key.size() / 2 == options.max_impacts) {
                    result.not_finite = interior_point(sub, d);
                    result.word = name;
                    return result;
                }
                auto key = node.key;
                key.push_back(k);
                key.push_back(s);
                Matrix next = step.map * node.M;
                check_bits(next, options.max_bits, "the map of word " + name);
                work.push_back({sub, std::move(next), key, name});
                budget.add(RegionBudget::bytes_of(work.back()), "regions");
            }
        }
    }
    result.regions = regions.size();
    for (const auto& region : regions)
        result.max_word = std::max(result.max_word, region.key.size() / 2);
    Law law;
    law.name = "sequential-friction-" + options.name;
    law.description = "Sequential impact law with Coulomb friction (docs/derive.md, \"Friction\") of " + system_text(options) +
                      ", normal restitution " + list_text(options.restitution) + ", rule " + to_string(options.rule) +
                      "; derived by impactcert derive sequential. Each step is the one-contact Newton law with friction "
                      "of the contact the rule picks among the approaching normals. Pieces are named by their words: "
                      "per impact the contact and one letter per tangent (s stick, f slip forward, b slip backward); "
                      "parts of a triangulated region by .1, .2, ...";
    law.masses = options.masses;
    law.M = options.M;
    law.W = options.W;
    law.velocity_names = options.velocity_names;
    law.contact_names = options.contact_names;
    law.friction = options.friction;
    add_region_pieces(regions, d, law, options.progress, &budget);
    result.peak_bytes = budget.peak();
    law.outcomes = !options.outcomes_override.empty()
                       ? options.outcomes_override
                       : unit_velocity_outcomes(mech.balls(), [&](const Vector& u) {
                             return simulate_sequential_friction(mech, options.restitution, options.rule, u,
                                                                 options.max_impacts);
                         });
    // Single-valued: the regions must tile R^d (the fan of the written law).
    if (const auto defect = tiling_defect(law)) {
        result.not_a_function = defect->gamma;
        result.not_a_function_reason = defect->reason;
        return result;
    }
    result.law = std::move(law);
    return result;
}

} // namespace impactcert
