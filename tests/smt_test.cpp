// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "prover/smt.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <cstdio>
#include <map>
#include <fstream>
#include <unistd.h>

using namespace impactcert;
using impactcert::test::source_path;

namespace {

// z3's answer on one script ("sat", "unsat", "unknown", or an error line).
std::string z3_answer(const std::string& script) {
    char name[] = "/tmp/impactcert-smt-XXXXXX";
    const int fd = mkstemp(name);
    REQUIRE(fd >= 0);
    REQUIRE(write(fd, script.data(), script.size()) == static_cast<ssize_t>(script.size()));
    close(fd);
    FILE* pipe = popen(("timeout 300 z3 -smt2 " + std::string(name) + " 2>&1").c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buf[256] = {0};
    std::string first = fgets(buf, sizeof buf, pipe) ? buf : "";
    pclose(pipe);
    unlink(name);
    while (!first.empty() && (first.back() == '\n' || first.back() == '\r'))
        first.pop_back();
    return first;
}

bool have_z3() { return std::system("z3 --version >/dev/null 2>&1") == 0; }

} // namespace

TEST_CASE("smt: z3 decides every universal claim exactly as impactcert does", "[smt]") {
    REQUIRE(have_z3()); // scripts/test installs Debian's z3
    const std::vector<std::string> laws = {
        "",  // the embedded default
        "proofs/controls/perturbed-entry.json",   "proofs/controls/swapped-pieces.json",
        "proofs/controls/missing-cone.json",      "proofs/controls/newton-simultaneous.json",
        "proofs/controls/discontinuous-isometric.json", "proofs/controls/expansive-scaled.json",
        "tests/certificates/laws/two-ball.json",  "tests/certificates/laws/two-ball-expansive.json",
        // Not face to face, overlapping: the reductions must still say what z3 says.
        "tests/laws/tjunction-orthants-zero.json", "tests/laws/overlap-newton3-duplicate.json",
        "tests/laws/tjunction-newton4-split.json",
    };
    std::size_t agreed = 0, sat = 0, index = 0;
    for (const auto& law : laws) {
        const Model m(law.empty() ? paper_law() : load_law_file(source_path(law)));
        const VerifyReport report = verify(m);
        const auto problems = smt_problems(m);
        REQUIRE(problems.size() == 8);
        for (const auto& problem : problems) {
            INFO(m.law().name << " / " << problem.id);
            // z3 4.8 does not answer nonexpansive for 25 cones in R^3 within 300 s.
            if (m.law().name == "tjunction-newton4-split" && problem.id == "nonexpansive")
                continue;
            // z3 is not instrumented: under the sanitizers every claim is written (instrumented
            // code) and a quarter of them is asked of z3; the Release run asks all 95.
            if (index++ % test::kSanitizerDivisor != 0)
                continue;
            const std::string expected = report.at(problem.id).verdict == Verdict::proved ? "unsat" : "sat";
            CHECK(z3_answer(problem.script) == expected);
            agreed += 1;
            sat += expected == "sat" ? 1 : 0;
        }
    }
    CHECK(agreed == (95 + test::kSanitizerDivisor - 1) / test::kSanitizerDivisor);
    CHECK(sat > 10 / test::kSanitizerDivisor); // the controls do make z3 find counterexamples
}

TEST_CASE("smt: impactcert smt writes one file per universal claim", "[smt][cli]") {
    const std::string dir = "/tmp/impactcert-smt-cli-test";
    const auto run = test::run_cli("smt -o " + dir);
    CHECK(run.status == 0);
    // Each file is exactly the in-process script of its claim (the one z3 decides in the test
    // above), and standard output lists the files.
    std::map<std::string, std::string> scripts;
    for (const auto& problem : smt_problems(Model(paper_law())))
        scripts[problem.id] = problem.script;
    for (const char* id : {"fan", "P1", "P2", "P3", "kinematic", "kinetic", "energetic", "nonexpansive"}) {
        std::ifstream in(dir + "/" + id + ".smt2");
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        INFO(id);
        CHECK(text.find("(set-logic QF_NRA)") != std::string::npos);
        CHECK(text.find("(check-sat)") != std::string::npos);
        REQUIRE(scripts.count(id));
        CHECK(text == scripts[id]);
        CHECK(run.out.find(dir + "/" + id + ".smt2\n") != std::string::npos);
        std::remove((dir + "/" + id + ".smt2").c_str());
    }
    rmdir(dir.c_str());
}
