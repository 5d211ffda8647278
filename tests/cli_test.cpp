// SPDX-License-Identifier: GPL-3.0-or-later
#include "support.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using impactcert::test::run_cli;
using impactcert::test::source_path;

TEST_CASE("cli: verify on the embedded default proves every claim and exits 0", "[cli]") {
    const auto run = run_cli("verify");
    CHECK(run.status == 0);
    CHECK(run.out.find("verdict: proved (12/12 claimed obligations proved") != std::string::npos);
    CHECK(run.err.empty());
}

TEST_CASE("cli: verify --json prints the impactcert-verdict/1 document", "[cli]") {
    const auto run = run_cli("verify --json");
    REQUIRE(run.status == 0);
    const auto j = nlohmann::json::parse(run.out);
    CHECK(j["format"] == "impactcert-verdict/1");
    CHECK(j["law"] == "newton3-sequential");
    CHECK(j["verdict"] == "proved");
    REQUIRE(j["obligations"].size() == 13);
    for (const auto& o : j["obligations"]) {
        const bool declared = o["id"] != "symmetries"; // the paper declares no symmetry
        CHECK(o["verdict"] == (declared ? "proved" : "skipped"));
        CHECK(o["claimed"] == declared);
        CHECK((o["checks"].get<int>() > 0) == declared);
        CHECK_FALSE(o.contains("counterexample"));
    }
    // Deterministic: byte for byte the same on a second run.
    CHECK(run_cli("verify --json").out == run.out);
}

TEST_CASE("cli: every control exits 1 with its counterexamples in the JSON", "[cli]") {
    for (const char* name : {"perturbed-entry", "swapped-pieces", "missing-cone", "newton-simultaneous",
                             "discontinuous-isometric", "expansive-scaled"}) {
        INFO(name);
        const auto run = run_cli("verify --json --law '" + source_path(std::string("proofs/controls/") + name + ".json") + "'");
        CHECK(run.status == 1);
        const auto j = nlohmann::json::parse(run.out);
        CHECK(j["verdict"] == "refuted");
        for (const auto& o : j["obligations"])
            CHECK(o.contains("counterexample") == (o["verdict"] == "refuted"));
    }
}

TEST_CASE("cli: --junit writes one testcase per obligation and a failure per refuted claim", "[cli]") {
    const std::string path = "/tmp/impactcert-cli-test-junit.xml";
    const auto run = run_cli("verify --law '" + source_path("proofs/controls/missing-cone.json") + "' --junit " + path);
    CHECK(run.status == 1);
    std::ifstream in(path);
    const std::string xml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::remove(path.c_str());
    CHECK(xml.find("<testsuites name=\"impactcert\" tests=\"13\" failures=\"4\"") != std::string::npos);
    std::size_t cases = 0;
    for (auto at = xml.find("<testcase "); at != std::string::npos; at = xml.find("<testcase ", at + 1))
        ++cases;
    CHECK(cases == 13);
    CHECK(xml.find("name=\"fan\"") != std::string::npos);
    CHECK(xml.find("<failure type=\"refuted\" message=\"fan refuted: {&quot;gamma&quot;") != std::string::npos);
}

TEST_CASE("cli: bad input exits 2 with one line naming the file and JSON path", "[cli]") {
    const std::string path = "/tmp/impactcert-cli-test-bad.json";
    std::ofstream(path) << R"({"format": "impactcert-law/1", "name": "x", "masses": ["1", "1", "1"],
        "pieces": [{"name": "a", "Q": [["1", "0"], ["0", "1/0"]]}]})";
    const auto run = run_cli("verify --law " + path);
    std::remove(path.c_str());
    CHECK(run.status == 2);
    CHECK(run.err == "impactcert: " + path + ": $.pieces[0].Q[1][1]: \"1/0\": zero denominator\n");
    CHECK(run.out.empty());
}

TEST_CASE("cli: a missing law file and an unknown option exit 2", "[cli]") {
    const auto missing = run_cli("verify --law /nonexistent/law.json");
    CHECK(missing.status == 2);
    CHECK(missing.err.find("/nonexistent/law.json: cannot read file") != std::string::npos);
    CHECK(run_cli("verify --frobnicate").status == 2);
    CHECK(run_cli("").status == 2);
}

TEST_CASE("cli: eval prints S exactly for arguments and stdin lines", "[cli]") {
    auto run = run_cli("eval -- -1 0");
    CHECK(run.status == 0);
    CHECK(run.out == "0 1\n");
    run = run_cli("eval", "-1/2 0x1.8p-1\n# a comment\n\n(1, 2)\n-0.1 0.3\n");
    CHECK(run.status == 0);
    CHECK(run.out == "1/2 1/4\n1 2\n1/10 1/5\n");
    run = run_cli("eval -- 1e300 -2.5e-3 -1E+2 1e-1");
    CHECK(run.status == 0);
    CHECK(run.out == "3" + std::string(302, '9') + "/400 1/400\n1/10 999/10\n"); // 10^300 - 1/400, ...
    run = run_cli("eval --velocities", "1 0 0\n1 1 0\n1 0 -1\n3/2 -1/3 0.25\n");
    CHECK(run.status == 0);
    CHECK(run.out == "0 0 1\n0 1 1\n-1 0 1\n-1/3 1/4 3/2\n");
}

TEST_CASE("cli: eval shows both values where a discontinuous law is two-valued", "[cli]") {
    const auto run = run_cli("eval --law '" + source_path("proofs/controls/newton-simultaneous.json") + "' -- -1 0");
    CHECK(run.status == 0);
    CHECK(run.out == "1 -1 | 1 0\n");
}

TEST_CASE("cli: eval rejects malformed numbers and uncovered points with exit 2", "[cli]") {
    auto run = run_cli("eval", "1 2 3\n");
    CHECK(run.status == 2);
    CHECK(run.err == "impactcert: stdin:1: expected 2 numbers, got 3\n");
    run = run_cli("eval", "1 1e\n");
    CHECK(run.status == 2);
    CHECK(run.err.find("stdin:1: 1e:") != std::string::npos);
    run = run_cli("eval -- 1 1e999999999");
    CHECK(run.status == 2);
    CHECK(run.err.find("arguments: 1e999999999: ") != std::string::npos);
    CHECK(run.err.find("100000") != std::string::npos);
    run = run_cli("eval --law '" + source_path("proofs/controls/missing-cone.json") + "' -- 1 -2");
    CHECK(run.status == 2);
    CHECK(run.err.find("lies in no cone") != std::string::npos);
}

namespace {

std::size_t lines_of(const std::string& s) { return static_cast<std::size_t>(std::count(s.begin(), s.end(), '\n')); }

// Text with every number that ends at `suffix` (a time: "    0.052 ms", right-aligned, or
// time="0.000635") blanked to "-", and the spaces before it to one. (No std::regex: GCC 12
// warns inside it at -O1 with the sanitizers.)
std::string blank_numbers_before(const std::string& s, const std::string& suffix, bool digits_after_prefix = false) {
    std::string out;
    std::size_t from = 0;
    for (std::size_t at = s.find(suffix); at != std::string::npos; at = s.find(suffix, at + suffix.size())) {
        std::size_t start = at;
        if (digits_after_prefix) { // time="..." : the number follows the suffix
            std::size_t end = at + suffix.size();
            while (end < s.size() && (std::isdigit(static_cast<unsigned char>(s[end])) || s[end] == '.'))
                ++end;
            out += s.substr(from, at + suffix.size() - from) + "-";
            from = end;
            continue;
        }
        while (start > 0 && (std::isdigit(static_cast<unsigned char>(s[start - 1])) || s[start - 1] == '.'))
            --start;
        if (start == at)
            continue; // no number before it
        std::size_t pad = start;
        while (pad > 0 && s[pad - 1] == ' ')
            --pad;
        out += s.substr(from, pad - from) + " -";
        from = at;
    }
    return out + s.substr(from);
}
std::string without_times(const std::string& s) { return blank_numbers_before(s, " ms"); }

} // namespace

TEST_CASE("cli: every usage error is one line on stderr with exit 2 - --help and --version exit 0", "[cli]") {
    for (const char* args : {"verify --frobnicate", "", "certify", "fuzz --jobs 0", "eval --law", "frobnicate",
                             "verify extra", "fuzz --samples x"}) {
        INFO("impactcert " << args);
        const auto run = run_cli(args);
        CHECK(run.status == 2);
        INFO("stderr: " << run.err);
        CHECK(run.err.rfind("impactcert: ", 0) == 0);
        CHECK(lines_of(run.err) == 1);
        CHECK(run.err.back() == '\n');
        CHECK(run.out.empty());
    }
    for (const char* args : {"--help", "verify --help", "fuzz -h"}) {
        INFO("impactcert " << args);
        const auto run = run_cli(args);
        CHECK(run.status == 0);
        CHECK(run.out.find("Usage:") != std::string::npos);
        CHECK(run.err.empty());
    }
    const auto version = run_cli("--version");
    CHECK(version.status == 0);
    CHECK(version.out.rfind("impactcert ", 0) == 0);
}

TEST_CASE("cli: a directory, a missing file or an unreadable one as --law is one line naming the path", "[cli]") {
    for (const char* cmd : {"verify", "eval --float", "report -o /tmp/impactcert-cli-test-report-dir"}) {
        INFO(cmd);
        auto run = run_cli(std::string(cmd) + " --law /tmp");
        CHECK(run.status == 2);
        CHECK(run.err == "impactcert: /tmp: is a directory\n");
        run = run_cli(std::string(cmd) + " --law /nonexistent/law.json");
        CHECK(run.status == 2);
        CHECK(run.err == "impactcert: /nonexistent/law.json: cannot read file: No such file or directory\n");
    }
    const std::string path = "/tmp/impactcert-cli-test-unreadable.json";
    std::ofstream(path) << "{}";
    auto run = run_cli("verify --law " + path + "/law.json"); // a file used as a directory
    CHECK(run.status == 2);
    CHECK(run.err == "impactcert: " + path + "/law.json: cannot read file: Not a directory\n");
    // Root reads anything: as root (CI), the case runs as the user nobody through setpriv
    // (util-linux), so that it is never skipped (issue 33, 10h).
    ::chmod(path.c_str(), 0);
    const std::string as_user = geteuid() == 0 ? "setpriv --reuid=65534 --regid=65534 --clear-groups " : "";
    const std::string cmd = as_user + "'" + IMPACTCERT_CLI + "' verify --law " + path;
    const int raw = std::system((cmd + " 2>/tmp/impactcert-cli-test-unreadable.err").c_str());
    CHECK(WIFEXITED(raw));
    CHECK(WEXITSTATUS(raw) == 2);
    std::ifstream err_file("/tmp/impactcert-cli-test-unreadable.err");
    const std::string err((std::istreambuf_iterator<char>(err_file)), std::istreambuf_iterator<char>());
    CHECK(err == "impactcert: " + path + ": cannot read file: Permission denied\n");
    std::remove("/tmp/impactcert-cli-test-unreadable.err");
    std::remove(path.c_str());
}

TEST_CASE("impactcert-verify: the output, errors and exit status of impactcert verify, for every kind of run", "[cli]") {
    // impactcert-verify is `impactcert verify` alone: the same option wiring (cli/options.cpp)
    // compiled into a program without derive, sweep or fuzz. Each run is made by both programs.
    const std::string law = source_path("proofs/controls/missing-cone.json"), cradle = source_path("proofs/cradle4/law.json");
    const std::string junit_a = "/tmp/impactcert-cli-test-verify-a.xml", junit_b = "/tmp/impactcert-cli-test-verify-b.xml";
    struct Case {
        std::string args;
        int status;
    };
    for (const Case& c : std::vector<Case>{{"", 0},
                                           {"--json", 0},
                                           {"--law '" + law + "' --json", 1},
                                           {"--law '" + law + "' --jobs 1", 1},
                                           {"--law '" + cradle + "' --stream", 0},
                                           {"--law '" + cradle + "' --json --no-integer-kernels", 0},
                                           {"--shard 2/3 --json", 0},
                                           {"--shard 1/2 --shard-block 7", 0},
                                           {"--stream", 3},
                                           {"--law '" + cradle + "' --max-pieces 3", 2},
                                           {"--law /nonexistent/law.json", 2},
                                           {"--law '" + law + "' --shard 1/2 --junit /tmp/x.xml", 2},
                                           {"--stream --shard 1/2", 2},
                                           {"--shard 4/3", 2},
                                           {"--jobs 0", 2},
                                           {"--max-faces -1", 2},
                                           {"--frobnicate", 2},
                                           {"certify", 2}}) {
        INFO("impactcert verify " << c.args);
        const auto full = run_cli("verify " + c.args);
        const auto lean = impactcert::test::run_program(IMPACTCERT_VERIFY_CLI, c.args);
        CHECK(full.status == c.status);
        CHECK(lean.status == full.status);
        CHECK(without_times(lean.out) == without_times(full.out)); // the table's times vary
        INFO("stderr: " << full.err);
        if (c.status == 2)
            CHECK(lines_of(full.err) == 1);
        // The one difference: the program's name at the start of an error line.
        REQUIRE(full.err.rfind("impactcert: ", 0) == (full.err.empty() ? std::string::npos : 0));
        CHECK(lean.err == (full.err.empty() ? "" : "impactcert-verify: " + full.err.substr(12)));
    }
    // --junit writes the same report.
    const auto full = run_cli("verify --law '" + law + "' --junit " + junit_a);
    const auto lean = impactcert::test::run_program(IMPACTCERT_VERIFY_CLI, "--law '" + law + "' --junit " + junit_b);
    CHECK(full.status == 1);
    CHECK(lean.status == 1);
    auto without_junit_times = [](const std::string& xml) { return blank_numbers_before(xml, "time=\"", true); };
    CHECK(without_junit_times(impactcert::test::read_file(junit_a)) == without_junit_times(impactcert::test::read_file(junit_b)));
    CHECK(impactcert::test::read_file(junit_a).find("<failure") != std::string::npos);
    std::remove(junit_a.c_str());
    std::remove(junit_b.c_str());
    // --help lists the same options; --version names the program.
    auto options_of = [](const std::string& help) {
        std::vector<std::string> out;
        std::istringstream in(help);
        for (std::string line; std::getline(in, line);)
            if (line.rfind("  -", 0) == 0)
                out.push_back(line);
        return out;
    };
    const auto full_help = run_cli("verify --help"), lean_help = impactcert::test::run_program(IMPACTCERT_VERIFY_CLI, "--help");
    CHECK(full_help.status == 0);
    CHECK(lean_help.status == 0);
    const auto full_options = options_of(full_help.out), lean_options = options_of(lean_help.out);
    CHECK(full_options.size() >= 12);
    CHECK(lean_options.size() == full_options.size() + 1); // and --version
    for (const auto& line : full_options)
        CHECK(std::find(lean_options.begin(), lean_options.end(), line) != lean_options.end());
    const auto version = impactcert::test::run_program(IMPACTCERT_VERIFY_CLI, "--version");
    CHECK(version.status == 0);
    CHECK(version.out.rfind("impactcert-verify ", 0) == 0);
}

TEST_CASE("scripts: verify configures as before, builds only impactcert-verify, one job per core", "[cli][scripts]") {
    // The scripts run against a scratch root with cmake, dpkg-query, nproc and the built program
    // replaced by stubs that log their arguments.
    const std::string root = "/tmp/impactcert-scripts-test", log = root + "/log";
    const std::string setup =
        "rm -rf " + root + " && mkdir -p " + root + "/scripts " + root + "/bin " + root + "/build && cp '" +
        source_path("scripts/lib.sh") + "' '" + source_path("scripts/verify") + "' " + root + "/scripts/ && cd " + root +
        " && printf '#!/bin/sh\\necho \"cmake $*\" >> " + log + "\\n' > bin/cmake" +
        " && printf '#!/bin/sh\\necho \"install ok installed\"\\n' > bin/dpkg-query" +
        " && printf '#!/bin/sh\\necho 7\\n' > bin/nproc" +
        " && printf '#!/bin/sh\\necho \"impactcert-verify $*\" >> " + log + "\\n' > build/impactcert-verify" +
        " && chmod +x bin/* build/impactcert-verify";
    REQUIRE(std::system(setup.c_str()) == 0);
    REQUIRE(std::system(("PATH=" + root + "/bin:$PATH " + root + "/scripts/verify --json 2>/dev/null").c_str()) == 0);
    CHECK(impactcert::test::read_file(log) == "cmake -S " + root + " -B " + root + "/build -G Ninja -DCMAKE_BUILD_TYPE=Release\n"
                                  "cmake --build " + root + "/build --target impactcert-verify -j 7\n"
                                  "impactcert-verify --json\n");
    // A tree configured before keeps its generator (cmake refuses to change it).
    std::remove(log.c_str());
    REQUIRE(std::system(("touch " + root + "/build/CMakeCache.txt && PATH=" + root + "/bin:$PATH " + root +
                         "/scripts/verify 2>/dev/null").c_str()) == 0);
    CHECK(impactcert::test::read_file(log) == "cmake -S " + root + " -B " + root + "/build -DCMAKE_BUILD_TYPE=Release\n"
                                  "cmake --build " + root + "/build --target impactcert-verify -j 7\n"
                                  "impactcert-verify \n"); // the stub's "$*" after a space
    // build_tree (scripts/test) builds everything, also one job per core.
    std::remove(log.c_str());
    REQUIRE(std::system(("PATH=" + root + "/bin:$PATH bash -c 'source " + root + "/scripts/lib.sh && build_tree " + root +
                         "/b -DX=1' 2>/dev/null").c_str()) == 0);
    CHECK(impactcert::test::read_file(log) == "cmake -S " + root + " -B " + root + "/b -G Ninja -DX=1\ncmake --build " + root + "/b -j 7\n");
    std::system(("rm -rf " + root).c_str());
}
