// SPDX-License-Identifier: GPL-3.0-or-later
// derive_test.cpp -- derived sequential impact laws (SPEC section 7) against the paper's law, the
// sort law, and a direct simulation in ball velocities that shares nothing with the derivation.
#include "prover/certificate.hpp"
#include "derive/derive.hpp"
#include "impactcert_check.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <random>
#include <set>
#include <sstream>

using namespace impactcert;
using impactcert::test::q;

namespace {

DeriveOptions options(std::vector<const char*> masses, std::vector<const char*> restitution,
                      ImpactRule rule = ImpactRule::most_negative) {
    DeriveOptions o;
    for (auto m : masses)
        o.masses.push_back(q(m));
    for (auto e : restitution)
        o.restitution.push_back(q(e));
    if (o.restitution.size() == 1)
        o.restitution.assign(o.masses.size() - 1, o.restitution[0]);
    o.rule = rule;
    return o;
}

Model derived(const DeriveOptions& o) {
    const DeriveResult r = derive_sequential(o);
    REQUIRE(r.law);
    return Model(*r.law);
}

Rational random_rational(std::mt19937_64& rng) {
    return Rational(static_cast<int>(rng() % 201) - 100, static_cast<int>(1 + rng() % 12));
}

// S of `a` and `b` agree at x: the same set of values (several on a boundary of a
// discontinuous law are compared as sets).
void require_same_values(const Model& a, const Model& b, const Vector& x) {
    auto va = a.values_at(x), vb = b.values_at(x);
    std::sort(va.begin(), va.end());
    std::sort(vb.begin(), vb.end());
    INFO("at " << to_string(x));
    REQUIRE(va == vb);
}

// The derived law against the ball-velocity simulation at random rational u-: the simulation's
// u+ is one of the law's values (exactly one off the boundaries).
void require_agrees_with_simulation(const DeriveOptions& o, const Model& m, std::size_t samples, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    for (std::size_t k = 0; k < samples; ++k) {
        Vector u(o.masses.size());
        for (auto& x : u)
            x = random_rational(rng);
        const auto sim = simulate_balls(o.masses, o.restitution, o.rule, u, 1000);
        REQUIRE(sim);
        const Vector gamma = m.contact_velocities(u);
        bool found = false;
        for (const auto& g_plus : m.values_at(gamma))
            found = found || m.post_impact_velocities(u, gamma, g_plus) == *sim;
        INFO("u- = " << to_string(u) << ", simulated u+ = " << to_string(*sim));
        REQUIRE(found);
    }
}

bool all_proved(const VerifyReport& r) {
    for (const auto& o : r.obligations) {
        INFO(o.id << " " << o.counterexample.dump());
        CHECK((o.verdict == Verdict::proved || o.verdict == Verdict::skipped));
    }
    return r.exit_status() == 0;
}

} // namespace

TEST_CASE("derive: three equal balls, e = 1, give the paper's law", "[derive]") {
    const Model d = derived(options({"1", "1", "1"}, {"1"}));
    const Model paper(paper_law());
    CHECK(d.pieces().size() == 6);
    for (const auto& r : paper.rays())
        require_same_values(d, paper, r);
    for (const auto& r : d.rays())
        require_same_values(d, paper, r);
    std::mt19937_64 rng(3);
    for (std::size_t k = 0; k < test::samples(10000); ++k)
        require_same_values(d, paper, Vector{random_rational(rng), random_rational(rng)});
    CHECK(all_proved(verify(d)));
    CHECK(d.law().outcomes.size() == 5);
    CHECK(d.law().single_impacts.size() == 2);
}

TEST_CASE("derive: four and five equal balls, e = 1, give the sort law", "[derive]") {
    for (std::size_t n : {4, 5}) {
        INFO(n << " balls");
        std::vector<const char*> masses(n, "1");
        const Model d = derived(options(masses, {"1"}));
        const Model sort(test::sorting_law(n));
        std::size_t factorial = 1;
        for (std::size_t k = 2; k <= n; ++k)
            factorial *= k;
        CHECK(d.pieces().size() == factorial);
        std::mt19937_64 rng(n);
        for (std::size_t k = 0; k < test::samples(10000); ++k) {
            Vector x(n - 1);
            for (auto& v : x)
                v = random_rational(rng);
            require_same_values(d, sort, x);
        }
        if (n == 4)
            CHECK(all_proved(verify(d)));
    }
}

#ifndef IMPACTCERT_SANITIZER_BUILD
// The Release build only: under the sanitizers the same verification runs on the 4-ball law above
// and on the 5-ball sorting law of report_test.cpp; this one took 28 s there.
TEST_CASE("derive: five equal balls, e = 1: every obligation proved", "[derive][slow]") {
    const Model d = derived(options({"1", "1", "1", "1", "1"}, {"1"}));
    CHECK(all_proved(verify(d)));
}
#endif

// One rule per test case (three ctest cases, run in parallel; each the same checks).
static void require_rule_agrees_with_simulation(ImpactRule rule) {
    const std::vector<std::pair<std::vector<const char*>, std::vector<const char*>>> cases = {
        {{"1", "2", "1"}, {"1"}},           {{"3", "1", "2"}, {"1/2"}},      {{"1", "5"}, {"3/4"}},
        {{"2", "1", "1"}, {"1", "1/3"}},    {{"1", "2", "3", "4"}, {"1/2"}}, {{"1", "1", "2", "1"}, {"1", "9/10", "4/5"}},
    };
    for (std::size_t index = 0; index < cases.size(); ++index) {
        const auto& [masses, e] = cases[index];
        // Under the sanitizers each rule takes two of the six systems (the three rules together take
        // all six): the same code, a third of the time.
        if (test::kSanitizerDivisor != 1 && index % 3 != static_cast<std::size_t>(rule) % 3)
            continue;
        {
            const DeriveOptions o = options(masses, e, rule);
            INFO("masses " << masses.size() << " " << masses[1] << ", rule " << to_string(rule));
            const Model m = derived(o);
            require_agrees_with_simulation(o, m, test::samples(10000), masses.size());
            // Every derivation is a valid law whose certificate the checker verifies, and whose
            // declared single impacts, factorisations and outcomes hold.
            // The declarations are made from the derivation itself, so "proved" alone would pass
            // by construction: require that they are there (every contact's single impact, some
            // outcomes, a factorisation for every longer word), and check every piece's rays and
            // centre -- boundary points the random samples miss -- against the ball simulation,
            // which shares nothing with the derivation.
            const std::size_t c = masses.size() - 1;
            CHECK(m.law().single_impacts.size() == c);
            CHECK(!m.law().outcomes.empty());
            CHECK(m.law().identities.empty() == (c == 1)); // two balls: one contact, words of one letter
            for (const auto& piece : m.pieces()) {
                std::vector<Vector> points;
                for (std::size_t k = 0; k < c; ++k)
                    points.push_back(piece.R.column(k));
                points.push_back(piece.R * Vector(c, Rational(1)));
                for (const auto& gamma : points) {
                    // A u- with W^T u- = gamma: u_1 = 0, u_{k+1} = u_k + gamma_k.
                    Vector u(c + 1);
                    for (std::size_t k = 0; k < c; ++k)
                        u[k + 1] = u[k] + gamma[k];
                    const auto sim = simulate_balls(o.masses, o.restitution, o.rule, u, 1000);
                    REQUIRE(sim);
                    bool found = false;
                    for (const auto& g_plus : m.values_at(gamma))
                        found = found || m.post_impact_velocities(u, gamma, g_plus) == *sim;
                    INFO("piece " << piece.name << ", gamma- = " << to_string(gamma));
                    CHECK(found);
                }
            }
            const VerifyReport r = verify(m);
            for (const char* id : {"single-impacts", "identities", "outcomes", "fan"})
                CHECK(r.at(id).verdict == (std::string(id) == "identities" && c == 1 ? Verdict::skipped : Verdict::proved));
            const auto checked = impactcert_check::check_text(make_certificate(m, r).dump());
            INFO(checked.message);
            CHECK(checked.status == impactcert_check::kVerified);
        }
    }
}

TEST_CASE("derive: unequal masses, restitutions and the most-negative rule agree with the ball simulation", "[derive]") {
    require_rule_agrees_with_simulation(ImpactRule::most_negative);
}

TEST_CASE("derive: unequal masses, restitutions and the left-first rule agree with the ball simulation", "[derive]") {
    require_rule_agrees_with_simulation(ImpactRule::left_first);
}

TEST_CASE("derive: unequal masses, restitutions and the right-first rule agree with the ball simulation", "[derive]") {
    require_rule_agrees_with_simulation(ImpactRule::right_first);
}

TEST_CASE("derive: masses 1,2,1 with e = 1 are discontinuous on the tie boundary", "[derive]") {
    const Model m = derived(options({"1", "2", "1"}, {"1"}));
    const VerifyReport r = verify(m);
    const auto& p1 = r.at("P1");
    REQUIRE(p1.verdict == Verdict::refuted);
    test::revalidate(m, p1);
    const Vector g = test::vec_of(p1.counterexample["gamma"]);
    CHECK(g[0] == g[1]); // on gamma_1 = gamma_2, where most-negative changes its choice
    CHECK(sign_of(g[0]) == Sign::negative);
}

TEST_CASE("derive: e = 0 has no finite law - the witness needs more impacts than allowed", "[derive]") {
    DeriveOptions o = options({"1", "1", "1"}, {"0"});
    o.max_impacts = 20;
    const DeriveResult r = derive_sequential(o);
    REQUIRE_FALSE(r.law);
    REQUIRE(r.not_finite);
    const auto [word, finished] = sequential_word(o, o.restitution, o.rule, *r.not_finite, 20);
    CHECK_FALSE(finished);
    CHECK(word.size() == 20);
    CHECK(r.word.size() == 21);
    // A sequence longer than the bound is a limit, not a proof (issue 32): exit 3 naming it.
    const auto run = test::run_cli("derive sequential --masses 1,1,1 --restitution 0 --max-impacts 20");
    CHECK(run.status == 3);
    CHECK(run.err.find("undecided: derive: gamma- = ") != std::string::npos);
    CHECK(run.err.find("raise the bound with --max-impacts") != std::string::npos);
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    // Issue 32's case: finite (282 pieces), but beyond the default bound of 100 impacts.
    const auto heavy = test::run_cli("derive sequential --masses 1,2000 --walls left --rule left-first");
    CHECK(heavy.status == 3);
    CHECK(heavy.err.find("--max-impacts") != std::string::npos);
    const auto raised = test::run_cli("derive sequential --masses 1,2000 --walls left --rule left-first --max-impacts 200 "
                                      "-o /tmp/impactcert-derive-test-heavy.json");
    CHECK(raised.status == 0);
    CHECK(raised.err.find("282 pieces") != std::string::npos);
}

TEST_CASE("derive: the CLI writes a law that loads - bad input is one line and exit 2", "[derive][cli]") {
    const auto ok = test::run_cli("derive sequential --masses 1,1,1");
    REQUIRE(ok.status == 0);
    const Model m(parse_law_text(ok.out, "stdout"));
    CHECK(m.pieces().size() == 6);
    for (const char* bad : {"--masses 1,0,1", "--masses 1,-2", "--masses 1", "--masses 1,1,1 --restitution 3/2",
                            "--masses 1,1,1 --restitution -1", "--masses 1,1,1 --restitution 1,1,1",
                            "--masses 1,1,1 --rule fastest", "--masses 1,x,1", "--masses 1,1 --max-impacts 0"}) {
        INFO(bad);
        const auto run = test::run_cli(std::string("derive sequential ") + bad);
        CHECK(run.status == 2);
        CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    }
}

TEST_CASE("sweep: the CSV holds the verdicts computed one by one, whatever the number of jobs", "[derive][sweep]") {
    const std::string dir = "/tmp/impactcert-sweep-test";
    std::filesystem::remove_all(dir);
    const auto run = test::run_cli("sweep --masses 1,m,1 --restitution e --vary m=1/2..2:3:log --vary e=1/2..1:3 --jobs 2 -o " + dir);
    REQUIRE(run.status == 0);
    const std::string csv = test::read_file(dir + "/sweep.csv");
    std::stringstream in(csv);
    std::string line;
    std::getline(in, line);
    CHECK(line.rfind("m,e,fan,P1,P2,", 0) == 0);
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream row(line);
        for (std::string cell; std::getline(row, cell, ',');)
            cells.push_back(cell);
        if (!line.empty() && line.back() == ',')
            cells.push_back("");
        REQUIRE(cells.size() == 2 + kObligationIds.size() + 4); // + order-independent, pieces, max_word, derive
        DeriveOptions o;
        o.masses = {Rational(1), q(cells[0]), Rational(1)};
        o.restitution = {q(cells[1]), q(cells[1])};
        const DeriveResult d = derive_sequential(o);
        INFO(line);
        REQUIRE(d.law);
        CHECK(cells.back() == "ok");
        const Model m(*d.law);
        const VerifyReport r = verify(m);
        for (std::size_t k = 0; k < kObligationIds.size(); ++k)
            CHECK(cells[2 + k] == to_string(r.at(kObligationIds[k]).verdict));
        // The order column: --rule any's decision. On this grid the order does not matter exactly
        // at (1, 1) (the braid angle pi/3) and at (1/2, 1/2), the two continuous laws.
        const OrderResult order = order_independence(o);
        CHECK(cells[2 + kObligationIds.size()] == (order.independent() ? "proved" : "refuted"));
        CHECK(order.independent() == ((o.masses[1] == Rational(1) && o.restitution[0] == Rational(1)) ||
                                      (o.masses[1] == q("1/2") && o.restitution[0] == q("1/2"))));
        CHECK(cells[3 + kObligationIds.size()] == std::to_string(m.pieces().size()));
        ++rows;
    }
    CHECK(rows == 9);
    // The log grid's middle point is a rational near the geometric mean of 1/2 and 2.
    CHECK(csv.find("\n1,") != std::string::npos);
    // One job gives the same files.
    const std::string one = dir + "-one";
    REQUIRE(test::run_cli("sweep --masses 1,m,1 --restitution e --vary m=1/2..2:3:log --vary e=1/2..1:3 --jobs 1 -o " + one).status == 0);
    CHECK(test::read_file(one + "/sweep.csv") == csv);
    CHECK(test::read_file(one + "/sweep.json") == test::read_file(dir + "/sweep.json"));
    const std::string html = test::read_file(dir + "/sweep.html");
    CHECK(std::count(html.begin(), html.end(), '<') > 100);
    CHECK(html.find("<title>m = 1, e = 1: proved</title>") != std::string::npos);
    // The exact conditions: the curves through (1/2, 1/2) and (1, 1), derived and verified there,
    // drawn as dots on the P1 map.
    const Json doc = Json::parse(test::read_file(dir + "/sweep.json"));
    const Json& exact = doc.at("exact_conditions").at("P1");
    REQUIRE(exact.at("computed") == true);
    std::set<std::string> continuous;
    for (const auto& curve : exact.at("curves"))
        for (const auto& check : curve.value("checks", Json::array())) {
            CHECK(check.at("P1") == "proved");
            continuous.insert(check.at("point").at("m").get<std::string>() + "," + check.at("point").at("e").get<std::string>());
        }
    CHECK(doc.at("exact_conditions").at("P2").at("holds") == "where e = 1");
    // ... and it agrees with the P2 column at every grid point.
    for (const auto& point : doc.at("points"))
        if (point.at("derive") == "ok")
            CHECK((point.at("obligations").at("P2").at("verdict") == "proved") == (point.at("point").at("e") == "1"));
    CHECK(continuous.count("1/2,1/2") == 1);
    CHECK(continuous.count("1,1") == 1);
    CHECK(html.find("<circle") != std::string::npos);
    CHECK(html.find("Where P1 holds exactly") != std::string::npos);
    CHECK(html.find("class=\"curve-label\"") != std::string::npos); // curves labelled by their impact count
    CHECK(html.find("<title>m = 1/2</title>") != std::string::npos);  // axis ticks, exact values on hover
    // Round-number ticks, not grid values: e = 1/2..1 in 3 points is ticked 0.5, 0.6, ..., 1 (0.6 is
    // no grid value), and the grid value 3/4 is no tick.
    CHECK(html.find("<title>e = 3/5</title>") != std::string::npos);
    CHECK(html.find("<title>e = 3/4</title>") == std::string::npos);
    std::filesystem::remove_all(dir);
    std::filesystem::remove_all(one);
}

TEST_CASE("sweep: e = 0 is recorded as no finite law - bad grids are one line and exit 2", "[derive][sweep]") {
    const std::string dir = "/tmp/impactcert-sweep-test-2";
    const auto run = test::run_cli("sweep --masses 1,1,1 --restitution e --vary e=0..1:2 --jobs 1 -o " + dir);
    REQUIRE(run.status == 0);
    const std::string csv = test::read_file(dir + "/sweep.csv");
    CHECK(csv.find("\n0,,,,,,,,,,,,,,,,,not-finite\n") != std::string::npos); // e, 13 obligations, order, pieces, max_word
    CHECK(csv.find("\n1,proved,proved,") != std::string::npos);
    std::filesystem::remove_all(dir);
    for (const char* bad : {"--masses 1,m,1 --vary x=1..2:3", "--masses 1,m,1 --vary m=1..2:3 --vary e=0..1:2",
                            "--masses 1,1,1 --restitution e --vary e=0..2:3", "--masses 1,m,1 --vary m=0..2:3",
                            "--masses 1,m,1 --vary m=1..2", "--masses 1,m,1 --vary m=-1..2:3:log",
                            "--masses 1,m,1 --vary 2m=1..2:3", "--masses 1,m,1 --vary m=1..2:0"}) {
        INFO(bad);
        const auto r = test::run_cli(std::string("sweep ") + bad + " -o " + dir);
        CHECK(r.status == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
}
