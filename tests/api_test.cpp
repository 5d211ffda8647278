// SPDX-License-Identifier: GPL-3.0-or-later
// api_test.cpp -- the C++ library (include/impactcert/impactcert.hpp) against the command line:
// the same law text, verdict JSON, certificate check, errors and fuzz report for the same
// inputs. Compiled against the public header alone and linked with libimpactcert.so only.
#include <impactcert/impactcert.hpp>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

extern "C" void impactcert_atan2_law(const double* in, double* out); // tests/impls/atan2_law.cpp

namespace ic = impactcert::api;

namespace {

struct Run {
    int status = -1;
    std::string out;
};

// The command line, its standard output captured (standard error discarded).
Run cli(const std::string& args) {
    Run r;
    FILE* p = popen((std::string(IMPACTCERT_CLI) + " " + args + " 2>/dev/null").c_str(), "r");
    REQUIRE(p != nullptr);
    char buf[65536];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, p)) > 0)
        r.out.append(buf, n);
    const int st = pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

std::string scratch(const std::string& name) {
    return "/tmp/impactcert-api-test-" + std::to_string(getpid()) + "-" + name;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A fuzz report without what names the implementation and how to reach it (its description, the
// replay commands, a process's standard error), the times, and nondeterminism (only a separate
// process can answer one input twice differently): what two runs of the same samples must share.
nlohmann::json without_run_details(const std::string& text) {
    nlohmann::json j = nlohmann::json::parse(text);
    for (const char* key : {"seconds", "samples_per_second", "implementation", "stderr"})
        j.erase(key);
    for (const char* section : {"checked_properties", "violations"})
        if (j.contains(section))
            j[section].erase("nondeterministic");
    std::function<void(nlohmann::json&)> walk = [&](nlohmann::json& x) {
        if (x.is_object()) {
            x.erase("replay");
            for (auto& [key, value] : x.items())
                walk(value);
        } else if (x.is_array()) {
            for (auto& value : x)
                walk(value);
        }
    };
    walk(j);
    return j;
}

} // namespace

TEST_CASE("api: a derived law is the command line's, byte for byte, and so is its verdict", "[api]") {
    ic::DeriveOptions o;
    o.restitution = {mpq_class(9, 10)};
    const ic::Derivation d = ic::derive(ic::System::chain({1, 2, 1}), o);
    REQUIRE(d.law);
    const Run derived = cli("derive sequential --masses 1,2,1 --restitution 9/10");
    REQUIRE(derived.status == 0);
    CHECK(d.law->to_json() == derived.out);
    const std::string path = scratch("law.json");
    d.law->write(path);
    CHECK(slurp(path) == derived.out);
    const ic::Report report = ic::verify(*d.law);
    const Run verified = cli("verify --json --law " + path);
    CHECK(report.json == verified.out);
    CHECK(report.exit_status == verified.status);
    // The 3-ball chain at e < 1 is discontinuous (P1 refuted, with its witness), and dissipative.
    CHECK(report.verdict == "refuted");
    CHECK(report.at("P1").verdict == "refuted");
    CHECK(!report.at("P1").counterexample.empty());
    CHECK(report.at("energetic").verdict == "proved");
    CHECK(report.at("P2").claimed == false);
    CHECK_THROWS_AS(report.at("no-such-obligation"), std::out_of_range);
    // Read back, the same law.
    const ic::Law again = ic::Law::read(path);
    CHECK(again.to_json() == derived.out);
    CHECK(again.pieces() == d.law->pieces());
    std::remove(path.c_str());
}

TEST_CASE("api: a refuted claim carries the command line's exact witness", "[api]") {
    // The 3-ball chain at e = 1/2: P1 fails (the law is discontinuous), with a witness.
    ic::DeriveOptions o;
    o.restitution = {mpq_class(1, 2)};
    const ic::Derivation d = ic::derive(ic::System::chain({1, 1, 1}), o);
    REQUIRE(d.law);
    const ic::Report report = ic::verify(*d.law);
    const std::string path = scratch("four.json");
    d.law->write(path);
    const Run verified = cli("verify --json --law " + path);
    std::remove(path.c_str());
    CHECK(report.json == verified.out);
    bool refuted = false;
    for (const auto& ob : report.obligations)
        if (ob.verdict == "refuted") {
            refuted = true;
            CHECK(!ob.counterexample.empty());
            CHECK(verified.out.find(ob.id) != std::string::npos);
        }
    CHECK(refuted);
    CHECK(report.exit_status == 1);
}

TEST_CASE("api: certify, and the independent checker verifies it, a changed byte is not verified", "[api]") {
    const ic::Law paper = ic::Law::paper();
    ic::Report report;
    const std::string cert = ic::certify(paper, {}, &report);
    CHECK(report.verdict == "proved");
    const ic::CheckResult ok = ic::check_certificate(cert);
    CHECK(ok.exit_status == 0);
    // The checker's own program agrees on the same text.
    const std::string path = scratch("paper.cert.json");
    {
        std::ofstream out(path);
        out << cert;
    }
    const int checked = std::system((std::string(IMPACTCERT_CHECKER) + " " + path + " >/dev/null 2>&1").c_str());
    CHECK(WEXITSTATUS(checked) == 0);
    std::remove(path.c_str());
    // Negative control: one digit of the evidence changed.
    std::string bad = cert;
    const auto at = bad.find("\"2\"");
    REQUIRE(at != std::string::npos);
    bad[at + 1] = '3';
    const ic::CheckResult rejected = ic::check_certificate(bad);
    CHECK(rejected.exit_status != 0);
    CHECK(!rejected.message.empty());
}

TEST_CASE("api: exact evaluation, with the pieces that hold the point", "[api]") {
    const ic::Law paper = ic::Law::paper();
    CHECK(paper.contacts() == 2);
    CHECK(paper.velocities() == 3);
    const auto v = paper.evaluate({-1, 0});
    REQUIRE(v.size() == 1);
    CHECK(v[0] == ic::Vector{0, 1});
    const auto w = paper.evaluate({mpq_class(-3, 7), mpq_class(1, 5)});
    REQUIRE(w.size() == 1);
    // gamma- in cone IIa or IIb of the paper's law: check against the command line's eval.
    const Run e = cli("eval -- -3/7 1/5");
    REQUIRE(e.status == 0);
    CHECK(e.out == w[0][0].get_str() + " " + w[0][1].get_str() + "\n");
    CHECK(!paper.pieces_at({-1, 1}).empty());
    // Its picture is the report's: the cones in the metric H (two contacts), on the sphere (three).
    const std::string svg = paper.figure_svg();
    CHECK(svg.rfind("<svg", 0) == 0);
    CHECK(svg.find("newton3-sequential") != std::string::npos);
    const Run report = cli("report --bare-figures -o " + scratch("report"));
    CHECK(report.status == 0);
    // The report's file frames that drawing (a margin, a white ground): the drawing's body is in it.
    CHECK(slurp(scratch("report") + "/figures/cones.svg").find(svg.substr(svg.find('>') + 1)) != std::string::npos);
    const ic::Law four = ic::derive(ic::System::chain({1, 1, 1, 1})).law.value();
    CHECK(four.figure_svg().find("<svg") == 0);
    CHECK_THROWS_AS(paper.evaluate({1}), ic::InputError);
    ic::Vector zero_den{1, 1};
    zero_den[0].get_den() = 0;
    CHECK_THROWS_AS(paper.evaluate(zero_den), ic::InputError);
}

TEST_CASE("api: bad input and limits are the command line's errors, with its exit statuses", "[api]") {
    const std::string path = scratch("bad.json");
    {
        std::ofstream out(path);
        out << "{\"format\": \"impactcert-law/1\", \"name\": \"x\"}";
    }
    try {
        (void)ic::Law::read(path);
        FAIL("read a law without pieces");
    } catch (const ic::InputError& e) {
        CHECK(e.exit_status() == 2);
        FILE* p = popen((std::string(IMPACTCERT_CLI) + " verify --law " + path + " 2>&1 >/dev/null").c_str(), "r");
        char buf[4096] = {};
        const std::size_t n = std::fread(buf, 1, sizeof buf - 1, p);
        pclose(p);
        const std::string line(buf, n);
        // The command line prints "impactcert: MESSAGE" (its message is the library's).
        CHECK(line.find(e.what()) != std::string::npos);
    }
    std::remove(path.c_str());
    CHECK_THROWS_AS(ic::System::chain({1, -1}), ic::InputError);
    CHECK_THROWS_AS(ic::System::parse("[1, 2]"), ic::InputError);
    ic::DeriveOptions o;
    o.max_impacts = 1; // the 3-ball chain at e = 1 needs 3 impacts at gamma- = (-1, 0)... some need more
    try {
        (void)ic::derive(ic::System::chain({1, 1, 1}), o);
        FAIL("derived with one impact at most");
    } catch (const ic::LimitError& e) {
        CHECK(e.exit_status() == 3);
        CHECK(std::string(e.what()).find("--max-impacts") != std::string::npos);
    }
    o.max_impacts = 100;
    o.restitution = {1, 1, 1};
    CHECK_THROWS_AS(ic::derive(ic::System::chain({1, 1, 1}), o), ic::InputError);
}

TEST_CASE("api: fuzzing a callable in-process gives the command line's report for the same function", "[api]") {
    // The deliberately wrong atan2 classification (tests/impls/atan2_law.cpp), in-process and
    // through --impl LIB.so:SYMBOL: the same samples, violations, coverage and examples.
    ic::FuzzOptions o; // the default tolerance: 0 ulps, as the command line's
    o.samples = 4000;
    o.seed = 7;
    const ic::FuzzResult r = ic::fuzz(
        ic::Law::paper(),
        [](const double* in, double* out, std::size_t count) {
            for (std::size_t i = 0; i < count; ++i)
                impactcert_atan2_law(in + 2 * i, out + 2 * i);
        },
        o);
    const Run run = cli(std::string("fuzz --json --jobs 1 --samples 4000 --seed 7 --impl ") +
                        IMPACTCERT_EXAMPLE_IMPL);
    CHECK(run.status == 1);
    CHECK(r.exit_status == 1);
    CHECK(r.verdict == "violations");
    CHECK(r.violating > 0);
    CHECK(r.samples == 4000);
    CHECK(without_run_details(r.json) == without_run_details(run.out));
    // A correct callable (the exact value of each piece, rounded: the paper's law is integer
    // matrices, so exact in double away from overflow) has no violation; the range keeps it away.
    ic::FuzzOptions fine = o;
    fine.range = "1e-100..1e100";
    fine.max_ulps = 1; // mpq_class::get_d truncates: within one ulp, not correctly rounded
    const ic::FuzzResult good = ic::fuzz(
        ic::Law::paper(),
        [](const double* in, double* out, std::size_t count) {
            for (std::size_t i = 0; i < count; ++i) {
                const double g1 = in[2 * i], g2 = in[2 * i + 1];
                const ic::Vector exact = ic::Law::paper().evaluate({mpq_class(g1), mpq_class(g2)}).front();
                out[2 * i] = exact[0].get_d();
                out[2 * i + 1] = exact[1].get_d();
            }
        },
        fine);
    CHECK(good.verdict == "no violation");
    CHECK(good.exit_status == 0);
    // The callable's exception is the caller's: it comes out of fuzz().
    CHECK_THROWS_WITH(ic::fuzz(
                          ic::Law::paper(), [](const double*, double*, std::size_t) { throw std::runtime_error("mine"); }, o),
                      "mine");
    CHECK_THROWS_AS(ic::fuzz(ic::Law::paper(), ic::BatchFunction{}, o), ic::InputError);
}

TEST_CASE("api: consistency fuzzing in-process gives the command line's report for the same map", "[api]") {
    // The map that changes nothing (tests/impls/echo_impl.cpp through the pipe): balls pass
    // through each other, a kinematic violation wherever a contact approaches.
    ic::ConsistencyOptions o;
    o.samples = 600;
    o.seed = 3;
    o.velocities = true;
    o.max_rel_error = 1e-6;
    o.reference = "approaching";
    o.restitution = ic::Vector{1};
    const ic::FuzzResult r = ic::fuzz_consistency(
        ic::System::chain({1, 2, 1}),
        [](const double* in, double* out, std::size_t count) { std::copy(in, in + 3 * count, out); }, o);
    CHECK(r.verdict == "violations");
    CHECK(r.exit_status == 1);
    const Run run = cli(std::string("fuzz --json --jobs 1 --masses 1,2,1 --velocities --samples 600 --seed 3 "
                                    "--max-rel-error 1e-6 --reference approaching --restitution 1 --impl-cmd ") +
                        IMPACTCERT_ECHO_IMPL);
    CHECK(run.status == 1);
    CHECK(without_run_details(r.json) == without_run_details(run.out));
    // Bad options are the command line's errors.
    ic::ConsistencyOptions bad = o;
    bad.reference = "sideways";
    CHECK_THROWS_AS(ic::fuzz_consistency(ic::System::chain({1, 2, 1}), [](const double*, double*, std::size_t) {}, bad),
                    ic::InputError);
    bad = o;
    bad.seconds = std::nan("");
    CHECK_THROWS_WITH(ic::fuzz_consistency(ic::System::chain({1, 2, 1}), [](const double*, double*, std::size_t) {}, bad),
                      "--seconds: must be a finite number >= 0");
    bad = o;
    bad.restitution = ic::Vector{2};
    CHECK_THROWS_WITH(ic::fuzz_consistency(ic::System::chain({1, 2, 1}), [](const double*, double*, std::size_t) {}, bad),
                      Catch::Contains("--restitution: contact 1 must be in [0, 1]"));
}
