// SPDX-License-Identifier: GPL-3.0-or-later
#include "derive/derive.hpp"

#include "derive/derive_planar.hpp"
#include "derive/derive_regions.hpp"
#include "base/errors.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>

namespace impactcert {

using namespace derive_detail;

ImpactRule parse_rule(const std::string& text) {
    if (text == "most-negative")
        return ImpactRule::most_negative;
    if (text == "left-first")
        return ImpactRule::left_first;
    if (text == "right-first")
        return ImpactRule::right_first;
    throw InputError("--rule: unknown rule \"" + text + "\" (most-negative, left-first, right-first; derive sequential also takes any)");
}

const char* to_string(ImpactRule rule) {
    switch (rule) {
    case ImpactRule::most_negative: return "most-negative";
    case ImpactRule::left_first: return "left-first";
    case ImpactRule::right_first: return "right-first";
    }
    return "?";
}

namespace {

// The contact the rule picks among the approaching ones (gamma_k < 0), or nothing.
std::optional<std::size_t> pick(ImpactRule rule, const Vector& gamma) {
    std::optional<std::size_t> k;
    for (std::size_t i = 0; i < gamma.size(); ++i) {
        if (sign_of(gamma[i]) != Sign::negative)
            continue;
        if (!k || rule == ImpactRule::right_first ||
            (rule == ImpactRule::most_negative && gamma[i] < gamma[*k]))
            k = i;
        if (rule == ImpactRule::left_first)
            break;
    }
    return k;
}

} // namespace

// Validates the process; the system is validated by make_mechanics (the caller).
void derive_detail::validate(const DeriveOptions& o, std::size_t c) {
    if (o.restitution.size() != c)
        throw InputError("--restitution: expected one value or " + std::to_string(c) +
                         " (one per contact), got " + std::to_string(o.restitution.size()));
    for (std::size_t k = 0; k < o.restitution.size(); ++k)
        if (sign_of(o.restitution[k]) == Sign::negative || o.restitution[k] > Rational(1))
            throw InputError("--restitution: contact " + std::to_string(k + 1) + " must be in [0, 1], got " +
                             to_string(o.restitution[k]));
    if (o.max_impacts == 0)
        throw InputError("--max-impacts: must be at least 1");
}

namespace {

std::string word_name(const std::vector<std::size_t>& word, std::size_t c) {
    if (word.empty())
        return "none";
    std::string s;
    for (std::size_t i = 0; i < word.size(); ++i) {
        if (c > 9 && i > 0)
            s += "-";
        s += std::to_string(word[i] + 1);
    }
    return s;
}

} // namespace

std::string word_text(const std::vector<std::size_t>& word, std::size_t contacts) {
    return word_name(word, contacts);
}

std::pair<std::vector<std::size_t>, bool> sequential_word(const System& system,
                                                          const std::vector<Rational>& restitution,
                                                          ImpactRule rule, const Vector& gamma,
                                                          std::size_t limit) {
    const Matrix G = make_mechanics(system).G;
    Vector g = gamma;
    std::vector<std::size_t> word;
    while (auto k = pick(rule, g)) {
        if (word.size() == limit)
            return {word, false};
        word.push_back(*k);
        g = two_body_impact(G, *k, restitution[*k]) * g;
    }
    return {word, true};
}

std::optional<Vector> simulate_balls(const std::vector<Rational>& m, const std::vector<Rational>& restitution,
                                     ImpactRule rule, Vector u, std::size_t limit) {
    for (std::size_t step = 0;; ++step) {
        Vector gamma(u.size() - 1);
        for (std::size_t k = 0; k + 1 < u.size(); ++k)
            gamma[k] = u[k + 1] - u[k];
        const auto k = pick(rule, gamma);
        if (!k)
            return u;
        if (step == limit)
            return std::nullopt;
        // Two balls i = k, j = k+1: the relative velocity u_i - u_j reverses with factor e; the
        // momentum m_i u_i + m_j u_j is kept.
        const std::size_t i = *k, j = *k + 1;
        const Rational closing = u[i] - u[j];
        const Rational e = restitution[i];
        const Rational total = m[i] + m[j];
        u[i] -= (Rational(1) + e) * m[j] / total * closing;
        u[j] += (Rational(1) + e) * m[i] / total * closing;
    }
}

std::optional<Vector> simulate_balls(const System& system, const std::vector<Rational>& restitution,
                                     ImpactRule rule, Vector u, std::size_t limit) {
    if (!system.M && !system.W)
        return simulate_balls(system.masses, restitution, rule, std::move(u), limit);
    // Any system: the impulse at contact k alone, in ball velocities. With w = W e_k and
    // gamma_k = w . u, the impulse lambda w (through M^-1) that turns gamma_k into -e gamma_k is
    // lambda = -(1 + e) gamma_k / (w . M^-1 w).
    const Mechanics m = make_mechanics(system);
    const std::size_t c = m.contacts();
    std::vector<Vector> w(c), Minv_w(c);
    for (std::size_t k = 0; k < c; ++k) {
        w[k] = m.W.column(k);
        Minv_w[k] = m.M_inv * w[k];
    }
    for (std::size_t step = 0;; ++step) {
        Vector gamma(c);
        for (std::size_t k = 0; k < c; ++k)
            gamma[k] = dot(w[k], u);
        const auto k = pick(rule, gamma);
        if (!k)
            return u;
        if (step == limit)
            return std::nullopt;
        const Rational lambda = -(Rational(1) + restitution[*k]) * gamma[*k] / dot(w[*k], Minv_w[*k]);
        u = u + lambda * Minv_w[*k];
    }
}

std::size_t entry_bits(const Matrix& m) {
    std::size_t bits = 0;
    for (std::size_t i = 0; i < m.rows(); ++i)
        for (std::size_t j = 0; j < m.cols(); ++j) {
            const auto& q = m(i, j);
            bits = std::max(bits, mpz_sizeinbase(mpq_numref(q.mpq()), 2) + mpz_sizeinbase(mpq_denref(q.mpq()), 2));
        }
    return bits;
}

namespace derive_detail {

void check_bits(const Matrix& m, std::size_t max_bits, const std::string& what) {
    const std::size_t bits = entry_bits(m);
    if (bits > max_bits)
        throw DeriveLimit(what + " has an entry of " + std::to_string(bits) + " bits, more than " + std::to_string(max_bits) +
                          " (raise it with --max-bits)");
}

std::string list_text(const std::vector<Rational>& xs) {
    std::string s;
    for (std::size_t i = 0; i < xs.size(); ++i)
        s += (i ? "," : "") + to_string(xs[i]);
    return s;
}

std::vector<OutcomeDecl> classical_experiments(std::size_t n) {
    auto ball_vector = [&](std::initializer_list<std::pair<std::size_t, int>> entries) {
        Vector u(n);
        for (const auto& [i, v] : entries)
            u[i] = v;
        return u;
    };
    std::vector<OutcomeDecl> out;
    out.push_back({"one ball in from the left", ball_vector({{0, 1}}), {}});
    if (n >= 2) {
        out.push_back({"two balls in from the left", ball_vector({{0, 1}, {1, 1}}), {}});
        out.push_back({"one ball from each side", ball_vector({{0, 1}, {n - 1, -1}}), {}});
    }
    out.push_back({"one ball in from the right", ball_vector({{n - 1, -1}}), {}});
    out.push_back({"all moving together", Vector(n, Rational(1)), {}});
    return out;
}

// The sign of det(a) by fraction-free (Bareiss) elimination when every entry is an integer
// (derived rays are primitive, experiments integral): no gcd; else by determinant().
Sign integer_determinant_sign(const Matrix& a) {
    const std::size_t n = a.rows();
    std::vector<mpz_class> m(n * n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            if (mpz_cmp_ui(mpq_denref(a(i, j).mpq()), 1) != 0)
                return sign_of(determinant(a));
            m[i * n + j] = mpz_class(mpq_numref(a(i, j).mpq()));
        }
    int sign = 1;
    mpz_class prev = 1;
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t p = k;
        while (p < n && m[p * n + k] == 0)
            ++p;
        if (p == n)
            return Sign::zero;
        if (p != k) {
            for (std::size_t j = 0; j < n; ++j)
                std::swap(m[p * n + j], m[k * n + j]);
            sign = -sign;
        }
        for (std::size_t i = k + 1; i < n; ++i) {
            for (std::size_t j = k + 1; j < n; ++j) {
                m[i * n + j] = m[k * n + k] * m[i * n + j] - m[i * n + k] * m[k * n + j];
                mpz_divexact(m[i * n + j].get_mpz_t(), m[i * n + j].get_mpz_t(), prev.get_mpz_t());
            }
            m[i * n + k] = 0;
        }
        prev = m[k * n + k];
    }
    return sgn(m[(n - 1) * n + (n - 1)]) * sign > 0 ? Sign::positive : Sign::negative;
}

OutcomeTracker::OutcomeTracker(const Law& head, const std::function<std::optional<Vector>(const Vector&)>& simulate)
    : mech_(make_mechanics(head.masses, head.M, head.W, head.friction)) {
    // Classical outcomes, by the independent simulation, where every piece containing gamma-
    // agrees with it.
    for (auto experiment : classical_experiments(mech_.balls())) {
        const auto u_plus = simulate(experiment.u_minus);
        if (!u_plus)
            continue;
        experiment.u_plus = *u_plus;
        Track track{experiment, transpose(mech_.W) * experiment.u_minus, true, false};
        tracks_.push_back(std::move(track));
    }
}

void OutcomeTracker::add(const PieceDecl& piece) {
    // Containment by the signs of Cramer's determinants (gamma = R s, s >= 0), without building a
    // Model: the pieces of a long word carry numbers of thousands of digits, and inverting every
    // ray matrix cost more than the derivation.
    const std::size_t c = mech_.contacts();
    auto det = [c](const Matrix& a) -> Sign {
        if (c == 2)
            return sign_of(a(0, 0) * a(1, 1) - a(0, 1) * a(1, 0));
        return integer_determinant_sign(a);
    };
    if (!piece.rays)
        throw std::logic_error("declare_outcomes: a derived piece without rays");
    std::optional<Matrix> R;
    std::optional<Sign> whole;
    for (auto& track : tracks_) {
        if (!track.agree)
            continue;
        if (!R) {
            R = Matrix::from_columns(*piece.rays);
            whole = det(*R);
        }
        bool inside = *whole != Sign::zero;
        for (std::size_t k = 0; k < c && inside; ++k) {
            Matrix Rk = *R;
            for (std::size_t i = 0; i < c; ++i)
                Rk(i, k) = track.gamma[i];
            const Sign sk = det(Rk);
            inside = sk == Sign::zero || sk == *whole;
        }
        if (!inside)
            continue;
        track.inside_any = true;
        const Vector impulse = mech_.H * (piece.Q * track.gamma - track.gamma);
        track.agree = track.experiment.u_minus + mech_.M_inv * (mech_.W * impulse) == track.experiment.u_plus;
    }
}

std::vector<OutcomeDecl> OutcomeTracker::outcomes() const {
    std::vector<OutcomeDecl> out;
    for (const auto& track : tracks_)
        if (track.agree && track.inside_any)
            out.push_back(track.experiment);
    return out;
}

void declare_outcomes(Law& law, const std::vector<OutcomeDecl>& override_outcomes,
                      const std::function<std::optional<Vector>(const Vector&)>& simulate) {
    if (!override_outcomes.empty()) {
        law.outcomes = override_outcomes;
        return;
    }
    OutcomeTracker tracker(law, simulate);
    for (const auto& piece : law.pieces)
        tracker.add(piece);
    law.outcomes = tracker.outcomes();
}

std::string system_text(const System& s) {
    if (!s.M && !s.W)
        return "a chain of " + std::to_string(s.masses.size()) + " balls, masses " + list_text(s.masses);
    return "system " + s.name + " (" + describe_system(s) + ")";
}

Law law_header(const DeriveOptions& options, std::size_t n) {
    Law law;
    const bool plain_chain = !options.M && !options.W;
    law.name = plain_chain ? "sequential-" + std::to_string(n) + "-balls" : "sequential-" + options.name;
    law.description = "Sequential impact law of " + system_text(options) + ", restitution " +
                      list_text(options.restitution) + ", rule " + to_string(options.rule) +
                      "; derived by impactcert derive sequential. Pieces are named by their words (contacts in "
                      "order of application; regions of several words with one matrix and a convex union are "
                      "merged under the first word); parts of a triangulated region by .1, .2, ...";
    law.masses = options.masses;
    law.M = options.M;
    law.W = options.W;
    law.velocity_names = options.velocity_names;
    law.contact_names = options.contact_names;
    return law;
}

std::vector<SingleImpactDecl> single_impacts_of(const std::map<std::size_t, std::string>& letter_piece,
                                                const std::vector<Rational>& restitution) {
    std::vector<SingleImpactDecl> out;
    for (const auto& [k, name] : letter_piece)
        out.push_back(SingleImpactDecl{name, static_cast<int>(k + 1), restitution[k]});
    return out;
}

std::optional<IdentityDecl> identity_of(const std::string& name, const std::vector<std::size_t>& word,
                                        const std::map<std::size_t, std::string>& letter_piece) {
    if (word.size() < 2)
        return std::nullopt;
    IdentityDecl id;
    id.lhs = name;
    for (auto it = word.rbegin(); it != word.rend(); ++it) {
        const auto letter = letter_piece.find(*it);
        if (letter == letter_piece.end())
            return std::nullopt; // a letter without its piece: no factorisation declared
        id.product.push_back(letter->second);
    }
    return id;
}

std::function<std::optional<Vector>(const Vector&)> outcome_simulation(const DeriveOptions& options) {
    return [&options](const Vector& u) {
        return simulate_balls(options, options.restitution, options.rule, u, options.max_impacts);
    };
}

} // namespace derive_detail

namespace {

// The declarations of a derived law from its pieces (name, word): single impacts (one-letter
// words), factorisations, outcomes.
void finish_law(const DeriveOptions& options, Law& law,
                const std::vector<std::pair<std::string, std::vector<std::size_t>>>& pieces) {
    std::map<std::size_t, std::string> letter_piece; // contact -> a piece of the one-letter word
    for (const auto& [name, word] : pieces)
        if (word.size() == 1 && !letter_piece.count(word[0]))
            letter_piece[word[0]] = name;
    law.single_impacts = single_impacts_of(letter_piece, options.restitution);
    for (const auto& [name, word] : pieces)
        if (auto id = identity_of(name, word, letter_piece))
            law.identities.push_back(std::move(*id));
    declare_outcomes(law, options.outcomes_override, outcome_simulation(options));
}

// Two contacts: the regions are sectors of the plane (derive_planar.hpp).
DeriveResult derive_planar(const DeriveOptions& options, const Mechanics& mech, const std::vector<Matrix>& Qk) {
    DeriveResult result;
    const std::size_t c = 2;
    auto planar = planar_regions(Qk, options.rule, options.max_impacts, options.max_bits,
                                 [&](const std::vector<std::size_t>& w) { return word_name(w, c); });
    if (planar.too_long_cell) {
        // The general path's witness: the sum of the extreme rays of the cell (PPL's generators).
        PPL::Generator_System gs;
        gs.insert(PPL::point());
        for (const auto& r : *planar.too_long_cell) {
            PPL::Linear_Expression e;
            for (std::size_t k = 0; k < c; ++k)
                e += PPL::Coefficient(mpz_class(mpq_numref(r[k].mpq()))) * PPL::Variable(static_cast<PPL::dimension_type>(k));
            gs.insert(PPL::ray(e));
        }
        const Vector x = interior_point(PPL::C_Polyhedron(gs), c);
        const auto sim = sequential_word(options, options.restitution, options.rule, x, options.max_impacts);
        if (sim.second || is_zero(x))
            throw std::logic_error("derive: the non-finite witness does not exceed the bound");
        result.not_finite = x;
        result.word = word_name(planar.too_long_word, c);
        return result;
    }
    result.regions = planar.regions.size();
    for (const auto& region : planar.regions)
        result.max_word = std::max(result.max_word, region.key.size());
    Law law = law_header(options, mech.balls());
    const auto written = add_planar_pieces(planar.regions, law);
    std::vector<std::pair<std::string, std::vector<std::size_t>>> pieces;
    for (const auto& piece : written)
        pieces.emplace_back(piece.name, planar.regions[piece.region].key);
    finish_law(options, law, pieces);
    result.law = std::move(law);
    return result;
}

} // namespace

namespace derive_detail {

// The words of the sequential process, depth first (derive_regions.hpp): each final region to
// `found`, or the first gamma- whose word exceeds max_impacts. The cells waiting are counted
// against `budget`; what `found` keeps is the caller's to count.
Explored explore_words(const DeriveOptions& options, const std::vector<Matrix>& Qk, RegionBudget& budget,
                       const std::function<void(Region&&)>& found) {
    const std::size_t c = Qk.size();
    Explored result;
    std::vector<Region> work;
    work.push_back({cone_of(c, {}), Matrix::identity(c), {}, {}});
    budget.add(RegionBudget::bytes_of(work.back()), "regions");
    std::size_t nodes = 0;
    while (!work.empty()) {
        if (options.progress && ++nodes % 1024 == 0)
            options.progress("regions", result.regions, 0);
        Region node = std::move(work.back());
        work.pop_back();
        budget.remove(RegionBudget::bytes_of(node));
        // Branches: no contact approaches (the word ends), or contact k is the one the rule picks.
        for (std::size_t branch = 0; branch <= c; ++branch) {
            PPL::C_Polyhedron cell = node.cone;
            auto add = [&](const Vector& a) {
                if (!is_zero(a)) // 0 >= 0 holds everywhere
                    cell.add_constraint(nonneg(a));
            };
            if (branch == c) {
                for (std::size_t j = 0; j < c; ++j)
                    add(node.M.row(j));
            } else {
                const std::size_t k = branch;
                // A contact whose velocity is 0 for every gamma- (after a plastic impact) never
                // approaches; a tie that holds everywhere goes to the lowest index.
                if (is_zero(node.M.row(k)))
                    continue;
                bool never = false;
                for (std::size_t j = 0; j < k; ++j)
                    never = never || (options.rule == ImpactRule::most_negative && node.M.row(j) == node.M.row(k));
                if (never)
                    continue;
                add(Rational(-1) * node.M.row(k)); // gamma_k <= 0
                for (std::size_t j = 0; j < c; ++j) {
                    if (j == k)
                        continue;
                    if (options.rule == ImpactRule::most_negative)
                        add(node.M.row(j) - node.M.row(k)); // gamma_k <= gamma_j
                    else if ((options.rule == ImpactRule::left_first && j < k) ||
                             (options.rule == ImpactRule::right_first && j > k))
                        add(node.M.row(j)); // gamma_j >= 0
                }
            }
            if (!full_dimensional(cell, c))
                continue;
            if (branch == c) {
                ++result.regions;
                result.max_word = std::max(result.max_word, node.key.size());
                found(Region{cell, node.M, node.key, word_name(node.key, c)});
                continue;
            }
            if (node.key.size() == options.max_impacts) {
                // A gamma- inside the cell: the sum of its generators.
                const Vector x = interior_point(cell, c);
                auto word = node.key;
                word.push_back(branch);
                const auto sim = sequential_word(options, options.restitution, options.rule, x, options.max_impacts);
                if (sim.second || is_zero(x))
                    throw std::logic_error("derive: the non-finite witness does not exceed the bound");
                result.not_finite = x;
                result.word = word_name(word, c);
                return result;
            }
            auto word = node.key;
            word.push_back(branch);
            Matrix next = Qk[branch] * node.M;
            check_bits(next, options.max_bits, "the map of word " + word_name(word, c));
            work.push_back({cell, std::move(next), word, {}});
            budget.add(RegionBudget::bytes_of(work.back()), "regions");
        }
    }
    return result;
}

} // namespace derive_detail

DeriveResult derive_sequential(const DeriveOptions& options) {
    const Mechanics mech = make_mechanics(options);
    if (mech.has_friction()) {
        if (mech.has_polygons())
            throw InputError("derive sequential: friction polygons are not offered here (derive newton derives them)");
        validate(options, mech.normals);
        return derive_sequential_friction(options, mech);
    }
    const std::size_t n = mech.balls(), c = mech.contacts();
    validate(options, c);
    const PplScope ppl;
    const Matrix& G = mech.G;
    std::vector<Matrix> Qk;
    for (std::size_t k = 0; k < c; ++k) {
        Qk.push_back(two_body_impact(G, k, options.restitution[k]));
        check_bits(Qk.back(), options.max_bits, "the impact matrix of contact " + std::to_string(k + 1));
    }

    DeriveResult result;
    if (c == 2 && !options.polyhedral)
        return derive_planar(options, mech, Qk);
    std::vector<Region> regions;
    RegionBudget budget(options.max_memory_mb); // the regions found and the cells waiting
    const Explored explored = explore_words(options, Qk, budget, [&](Region&& region) {
        budget.add(RegionBudget::bytes_of(region), "regions");
        regions.push_back(std::move(region));
    });
    if (explored.not_finite) {
        result.not_finite = explored.not_finite;
        result.word = explored.word;
        return result;
    }
    result.regions = explored.regions;
    result.max_word = explored.max_word;
    Law law = law_header(options, n);
    const auto written = add_region_pieces(regions, c, law, options.progress, &budget);
    result.peak_bytes = budget.peak();
    std::vector<std::pair<std::string, std::vector<std::size_t>>> pieces;
    for (const auto& piece : written)
        pieces.emplace_back(piece.name, regions[piece.region].key);
    finish_law(options, law, pieces);
    result.law = std::move(law);
    return result;
}

} // namespace impactcert
