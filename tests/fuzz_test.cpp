#include "fuzz.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

using namespace impactcert;

TEST_CASE("fuzz: samples are a pure function of seed and index", "[fuzz]") {
    for (std::uint64_t i = 0; i < 1000; ++i) {
        const auto a = fuzz::make_paper_sample(42, i), b = fuzz::make_paper_sample(42, i);
        CHECK(fuzz::hex(a.a[0]) == fuzz::hex(b.a[0]));
        CHECK(fuzz::hex(a.a[1]) == fuzz::hex(b.a[1]));
    }
    CHECK(fuzz::hex(fuzz::make_paper_sample(1, 5).a[0]) != fuzz::hex(fuzz::make_paper_sample(2, 5).a[0]));
}

TEST_CASE("fuzz: the generators reach every region that matters", "[fuzz]") {
    std::set<std::string> kinds;
    std::size_t subnormal = 0, huge = 0, zero = 0, on_diagonal = 0;
    for (std::uint64_t i = 0; i < 100000; ++i) {
        const auto s = fuzz::make_paper_sample(1, i);
        kinds.insert(s.kind);
        for (double g : s.a.g) {
            subnormal += (g != 0 && std::fabs(g) < 2.2250738585072014e-308) ? 1 : 0;
            huge += std::fabs(g) > 1e300 ? 1 : 0;
            zero += g == 0 ? 1 : 0;
        }
        on_diagonal += (s.a[0] == -s.a[1] && s.a[0] != 0) ? 1 : 0;
    }
    CHECK(kinds == std::set<std::string>{"log-uniform", "boundary-ray", "signed-zero", "subnormal", "overflow-region",
                                         "close-pair"});
    CHECK(subnormal > 1000);
    CHECK(huge > 1000);
    CHECK(zero > 1000);
    CHECK(on_diagonal > 100); // exactly on the rays (-1,1) and (1,-1)
}

TEST_CASE("fuzz: ulp distance counts representable doubles, with +0 == -0", "[fuzz]") {
    CHECK(fuzz::ulp_distance(1.0, std::nextafter(1.0, 2.0)) == 1);
    CHECK(fuzz::ulp_distance(0.0, -0.0) == 0);
    CHECK(fuzz::ulp_distance(-4.9406564584124654e-324, 4.9406564584124654e-324) == 2);
    CHECK(fuzz::ulp_distance(-1.0, -1.0) == 0);
}

TEST_CASE("fuzz: the built-in float law has no violation and 0 ulp error", "[fuzz]") {
    fuzz::Options o;
    o.seed = 1;
    o.samples = 2000000;
    o.jobs = 2;
    const auto sum = fuzz::run(o, nullptr, nullptr);
    CHECK(sum.samples == 2000000);
    CHECK(sum.pairs > 100000);
    CHECK(sum.violations() == 0);
    CHECK(sum.max_ulps[0] == 0);
    CHECK(sum.max_ulps[1] == 0);
}

TEST_CASE("fuzz: a deliberately wrong implementation is caught within a second, with a replay that reproduces it",
          "[fuzz][cli]") {
    const std::string impl = IMPACTCERT_EXAMPLE_IMPL;
    const auto run = test::run_cli("fuzz --impl '" + impl + "' --seed 1 --samples 100000000 --seconds 1 --jobs 1");
    INFO(run.out << run.err);
    CHECK(run.status == 1);
    CHECK(run.out.find("verdict: violations found") != std::string::npos);
    const auto at = run.out.find("replay: impactcert eval --float --impl ");
    REQUIRE(at != std::string::npos);
    std::string replay = run.out.substr(at + std::string("replay: impactcert ").size());
    replay = replay.substr(0, replay.find('\n'));
    const auto again = test::run_cli(replay);
    INFO(replay << "\n" << again.out << again.err);
    CHECK(again.status == 0);
    CHECK(again.out.find("impl ") == 0);
    CHECK(again.out.find("(error 0, 0 ulp)") == std::string::npos); // the error shows again
}

TEST_CASE("fuzz: JSON summary and bad options", "[fuzz][cli]") {
    const auto run = test::run_cli("fuzz --samples 20000 --jobs 2 --json");
    CHECK(run.status == 0);
    const auto j = nlohmann::json::parse(run.out);
    CHECK(j["format"] == "impactcert-fuzz/1");
    CHECK(j["samples"] == 20000);
    CHECK(j["verdict"] == "no violation");
    CHECK(test::run_cli("fuzz --samples 0").status == 2);
    CHECK(test::run_cli("fuzz --impl nowhere.so:f --samples 10").status == 2);
    CHECK(test::run_cli("fuzz --jobs 0").status == 2);
}

TEST_CASE("fuzz: a seed is a decimal integer in [0, 2^64 - 1], anything else is rejected", "[fuzz]") {
    CHECK(fuzz::parse_seed("0") == std::optional<std::uint64_t>(0));
    CHECK(fuzz::parse_seed("42") == std::optional<std::uint64_t>(42));
    CHECK(fuzz::parse_seed("007") == std::optional<std::uint64_t>(7));
    CHECK(fuzz::parse_seed("18446744073709551615") == std::optional<std::uint64_t>(18446744073709551615ULL));
    for (const char* bad : {"", "-5", "-0", "+5", "1e23", "18446744073709551616", "99999999999999999999999", "0x10",
                            " 7", "7 ", "1.0", "seed"}) {
        INFO("seed '" << bad << "'");
        std::string why;
        CHECK_FALSE(fuzz::parse_seed(bad, &why));
        CHECK_FALSE(why.empty());
    }
}

TEST_CASE("fuzz: --seed out of range or not an integer exits 2 with one line", "[fuzz][cli]") {
    for (const char* bad : {"-5", "1e23", "18446744073709551616", "0x10"}) {
        INFO("--seed " << bad);
        const auto run = test::run_cli(std::string("fuzz --samples 10 --seed ") + bad);
        CHECK(run.status == 2);
        CHECK(run.err.rfind("impactcert: --seed", 0) == 0);
        CHECK(run.err.find(bad) != std::string::npos);
        CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
        CHECK(run.out.empty());
    }
    const auto run = test::run_cli("fuzz --samples 1000 --json --seed 18446744073709551615");
    CHECK(run.status == 0);
    CHECK(nlohmann::json::parse(run.out)["seed"] == 18446744073709551615ULL);
}
