// SPDX-License-Identifier: GPL-3.0-or-later
// reliability_test.cpp -- issue 18: no signal, no runaway, no lost write, on the inputs impactcert
// itself produces. Each case is a reproduction of a defect found by review, named after it.
#include "prover/certificate.hpp"
#include "derive/derive.hpp"
#include "impactcert_check.hpp"
#include "exact/exact_double.hpp"
#include "fuzz/fuzz.hpp"
#include "model/law_json.hpp"
#include "prover/obligations.hpp"
#include "model/paper_law.hpp"
#include "report/report.hpp"
#include "sweep/sweep.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <csignal>

#include <cctype>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <tuple>

using namespace impactcert;
using impactcert::test::q;
using impactcert::test::run_cli;

namespace {

// The paper's law in the coordinates gamma' = D gamma, D = diag(d1, d2): W' = W D, Q' = D Q D^-1,
// rays' = D rays. Every obligation still holds (H' = D^-1 H D^-1).
Law scaled_paper(const Rational& d1, const Rational& d2) {
    Law law = paper_law();
    Matrix D(2, 2), Di(2, 2);
    D(0, 0) = d1, D(1, 1) = d2;
    Di(0, 0) = Rational(1) / d1, Di(1, 1) = Rational(1) / d2;
    Matrix W(3, 2);
    W(0, 0) = -1, W(1, 0) = 1, W(1, 1) = -1, W(2, 1) = 1;
    law.W = W * D;
    law.name = "paper-scaled";
    for (auto& p : law.pieces) {
        const Matrix Qi = *inverse(p.Q);
        std::vector<Vector> rays;
        for (std::size_t k = 0; k < 2; ++k)
            rays.push_back(D * (p.rays ? (*p.rays)[k] : Qi.column(k)));
        p.rays = rays;
        p.Q = D * p.Q * Di;
    }
    return law;
}

Rational power_of_two(int e) {
    Rational r(1);
    const Rational two = e >= 0 ? Rational(2) : Rational(1, 2);
    for (int i = 0; i < std::abs(e); ++i)
        r *= two;
    return r;
}

// "nan" or "inf" as a word of its own (printf's output for a non-finite double), not inside
// "Winandy" or "infinite".
bool has_non_number(const std::string& text) {
    for (const char* word : {"nan", "inf"})
        for (auto at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
            const bool before = at > 0 && std::isalpha(static_cast<unsigned char>(text[at - 1]));
            const bool after = at + 3 < text.size() && std::isalpha(static_cast<unsigned char>(text[at + 3]));
            if (!before && !after)
                return true;
        }
    return false;
}

fuzz::Summary fuzz_float_law(const Model& model, std::uint64_t samples) {
    const VerifyReport report = verify(model);
    const bool continuous = report.at("fan").verdict == Verdict::proved && report.at("P1").verdict == Verdict::proved;
    const fuzz::LawReference ref(model, false, continuous);
    const auto impl = fuzz::builtin_float_law(model);
    fuzz::Options o;
    o.samples = samples;
    o.jobs = 1;
    o.tolerance = fuzz::Tolerance::stated_bound;
    return fuzz::run(o, ref, *impl, fuzz::Properties{}, nullptr);
}

} // namespace

TEST_CASE("defect 18.1 check: no non-finite double reaches an exact conversion", "[reliability]") {
    REQUIRE(exact_of_double(0.5) == q("1/2"));
    REQUIRE(!exact_of_double(INFINITY));
    REQUIRE(!exact_of_double(std::nan("")));
    REQUIRE_THROWS_AS(exact_double(-INFINITY, "test"), std::logic_error);
}

TEST_CASE("defect 18.1 fail: fuzz on derived laws with extreme masses ran into SIGFPE", "[reliability]") {
    struct Case {
        std::vector<const char*> masses;
        const char* e;
        ImpactRule rule;
    };
    for (const Case& c : {Case{{"1", "1", "100000000000000000000"}, "1", ImpactRule::most_negative},
                          Case{{"1/1000000000000000000000000000000", "1", "1000000000000000000000000000000"}, "1", ImpactRule::most_negative},
                          Case{{"1000000000000000000000000000000", "1", "1/1000000000000000000000000000000"}, "1/2", ImpactRule::most_negative},
                          Case{{"1", "1000000000000000000000000000000", "1"}, "1", ImpactRule::left_first}}) {
        DeriveOptions o;
        for (auto m : c.masses)
            o.masses.push_back(q(m));
        o.restitution.assign(2, q(c.e));
        o.rule = c.rule;
        const DeriveResult r = derive_sequential(o);
        REQUIRE(r.law);
        const Model model(*r.law);
        const fuzz::Summary sum = fuzz_float_law(model, 20000);
        INFO(c.masses[0] << "," << c.masses[1] << "," << c.masses[2]);
        REQUIRE(sum.samples == 20000);
        // No violation of any kind (issue 33, 10b: `inaccurate == 0` alone let an output of inf
        // or NaN pass): within the stated bound, finite, in a cone, the right piece's formula.
        CHECK(sum.inaccurate == 0);
        CHECK(sum.non_finite == 0);
        CHECK(sum.misclassified == 0);
        CHECK(sum.outside == 0);
        CHECK(sum.violations() == 0);
    }
}

TEST_CASE("defect 18.1 fail: the paper's law in scaled coordinates, proved and fuzzed cleanly", "[reliability]") {
    for (const auto& [e1, e2] : std::vector<std::pair<int, int>>{{100, 0}, {60, -60}, {300, 0}, {-300, 0}, {512, -512}}) {
        INFO("diag(2^" << e1 << ", 2^" << e2 << ")");
        const Model model(scaled_paper(power_of_two(e1), power_of_two(e2)));
        REQUIRE(verify(model).exit_status() == 0);
        const fuzz::Summary sum = fuzz_float_law(model, 20000);
        REQUIRE(sum.samples == 20000);
        CHECK(sum.non_finite == 0);
        CHECK(sum.outside == 0);
        CHECK(sum.violations() == 0);
    }
}

TEST_CASE("defect 18.6 fail: a certificate with a repeated key is malformed, wherever the key is", "[reliability]") {
    const std::string text = test::read_file(test::source_path("proofs/newton3/certificate.json"));
    REQUIRE(impactcert_check::check_text(text).status == impactcert_check::kVerified); // positive control
    // The law's name twice (first-wins and last-wins readers would see different laws), a key
    // repeated deep inside an obligation, and at the top level.
    struct Mutation {
        std::string after, insert, path;
    };
    for (const Mutation& m : {Mutation{"\"name\": \"newton3-sequential\"", ", \"name\": \"other\"", "$.law.name"},
                              Mutation{"\"format\": \"impactcert-certificate/1\"", ", \"format\": \"impactcert-certificate/1\"", "$.format"}}) {
        std::string mutated = text;
        const auto at = mutated.find(m.after);
        REQUIRE(at != std::string::npos);
        mutated.insert(at + m.after.size(), m.insert);
        const auto outcome = impactcert_check::check_text(mutated);
        INFO(outcome.message);
        REQUIRE(outcome.status == impactcert_check::kMalformed);
        REQUIRE(outcome.message.find(m.path + ": duplicate key") != std::string::npos);
    }
    // An object with 100,000 keys is refused at once (key lookups are linear in nlohmann's ordered
    // objects: read whole, it took minutes).
    std::string many = "{";
    for (int k = 0; k < 100000; ++k)
        many += std::string(k ? "," : "") + "\"k" + std::to_string(k) + "\": 0";
    const auto wide = impactcert_check::check_text(many + "}");
    REQUIRE(wide.status == impactcert_check::kMalformed);
    REQUIRE(wide.message.find("more than 4096 keys") != std::string::npos);
    // A repeated key inside an array element: the path names the element.
    std::string mutated = text;
    const auto ray = mutated.find("\"rays\": [");
    REQUIRE(ray != std::string::npos);
    const auto piece_name = mutated.rfind("\"name\"", ray);
    mutated.insert(piece_name, "\"name\": \"x\", ");
    const auto outcome = impactcert_check::check_text(mutated);
    INFO(outcome.message);
    REQUIRE(outcome.status == impactcert_check::kMalformed);
    REQUIRE(outcome.message.find("$.law.pieces[0].name: duplicate key \"name\"") != std::string::npos);
}

TEST_CASE("defect 18.7 fail: fuzz refuses a law beyond its dimension before any proof work", "[reliability][cli]") {
    // One piece, c = 40 (Q = I, the orthant's rays): refused at once, with the limit named.
    std::string rows, ones;
    for (int i = 0; i < 40; ++i) {
        std::string row;
        for (int j = 0; j < 40; ++j)
            row += std::string(j ? "," : "") + (i == j ? "\"1\"" : "\"0\"");
        rows += std::string(i ? "," : "") + "[" + row + "]";
    }
    for (int i = 0; i < 41; ++i)
        ones += std::string(i ? "," : "") + "\"1\"";
    const std::string path = "/tmp/impactcert-reliability-c40.json";
    std::ofstream(path) << R"({"format": "impactcert-law/1", "name": "c40", "masses": [)" << ones
                        << R"(], "pieces": [{"name": "I", "Q": [)" << rows << "], \"rays\": [" << rows << "]}]}";
    for (const char* cmd : {"fuzz --samples 10 --law ", "eval --float --impl-cmd cat --law "}) {
        std::string zeros;
        for (int i = 0; i < 40; ++i)
            zeros += " 0";
        const auto run = run_cli(cmd + path + (std::string(cmd).find("eval") != std::string::npos ? " --" + zeros : ""));
        INFO(cmd << " -> " << run.err);
        REQUIRE(run.status == 2);
        REQUIRE(run.err.find("at most 32") != std::string::npos);
    }
}

TEST_CASE("defect 18.9 fail: unsigned options refuse -1, 2^64 and non-integers as written", "[reliability][cli]") {
    for (const char* args : {"derive cradle --balls -1", "derive cradle --balls 18446744073709551616", "verify --max-faces -1",
                             "verify --max-pieces 1e6", "verify --jobs -2", "fuzz --jobs -1", "fuzz --keep -1",
                             "derive sequential --masses 1,1 --max-impacts -1", "sweep --masses 1,m --vary m=1..2:2 --jobs -1 -o /tmp/x",
                             "fuzz --samples -1", "fuzz --samples nan", "fuzz --impl-timeout 0", "fuzz --seconds nan"}) {
        const auto run = run_cli(args);
        INFO(args << " -> " << run.err);
        REQUIRE(run.status == 2);
        REQUIRE(std::count(run.err.begin(), run.err.end(), '\n') == 1);
        REQUIRE(run.err.find("18446744073709551615") == std::string::npos);
        REQUIRE(run.err.size() < 200);
    }
    // A positive control: the same options with valid values.
    REQUIRE(run_cli("derive cradle --balls 3").status == 0);
}

TEST_CASE("defect 18.3 fail: sweep validates before work, grids at any scale, bounded, and workers that cannot write", "[reliability][cli][sweep]") {
    // (b) an invalid constant is refused before a 3,000-point log grid is built.
    auto run = run_cli("sweep --masses 1,m,1 --restitution -1 --vary m=1/4..4:3000:log -o /tmp/impactcert-rel-sweep");
    REQUIRE(run.status == 2);
    REQUIRE(run.err.find("--restitution: -1 = -1 is outside [0, 1]") != std::string::npos);
    // (d) a log grid below 1/1000 is logarithmic and positive; (c) at 10^100000 it answers, and the
    // derivation at such masses is undecided (--max-bits), recorded as such.
    const std::string dir = "/tmp/impactcert-rel-sweep";
    std::filesystem::remove_all(dir);
    run = run_cli("sweep --masses 1,m,1 --vary m=1e-10..1:3:log --jobs 1 -o " + dir);
    REQUIRE(run.status == 0);
    std::string csv = test::read_file(dir + "/sweep.csv");
    REQUIRE(csv.find("\n1/10000000000,") != std::string::npos);
    REQUIRE(csv.find("\n1/100000,") != std::string::npos);
    REQUIRE(csv.find("\n1,") != std::string::npos);
    run = run_cli("sweep --masses 1,m,1 --vary m=1..1e100000:3:log --jobs 2 -o " + dir);
    REQUIRE(run.status == 0);
    csv = test::read_file(dir + "/sweep.csv");
    REQUIRE(csv.find(",undecided\n") != std::string::npos);
    REQUIRE(csv.find("\n1,proved,") != std::string::npos);
    // Ticks at any scale are short (a 50,001-digit label held a PDF converter for minutes).
    const std::string fan = test::read_file(dir + "/figures/fan.svg");
    CHECK(fan.find("</title>1e+100000</text>") != std::string::npos);
    CHECK(fan.find("</title>1e+50000</text>") != std::string::npos);
    // A log grid keeps distinct points at any count: 3,000 between 1/4 and 4 (needs 5 digits).
    SweepParameter p = parse_vary("m=1/4..4:3000:log");
    const auto values = grid_values(p);
    REQUIRE(values.size() == 3000);
    REQUIRE(values.front() == q("1/4"));
    REQUIRE(values.back() == q("4"));
    for (std::size_t i = 1; i < values.size(); ++i)
        REQUIRE(values[i - 1] < values[i]);
    REQUIRE(values[1500] > q("0.99"));
    REQUIRE(values[1500] < q("1.01"));
    // (e) 10^8 points are refused before anything is built: undecided, naming --max-points.
    run = run_cli("sweep --masses 1,m,e --vary m=1..2:10000 --vary e=0..1:10000 -o " + dir);
    REQUIRE(run.status == 3);
    REQUIRE(run.err.find("--max-points") != std::string::npos);
    // (a) worker part files that cannot be created: one line, exit 2 (not an internal error).
    run = run_cli("sweep --masses 1,m,1 --vary m=1/2..2:3 --jobs 2 -o /proc/self");
    REQUIRE(run.status == 2);
    std::filesystem::create_directories(dir + "-blocked/.sweep-part-0");
    run = run_cli("sweep --masses 1,m,1 --vary m=1/2..2:3 --jobs 2 -o " + dir + "-blocked");
    REQUIRE(run.status == 2);
    REQUIRE(run.err.find(".sweep-part-0: cannot write") != std::string::npos);
}

TEST_CASE("defect 18.4 fail: derive bounds the size of its numbers, and shortens its witnesses", "[reliability][cli]") {
    for (const char* args : {"--masses 1,1,1 --restitution 1e-1000", "--masses 1,1,1 --restitution 1e-100000",
                             "--masses 1,1e50000,1"}) {
        const auto run = run_cli(std::string("derive sequential ") + args);
        INFO(args << " -> " << run.err);
        REQUIRE(run.status == 3);
        REQUIRE(run.err.find("--max-bits") != std::string::npos);
        REQUIRE(run.err.size() < 300);
    }
    for (const char* args : {"newton --masses 1,1e50000,1", "poisson --masses 1,1,1 --restitution 1e-100000"}) {
        const auto run = run_cli(std::string("derive ") + args);
        INFO(args << " -> " << run.err);
        REQUIRE(run.status == 3);
    }
    // A long witness: one short line on stderr, the exact gamma- in --json (and it does exceed
    // the bound: the sequence, simulated exactly, is longer).
    const auto run = run_cli("derive sequential --masses 1,1,1 --restitution 1e-10 --json");
    REQUIRE(run.status == 3); // a limit (--max-impacts), not a refutation
    REQUIRE(run.err.find("--max-impacts") != std::string::npos);
    REQUIRE(run.err.size() < 400);
    REQUIRE(run.err.find('~') != std::string::npos);
    const Json j = Json::parse(run.out);
    const Vector gamma = test::vec_of(j["gamma_minus"]);
    DeriveOptions o;
    o.masses = {q("1"), q("1"), q("1")};
    o.restitution = {q("1/10000000000"), q("1/10000000000")};
    const auto [word, finished] = sequential_word(o, o.restitution, o.rule, gamma, 100);
    REQUIRE(!finished);
    // A positive control: the same restitution with a higher bound derives.
    REQUIRE(run_cli("derive sequential --masses 1,1,1 --restitution 1/2").status == 0);
}

TEST_CASE("defect 18.5 fail: every output stream and file is flushed and checked (a full disk is exit 2)", "[reliability][cli]") {
    for (const char* cmd :
         {"verify --junit /dev/full", "certify -o /dev/full", "derive cradle --balls 4 -o /dev/full",
          "derive newton --masses 1,1,1 -o /dev/full", "derive sequential --masses 1,1,1 -o /dev/full",
          "smt -o /proc/self", "report -o /proc/self", "fuzz --samples 100 --junit /dev/full",
          "sweep --masses 1,m,1 --vary m=1..2:2 --jobs 1 -o /proc/self", "verify > /dev/full", "verify --json > /dev/full",
          "derive cradle --balls 4 > /dev/full", "derive sequential --masses 1,1,1 > /dev/full", "eval -- -1 0 > /dev/full",
          "eval --float -- -1 0 > /dev/full", "smt -o /tmp/impactcert-rel-smt > /dev/full", "fuzz --samples 100 > /dev/full",
          "fuzz --samples 100 --json > /dev/full"}) {
        const auto run = run_cli(cmd);
        INFO(cmd << " -> " << run.err);
        REQUIRE(run.status == 2);
        REQUIRE(std::count(run.err.begin(), run.err.end(), '\n') == 1);
        REQUIRE(run.err.find("cannot write") != std::string::npos);
    }
    // Positive control: the same to a writable place.
    REQUIRE(run_cli("verify --junit /tmp/impactcert-rel-junit.xml").status == 0);
}

TEST_CASE("defect 18.8 fail: report draws exact directions at any scale (no nan, no inf)", "[reliability][report]") {
    for (const auto& [e1, e2] : std::vector<std::pair<int, int>>{{1000, -1000}, {-1000, 1000}, {0, 0}}) {
        INFO("diag(2^" << e1 << ", 2^" << e2 << ")");
        const Model model(scaled_paper(power_of_two(e1), power_of_two(e2)));
        const VerifyReport report = verify(model);
        REQUIRE(report.exit_status() == 0);
        const std::string html = report_html(model, report);
        REQUIRE(html.find("<svg") != std::string::npos);
        REQUIRE(!has_non_number(html));
    }
    // A refuted law in those coordinates: its counterexample marks are drawn too, finite.
    Law law = scaled_paper(power_of_two(1000), power_of_two(-1000));
    std::swap(law.pieces[0].Q, law.pieces[1].Q);
    law.identities.clear();
    law.single_impacts.clear();
    law.outcomes.clear();
    law.claims.reset();
    const Model bad(law);
    const VerifyReport report = verify(bad);
    REQUIRE(report.exit_status() == 1);
    const std::string html = report_html(bad, report);
    REQUIRE(html.find("class=\"counterexample\"") != std::string::npos);
    REQUIRE(!has_non_number(html));
}

namespace {

// Runs a command under a 1 GB address-space cap; returns the exit status (-1 for a signal).
// AddressSanitizer reserves terabytes of address space for its shadow: no cap in that build.
// Under AddressSanitizer no address-space cap applies (its shadow memory needs the space), so
// the expansions that must stop at the byte budget stop at a smaller one there: the same
// decision, on a tenth of the numbers (the Release run keeps the defaults and the 1 GB cap).
#ifdef IMPACTCERT_SANITIZER_BUILD
const std::string kBudget = " --max-memory 64";
#else
const std::string kBudget;
#endif

int capped(const std::string& command, std::string* err = nullptr) {
#ifdef IMPACTCERT_SANITIZER_BUILD
    const std::string cap;
#else
    const std::string cap = "ulimit -v 1000000; ";
#endif
    const std::string err_path = "/tmp/impactcert-rel-capped.err";
    const int status = std::system((cap + command + " >/dev/null 2>" + err_path).c_str());
    if (err)
        *err = test::read_file(err_path);
    if (!WIFEXITED(status))
        return -1;
    return WEXITSTATUS(status);
}

std::string compact_flips_law(int c) {
    // H = I (unit masses, W = I), one listed orthant, the c sign flips: 2^c orthants in all.
    auto matrix = [&](int flip) {
        std::string rows;
        for (int i = 0; i < c; ++i) {
            std::string row;
            for (int j = 0; j < c; ++j)
                row += std::string(j ? "," : "") + (i != j ? "\"0\"" : i == flip ? "\"-1\"" : "\"1\"");
            rows += std::string(i ? "," : "") + "[" + row + "]";
        }
        return "[" + rows + "]";
    };
    std::string masses, syms;
    for (int i = 0; i < c; ++i) {
        masses += std::string(i ? "," : "") + "\"1\"";
        syms += std::string(i ? "," : "") + "{\"name\": \"f" + std::to_string(i + 1) + "\", \"P\": " + matrix(i) +
                ", \"P_prime\": " + matrix(i) + "}";
    }
    return R"({"format": "impactcert-law/1", "name": "flips", "masses": [)" + masses + R"(], "contacts": {"W": )" +
           matrix(-1) + R"(}, "pieces": [{"name": "o", "Q": )" + matrix(-1) + R"(, "rays": )" + matrix(-1) +
           R"(}], "symmetries": [)" + syms + R"(], "pieces_listed": "orbit-representatives", "claims": ["fan", "P1"]})";
}

const char* kRotations = R"({"format": "impactcert-law/1", "name": "rot", "masses": ["1", "1"],
    "contacts": {"W": [["1", "0"], ["0", "1"]]},
    "pieces": [{"name": "o", "Q": [["1", "0"], ["0", "1"]], "rays": [["1", "0"], ["0", "1"]]}],
    "symmetries": [{"name": "a", "P": [["3/5", "-4/5"], ["4/5", "3/5"]], "P_prime": [["3/5", "-4/5"], ["4/5", "3/5"]]},
                   {"name": "b", "P": [["5/13", "-12/13"], ["12/13", "5/13"]], "P_prime": [["5/13", "-12/13"], ["12/13", "5/13"]]}],
    "pieces_listed": "orbit-representatives", "claims": ["fan"]})";

// In R^4, two rotations whose traces cancel: tr P is an integer (0), the coefficient of x^2 in
// det(xI - P) is 14/25 (Lemma S0 needs every coefficient, not the trace alone).
const char* kCancelling = R"({"format": "impactcert-law/1", "name": "p4", "masses": ["1", "1", "1", "1"],
    "contacts": {"W": [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]]},
    "pieces": [{"name": "o", "Q": [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]]}],
    "symmetries": [{"name": "a", "P": [["3/5", "-4/5", "0", "0"], ["4/5", "3/5", "0", "0"], ["0", "0", "-3/5", "-4/5"], ["0", "0", "4/5", "-3/5"]],
                    "P_prime": [["1", "0", "0", "0"], ["0", "1", "0", "0"], ["0", "0", "1", "0"], ["0", "0", "0", "1"]]}],
    "pieces_listed": "orbit-representatives", "claims": ["fan"]})";

// Two reflections of order 2 whose product is the rotation above: not refused by Lemma S0 (each
// generator has finite order); the growth rule stops the expansion.
const char* kReflections = R"({"format": "impactcert-law/1", "name": "refl", "masses": ["1", "1"],
    "contacts": {"W": [["1", "0"], ["0", "1"]]},
    "pieces": [{"name": "o", "Q": [["1", "0"], ["0", "1"]], "rays": [["1", "0"], ["0", "1"]]}],
    "symmetries": [{"name": "a", "P": [["1", "0"], ["0", "-1"]], "P_prime": [["1", "0"], ["0", "-1"]]},
                   {"name": "b", "P": [["3/5", "4/5"], ["4/5", "-3/5"]], "P_prime": [["3/5", "4/5"], ["4/5", "-3/5"]]}],
    "pieces_listed": "orbit-representatives", "claims": ["fan"]})";

} // namespace

TEST_CASE("defect 18.2 fail: memory is budgeted in bytes, growth is stopped, under a 1 GB cap", "[reliability][cli]") {
    const std::string dir = "/tmp/impactcert-rel-memory";
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/flips20.json") << compact_flips_law(20);
    std::ofstream(dir + "/flips4.json") << compact_flips_law(4);
    std::ofstream(dir + "/rot.json") << kRotations;
    std::ofstream(dir + "/refl.json") << kReflections;
    std::ofstream(dir + "/p4.json") << kCancelling;
    const std::string cli = std::string("'") + IMPACTCERT_CLI + "' ";
    const std::string checker = std::string("'") + IMPACTCERT_CHECKER + "' ";
    std::string err;
    // (b) verify: 2^20 orthants of c = 20 stop at the byte budget, one line naming --max-memory.
    REQUIRE(capped(cli + "verify --law " + dir + "/flips20.json" + kBudget, &err) == 2);
    REQUIRE(err.find("--max-memory") != std::string::npos);
    REQUIRE(std::count(err.begin(), err.end(), '\n') == 1);
    // (c) two rational rotations: refused at once (Lemma S0: each is of infinite order), and two
    // reflections whose product is a rotation: the numbers grow, stopped by the growth rule.
    REQUIRE(capped(cli + "verify --law " + dir + "/rot.json", &err) == 2);
    REQUIRE(err.find("$.symmetries[0].P: of infinite order") != std::string::npos);
    REQUIRE(capped(cli + "verify --law " + dir + "/rot.json --stream", &err) == 2);
    REQUIRE(err.find("$.symmetries[0].P: of infinite order") != std::string::npos);
    REQUIRE(capped(cli + "verify --law " + dir + "/p4.json", &err) == 2);
    REQUIRE(err.find("$.symmetries[0].P: of infinite order: the coefficient of x^2 in det(xI - P) is 14/25") != std::string::npos);
    REQUIRE(capped(cli + "verify --law " + dir + "/p4.json --stream", &err) == 2);
    REQUIRE(err.find("$.symmetries[0].P: of infinite order") != std::string::npos);
    REQUIRE(capped(cli + "verify --law " + dir + "/refl.json", &err) == 2);
    REQUIRE(err.find("the numbers grow (a symmetry of infinite order?)") != std::string::npos);
    // Positive control: the same construction with 16 orthants is proved.
    REQUIRE(capped(cli + "verify --law " + dir + "/flips4.json") == 0);
    // (a) the checker, on certificates carrying those laws (the certificate of the c = 4 law with
    // its law replaced): undecided or rejected with one line, never a signal.
    REQUIRE(capped(cli + "certify --law " + dir + "/flips4.json -o " + dir + "/flips4.cert.json") == 0);
    REQUIRE(capped(checker + dir + "/flips4.cert.json") == 0);
    Json cert = Json::parse(test::read_file(dir + "/flips4.cert.json"));
    // The law's hash is recomputed, so that the checker must expand the law to refuse it (with
    // the stale hash it rejected the certificate before any expansion, which tested nothing):
    // the 2^20 orthants stop at the byte budget (undecided, naming the option), the rotations
    // at once (Lemma S0), the reflections at their growing numbers (both rejected).
    for (const auto& [name, text, want_status, want_text] :
         std::vector<std::tuple<std::string, std::string, int, std::string>>{
             {"flips20", compact_flips_law(20), 3, "--max-memory"},
             {"rot", kRotations, 1, "$.law.symmetries[0].P: of infinite order"},
             {"p4", kCancelling, 1, "$.law.symmetries[0].P: of infinite order"},
             {"refl", kReflections, 1, "has numbers of more than 16 times the bits"}}) {
        Json law = Json::parse(text);
        law.erase("claims");
        Json forged = cert;
        forged["law"] = law;
        forged["law_sha256"] = sha256_hex(law.dump());
        std::ofstream(dir + "/" + name + ".cert.json") << forged.dump();
        // (The reflections keep the default budget: at ASan's smaller one the bytes run out first.)
        const int status = capped(checker + dir + "/" + name + ".cert.json" + (name == "flips20" ? kBudget : ""), &err);
        INFO(name << " -> " << status << ": " << err);
        CHECK(status == want_status);
        CHECK(err.find(want_text) != std::string::npos);
        CHECK(err.find("law_sha256") == std::string::npos);
        REQUIRE(std::count(err.begin(), err.end(), '\n') == 1);
    }
    // (d) derive cradle says when verify's defaults cannot load what it writes.
    const auto run = run_cli("derive cradle --balls 10 -o " + dir + "/c10.json");
    REQUIRE(run.status == 0);
    REQUIRE(run.err.find("need --max-pieces 3628800 --max-memory") != std::string::npos);
    REQUIRE(capped(cli + "verify --law " + dir + "/c10.json" + kBudget, &err) == 2);
    REQUIRE(err.find("raise it with --max-") != std::string::npos);
    const auto small = run_cli("derive cradle --balls 6 -o " + dir + "/c6.json");
    REQUIRE(small.err.find("note:") == std::string::npos);
}

// Under an address-space cap (ulimit -v, as batch systems set one), a run that fits completes
// with the result of an uncapped run, whatever number of its threads could start or find memory
// for their own heaps, and one that does not fit ends with its status and one line: exit 3
// (impactcert) or 2 (impactcert-check, "not checked"), never a signal. Caught by this test: a
// thread that could not start (no memory for its stack) destroyed with its joinable siblings
// (std::terminate, SIGABRT); threads that started but found no memory for their heap (mimalloc
// gives each its own segments), which turned a run that fits into exit 3 and, in the checker,
// into SIGABRT once its hundreds of kept exceptions had used up the runtime's reserve;
// mimalloc's own operator new, which aborts (src/base/allocation.cpp); a file read into a string that
// could not grow, silently shortened and then reported as malformed JSON. The caps start above
// the programs' start-up footprint (about 44 MB of address space with mimalloc: below it the
// loader and the static initialisers cannot run, which no program can report). Release build
// only: the sanitizers' shadow memory needs terabytes of address space.
TEST_CASE("memory caps: a run that fits completes on any threads, one that does not is one line, never a signal", "[reliability][cli][checker]") {
#ifdef IMPACTCERT_SANITIZER_BUILD
    WARN("not run under the sanitizers (their shadow memory needs the address space a cap takes away)");
#else
    const test::ScratchDir scratch("rel-caps");
    const std::string& dir = scratch.path;
    const std::string cli = std::string("'") + IMPACTCERT_CLI + "' ";
    const std::string checker = std::string("'") + IMPACTCERT_CHECKER + "' ";
    auto uncapped = [&](const std::string& args) {
        REQUIRE(std::system((cli + args + " 2>/dev/null").c_str()) == 0);
    };
    // Uncapped references: the paper's certificate, a derived chain, and the explicit 5-ball
    // cradle's certificate (120 pieces, 14,400 pair entries for the checker's threads).
    uncapped("certify -o " + dir + "/paper.cert.json");
    uncapped("derive sequential --masses 1,2,3,4 --restitution 1/2 -o " + dir + "/d4.json");
    uncapped("derive cradle --balls 5 --pieces all --no-symmetries -o " + dir + "/cradle5.json");
    uncapped("certify --law " + dir + "/cradle5.json -o " + dir + "/cradle5.cert.json");
    auto run = [&](int kb, const std::string& command, std::string& out, std::string& err) {
        const std::string line = "ulimit -v " + std::to_string(kb) + "; " + command + " >" + dir + "/out 2>" + dir + "/err";
        const int status = std::system(line.c_str());
        out = test::read_file(dir + "/out");
        err = test::read_file(dir + "/err");
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    };
    // Each command fits in every cap: exit 0 and the uncapped result, on 2 or 8 threads (at the
    // small caps some cannot start, at the middle ones some start and find no memory for their
    // heap, at the large ones all run).
    struct Case {
        std::string command, output, want; // output: the file written ("" for stdout), want: its text or a line in it
    };
    const std::vector<Case> cases{
        {cli + "verify --jobs 8", "", "verdict: proved (12/12 claimed obligations proved"},
        {cli + "verify --jobs 2 --law " + dir + "/cradle5.json", "", "verdict: proved"},
        {cli + "certify --jobs 2 -o " + dir + "/capped.json", dir + "/capped.json", test::read_file(dir + "/paper.cert.json")},
        {cli + "certify --jobs 8 --law " + dir + "/cradle5.json -o " + dir + "/capped.json", dir + "/capped.json",
         test::read_file(dir + "/cradle5.cert.json")},
        {cli + "derive sequential --masses 1,2,3,4 --restitution 1/2 -o " + dir + "/capped.json", dir + "/capped.json",
         test::read_file(dir + "/d4.json")},
        {checker + "--jobs 8 " + dir + "/paper.cert.json", "", "verified (newton3-sequential: proved)"},
        {checker + "--jobs 2 " + dir + "/cradle5.cert.json", "", "verified (cradle-5: proved)"},
        {checker + "--jobs 8 " + dir + "/cradle5.cert.json", "", "verified (cradle-5: proved)"}};
    for (const int mb : {52, 64, 80, 100, 300})
        for (const auto& c : cases) {
            std::string out, err;
            std::filesystem::remove(dir + "/capped.json");
            const int status = run(mb * 1000, c.command, out, err);
            INFO(c.command << " under " << mb << " MB: status " << status << ", stderr: " << err);
            REQUIRE(status == 0);
            if (c.output.empty())
                REQUIRE(out.find(c.want) != std::string::npos);
            else
                REQUIRE(test::read_file(c.output) == c.want);
        }
    // A file larger than the cap (2 GB, sparse: nothing on disk) is out of memory, one line, not
    // "malformed".
    const std::string big = dir + "/big.json", small = dir + "/small.json";
    std::ofstream(big).close();
    std::ofstream(small).close();
    std::filesystem::resize_file(big, 2000000000);
    std::filesystem::resize_file(small, 50000000);
    std::string out, err;
    REQUIRE(run(1000000, cli + "verify --law " + big, out, err) == 3);
    REQUIRE(err == "impactcert: out of memory (raise the memory limit, or lower the limits that size the work)\n");
    REQUIRE(run(1000000, checker + big, out, err) == 2);
    REQUIRE(err == "impactcert-check: " + big + ": error: out of memory while reading (status 2: not checked)\n");
    // Negative control: under the same cap, a file of the same kind that fits (50 MB) is read in
    // full and refused for what it is.
    REQUIRE(run(1000000, checker + small, out, err) == 2);
    REQUIRE(err.find("a NUL character") != std::string::npos);
    REQUIRE(run(1000000, cli + "verify --law " + small, out, err) == 2);
    REQUIRE(err.find("a NUL character") != std::string::npos);
    // A derivation that does not fit (the 6-ball chain needs about 1 GB): exit 3 and one line.
    REQUIRE(run(60000, cli + "derive sequential --masses 1,2,3,4,5,6 --restitution 9/10 -o " + dir + "/six.json", out, err) == 3);
    REQUIRE(err == "impactcert: out of memory (raise the memory limit, or lower the limits that size the work)\n");
#endif
}

// certify streams its certificate as the obligations are decided: a run killed half-way (a
// batch system's time limit), out of memory or beyond a limit used to leave a shortened file
// under the certificate's name. Written beside it and renamed at the end, the file is the old
// one or the whole new one at every moment. The kill times straddle the run (about 1.5 s in
// Release, more under the sanitizers): each outcome is accepted but a third one.
TEST_CASE("output files: a run that ends early leaves the previous file, never a shortened one", "[reliability][cli]") {
    const test::ScratchDir scratch("rel-output");
    const std::string& dir = scratch.path;
    const std::string cli = std::string("'") + IMPACTCERT_CLI + "' ";
    REQUIRE(std::system((cli + "derive cradle --balls 5 --pieces all --no-symmetries -o " + dir + "/c5.json 2>/dev/null").c_str()) == 0);
    // Killed after 0.1 .. 1 s, then given a minute: the last run's certificate is the whole one
    // (the test's time is one certify), and every earlier run left that or the previous file.
    std::vector<std::string> left;
    for (const char* after : {"0.1", "0.3", "0.6", "1.0", "60"}) {
        std::ofstream(dir + "/cert.json") << "the previous file\n";
        const int status = std::system(("timeout -s KILL " + std::string(after) + " " + cli + "certify --law " + dir +
                                        "/c5.json -o " + dir + "/cert.json 2>/dev/null").c_str());
        left.push_back(test::read_file(dir + "/cert.json"));
        INFO("killed after " << after << " s: status " << status << ", " << left.back().size() << " bytes");
        bool partial = false; // a temporary file left beside it (by a kill, never by a finished run)
        for (const auto& e : std::filesystem::directory_iterator(dir))
            if (e.path().filename().string().find(".partial-") != std::string::npos) {
                partial = true;
                std::filesystem::remove(e.path());
            }
        if (std::string(after) == "60") {
            REQUIRE(status == 0);
            REQUIRE(!partial);
        }
    }
    const std::string whole = left.back();
    REQUIRE(whole.size() > 1000000);
    REQUIRE(whole.find("\"verdict\": \"proved\"") != std::string::npos);
    for (std::size_t k = 0; k + 1 < left.size(); ++k) {
        INFO("run " << k << ": " << left[k].size() << " bytes");
        REQUIRE((left[k] == "the previous file\n" || left[k] == whole));
    }
    // Certainly mid-write (issue 33, 10e: no kill above is known to strike while the file is
    // written): a file size limit of 64 KiB kills certify with SIGXFSZ in the middle of writing
    // its 1 MB certificate. The previous file must be what is left.
    std::ofstream(dir + "/cert.json") << "the previous file\n";
    const int xfsz = std::system(("bash -c \"ulimit -f 64; exec " + cli + "certify --law " + dir + "/c5.json -o " + dir +
                                  "/cert.json\" 2>/dev/null").c_str());
    INFO("status " << xfsz);
    REQUIRE(WIFEXITED(xfsz));
    REQUIRE(WEXITSTATUS(xfsz) == 128 + SIGXFSZ); // died of the limit, while writing
    REQUIRE(test::read_file(dir + "/cert.json") == "the previous file\n");
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().filename().string().find(".partial-") != std::string::npos)
            std::filesystem::remove(e.path());
    // What the rename must not change: a symbolic link stays a link (its target is written), a
    // file's mode is kept, hard links keep sharing their file, and -o /dev/stdout writes to the
    // standard output (a rename over the /dev/stdout link would break it for the machine).
    namespace fs = std::filesystem;
    const std::string paper = test::read_file(test::source_path("proofs/newton3/certificate.json"));
    auto certify_to = [&](const std::string& out, const std::string& redirect = "") {
        return std::system((cli + "certify -o " + out + " 2>/dev/null" + redirect).c_str());
    };
    std::ofstream(dir + "/target.json") << "old\n";
    fs::create_symlink("target.json", dir + "/link.json");
    REQUIRE(certify_to(dir + "/link.json") == 0);
    REQUIRE(fs::is_symlink(fs::symlink_status(dir + "/link.json")));
    REQUIRE(test::read_file(dir + "/target.json") == paper);
    std::ofstream(dir + "/private.json") << "old\n";
    fs::permissions(dir + "/private.json", fs::perms::owner_read | fs::perms::owner_write);
    REQUIRE(certify_to(dir + "/private.json") == 0);
    REQUIRE(fs::status(dir + "/private.json").permissions() == (fs::perms::owner_read | fs::perms::owner_write));
    REQUIRE(test::read_file(dir + "/private.json") == paper);
    std::ofstream(dir + "/h1.json") << "old\n";
    fs::create_hard_link(dir + "/h1.json", dir + "/h2.json");
    REQUIRE(certify_to(dir + "/h1.json") == 0);
    REQUIRE(test::read_file(dir + "/h2.json") == paper);
    REQUIRE(certify_to("/dev/stdout", " >" + dir + "/piped.json") == 0);
    REQUIRE(test::read_file(dir + "/piped.json") == paper);
}

TEST_CASE("defect 18.10g: impactcert-check as a program: exit 0, 1, 2 and 3, and its options", "[reliability][cli][checker]") {
    const std::string checker = std::string("'") + IMPACTCERT_CHECKER + "' ";
    const std::string cradle = test::source_path("proofs/cradle4/certificate.json");
    auto run = [&](const std::string& args, std::string* out) {
        const std::string path = "/tmp/impactcert-rel-check.out";
        const int status = std::system((checker + args + " >" + path + " 2>&1").c_str());
        *out = test::read_file(path);
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    std::string out;
    REQUIRE(run(cradle, &out) == 0);
    REQUIRE(out.find("verified (cradle-4: proved)") != std::string::npos);
    REQUIRE(run("--jobs 2 " + cradle, &out) == 0);
    // 1: a tampered verdict, rejected with the path.
    std::string text = test::read_file(cradle);
    const auto at = text.find("\"verdict\": \"proved\"", text.find("\"obligations\""));
    REQUIRE(at != std::string::npos);
    text.replace(at, std::string("\"verdict\": \"proved\"").size(), "\"verdict\": \"refuted\"");
    std::ofstream("/tmp/impactcert-rel-tampered.json") << text;
    REQUIRE(run("/tmp/impactcert-rel-tampered.json", &out) == 1);
    REQUIRE(out.find("rejected: $.") != std::string::npos);
    REQUIRE(std::count(out.begin(), out.end(), '\n') == 1);
    // 3: limits below what the certificate needs, each named.
    for (const char* option : {"--max-pieces 2", "--max-memory 0"}) {
        REQUIRE(run(std::string(option) + " " + cradle, &out) == 3);
        INFO(option << " -> " << out);
        REQUIRE(out.find(std::string(option).substr(0, std::string(option).find(' '))) != std::string::npos);
    }
    // 2: a verdict that cannot be written is not given.
    const int full = std::system((checker + cradle + " >/dev/full 2>/dev/null").c_str());
    REQUIRE(WIFEXITED(full));
    REQUIRE(WEXITSTATUS(full) == 2);
    // 2: bad options and unreadable input.
    for (const char* args : {"--frobnicate 1", "--max-pieces abc", "--jobs 0", "--max-memory -1", "/nonexistent.json", ""}) {
        REQUIRE(run(std::string(args) + (std::string(args).find(".json") == std::string::npos && *args ? " " + cradle : ""), &out) == 2);
    }
    // --help and --version alone: printed, exit 0 (issue 32: --help was exit 2, --version "needs a
    // value"). With a certificate beside them nothing is checked, and a gate must not pass: 2.
    REQUIRE(run("--help", &out) == 0);
    REQUIRE(out.find("usage: impactcert-check") != std::string::npos);
    REQUIRE(out.find("exit 0 verified, 1 rejected") != std::string::npos);
    REQUIRE(run("--version", &out) == 0);
    REQUIRE(out.rfind("impactcert-check ", 0) == 0);
    REQUIRE(std::count(out.begin(), out.end(), '\n') == 1);
    REQUIRE(run("--help " + cradle, &out) == 2);
    REQUIRE(out.find("nothing was checked") != std::string::npos);
    REQUIRE(run(cradle + " --version", &out) == 2);
}

TEST_CASE("reading JSON: NUL bytes, control characters in keys, empty and 4097th keys give one exact line", "[reliability][cli]") {
    // The law reader: an unknown key holding a newline and a terminal escape is named, escaped.
    const std::string dir = "/tmp/impactcert-rel-keys";
    std::filesystem::create_directories(dir);
    std::ofstream(dir + "/keys.json") << R"({"format": "impactcert-law/1", "a\nb\u001b[31m": 1})";
    const auto run = run_cli("verify --law " + dir + "/keys.json");
    CHECK(run.status == 2);
    INFO(run.err);
    CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    CHECK(run.err.find('\x1b') == std::string::npos);
    CHECK(run.err.find("\\u001b[31m") != std::string::npos);
    // The checker: whatever follows a NUL byte would not be read, so the text is refused.
    const std::string cert = test::read_file(test::source_path("proofs/newton4/certificate.json"));
    REQUIRE(impactcert_check::check_text(cert).status == impactcert_check::kVerified);
    const auto nul = impactcert_check::check_text(cert + std::string(1, '\0') + R"({"format": 1, "format": 2})");
    CHECK(nul.status == impactcert_check::kMalformed);
    CHECK(nul.message.find("a NUL character") != std::string::npos);
    // An empty key repeated is a repeated key (it once read as the 4096-key limit), and the
    // limit names itself.
    const auto empty = impactcert_check::check_text(R"({"": 1, "": 2})");
    CHECK(empty.status == impactcert_check::kMalformed);
    INFO(empty.message);
    CHECK(empty.message.find("$.: duplicate key \"\"") != std::string::npos);
    std::string many = "{";
    for (int k = 0; k < 4097; ++k)
        many += (k ? ", \"k" : "\"k") + std::to_string(k) + "\": 0";
    const auto too_many = impactcert_check::check_text(many + "}");
    CHECK(too_many.status == impactcert_check::kMalformed);
    CHECK(too_many.message.find("more than 4096 keys in one object") != std::string::npos);
}
