// SPDX-License-Identifier: GPL-3.0-or-later
// research_test.cpp -- order independence (`derive sequential --rule any`) and collision counts
// against the literature: the braid relation for three elastic balls, ceil(pi / theta) for the
// left-first and right-first rules, Galperin's pi billiard (31, 314, 3141 impacts).
//
// Second routes: every admissible word at a point enumerated by plain simulation (no cones); the
// witness replayed in ball velocities with the two-ball collision formulas; the counts from a
// closed formula in long double, away from integers (the exact pi / k cases by their cosines).
#include "derive/derive.hpp"
#include "base/json.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>
#include <random>
#include <set>

using namespace impactcert;
using impactcert::test::q;

namespace {

DeriveOptions chain(const std::vector<int>& masses, const char* e = "1", Walls walls = Walls::none) {
    std::vector<Rational> m;
    for (int x : masses)
        m.push_back(Rational(x));
    DeriveOptions o;
    static_cast<System&>(o) = chain_system(m, walls);
    o.restitution.assign(make_mechanics(o).contacts(), q(e));
    return o;
}

// Every gamma+ that some admissible order reaches from gamma- (depth-first over the approaching
// contacts, by the plain impulse formula).
void all_outcomes(const Matrix& G, const std::vector<Rational>& e, const Vector& g, std::size_t depth,
                  std::set<std::vector<std::string>>& out) {
    REQUIRE(depth < 200);
    bool any = false;
    for (std::size_t k = 0; k < g.size(); ++k) {
        if (sign_of(g[k]) != Sign::negative)
            continue;
        any = true;
        const Rational s = (Rational(1) + e[k]) * g[k] / G(k, k);
        Vector next = g;
        for (std::size_t j = 0; j < g.size(); ++j)
            next[j] = next[j] - s * G(j, k);
        all_outcomes(G, e, next, depth + 1, out);
    }
    if (!any) {
        std::vector<std::string> key;
        for (const auto& x : g)
            key.push_back(to_string(x));
        out.insert(key);
    }
}

// Chain relative velocities gamma_k = u_{k+1} - u_k; the words replayed in ball velocities.
Vector replay_in_balls(const std::vector<int>& masses, const Vector& gamma, const std::vector<std::size_t>& word) {
    Vector u(masses.size());
    for (std::size_t k = 0; k < gamma.size(); ++k)
        u[k + 1] = u[k] + gamma[k];
    for (const std::size_t k : word) {
        const Rational m1(masses[k]), m2(masses[k + 1]);
        REQUIRE(u[k + 1] < u[k]); // the contact approaches: the word is admissible here
        const Rational p = m1 * u[k] + m2 * u[k + 1];
        const Rational a = (p + m2 * (u[k + 1] - u[k])) / (m1 + m2); // e = 1
        const Rational b = (p + m1 * (u[k] - u[k + 1])) / (m1 + m2);
        u[k] = a;
        u[k + 1] = b;
    }
    Vector g(gamma.size());
    for (std::size_t k = 0; k < g.size(); ++k)
        g[k] = u[k + 1] - u[k];
    return g;
}

Rational energy(const std::vector<int>& masses, const Vector& gamma) {
    Vector u(masses.size());
    for (std::size_t k = 0; k < gamma.size(); ++k)
        u[k + 1] = u[k] + gamma[k];
    // In the centre-of-mass frame: T - P^2 / (2 M) depends on gamma only.
    Rational t, p, mass;
    for (std::size_t i = 0; i < u.size(); ++i) {
        t = t + Rational(masses[i]) * u[i] * u[i];
        p = p + Rational(masses[i]) * u[i];
        mass = mass + Rational(masses[i]);
    }
    return t - p * p / mass;
}

// ceil(pi / theta) for a wedge whose cos^2 is `cos2` (rational, in (0, 1)); exact at the angles
// pi / k with a rational cos^2 (k = 3, 4, 6: 1/4, 1/2, 3/4, Niven's theorem), elsewhere pi / theta
// is irrational and the long double value is kept away from integers.
std::size_t ceil_pi_over_theta(const Rational& cos2) {
    if (cos2 == q("1/4"))
        return 3;
    if (cos2 == q("1/2"))
        return 4;
    if (cos2 == q("3/4"))
        return 6;
    const long double c = std::sqrt(static_cast<long double>(CGAL::to_double(cos2)));
    const long double k = 3.14159265358979323846264338327950288L / std::acos(c);
    REQUIRE(std::fabs(k - std::round(k)) > 1e-6L);
    return static_cast<std::size_t>(std::ceil(k));
}

bool braid_angle(const Rational& cos2) { return cos2 == q("1/4") || cos2 == q("1/2") || cos2 == q("3/4"); }

Rational chain_cos2(int a, int b, int c) { return Rational(a * c, (a + b) * (b + c)); }

} // namespace

TEST_CASE("order independence: the issue's mass triples, with second routes", "[research][order]") {
    for (const std::vector<int>& m : {std::vector<int>{1, 1, 1}, {2, 3, 5}, {2, 1, 3}, {4, 1, 15}}) {
        INFO("masses " << m[0] << "," << m[1] << "," << m[2]);
        const DeriveOptions o = chain(m);
        const OrderResult r = order_independence(o);
        REQUIRE(r.independent());
        // Every admissible order has at most ceil(pi / theta) impacts, and some has that many.
        CHECK(r.max_word == ceil_pi_over_theta(chain_cos2(m[0], m[1], m[2])));
        // Second route: at random gamma-, every admissible order by plain simulation ends at one gamma+.
        const Matrix G = make_mechanics(o).G;
        std::mt19937_64 rng(17);
        for (std::size_t s = 0; s < test::samples(400); ++s) {
            const Vector g{Rational(static_cast<int>(rng() % 41) - 20, 1 + static_cast<int>(rng() % 5)),
                           Rational(static_cast<int>(rng() % 41) - 20, 1 + static_cast<int>(rng() % 5))};
            std::set<std::vector<std::string>> outs;
            all_outcomes(G, o.restitution, g, 0, outs);
            INFO("gamma- " << to_string(g));
            REQUIRE(outs.size() == 1);
        }
    }
}

TEST_CASE("order independence: refuted with witnesses replayed in ball velocities", "[research][order]") {
    for (const std::vector<int>& m : {std::vector<int>{1, 2, 1}, {2, 1, 2}, {1, 1, 2}}) {
        INFO("masses " << m[0] << "," << m[1] << "," << m[2]);
        const DeriveOptions o = chain(m);
        const OrderResult r = order_independence(o);
        REQUIRE(r.witness);
        const OrderWitness& w = *r.witness;
        CHECK(order_witness_holds(o, o.restitution, w));
        // The second route: the two-ball formulas on u, and energy kept by both orders (e = 1).
        CHECK(replay_in_balls(m, w.gamma_minus, w.word_a) == w.gamma_a);
        CHECK(replay_in_balls(m, w.gamma_minus, w.word_b) == w.gamma_b);
        CHECK(w.gamma_a != w.gamma_b);
        CHECK(energy(m, w.gamma_a) == energy(m, w.gamma_minus));
        CHECK(energy(m, w.gamma_b) == energy(m, w.gamma_minus));
        for (const auto& x : w.gamma_a)
            CHECK(sign_of(x) != Sign::negative);
        for (const auto& x : w.gamma_b)
            CHECK(sign_of(x) != Sign::negative);
        // Mutations of the witness are refused by the checker.
        OrderWitness bad = w;
        bad.gamma_b = bad.gamma_a;
        CHECK_FALSE(order_witness_holds(o, o.restitution, bad));
        bad = w;
        bad.word_a.pop_back();
        CHECK_FALSE(order_witness_holds(o, o.restitution, bad));
        bad = w;
        bad.word_b.push_back(bad.word_b.back());
        CHECK_FALSE(order_witness_holds(o, o.restitution, bad));
        bad = w;
        bad.gamma_minus = Rational(-1) * bad.gamma_minus; // nothing approaches: no word is admissible
        CHECK_FALSE(order_witness_holds(o, o.restitution, bad));
    }
}

TEST_CASE("three elastic balls: order independent exactly at the angles pi / k (the braid relation)",
          "[research][order]") {
    std::size_t independent = 0;
    for (int a = 1; a <= 5; ++a)
        for (int b = 1; b <= 5; ++b)
            for (int c = 1; c <= 5; ++c) {
                INFO("masses " << a << "," << b << "," << c);
                const OrderResult r = order_independence(chain({a, b, c}));
                REQUIRE_FALSE(r.not_finite);
                CHECK(r.independent() == braid_angle(chain_cos2(a, b, c)));
                independent += r.independent();
            }
    CHECK(independent == 9); // (1,1,1) and its multiples, (2,3,5), (5,3,2), (2,1,3), (3,1,2), ... on this grid
}

TEST_CASE("collision counts: left-first and right-first reach ceil(pi / theta), most-negative one less or equal",
          "[research][counts]") {
    std::size_t below = 0, at = 0;
    for (int a : {1, 2, 3, 7, 20})
        for (int b : {1, 2, 5, 10})
            for (int c : {1, 3, 4, 50}) {
                INFO("masses " << a << "," << b << "," << c);
                const std::size_t k = ceil_pi_over_theta(chain_cos2(a, b, c));
                for (ImpactRule rule : {ImpactRule::left_first, ImpactRule::right_first}) {
                    DeriveOptions o = chain({a, b, c});
                    o.rule = rule;
                    const DeriveResult d = derive_sequential(o);
                    REQUIRE(d.law);
                    CHECK(d.max_word == k);
                }
                DeriveOptions o = chain({a, b, c});
                const DeriveResult d = derive_sequential(o);
                REQUIRE(d.law);
                CHECK((d.max_word == k || d.max_word + 1 == k));
                (d.max_word == k ? at : below) += 1;
            }
    // Both happen: most-negative compares the gamma_k as given, not the angle.
    CHECK(at > 0);
    CHECK(below > 0);
}

TEST_CASE("Galperin's pi billiard: 31, 314, 3141 impacts from rest against the wall", "[research][counts]") {
    const std::vector<std::pair<int, std::size_t>> cases = {{100, 31}, {10000, 314}, {1000000, 3141}};
    for (const auto& [ratio, count] : cases) {
        INFO("mass ratio " << ratio);
        DeriveOptions o = chain({1, ratio}, "1", Walls::left);
        // The light ball at rest at the wall, the heavy one coming in: gamma = (u1, u2 - u1) = (0, -1).
        const Vector gamma{Rational(0), Rational(-1)};
        for (ImpactRule rule : {ImpactRule::left_first, ImpactRule::right_first, ImpactRule::most_negative}) {
            const auto [word, stopped] = sequential_word(o, o.restitution, rule, gamma, 10000);
            REQUIRE(stopped);
            CHECK(word.size() == count);
        }
        // One impact fewer than the wedge's bound ceil(pi / theta), tan(theta) = sqrt(m / M).
        CHECK(ceil_pi_over_theta(Rational(ratio, ratio + 1)) == count + 1);
    }
    // The derived law of ratio 100 reaches the bound, 32, elsewhere (left-first and right-first).
    for (ImpactRule rule : {ImpactRule::left_first, ImpactRule::right_first}) {
        DeriveOptions o = chain({1, 100}, "1", Walls::left);
        o.rule = rule;
        const DeriveResult d = derive_sequential(o);
        REQUIRE(d.law);
        CHECK(d.max_word == 32);
    }
}

TEST_CASE("derive sequential --rule any on the command line", "[research][order][cli]") {
    const std::string dir = std::filesystem::temp_directory_path() / ("impactcert-rule-any-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto run = test::run_cli("derive sequential --masses 2,1,3 --rule any -o " + dir + "/law.json");
    REQUIRE(run.status == 0);
    CHECK(test::read_file(dir + "/law.json").find("order independent") != std::string::npos);
    CHECK(test::run_cli("verify --law " + dir + "/law.json").status == 0);
    std::filesystem::remove_all(dir);
    run = test::run_cli("derive sequential --masses 1,2,1 --rule any --json");
    REQUIRE(run.status == 1);
    const Json j = Json::parse(run.out);
    CHECK(j.at("verdict") == "order-dependent");
    OrderWitness w;
    w.gamma_minus = test::vec_of(j.at("gamma_minus"));
    for (int i = 0; i < 2; ++i) {
        std::vector<std::size_t> word;
        for (char ch : j.at("words").at(i).get<std::string>())
            word.push_back(static_cast<std::size_t>(ch - '1'));
        (i == 0 ? w.word_a : w.word_b) = word;
        (i == 0 ? w.gamma_a : w.gamma_b) = test::vec_of(j.at("gamma_plus").at(i));
    }
    const DeriveOptions o = chain({1, 2, 1});
    CHECK(order_witness_holds(o, o.restitution, w));
    // The plastic chain: an admissible order runs past the bound: undecided (exit 3), with the point.
    run = test::run_cli("derive sequential --masses 1,1,1 --restitution 0 --rule any");
    CHECK(run.status == 3);
    CHECK(run.err.find("more than 100 impacts") != std::string::npos);
    CHECK(run.err.find("--max-impacts") != std::string::npos);
    // A limit is undecided, naming the option.
    run = test::run_cli("derive sequential --masses 1,1,1,1 --rule any --max-words 5");
    CHECK(run.status == 3);
    CHECK(run.err.find("--max-words") != std::string::npos);
    CHECK(test::run_cli("derive sequential --masses 1,1,1 --rule sideways").status == 2);
    // -o - is standard output, as the default.
    const auto dash = test::run_cli("derive sequential --masses 2,1,3 --rule any -o -");
    CHECK(dash.status == 0);
    CHECK(dash.out.find("\"format\": \"impactcert-law/1\"") != std::string::npos);
}

// ---- Where continuity holds exactly (exact_conditions.hpp).

#include "exact/exact_conditions.hpp"
#include "prover/obligations.hpp"

namespace {

ConditionFamily one_m_one() {
    ConditionFamily f;
    f.masses = {"1", "m", "1"};
    f.restitution = {"e"};
    f.parameters.push_back({"m", {q("1/4"), q("1/2"), q("1"), q("3/2"), q("4")}});
    std::vector<Rational> es;
    for (int k = 0; k <= 8; ++k)
        es.push_back(Rational(k, 8));
    f.parameters.push_back({"e", es});
    return f;
}

DeriveResult derive_at(const Rational& m, const Rational& e) {
    DeriveOptions o;
    o.masses = {Rational(1), m, Rational(1)};
    o.restitution = {e, e};
    return derive_sequential(o);
}

// The jump at the tie read off the derived law (a second route, no polynomials): the limits of
// S at (-1, -1) from the side where contact 1 is more negative and from the other side, each by
// linear extrapolation inside one piece (2 S(d + h v) - S(d + 2 h v) = A d when both points lie in
// the piece of matrix A).
Vector law_jump(const Model& model) {
    const Rational h(1, 1000000000);
    auto one = [&](const Vector& x) {
        const auto v = model.values_at(x);
        REQUIRE(v.size() == 1);
        return v[0];
    };
    auto limit = [&](std::size_t k) {
        Vector a{Rational(-1), Rational(-1)}, b = a;
        a[k] = a[k] - h;
        b[k] = b[k] - h - h;
        return Rational(2) * one(a) - one(b);
    };
    return limit(0) - limit(1);
}

Verdict p1_of(const Model& m) { return verify(m).at("P1").verdict; }

// P1 of the derived sequential law of a chain (most-negative), with one restitution per contact.
Verdict chain_p1(const std::vector<int>& masses, const std::vector<Rational>& restitution) {
    DeriveOptions o;
    for (int m : masses)
        o.masses.push_back(Rational(m));
    o.restitution = restitution;
    const DeriveResult d = derive_sequential(o);
    REQUIRE(d.law);
    return p1_of(Model(*d.law));
}

} // namespace

// One computation of the curves (minutes under the sanitizers) for both halves: the crossings of
// m = 1/2, then rational points on and off the curves.
TEST_CASE("exact conditions: the curves of 1,m,1 cross m = 1/2 at 0.276712 and 0.220789, and points on them are continuous laws",
          "[research][conditions]") {
    const ConditionFamily family = one_m_one();
    const ConditionsResult r = continuity_conditions(family);
    REQUIRE(r.computed);
    std::vector<const Crossing*> on_half;
    std::vector<const ConditionCurve*> owner;
    for (const auto& curve : r.curves)
        for (const auto& x : curve.crossings)
            if (x.varies == 1 && x.at == q("1/2") && x.grid_line) {
                on_half.push_back(&x);
                owner.push_back(&curve);
                // Certified: g changes sign across the enclosure, or the root is exact.
                if (x.exact) {
                    CHECK(evaluate_condition(curve, {x.at, *x.exact}) == Rational(0));
                } else {
                    CHECK(x.hi - x.lo <= Rational(1, 1000000000));
                    CHECK(sign_of(evaluate_condition(curve, {x.at, x.lo})) !=
                          sign_of(evaluate_condition(curve, {x.at, x.hi})));
                }
            }
    auto find = [&](const char* approx) -> std::size_t {
        const Rational a = q(approx);
        for (std::size_t i = 0; i < on_half.size(); ++i)
            if (on_half[i]->lo - a < Rational(1, 2000000) && a - on_half[i]->hi < Rational(1, 2000000))
                return i;
        FAIL("no crossing of m = 1/2 near e = " << approx);
        return 0;
    };
    const std::size_t five = find("0.276712"), six = find("0.220789");
    CHECK(owner[five]->word_a == "12121"); // five impacts after the tie
    CHECK(owner[six]->word_a == "121212");
    // The derived laws on both sides of each crossing say the same: discontinuous on both sides,
    // with a jump that changes sign (read off the law itself), in the same cell.
    for (const std::size_t i : {five, six}) {
        const Rational below = on_half[i]->lo - Rational(1, 100000), above = on_half[i]->hi + Rational(1, 100000);
        INFO("crossing near e = " << to_string(on_half[i]->lo));
        CHECK(tie_words(family, {q("1/2"), below}) == tie_words(family, {q("1/2"), above}));
        const DeriveResult a = derive_at(q("1/2"), below), b = derive_at(q("1/2"), above);
        REQUIRE(a.law);
        REQUIRE(b.law);
        const Model ma(*a.law), mb(*b.law);
        CHECK(p1_of(ma) == Verdict::refuted);
        CHECK(p1_of(mb) == Verdict::refuted);
        const Vector ja = law_jump(ma), jb = law_jump(mb);
        CHECK(sign_of(ja[0]) != Sign::zero);
        CHECK(static_cast<int>(sign_of(ja[0])) == -static_cast<int>(sign_of(jb[0])));
        // The symmetric family: J = (a - b, b - a).
        CHECK(ja[1] == Rational(-1) * ja[0]);
    }
    // (1/2, 1/2) is an exact crossing of the four-impact curve.
    bool half = false;
    for (const auto* x : on_half)
        half = half || (x->exact && *x->exact == q("1/2"));
    CHECK(half);
    // Rational points on the curves are continuous laws, points off them are not.
    auto curve_at = [&](const Rational& m, const Rational& e) -> const ConditionCurve* {
        const auto words = tie_words(family, {m, e});
        if (!words)
            return nullptr; // on a cell wall
        for (const auto& c : r.curves)
            if (c.word_a == words->first && c.word_b == words->second)
                return &c;
        return nullptr;
    };
    for (const auto& [m, e] : std::vector<std::pair<const char*, const char*>>{{"1/2", "1/2"}, {"1/3", "1/3"}, {"3/2", "1/4"}, {"5/4", "1/8"}, {"1", "1"}}) {
        INFO("(m, e) = (" << m << ", " << e << ")");
        const ConditionCurve* c = curve_at(q(m), q(e));
        REQUIRE(c);
        CHECK(evaluate_condition(*c, {q(m), q(e)}) == Rational(0));
        const DeriveResult d = derive_at(q(m), q(e));
        REQUIRE(d.law);
        const Model model(*d.law);
        CHECK(p1_of(model) == Verdict::proved);
        CHECK(law_jump(model) == Vector{Rational(0), Rational(0)});
    }
    // Negative controls from the issue: not on a curve, and the derived law jumps.
    for (const auto& [m, e] : std::vector<std::pair<const char*, const char*>>{{"2/5", "2/5"}, {"3/5", "3/5"}, {"2/3", "2/3"}}) {
        INFO("(m, e) = (" << m << ", " << e << ")");
        const ConditionCurve* c = curve_at(q(m), q(e));
        if (c)
            CHECK(evaluate_condition(*c, {q(m), q(e)}) != Rational(0));
        const DeriveResult d = derive_at(q(m), q(e));
        REQUIRE(d.law);
        const Model model(*d.law);
        CHECK(p1_of(model) == Verdict::refuted);
        CHECK_FALSE(law_jump(model) == Vector{Rational(0), Rational(0)});
    }
    // Outside the scope: four balls, or a parameter that is not in the family.
    ConditionFamily four = family;
    four.masses = {"1", "m", "1", "1"};
    CHECK_FALSE(continuity_conditions(four).computed);
}

TEST_CASE("exact conditions: coprime jump components are listed with their isolated zeros, not dropped",
          "[research][conditions]") {
    // The chain 1,1,1 with one restitution per contact: in the cell 121 / 212 the two components of
    // the jump are coprime cubics that both vanish at (e, f) = (1, 1), the paper's law.
    ConditionFamily f;
    f.masses = {"1", "1", "1"};
    f.restitution = {"e", "f"};
    f.parameters.push_back({"e", {q("1/4"), q("1/2"), q("3/4"), q("1")}});
    f.parameters.push_back({"f", {q("1/4"), q("1/2"), q("3/4"), q("1")}});
    const ConditionsResult r = continuity_conditions(f);
    REQUIRE(r.computed);
    const auto words = tie_words(f, {Rational(1), Rational(1)});
    REQUIRE(words);
    const ConditionCurve* cell = nullptr;
    for (const auto& c : r.curves)
        if (c.word_a == words->first && c.word_b == words->second)
            cell = &c;
    REQUIRE(cell);
    CHECK(cell->isolated);
    CHECK(std::find(cell->points.begin(), cell->points.end(), std::vector<Rational>{Rational(1), Rational(1)}) !=
          cell->points.end());
    // Every listed point is a continuous law; a point of the same cell not listed is not.
    for (const auto& p : cell->points)
        CHECK(chain_p1({1, 1, 1}, p) == Verdict::proved);
    CHECK(tie_words(f, {q("1"), q("3/4")}) == words);
    CHECK(chain_p1({1, 1, 1}, {q("1"), q("3/4")}) == Verdict::refuted);
}

TEST_CASE("derive --rule any: the pair stage is bounded by --max-words too", "[research][order][cli]") {
    // Four balls and a wall: thousands of final cells; the default limits answer undecided quickly.
    auto run = test::run_cli("derive sequential --masses 1,1,1,1 --walls left --rule any --max-words 3000");
    CHECK(run.status == 3);
    CHECK(run.err.find("--max-words") != std::string::npos);
    // Five equal balls need 4 to 5 million pairs; 400 cells (40,000 pairs) stop short: undecided, naming the option.
    run = test::run_cli("derive sequential --masses 1,1,1,1,1 --rule any --max-words 400");
    CHECK(run.status == 3);
    CHECK(run.err.find("--max-words") != std::string::npos);
    // The pair stage's own message (issue 33, 10f: "--max-words" is in the word stage's too).
    CHECK(run.err.find("pairs of final cells to compare") != std::string::npos);
    CHECK(run.err.find("admissible words (--max-words)") == std::string::npos);
}

#ifndef IMPACTCERT_SANITIZER_BUILD
// The Release build only: the same computation of the curves runs under the sanitizers in the test
// of the crossings above (this one computes them twice, 42 s there).
TEST_CASE("exact conditions: a grid that runs downwards finds the same crossings", "[research][conditions]") {
    ConditionFamily up = one_m_one();
    ConditionFamily down = up;
    for (auto& p : down.parameters)
        std::reverse(p.values.begin(), p.values.end());
    auto half_line = [](const ConditionsResult& r) {
        std::vector<std::pair<std::string, std::string>> found; // (words, lo) on m = 1/2
        for (const auto& c : r.curves)
            for (const auto& x : c.crossings)
                if (x.varies == 1 && x.at == q("1/2"))
                    found.push_back({c.word_a, to_string(x.lo)});
        std::sort(found.begin(), found.end());
        return found;
    };
    const auto a = half_line(continuity_conditions(up)), b = half_line(continuity_conditions(down));
    CHECK(a.size() >= 3);
    CHECK(a == b);
}
#endif

TEST_CASE("exact conditions: a grid line that lies on a curve is listed at its grid points", "[research][conditions]") {
    // Masses 2,1,3 with restitutions e, f: in the cell 1212 / 2121 the jump's gcd is
    // (1 - e^2)(1 - f^2), so the lines e = 1 and f = 1 are continuous laws throughout.
    ConditionFamily f;
    f.masses = {"2", "1", "3"};
    f.restitution = {"e", "f"};
    for (const char* name : {"e", "f"})
        f.parameters.push_back({name, {q("1/4"), q("1/2"), q("3/4"), q("1")}});
    const ConditionsResult r = continuity_conditions(f);
    REQUIRE(r.computed);
    std::size_t along = 0;
    for (const auto& c : r.curves)
        for (const auto& x : c.crossings) {
            if (!x.along)
                continue;
            ++along;
            REQUIRE(x.exact);
            CHECK(x.at == Rational(1));
            std::vector<Rational> at(2);
            at[x.varies] = *x.exact;
            at[1 - x.varies] = x.at;
            CHECK(evaluate_condition(c, at) == Rational(0));
            CHECK(chain_p1({2, 1, 3}, at) == Verdict::proved);
        }
    CHECK(along >= 8); // four grid points on each of the two lines (more with the points between)
    // Off those lines, inside the cell, the law jumps.
    CHECK(chain_p1({2, 1, 3}, {q("3/4"), q("1/2")}) == Verdict::refuted);
}
