// SPDX-License-Identifier: GPL-3.0-or-later
// classical_test.cpp -- systems beyond chains (SPEC section 8), the classical Newton- and
// Poisson-type laws derived exactly, and the sequential law on walls and planar disks, each
// against a solution that shares nothing with the derivation: the LCPs solved in ball velocities
// by enumerating active sets, and the sequential process simulated impulse by impulse through M
// and W.
#include "derive/derive.hpp"
#include "model/law_json.hpp"
#include "prover/obligations.hpp"
#include "support.hpp"
#include "model/system.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

using namespace impactcert;
using impactcert::test::q;
using impactcert::test::run_cli;
using impactcert::test::source_path;

namespace {

Rational small_rational(std::mt19937_64& rng) {
    // Small numerators and denominators: ties, zeros and boundaries come up often.
    return Rational(static_cast<int>(rng() % 13) - 6, static_cast<int>(1 + rng() % 4));
}

Vector random_u(std::mt19937_64& rng, std::size_t n) {
    Vector u(n);
    for (auto& x : u)
        x = small_rational(rng);
    return u;
}

// Every value the law takes at gamma- = W^T u (several on a boundary) gives `expected`.
void require_law_gives(const Model& m, const Vector& u, const Vector& expected) {
    const Vector gamma = m.contact_velocities(u);
    const auto values = m.values_at(gamma);
    INFO("u- = " << to_string(u) << ", expected u+ = " << to_string(expected));
    REQUIRE(!values.empty());
    for (const auto& g : values)
        REQUIRE(m.post_impact_velocities(u, gamma, g) == expected);
}

System planar_disks() {
    // Three disks of masses 1, 2, 3 (two coordinates each): disk 1 touches disk 2 along (1, 0),
    // disk 2 touches disk 3 along (3/5, 4/5); gamma = n . (v_j - v_i).
    System s;
    s.name = "three-disks";
    s.masses = {q("1"), q("1"), q("2"), q("2"), q("3"), q("3")};
    Matrix W(6, 2);
    W(0, 0) = -1, W(2, 0) = 1;
    W(2, 1) = q("-3/5"), W(3, 1) = q("-4/5"), W(4, 1) = q("3/5"), W(5, 1) = q("4/5");
    s.W = W;
    return s;
}

// A full (coupled) mass matrix on a chain: the case the LCP table lacked (issue 33, 10c).
System coupled_chain() {
    System s;
    s.name = "coupled";
    Matrix M(3, 3);
    M(0, 0) = 2, M(0, 1) = 1, M(1, 0) = 1, M(1, 1) = 2, M(2, 2) = 1;
    s.M = M;
    Matrix W(3, 2);
    W(0, 0) = -1, W(1, 0) = 1, W(1, 1) = -1, W(2, 1) = 1;
    s.W = W;
    return s;
}

} // namespace

TEST_CASE("derive newton and poisson agree with the LCP solved by active sets in ball velocities", "[classical]") {
    struct Case {
        const char* what;
        System system;
        std::vector<Rational> e;
    };
    const std::vector<Case> cases = {
        {"3 equal balls, e = 1", chain_system({q("1"), q("1"), q("1")}, Walls::none), {q("1"), q("1")}},
        {"3 balls 1,2,3, e = 1/2, 3/4", chain_system({q("1"), q("2"), q("3")}, Walls::none), {q("1/2"), q("3/4")}},
        {"4 balls, e = 9/10", chain_system({q("2"), q("1"), q("3"), q("1")}, Walls::none), {q("9/10"), q("9/10"), q("9/10")}},
        {"2 balls and a left wall, e = 1, 1/3", chain_system({q("1"), q("3")}, Walls::left), {q("1"), q("1/3")}},
        {"3 balls and a right wall, e = 1", chain_system({q("1"), q("1"), q("1")}, Walls::right), {q("1"), q("1"), q("1")}},
        {"3 balls, full M (coupled), e = 1, 1/2", coupled_chain(), {q("1"), q("1/2")}},
    };
    std::mt19937_64 rng(20261124);
    for (const auto& c : cases) {
        const Mechanics mech = make_mechanics(c.system);
        for (int kind = 0; kind < 3; ++kind) {
            ClassicalOptions o;
            static_cast<System&>(o) = c.system;
            o.restitution = c.e;
            o.on = kind == 1 ? RestitutionOn::approaching : RestitutionOn::all;
            const Model m(kind == 2 ? derive_poisson(o) : derive_newton(o));
            INFO(c.what << (kind == 0 ? ", newton" : kind == 1 ? ", newton approaching" : ", poisson"));
            // 10,000 or more per law for c = 2 (three systems) and for c = 3 (two systems).
            const std::size_t samples = test::samples(mech.contacts() == 2 ? 10000 / 3 + 1 : 5000);
            for (std::size_t k = 0; k < samples; ++k) {
                const Vector u = random_u(rng, mech.balls());
                const Vector expected = kind == 2 ? simulate_poisson(mech, c.e, u) : simulate_newton(mech, c.e, o.on, u);
                require_law_gives(m, u, expected);
            }
        }
    }
}

TEST_CASE("the independent LCP solution satisfies the Newton law's conditions (negative control: a wrong e fails)", "[classical]") {
    const Mechanics m = make_mechanics(chain_system({q("1"), q("1"), q("1")}, Walls::none));
    const std::vector<Rational> e = {q("1"), q("1")};
    // SPEC section 8: both classical laws give (1,0,0) -> (-1/3, 2/3, 2/3) for three equal elastic balls.
    REQUIRE(simulate_newton(m, e, RestitutionOn::all, test::vec({"1", "0", "0"})) == test::vec({"-1/3", "2/3", "2/3"}));
    REQUIRE(simulate_poisson(m, e, test::vec({"1", "0", "0"})) == test::vec({"-1/3", "2/3", "2/3"}));
    // The engines' law: (0, 1, -1) -> (-2/3, -2/3, 4/3), T from 1 to 4/3.
    const Vector up = simulate_newton(m, e, RestitutionOn::approaching, test::vec({"0", "1", "-1"}));
    REQUIRE(up == test::vec({"-2/3", "-2/3", "4/3"}));
    REQUIRE(m.energy2(up) == q("8/3"));
    // By hand, with no construction shared: three equal balls and a right wall, e = 1, u- = (0, 1, 1).
    // Only the wall approaches; balls 2 and 3 touch (gamma = 0), so Newton's condition at their
    // contact keeps them together: a mass of 2 bouncing off the wall, u+ = (0, -1, -1), with
    // impulses 2 (between 2 and 3) and 4 (the wall), both >= 0. The derived law agrees.
    {
        const System wall = chain_system({q("1"), q("1"), q("1")}, Walls::right);
        const Mechanics mw = make_mechanics(wall);
        const std::vector<Rational> e3 = {q("1"), q("1"), q("1")};
        REQUIRE(simulate_newton(mw, e3, RestitutionOn::all, test::vec({"0", "1", "1"})) == test::vec({"0", "-1", "-1"}));
        ClassicalOptions ow;
        static_cast<System&>(ow) = wall;
        ow.restitution = e3;
        require_law_gives(Model(derive_newton(ow)), test::vec({"0", "1", "1"}), test::vec({"0", "-1", "-1"}));
        // And a single ball against the wall: (0, 0, 1) -> (0, 0, -1).
        require_law_gives(Model(derive_newton(ow)), test::vec({"0", "0", "1"}), test::vec({"0", "0", "-1"}));
    }
    // A law derived with another restitution disagrees with the simulation somewhere.
    ClassicalOptions o;
    o.masses = {q("1"), q("1"), q("1")};
    o.restitution = {q("1/2"), q("1/2")};
    const Model wrong(derive_newton(o));
    const Vector u = test::vec({"1", "0", "0"});
    const Vector gamma = wrong.contact_velocities(u);
    REQUIRE(wrong.post_impact_velocities(u, gamma, wrong.values_at(gamma).at(0)) != simulate_newton(m, e, RestitutionOn::all, u));
}

TEST_CASE("derive sequential on a wall system and on planar disks agrees with the impulse-by-impulse simulation", "[classical]") {
    std::mt19937_64 rng(7);
    const std::vector<std::pair<System, std::vector<Rational>>> cases = {
        {chain_system({q("1"), q("2"), q("1")}, Walls::left), {q("1"), q("1/2"), q("1")}},
        {chain_system({q("1"), q("1")}, Walls::right), {q("1/2"), q("1")}},
        {planar_disks(), {q("1"), q("1/2")}},
    };
    for (const auto& [system, e] : cases) {
        for (auto rule : {ImpactRule::most_negative, ImpactRule::left_first}) {
            DeriveOptions o;
            static_cast<System&>(o) = system;
            o.restitution = e;
            o.rule = rule;
            o.max_impacts = 200;
            const DeriveResult r = derive_sequential(o);
            REQUIRE(r.law);
            const Model m(*r.law);
            INFO(system.name << ", " << to_string(rule));
            for (std::size_t k = 0; k < test::samples(5000); ++k) {
                const Vector u = random_u(rng, m.balls());
                const auto sim = simulate_balls(system, e, rule, u, 10000);
                REQUIRE(sim);
                // The law may be discontinuous: the simulated u+ is one of its values.
                const Vector gamma = m.contact_velocities(u);
                bool found = false;
                for (const auto& g : m.values_at(gamma))
                    found = found || m.post_impact_velocities(u, gamma, g) == *sim;
                INFO("u- = " << to_string(u) << ", simulated " << to_string(*sim));
                REQUIRE(found);
            }
        }
    }
}

TEST_CASE("the classical laws of three equal elastic balls: what each fails, with exact witnesses", "[classical]") {
    struct Expect {
        const char* dir;
        std::vector<const char*> refuted, proved;
    };
    const std::vector<Expect> expected = {
        {"newton", {"P3", "kinematic", "outcomes"}, {"fan", "P1", "P2", "kinetic", "energetic", "nonexpansive", "nonexpansive-lemma"}},
        {"newton-approaching", {"P2", "P3", "energetic", "nonexpansive", "nonexpansive-lemma", "outcomes"},
         {"fan", "P1", "kinematic", "kinetic"}},
        {"poisson", {"P2", "P3", "outcomes"}, {"fan", "P1", "kinematic", "kinetic", "energetic", "nonexpansive", "nonexpansive-lemma"}},
    };
    for (const auto& x : expected) {
        INFO(x.dir);
        const std::string path = source_path(std::string("proofs/classical3/") + x.dir + "/law.json");
        const Model committed = load_model_file(path);
        // The committed law is what derive writes today.
        ClassicalOptions o;
        o.masses = {q("1"), q("1"), q("1")};
        o.restitution = {q("1"), q("1")};
        o.on = std::string(x.dir) == "newton-approaching" ? RestitutionOn::approaching : RestitutionOn::all;
        o.outcomes_override = load_law_file(source_path("proofs/newton3/law.json")).outcomes;
        const Law fresh = std::string(x.dir) == "poisson" ? derive_poisson(o) : derive_newton(o);
        REQUIRE(law_to_json(fresh) == law_to_json(committed.law()));
        const VerifyReport report = verify(committed);
        for (const char* id : x.refuted)
            CHECK(report.at(id).verdict == Verdict::refuted);
        for (const char* id : x.proved)
            CHECK(report.at(id).verdict == Verdict::proved);
        test::require_sound(committed, report); // every witness re-checked, the certificate verified
        // The classical outcome (1,0,0) -> (0,0,1) is missed: S gives (-1/3, 2/3, 2/3).
        const Vector u = test::vec({"1", "0", "0"});
        const Vector gamma = committed.contact_velocities(u);
        const auto values = committed.values_at(gamma);
        REQUIRE(!values.empty()); // (issue 33, 10g: an empty list checked nothing)
        for (const auto& g : values)
            REQUIRE(committed.post_impact_velocities(u, gamma, g) == test::vec({"-1/3", "2/3", "2/3"}));
    }
    // Second route for the two headline witnesses. Newton (all): a ray whose image has a negative
    // component; approaching only: a gamma- whose energy grows.
    const Model newton = load_model_file(source_path("proofs/classical3/newton/law.json"));
    const auto kin = verify(newton).at("kinematic").counterexample;
    const Vector ray = test::vec_of(kin["ray"]);
    const Vector image = newton.pieces()[newton.piece_index(kin["piece"].get<std::string>())].Q * ray;
    REQUIRE(std::any_of(image.begin(), image.end(), [](const Rational& v) { return sign_of(v) == Sign::negative; }));
    const Model engines = load_model_file(source_path("proofs/classical3/newton-approaching/law.json"));
    const auto en = verify(engines).at("energetic").counterexample;
    const Vector g = test::vec_of(en["gamma"]);
    bool gains = false;
    for (const auto& v : engines.values_at(g))
        gains = gains || engines.energy(v) > engines.energy(g);
    REQUIRE(gains);
}

TEST_CASE("systems: files, full mass matrices, and bad systems (exit 2, one line)", "[classical][cli]") {
    const std::string dir = "/tmp/impactcert-classical-test";
    std::filesystem::create_directories(dir);
    auto write = [&](const std::string& name, const std::string& text) {
        std::ofstream(dir + "/" + name) << text;
        return dir + "/" + name;
    };
    // A full SPD mass matrix: derive, verify, certify and check it.
    const std::string full = write("full.json", R"({"format": "impactcert-system/1", "name": "coupled",
        "M": [["2","1","0"],["1","2","0"],["0","0","1"]], "contacts": "chain"})");
    auto run = run_cli("derive newton --system " + full + " -o " + dir + "/full-law.json");
    REQUIRE(run.status == 0);
    // Pinned (issue 33, 10c): with coupled masses the Newton law is not kinematic -- at the ray
    // (-2, 1) of piece J1 the image is (2, -1): the separating contact is made to approach, which
    // Newton's inequality allows (gamma+ + e gamma- = 0); the rest holds. Exit 1 (refuted).
    run = run_cli("certify --law " + dir + "/full-law.json -o " + dir + "/full.cert.json");
    REQUIRE(run.status == 1);
    {
        const Model law = load_model_file(dir + "/full-law.json");
        const VerifyReport report = verify(law);
        for (const char* id : {"P3", "kinematic"})
            CHECK(report.at(id).verdict == Verdict::refuted);
        for (const char* id : {"fan", "P1", "P2", "kinetic", "energetic", "single-impacts", "nonexpansive",
                               "nonexpansive-lemma", "outcomes"})
            CHECK(report.at(id).verdict == Verdict::proved);
        test::require_sound(law, report);
        const auto& w = report.at("kinematic").counterexample;
        const Vector ray = test::vec_of(w["ray"]);
        const Vector image = law.pieces()[law.piece_index(w["piece"].get<std::string>())].Q * ray;
        REQUIRE(std::any_of(image.begin(), image.end(), [](const Rational& v) { return sign_of(v) == Sign::negative; }));
    }
    const auto check = std::system(("'" + std::string(IMPACTCERT_CHECKER) + "' " + dir + "/full.cert.json >/dev/null 2>&1").c_str());
    REQUIRE(WEXITSTATUS(check) == 0);
    const Model coupled = load_model_file(dir + "/full-law.json");
    REQUIRE(coupled.law().M);
    REQUIRE(coupled.M() == *coupled.law().M);
    // Bad systems.
    const std::vector<std::pair<std::string, std::string>> bad = {
        {R"({"format": "impactcert-system/1", "name": "s", "M": [["1","2"],["2","1"]]})", "$.M: not positive definite"},
        {R"({"format": "impactcert-system/1", "name": "s", "M": [["1","1"],["0","1"]]})", "$.M[1][0]: M is not symmetric"},
        {R"({"format": "impactcert-system/1", "name": "s", "masses": ["1","1","1"], "contacts": {"W": [["1"],["1"]]}})",
         "$.contacts.W: expected 3 rows"},
        {R"({"format": "impactcert-system/1", "name": "s", "masses": ["1","1"], "M": [["1","0"],["0","1"]]})",
         "exactly one of \"masses\""},
        {R"({"format": "impactcert-system/1", "name": "s", "masses": ["1","-1"]})", "$.masses[1]: mass must be positive"},
        {R"({"format": "impactcert-system/1", "name": "s", "masses": ["1","1"], "walls": "left"})", "walls"},
    };
    for (const auto& [text, message] : bad) {
        const std::string path = write("bad.json", text);
        for (const char* cmd : {"derive newton --system ", "derive sequential --system ", "derive poisson --system "}) {
            run = run_cli(cmd + path);
            INFO(cmd << text << " -> " << run.err);
            REQUIRE(run.status == 2);
            REQUIRE(run.err.find(message) != std::string::npos);
            REQUIRE(std::count(run.err.begin(), run.err.end(), '\n') == 1);
        }
    }
    // Dependent columns: derive newton reads them (proofs/README.md, "Redundant contacts"), the
    // sequential and Poisson laws refuse them in one line naming the rank.
    {
        const std::string path = write("dependent.json", R"({"format": "impactcert-system/1", "name": "s", "masses": ["1","1"], "contacts": {"W": [["1","2"],["1","2"]]}})");
        for (const char* cmd : {"derive sequential --system ", "derive poisson --system "}) {
            run = run_cli(cmd + path);
            INFO(cmd << " -> " << run.err);
            REQUIRE(run.status == 2);
            REQUIRE(run.err.find("$.contacts.W: 2 contacts but rank 1") != std::string::npos);
            REQUIRE(std::count(run.err.begin(), run.err.end(), '\n') == 1);
        }
        run = run_cli("derive newton --system " + path + " -o " + dir + "/dependent-law.json");
        INFO(run.err);
        REQUIRE(run.status == 0);
        const Model dependent = load_model_file(dir + "/dependent-law.json");
        REQUIRE(dependent.redundant());
        REQUIRE(dependent.contacts() == 1);
    }
    run = run_cli("derive newton --masses 1,1 --walls sideways");
    REQUIRE(run.status == 2);
    run = run_cli("derive newton --masses 1,1 --walls both"); // jammed: 3 contacts, 2 velocities
    REQUIRE(run.status == 2);
    REQUIRE(run.err.find("jammed") != std::string::npos);
    run = run_cli("derive poisson --masses 1,1,1 --restitution-on approaching");
    REQUIRE(run.status == 2);
    run = run_cli("derive newton --masses 1,1,1,1,1,1,1,1,1,1");
    REQUIRE(run.status == 2);
    REQUIRE(run.err.find("at most 8 contacts") != std::string::npos);
    run = run_cli("derive poisson --masses 1,1,1,1,1,1,1"); // c = 6: tens of thousands of cells
    REQUIRE(run.status == 2);
    REQUIRE(run.err.find("at most 5 contacts for the Poisson law") != std::string::npos);
    run = run_cli("derive newton --masses 1,1,1 --system " + full);
    REQUIRE(run.status == 2);
}

// Reliability round four, 1: restitution 0 made the expansion LCP degenerate, and derive poisson
// wrote the same cone with the same matrix more than once (verify refuted `fan`). Now: fan proved,
// no two pieces alike, and the law still agrees with the LCP solved in ball velocities.
TEST_CASE("derive poisson with restitution 0 (and mixed lists): fan proved, every piece distinct", "[classical][reliability]") {
    struct Case {
        const char* what;
        System system;
        std::vector<Rational> e;
    };
    const std::vector<Case> cases = {
        {"3 equal balls, e = 0", chain_system({q("1"), q("1"), q("1")}, Walls::none), {q("0"), q("0")}},
        {"3 balls, e = 0, 1", chain_system({q("1"), q("2"), q("3")}, Walls::none), {q("0"), q("1")}},
        {"4 balls, e = 1, 0, 1", chain_system({q("1"), q("1"), q("1"), q("1")}, Walls::none), {q("1"), q("0"), q("1")}},
        {"2 balls and a left wall, e = 0", chain_system({q("1"), q("3")}, Walls::left), {q("0"), q("0")}},
        {"3 balls and a right wall, e = 0, 1/2, 0", chain_system({q("2"), q("1"), q("2")}, Walls::right), {q("0"), q("1/2"), q("0")}},
        {"planar disks, e = 0, 1", planar_disks(), {q("0"), q("1")}},
    };
    std::mt19937_64 rng(20261126);
    for (const auto& c : cases) {
        INFO(c.what);
        ClassicalOptions o;
        static_cast<System&>(o) = c.system;
        o.restitution = c.e;
        const Law law = derive_poisson(o);
        std::set<std::string> names;
        std::set<std::pair<std::vector<Vector>, std::string>> shapes;
        for (const auto& p : law.pieces) {
            REQUIRE(names.insert(p.name).second);
            std::vector<Vector> rays = *p.rays;
            std::sort(rays.begin(), rays.end());
            std::string qtext;
            for (std::size_t i = 0; i < p.Q.rows(); ++i)
                qtext += to_string(p.Q.row(i)) + ";";
            REQUIRE(shapes.emplace(rays, qtext).second); // no cone with its matrix twice
        }
        const Model m(law);
        const std::vector<std::string> only{"fan"};
        REQUIRE(verify(m, Limits{}, {}, &only).at("fan").verdict == Verdict::proved);
        const Mechanics mech = make_mechanics(c.system);
        for (int k = 0; k < 500; ++k) {
            const Vector u = random_u(rng, mech.balls());
            require_law_gives(m, u, simulate_poisson(mech, c.e, u));
        }
    }
}
