// SPDX-License-Identifier: GPL-3.0-or-later
#include "derive/derive.hpp"
#include "exact/eft.hpp"
#include "fuzz/float_eval.hpp"
#include "fuzz/fuzz.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <cfenv>
#include <fstream>
#include <map>
#include <random>
#include <set>

using namespace impactcert;
using impactcert::test::source_path;

namespace {
// Exactly on some facet of some cone: inside a piece's closed cone with a cone coordinate zero.
bool on_a_facet(const Model& model, const double* a, std::size_t dim) {
    Vector x;
    for (std::size_t j = 0; j < dim; ++j)
        x.push_back(Rational(a[j]));
    for (const auto& piece : model.pieces()) {
        bool inside = true, some_zero = false;
        for (const auto& c : piece.R_inv * x) {
            inside = inside && sign_of(c) != Sign::negative;
            some_zero = some_zero || sign_of(c) == Sign::zero;
        }
        if (inside && some_zero)
            return true;
    }
    return false;
}
} // namespace

TEST_CASE("fuzz: samples are a pure function of seed and index", "[fuzz]") {
    for (std::uint64_t i = 0; i < 1000; ++i) {
        const auto a = fuzz::make_paper_sample(42, i), b = fuzz::make_paper_sample(42, i);
        CHECK(fuzz::hex(a.a[0]) == fuzz::hex(b.a[0]));
        CHECK(fuzz::hex(a.a[1]) == fuzz::hex(b.a[1]));
    }
    // Beyond the deterministic prefix (the same for every seed), the seed matters.
    CHECK(fuzz::hex(fuzz::make_paper_sample(1, 5000).a[0]) != fuzz::hex(fuzz::make_paper_sample(2, 5000).a[0]));
    CHECK(fuzz::hex(fuzz::make_paper_sample(1, 5).a[0]) == fuzz::hex(fuzz::make_paper_sample(2, 5).a[0]));
}

TEST_CASE("fuzz: ulp distance counts representable doubles, with +0 == -0", "[fuzz]") {
    CHECK(fuzz::ulp_distance(1.0, std::nextafter(1.0, 2.0)) == 1);
    CHECK(fuzz::ulp_distance(0.0, -0.0) == 0);
    CHECK(fuzz::ulp_distance(-4.9406564584124654e-324, 4.9406564584124654e-324) == 2);
    CHECK(fuzz::ulp_distance(-1.0, -1.0) == 0);
}

TEST_CASE("fuzz: a deliberately wrong implementation is caught within a second, with a replay that reproduces it",
          "[fuzz][cli]") {
    const std::string impl = IMPACTCERT_EXAMPLE_IMPL;
    const auto run = test::run_cli("fuzz --impl '" + impl + "' --seed 1 --samples 100000000 --seconds 1 --jobs 1");
    INFO(run.out << run.err);
    CHECK(run.status == 1);
    CHECK(run.out.find("verdict: violations found") != std::string::npos);
    const auto at = run.out.find(std::string(IMPACTCERT_CLI) + " eval --float --impl ");
    REQUIRE(at != std::string::npos);
    const auto from = run.out.rfind("replay: ", at);
    REQUIRE(from != std::string::npos);
    std::string replay = run.out.substr(from + std::string("replay: ").size());
    replay = replay.substr(0, replay.find('\n'));
    const auto again = test::run_replay(replay);
    INFO(replay << "\n" << again.out << again.err);
    CHECK(again.status == 1); // the replay of a violation exits 1, as the fuzzer did (issue 32: it exited 0)
    CHECK(again.out.find("not within 0 ulp of the correctly rounded value (--max-ulps)") != std::string::npos);
    CHECK(again.out.find("impl ") == 0);
    CHECK(again.out.find(", error ") != std::string::npos);
    CHECK(again.out.find(", error 0, 0 ulp") == std::string::npos); // the error shows again
    // Negative control: the same point with every error allowed exits 0.
    std::string lenient = replay;
    lenient.replace(lenient.find(" -- "), 4, " --max-ulps 18446744073709551615 -- ");
    const auto allowed = test::run_replay(lenient);
    INFO(lenient << "\n" << allowed.out << allowed.err);
    CHECK(allowed.status == 0);
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

// ---------------------------------------------------------------------------------------------
// Any law

namespace {

Model law_file(const std::string& relative) { return Model(load_law_file(source_path(relative))); }

Model derived_law(std::vector<const char*> masses, const char* e) {
    DeriveOptions o;
    for (const char* m : masses)
        o.masses.push_back(*parse_rational(m));
    for (std::size_t k = 0; k + 1 < masses.size(); ++k)
        o.restitution.push_back(*parse_rational(e));
    const auto r = derive_sequential(o);
    REQUIRE(r.law);
    return Model(*r.law);
}

// The fast reference equals the GMP reference at every generated point (and both pieces agree).
void require_fast_equals_exact(const Model& model, bool velocities, bool continuous, std::uint64_t samples) {
    const fuzz::LawReference ref(model, velocities, continuous);
    REQUIRE(ref.fast_path());
    const fuzz::Generator gen(ref);
    std::map<std::string, std::uint64_t> slow_by_kind;
    std::uint64_t slow = 0;
    for (std::uint64_t i = 0; i < samples; ++i) {
        fuzz::Sample s;
        gen.make(3, i, s);
        for (const double* x : {s.a, s.b}) {
            if (x == s.b && !s.pair)
                break;
            fuzz::RefPoint fast, exact;
            ref.eval(x, fast);
            ref.eval_exact(x, exact);
            slow += fast.slow;
            std::string where;
            for (std::size_t j = 0; j < ref.in_dim(); ++j)
                where += fuzz::hex(x[j]) + " ";
            INFO(model.law().name << (velocities ? " (velocities) " : " ") << s.kind << ": " << where);
            REQUIRE(fast.in_domain == exact.in_domain);
            REQUIRE(fast.values == exact.values);
            for (std::size_t v = 0; v < fast.values; ++v)
                for (std::size_t k = 0; k < ref.out_dim(); ++k) {
                    INFO("component " << k << ": fast " << fuzz::hex(fast.value[v][k]) << ", exact "
                                      << fuzz::hex(exact.value[v][k]));
                    REQUIRE(fuzz::ulp_distance(fast.value[v][k], exact.value[v][k]) == 0);
                    REQUIRE(fast.exact[v][k] == exact.exact[v][k]);
                }
        }
    }
    // The fast path decides nearly everything without GMP.
    CHECK(slow < samples / 50);
}

} // namespace

TEST_CASE("fuzz reference: the error-free fast path equals GMP at every generated point", "[fuzz][reference]") {
    require_fast_equals_exact(Model(paper_law()), false, true, test::samples(200000));
    require_fast_equals_exact(Model(paper_law()), true, true, test::samples(50000));
    require_fast_equals_exact(law_file("proofs/newton4/law.json"), false, true, test::samples(100000));
    require_fast_equals_exact(law_file("proofs/newton4/law.json"), true, true, test::samples(50000));
    // Rational entries (denominators), not face to face, several-valued on boundaries:
    require_fast_equals_exact(derived_law({"1", "2", "3"}, "1/2"), false, true, test::samples(50000));
    require_fast_equals_exact(derived_law({"1", "2", "3", "4"}, "1/2"), true, true, test::samples(20000));
    require_fast_equals_exact(law_file("tests/laws/tjunction-newton4-split.json"), false, true, test::samples(50000));
    require_fast_equals_exact(law_file("proofs/controls/discontinuous-isometric.json"), false, false, test::samples(50000));
}

TEST_CASE("fuzz reference: correct rounding of integer rows at every scale, ties and overflow included",
          "[fuzz][reference]") {
    // Random rows a/d and points over the whole double range, checked against nearest_double of
    // the exact rational; ties are forced by points whose value is a midpoint.
    std::mt19937_64 rng(7);
    auto pick = [&](std::uint64_t n) { return rng() % n; };
    std::uint64_t decided = 0;
    const std::size_t trials = test::samples(200000);
    for (std::size_t trial = 0; trial < trials; ++trial) {
        eft::IntRow row;
        row.m = 1 + pick(4);
        for (std::size_t j = 0; j < row.m; ++j) {
            const int kind = static_cast<int>(pick(4));
            row.a[j] = kind == 0 ? 0.0 : static_cast<double>(static_cast<std::int64_t>(pick(kind == 3 ? (1ull << 52) : 7)) - (kind == 3 ? (1ll << 51) : 3));
        }
        row.d = pick(3) == 0 ? 1.0 : static_cast<double>(1 + pick(pick(2) ? 10 : (1ull << 52)));
        row.prepare();
        double x[4];
        const int e = static_cast<int>(pick(2100)) - 1075;
        for (std::size_t j = 0; j < row.m; ++j) {
            const double mant = static_cast<double>(rng() >> 11) * 0x1p-53;
            x[j] = pick(8) == 0 ? 0.0 : std::ldexp(mant, e - static_cast<int>(pick(pick(2) ? 3 : 200))) * (pick(2) ? 1 : -1);
        }
        if (pick(10) == 0 && row.m >= 2) { // a tie: x1 = x0 + half an ulp of it, a = (1, 1)/2... built exactly
            row.a[0] = 1;
            row.a[1] = 1;
            row.d = 1;
            x[0] = std::ldexp(1.0 + static_cast<double>(rng() >> 12) * 0x1p-52, e % 900);
            x[1] = std::ldexp(std::nextafter(x[0], INFINITY) - x[0], -1) * (pick(2) ? 1 : -1);
            for (std::size_t j = 2; j < row.m; ++j)
                row.a[j] = 0;
            row.prepare();
        }
        double xs[4];
        int k = 0;
        if (!eft::scale_into_safe_range(x, row.m, xs, k))
            continue;
        Rational exact = 0;
        for (std::size_t j = 0; j < row.m; ++j)
            exact += Rational(row.a[j]) * Rational(x[j]);
        exact /= Rational(row.d);
        double y = 0;
        bool is_exact = false;
        REQUIRE(std::fegetround() == FE_TONEAREST);
        if (!row.nearest(xs, k, y, is_exact))
            continue;
        ++decided;
        const double want = nearest_double(exact);
        std::string what = "a =";
        for (std::size_t j = 0; j < row.m; ++j)
            what += " " + std::to_string(row.a[j]);
        what += " / " + std::to_string(row.d) + ", x =";
        for (std::size_t j = 0; j < row.m; ++j)
            what += " " + fuzz::hex(x[j]);
        INFO(what << ", got " << fuzz::hex(y) << ", want " << fuzz::hex(want));
        REQUIRE(fuzz::ulp_distance(y, want) == 0);
        REQUIRE(is_exact == (std::isfinite(want) && Rational(want) == exact));
        if (row.terms < 0) { // the sign as well
            Rational num = 0;
            for (std::size_t j = 0; j < row.m; ++j)
                num += Rational(row.a[j]) * Rational(x[j]);
            REQUIRE(row.sign(xs) == static_cast<int>(sign_of(num)));
        }
    }
    CHECK(decided > trials * 3 / 4);
}

TEST_CASE("fuzz reference: the general reference equals the paper law's independent TwoSum route", "[fuzz][reference]") {
    const Model paper(paper_law());
    const fuzz::LawReference ref(paper, false, true);
    for (std::uint64_t i = 0; i < test::samples(500000); ++i) {
        const auto s = fuzz::make_paper_sample(9, i);
        fuzz::RefPoint r;
        ref.eval(s.a, r);
        const auto two_sum = fuzz::reference_fast(s.a[0], s.a[1]);
        INFO(s.kind << " " << fuzz::hex(s.a[0]) << " " << fuzz::hex(s.a[1]));
        REQUIRE(r.values == 1);
        REQUIRE(fuzz::ulp_distance(r.value[0][0], two_sum.value[0]) == 0);
        REQUIRE(fuzz::ulp_distance(r.value[0][1], two_sum.value[1]) == 0);
    }
}

TEST_CASE("fuzz generators: reproducible, every kind, exact facet points, the whole range", "[fuzz]") {
    for (const char* path : {"proofs/newton4/law.json", "tests/laws/one-piece-c8.json"}) {
        const Model model = law_file(path);
        const fuzz::LawReference ref(model, false, true);
        const fuzz::Generator gen(ref);
        std::set<std::string> kinds;
        std::uint64_t subnormal = 0, huge = 0, zero = 0, facet = 0, on_facet = 0, pairs = 0;
        for (std::uint64_t i = 0; i < 40000; ++i) {
            fuzz::Sample s, t;
            gen.make(5, i, s);
            gen.make(5, i, t);
            REQUIRE(std::memcmp(s.a, t.a, sizeof s.a) == 0);
            kinds.insert(s.kind);
            pairs += s.pair;
            for (std::size_t j = 0; j < ref.in_dim(); ++j) {
                subnormal += s.a[j] != 0 && std::fabs(s.a[j]) < 0x1p-1022;
                huge += std::fabs(s.a[j]) > 0x1p1000;
                zero += s.a[j] == 0;
            }
            if (std::string(s.kind) == "facet") {
                ++facet;
                on_facet += on_a_facet(model, s.a, ref.in_dim());
            }
        }
        INFO(path);
        CHECK(kinds == std::set<std::string>(fuzz::Generator::kinds().begin(), fuzz::Generator::kinds().end()));
        CHECK(subnormal > 400);
        CHECK(huge > 400);
        CHECK(zero > 400);
        CHECK(pairs > 2000);
        CHECK(on_facet * 10 > facet * 9); // integer rays: facet points are exact
    }
    // Beyond the deterministic prefix (the same for every seed), the seed matters.
    CHECK(fuzz::hex(fuzz::make_paper_sample(1, 5000).a[0]) != fuzz::hex(fuzz::make_paper_sample(2, 5000).a[0]));
    CHECK(fuzz::hex(fuzz::make_paper_sample(1, 5).a[0]) == fuzz::hex(fuzz::make_paper_sample(2, 5).a[0]));
}

TEST_CASE("fuzz --range in law mode: samples scaled by powers of two into LO..HI, small components zeroed",
          "[fuzz]") {
    const Model model = law_file("proofs/newton4/law.json");
    const fuzz::LawReference ref(model, false, true);
    const fuzz::Generator gen(ref);
    const std::size_t m = ref.in_dim();
    for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{{1e-3, 1e3}, {1, 1}, {0.75, 1.25}, {1e-300, 1e300}}) {
        std::uint64_t zeroed = 0, kept = 0, facet_kept = 0, facet = 0, top_in = 0, moving = 0;
        for (std::uint64_t i = 0; i < 40000; ++i) {
            fuzz::Sample s;
            gen.make(5, i, s);
            const fuzz::Sample before = s;
            fuzz::fit_range(s, m, lo, hi);
            double top = 0, top_before = 0;
            for (std::size_t j = 0; j < m; ++j) {
                for (const double* v : {s.a, s.b}) {
                    if (v == s.b && !s.pair)
                        continue;
                    INFO("sample " << i << " component " << j << " = " << v[j]);
                    REQUIRE((v[j] == 0 || (std::fabs(v[j]) >= lo && std::fabs(v[j]) <= hi)));
                    top = std::max(top, std::fabs(v[j]));
                }
                top_before = std::max(top_before, std::fabs(before.a[j]));
                if (before.pair)
                    top_before = std::max(top_before, std::fabs(before.b[j]));
            }
            if (top_before == 0)
                continue;
            // One power of two for the whole sample: the ratio of every kept component to the
            // largest one is unchanged (exact, so a facet point stays on its facet).
            std::size_t big = 0;
            for (std::size_t j = 0; j < m; ++j)
                if (std::fabs(before.a[j]) > std::fabs(before.a[big]))
                    big = j;
            for (std::size_t j = 0; j < m && s.a[big] != 0; ++j) {
                if (s.a[j] == 0) {
                    zeroed += before.a[j] != 0;
                    continue;
                }
                ++kept;
                if (hi >= 2 * lo) // a power of two always fits
                    REQUIRE(s.a[j] / s.a[big] == before.a[j] / before.a[big]);
            }
            ++moving;
            top_in += top >= lo;
            if (std::string(s.kind) == "facet") {
                ++facet;
                facet_kept += on_a_facet(model, s.a, m);
            }
        }
        INFO("range " << lo << ".." << hi);
        CHECK(kept > 40000);
        CHECK(moving > 35000);
        CHECK(top_in == moving); // the largest component reaches LO
        if (hi >= 2 * lo)
            CHECK(facet_kept * 10 > facet * 8); // facet points mostly stay on facets (zeroed ones may leave)
        if (hi / lo > 1e100)
            CHECK(zeroed < kept);           // a wide range zeroes little
        else
            CHECK(zeroed > 0);              // a narrow one zeroes the tiny components
    }
}

// Issue 44: with --range 1e-150..1e150, 99.4% of the samples had their largest component above
// 1e125 (each was pushed to the top of the range), and a solver with an absolute 1e-6 threshold
// passed a million samples. The scale is now drawn among the powers of two that fit.
TEST_CASE("fuzz --range in law mode: the samples' scales are log-uniform over the range, and the prefix "
          "covers every piece, facet side and ray at both ends",
          "[fuzz]") {
    const Model model = law_file("proofs/newton4/law.json");
    const fuzz::LawReference ref(model, false, true);
    const std::size_t m = ref.in_dim();
    for (const auto& [lo, hi] : std::vector<std::pair<double, double>>{{1e-150, 1e150}, {1e-3, 1e3}}) {
        const fuzz::Generator gen(ref, lo, hi);
        const double decades = std::log10(hi / lo);
        std::vector<std::uint64_t> per_decade(static_cast<std::size_t>(decades) + 1, 0);
        std::uint64_t moving = 0;
        for (std::uint64_t i = gen.prefix_count(); i < gen.prefix_count() + 60000; ++i) {
            fuzz::Sample s;
            gen.make(7, i, s);
            double top = 0;
            for (std::size_t j = 0; j < m; ++j) {
                REQUIRE((s.a[j] == 0 || (std::fabs(s.a[j]) >= lo && std::fabs(s.a[j]) <= hi)));
                top = std::max(top, std::fabs(s.a[j]));
            }
            if (top == 0)
                continue;
            ++moving;
            ++per_decade[static_cast<std::size_t>(std::min(decades, std::floor(std::log10(top / lo))))];
        }
        INFO("range " << lo << ".." << hi);
        // Every decade of the range holds about its share (log-uniform): none below half of it, none
        // above twice (the end decades partly: the powers of two that fit there are fewer).
        const double share = static_cast<double>(moving) / decades;
        for (std::size_t d = 1; d + 1 < per_decade.size(); ++d) {
            INFO("decade " << d);
            CHECK(static_cast<double>(per_decade[d]) > share / 2);
            CHECK(static_cast<double>(per_decade[d]) < share * 2);
        }
        // The prefix: at rest first, then every piece and both sides of every facet, at the
        // middle of the range, and the pieces again at its top and bottom.
        std::set<long> facets;
        std::uint64_t top_end = 0, bottom_end = 0;
        for (std::uint64_t i = 0; i < gen.prefix_count(); ++i) {
            fuzz::Sample s;
            gen.make(7, i, s);
            CHECK(std::string(s.kind) == "prefix");
            if (s.facet >= 0)
                facets.insert(s.facet);
            double top = 0;
            for (std::size_t j = 0; j < m; ++j)
                top = std::max(top, std::fabs(s.a[j]));
            if (i == 0)
                CHECK(top == 0);
            top_end += top > hi / 2;
            bottom_end += top > 0 && top < 2 * lo;
        }
        CHECK(facets.size() == gen.facets());
        if (lo == 1e-3) { // every binade of a narrow range, not every other one (a parity bug of the draw)
            const fuzz::Generator narrow(ref, 1, 16);
            std::uint64_t binade[5] = {};
            for (std::uint64_t i = narrow.prefix_count(); i < narrow.prefix_count() + 8000; ++i) {
                fuzz::Sample t;
                narrow.make(3, i, t);
                double big = 0;
                for (std::size_t j = 0; j < m; ++j)
                    big = std::max(big, std::fabs(t.a[j]));
                if (big > 0)
                    ++binade[std::min(4, std::ilogb(big))];
            }
            for (int e = 0; e < 4; ++e) {
                INFO("binade [2^" << e << ", 2^" << e + 1 << "): " << binade[e]);
                CHECK(binade[e] > 1000);
            }
        }
        CHECK(top_end >= model.pieces().size());
        CHECK(bottom_end >= model.pieces().size());
    }
}

TEST_CASE("fuzz: hex text round-trips through strtod and matches printf's %a", "[fuzz]") {
    std::mt19937_64 rng(3);
    for (int i = 0; i < 100000; ++i) {
        std::uint64_t bits = rng();
        double x;
        std::memcpy(&x, &bits, 8);
        if (!std::isfinite(x))
            continue;
        const std::string h = fuzz::hex(x);
        char buf[64];
        std::snprintf(buf, sizeof buf, "%a", x);
        REQUIRE(h == buf);
        REQUIRE(std::strtod(h.c_str(), nullptr) == x);
    }
    CHECK(fuzz::hex(0.0) == "0x0p+0");
    CHECK(fuzz::hex(-0.0) == "-0x0p+0");
}

namespace {

fuzz::Summary fuzz_law(const Model& model, const fuzz::Implementation& impl, std::uint64_t samples,
                       fuzz::Tolerance tol, double rel = 0, unsigned jobs = 2, bool velocities = false) {
    const fuzz::LawReference ref(model, velocities, true);
    fuzz::Options o;
    o.seed = 11;
    o.samples = samples;
    o.jobs = jobs;
    o.tolerance = tol;
    o.max_rel_error = rel;
    return fuzz::run(o, ref, impl, fuzz::Properties{true, true, true}, nullptr);
}

std::string newton4_impl(const char* symbol) { return std::string(IMPACTCERT_NEWTON4_IMPLS) + ":" + symbol; }

} // namespace

TEST_CASE("fuzz: the built-in float laws have no violation", "[fuzz]") {
    const Model paper(paper_law());
    auto sum = fuzz_law(paper, *fuzz::builtin_paper(false), 1000000, fuzz::Tolerance::ulps);
    CHECK(sum.samples == 1000000);
    CHECK(sum.pairs > 50000);
    CHECK(sum.violations() == 0);
    CHECK(sum.max_ulps == std::vector<std::uint64_t>{0, 0});
    sum = fuzz_law(paper, *fuzz::builtin_paper(true), 300000, fuzz::Tolerance::ulps, 0, 2, true);
    CHECK(sum.violations() == 0);
    CHECK(sum.max_ulps == std::vector<std::uint64_t>{0, 0, 0}); // sorting is exact
    // FloatLaw of any law against its own stated bound (checked exactly where it is tight).
    const Model newton4 = law_file("proofs/newton4/law.json");
    sum = fuzz_law(newton4, *fuzz::builtin_float_law(newton4), 30000, fuzz::Tolerance::stated_bound);
    CHECK(sum.violations() == 0);
    const Model derived = derived_law({"1", "2", "3"}, "1/2");
    sum = fuzz_law(derived, *fuzz::builtin_float_law(derived), 30000, fuzz::Tolerance::stated_bound);
    CHECK(sum.violations() == 0);
}

TEST_CASE("fuzz: a correct implementation that does not round correctly passes --max-rel-error, fails --max-ulps 0",
          "[fuzz]") {
    const Model newton4 = law_file("proofs/newton4/law.json");
    const auto impl = fuzz::load_symbol(newton4_impl("newton4_sorted"), 3, 3);
    auto sum = fuzz_law(newton4, *impl, 500000, fuzz::Tolerance::relative, 1e-12);
    CHECK(sum.violations() == 0);
    CHECK(sum.max_rel_error > 0);
    CHECK(sum.max_rel_error < 1e-15);
    sum = fuzz_law(newton4, *impl, 100000, fuzz::Tolerance::ulps);
    CHECK(sum.inaccurate > 0);
    CHECK(sum.misclassified == 0);
    CHECK(sum.negative + sum.energy + sum.nonexpansive + sum.non_finite == 0);
}

TEST_CASE("fuzz: wrong implementations of the kinds simulators ship are found in under a second, with replays",
          "[fuzz][cli]") {
    const std::string law = source_path("proofs/newton4/law.json");
    struct Case {
        const char* symbol;
        const char* finding;
    };
    for (const Case c : {Case{"newton4_tolerance", "negative contact velocity"},
                         Case{"newton4_two_sweeps", "classification: the output is piece"},
                         Case{"newton4_impulse", "non-finite output"}}) {
        INFO(c.symbol);
        const auto run = test::run_cli("fuzz --law '" + law + "' --impl '" + newton4_impl(c.symbol) +
                                       "' --max-rel-error 1e-12 --samples 100000000 --seconds 1 --jobs 1 --keep 100");
        INFO(run.out << run.err);
        CHECK(run.status == 1);
        const auto at = run.out.find(c.finding);
        REQUIRE(at != std::string::npos);
        const auto r = run.out.find("replay: ", at);
        REQUIRE(r != std::string::npos);
        std::string replay = run.out.substr(r + std::string("replay: ").size());
        replay = replay.substr(0, replay.find('\n'));
        const auto again = test::run_replay(replay);
        INFO(replay << "\n" << again.out << again.err);
        CHECK(again.status == 1);
        CHECK(again.out.rfind("impl ", 0) == 0);
        CHECK(again.out.find(", error 0, 0, 0 ulp") == std::string::npos);
    }
}

TEST_CASE("fuzz --impl-cmd: any language through a pipe, failures reported and survived", "[fuzz][cli]") {
    const std::string law = source_path("proofs/newton4/law.json");
    const std::string py = "python3 " + source_path("tests/impls/newton4_impl.py");
    // (The sanitizer run: a quarter of the samples, test::samples.)
    const std::string n = std::to_string(test::samples(20000));
    auto run = test::run_cli("fuzz --law '" + law + "' --impl-cmd '" + py + " sorted' --max-rel-error 1e-12 --samples " + n + " --json");
    INFO(run.out << run.err);
    CHECK(run.status == 0);
    CHECK(nlohmann::json::parse(run.out)["verdict"] == "no violation");
    run = test::run_cli("fuzz --law '" + law + "' --impl-cmd '" + py + " tolerance' --max-rel-error 1e-12 --samples " + n);
    CHECK(run.status == 1);
    // The replay carries the run's tolerance (it used to judge at 0 ulp).
    CHECK(run.out.find(" && " + std::string(IMPACTCERT_CLI) + " eval --float --max-rel-error 1e-12 --law") != std::string::npos);
    CHECK(run.out.find("--impl-cmd") != std::string::npos);
    // A crash, a hang and a short answer: each point is reported, the run goes on to the end.
    const std::string bad = "python3 " + source_path("tests/impls/misbehaving_impl.py");
    for (const char* mode : {"crash", "short", "hang", "extra"}) {
        INFO(mode);
        // Each hang costs 2.3 s and each crash a new interpreter (it crashes on about half the
        // inputs): a few of each suffice to show that the run goes on to the end.
        const int samples = std::string(mode) == "hang" ? 6 : std::string(mode) == "crash" ? 40 : 300;
        run = test::run_cli("fuzz --law '" + law + "' --impl-cmd '" + bad + " " + mode +
                            "' --max-ulps 1000000000000000000 --samples " + std::to_string(samples) +
                            " --jobs 1 --impl-timeout 0.3 --json");
        INFO(run.out << run.err);
        CHECK(run.status == 1);
        const auto j = nlohmann::json::parse(run.out);
        CHECK(j["samples"] == samples);
        // "extra": a line too many puts every later answer out of step; the batch is malformed,
        // never blamed on the wrong inputs.
        const std::string key = std::string(mode) == "short" || std::string(mode) == "extra" ? "malformed"
                                : mode == std::string("crash")                             ? "crashed"
                                                                                           : "hung";
        CHECK(j["violations"][key].get<long>() > 0);
    }
    // Bad input: one line, exit 2 (a command that writes bytes but never a line included).
    for (const std::string& args : std::vector<std::string>{"--impl-cmd '" + bad + " trickle' --impl-timeout 0.5",
                                                            "--max-ulps -1", "--max-ulps 18446744073709551616",
                                                            "--impl-cmd ''", "--impl ''", "--seconds nan",
                                                            "--impl-cmd cat --impl-timeout nan", "--keep -1",
                                                            "--junit /nonexistent/dir/junit.xml",
                                                            "--impl-cmd /nonexistent/program", "--impl-cmd " + source_path("README.md"),
                                   "--impl '" + std::string(IMPACTCERT_NEWTON4_IMPLS) + ":no_such_symbol'",
                                   "--impl /nonexistent.so:f", "--velocities"}) {
        INFO(args);
        run = test::run_cli("fuzz --law '" + law + "' " + args + " --samples 10");
        CHECK(run.status == 2);
        CHECK(std::count(run.err.begin(), run.err.end(), '\n') == 1);
    }
    // The protocol at speed: the echo program (the identity, wrong for this law).
    const std::size_t fast = test::samples(200000);
    run = test::run_cli("fuzz --law '" + law + "' --impl-cmd " + IMPACTCERT_ECHO_IMPL + " --samples " + std::to_string(fast) +
                        " --json --keep 1");
    CHECK(run.status == 1);
    CHECK(nlohmann::json::parse(run.out)["samples"] == fast);
}

TEST_CASE("fuzz --velocities: implementations in ball velocities", "[fuzz]") {
    const Model newton4 = law_file("proofs/newton4/law.json");
    auto sum = fuzz_law(newton4, *fuzz::load_symbol(newton4_impl("newton4_balls_sorted"), 4, 4), 200000,
                        fuzz::Tolerance::ulps, 0, 2, true);
    CHECK(sum.violations() == 0);
    CHECK(sum.max_ulps == std::vector<std::uint64_t>{0, 0, 0, 0});
    sum = fuzz_law(newton4, *fuzz::load_symbol(newton4_impl("newton4_balls_one_sweep"), 4, 4), 20000,
                   fuzz::Tolerance::relative, 1e-12, 2, true);
    CHECK(sum.inaccurate > 0);
    CHECK(sum.negative > 0); // the balls still approach: W^T u+ has a negative component
    // A law with unequal masses: u+ is not a permutation, the reference rounds A u- correctly.
    const Model derived = derived_law({"1", "2", "3", "4"}, "1/2");
    const fuzz::LawReference ref(derived, true, true);
    CHECK(ref.in_dim() == 4);
    CHECK(ref.fast_path());
}

TEST_CASE("fuzz: results do not depend on --jobs - JUnit and JSON reports", "[fuzz][cli]") {
    const Model newton4 = law_file("proofs/newton4/law.json");
    const auto impl = fuzz::load_symbol(newton4_impl("newton4_two_sweeps"), 3, 3);
    const auto one = fuzz_law(newton4, *impl, 60000, fuzz::Tolerance::relative, 1e-12, 1);
    const auto two = fuzz_law(newton4, *impl, 60000, fuzz::Tolerance::relative, 1e-12, 2);
    CHECK(one.inaccurate == two.inaccurate);
    CHECK(one.negative == two.negative);
    CHECK(one.misclassified == two.misclassified);
    REQUIRE(one.examples.size() == two.examples.size());
    for (std::size_t i = 0; i < one.examples.size(); ++i)
        CHECK(one.examples[i].replay == two.examples[i].replay);
    const std::string junit = "/tmp/impactcert-fuzz-test-junit.xml";
    const auto run = test::run_cli("fuzz --law '" + source_path("proofs/newton4/law.json") + "' --impl '" +
                                   newton4_impl("newton4_two_sweeps") + "' --samples 20000 --junit " + junit + " --json");
    CHECK(run.status == 1);
    const auto j = nlohmann::json::parse(run.out);
    CHECK(j["violations"]["classification"].get<long>() > 0);
    CHECK(j["examples"][0]["replay"].get<std::string>().find(" && " + std::string(IMPACTCERT_CLI) + " eval --float --law") !=
          std::string::npos);
    std::ifstream f(junit);
    const std::string xml((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    CHECK(xml.find("<testcase classname=\"impactcert.fuzz\" name=\"classification\" time=") != std::string::npos);
    CHECK(xml.find("<failure type=\"violations\" message=") != std::string::npos);
    CHECK(test::run_cli("fuzz --max-ulps 1 --max-rel-error 1e-9 --samples 10").status == 2);
    CHECK(test::run_cli("fuzz --max-rel-error -1 --samples 10").status == 2);
}

namespace {

// A correct implementation except that it returns the largest double where the correctly
// rounded value overflows but the exact value is within 2^-20 of the largest double: well
// within a relative tolerance of 10^-6 of the exact (finite) value.
class ClampingImpl final : public fuzz::Implementation {
  public:
    explicit ClampingImpl(const fuzz::LawReference& ref) : ref_(ref) {}
    void eval(const double* in, double* out, double*, std::size_t count, fuzz::ImplStatus* status) override {
        const std::size_t m = ref_.in_dim();
        for (std::size_t i = 0; i < count; ++i) {
            fuzz::RefPoint r;
            ref_.eval(in + i * m, r);
            for (std::size_t j = 0; j < m; ++j) {
                const double v = r.values ? r.value[0][j] : 0.0;
                out[i * m + j] = v;
                if (std::isinf(v)) {
                    const Rational exact = ref_.exact_value(in + i * m, r.piece[0])[j];
                    const Rational near = Rational(std::numeric_limits<double>::max()) * (1 + Rational(1) / (1 << 20));
                    if ((sign_of(exact) == Sign::negative ? -exact : exact) < near)
                        out[i * m + j] = std::copysign(std::numeric_limits<double>::max(), v);
                }
            }
            status[i] = fuzz::ImplStatus::ok;
        }
    }
    std::unique_ptr<fuzz::Implementation> clone() const override { return std::make_unique<ClampingImpl>(ref_); }
    std::string describe() const override { return "clamping"; }
    std::string replay_flags() const override { return ""; }

  private:
    const fuzz::LawReference& ref_;
};

} // namespace

TEST_CASE("fuzz --max-rel-error: exact values beyond the double range, decided exactly", "[fuzz]") {
    // expansive-scaled doubles the input: near the top of the range the exact output overflows.
    const Model law = law_file("proofs/controls/expansive-scaled.json");
    const fuzz::LawReference ref(law, false, true);
    const ClampingImpl impl(ref);
    fuzz::Options o;
    o.seed = 11;
    o.samples = 200000;
    o.jobs = 2;
    o.tolerance = fuzz::Tolerance::relative;
    o.max_rel_error = 1e-6;
    const auto sum = fuzz::run(o, ref, impl, fuzz::Properties{}, nullptr); // the law is expansive
    INFO("inaccurate " << sum.inaccurate << ", non-finite " << sum.non_finite << ", negative " << sum.negative
                       << ", energy " << sum.energy << ", nonexpansive " << sum.nonexpansive << ": "
                       << (sum.examples.empty() ? "" : sum.examples[0].what + " " + sum.examples[0].replay));
    CHECK(sum.violations() == 0);
    o.tolerance = fuzz::Tolerance::ulps;
    const auto strict = fuzz::run(o, ref, impl, fuzz::Properties{}, nullptr);
    CHECK(strict.inaccurate > 0); // DBL_MAX is not the correctly rounded infinity
}
