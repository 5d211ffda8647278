// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/float_eval.hpp"
#include "fuzz/fuzz.hpp"
#include "model/law_json.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>

using namespace impactcert;
using impactcert::test::source_path;

namespace {

// The stated bound holds exactly: |value - Q gamma| <= bound, and the piece contains gamma.
void check_bound(const Model& m, const FloatLaw::Result& r, const std::vector<double>& g) {
    REQUIRE(r.ok);
    Vector gamma;
    for (double x : g)
        gamma.emplace_back(x);
    const auto containing = m.pieces_containing(gamma);
    REQUIRE(std::find(containing.begin(), containing.end(), r.piece) != containing.end());
    const Vector exact = m.pieces()[r.piece].Q * gamma;
    for (std::size_t i = 0; i < exact.size(); ++i)
        REQUIRE(abs_of(Rational(r.value[i]) - exact[i]) <= Rational(r.bound[i]));
}

} // namespace

TEST_CASE("float evaluator: the paper's law file, bound holds exactly on 100,000 samples", "[float_eval]") {
    const Model m(load_law_file(source_path("proofs/newton3/law.json")));
    const FloatLaw law(m);
    std::size_t fallbacks = 0;
    const std::size_t n = test::samples(100000);
    for (std::uint64_t i = 0; i < n; ++i) {
        const auto s = fuzz::make_paper_sample(5, i);
        const std::vector<double> g = {s.a[0], s.a[1]};
        const auto r = law.eval(g);
        INFO(fuzz::hex(g[0]) << " " << fuzz::hex(g[1]));
        if (!r.ok) {
            // Only the overflow region may overflow Q gamma's double evaluation.
            REQUIRE(r.error == "overflow in the output");
            continue;
        }
        check_bound(m, r, g);
        fallbacks += r.exact_fallback ? 1 : 0;
    }
    CHECK(fallbacks > n / 100); // boundary samples need the exact classification
    CHECK(fallbacks < n / 2);   // the filter decides the rest
}

TEST_CASE("float evaluator: the 4-ball law (c = 3), bound holds exactly, ties classified exactly", "[float_eval]") {
    const Model m(load_law_file(source_path("proofs/newton4/law.json")));
    const FloatLaw law(m);
    std::mt19937_64 rng(8);
    std::uniform_int_distribution<int> small(-3, 3);
    std::uniform_real_distribution<double> real(-10, 10);
    std::size_t fallbacks = 0;
    const std::size_t n = test::samples(20000);
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<double> g(3);
        for (auto& x : g)
            x = (i % 2) ? small(rng) * 0.5 : real(rng); // half on ties (cone boundaries)
        const auto r = law.eval(g);
        check_bound(m, r, g);
        fallbacks += r.exact_fallback ? 1 : 0;
    }
    CHECK(fallbacks > n / 20); // the ties on cone boundaries: about 30 % of the samples
}

TEST_CASE("float evaluator: non-finite input and overflow are reported, not returned", "[float_eval]") {
    const Model m(load_law_file(source_path("proofs/controls/expansive-scaled.json")));
    const FloatLaw law(m);
    CHECK_FALSE(law.eval({std::nan(""), 1.0}).ok);
    const auto r = law.eval({1e308, 1e308}); // doubling 1e308 overflows
    CHECK_FALSE(r.ok);
    CHECK(r.error == "overflow in the output");
}

// ---------------------------------------------------------------------------------------------
// Laws at the edges of the double range.

namespace {

std::string pow10_text(unsigned k) { return "1" + std::string(k, '0'); }
std::string inv_pow10_text(unsigned k) { return "1/" + pow10_text(k); }
std::string quoted(const std::string& s) { return "\"" + s + "\""; }

// {"name": .., "Q": [[..]], "rays": [[..]]} from rows of rational texts.
std::string piece_json(const std::string& name, const std::vector<std::vector<std::string>>& Q,
                       const std::vector<std::vector<std::string>>& rays) {
    auto mat = [](const std::vector<std::vector<std::string>>& m) {
        std::string s = "[";
        for (std::size_t i = 0; i < m.size(); ++i) {
            s += i ? ", [" : "[";
            for (std::size_t j = 0; j < m[i].size(); ++j)
                s += (j ? ", " : "") + quoted(m[i][j]);
            s += "]";
        }
        return s + "]";
    };
    return "{\"name\": " + quoted(name) + ", \"Q\": " + mat(Q) + ", \"rays\": " + mat(rays) + "}";
}

std::string law_json(const std::string& name, std::size_t balls, const std::vector<std::string>& pieces) {
    std::string s = "{\"format\": \"impactcert-law/1\", \"name\": " + quoted(name) + ", \"masses\": [";
    for (std::size_t i = 0; i < balls; ++i)
        s += i ? ", \"1\"" : "\"1\"";
    s += "], \"pieces\": [";
    for (std::size_t i = 0; i < pieces.size(); ++i)
        s += (i ? ", " : "") + pieces[i];
    return s + "]}";
}

Model model_of(const std::string& json) { return Model(parse_law_text(json, "edge-law")); }

// The four quadrants of the plane, each with its own Q.
std::string quadrant_law(const std::string& name, const std::vector<std::vector<std::vector<std::string>>>& Qs) {
    const std::vector<std::vector<std::vector<std::string>>> rays = {
        {{"1", "0"}, {"0", "1"}}, {{"0", "1"}, {"-1", "0"}}, {{"-1", "0"}, {"0", "-1"}}, {{"0", "-1"}, {"1", "0"}}};
    std::vector<std::string> pieces;
    for (std::size_t p = 0; p < 4; ++p)
        pieces.push_back(piece_json("Q" + std::to_string(p + 1), Qs[p % Qs.size()], rays[p]));
    return law_json(name, 3, pieces);
}

// A thin first-quadrant fan: A between the rays (10^k+1, 1) and (1, 10^k), slivers B and C along
// the axes, and the other quadrants. B doubles, C triples: a misclassification is visible.
std::string thin_law(unsigned k, const std::string& near_x = "", const std::string& near_y = "") {
    const std::string big = pow10_text(k);
    std::string big1 = big;
    big1.back() = '1';
    const std::vector<std::string> rx = near_x.empty() ? std::vector<std::string>{big1, "1"}
                                                       : std::vector<std::string>{"1", near_x};
    const std::vector<std::string> ry = near_y.empty() ? std::vector<std::string>{"1", big}
                                                       : std::vector<std::string>{near_y, "1"};
    const std::vector<std::vector<std::string>> swap = {{"0", "1"}, {"1", "0"}};
    return law_json("thin-" + std::to_string(k), 3,
                    {piece_json("A", {{"1", "0"}, {"0", "1"}}, {rx, ry}),
                     piece_json("B", {{"2", "0"}, {"0", "2"}}, {{"1", "0"}, rx}),
                     piece_json("C", {{"3", "0"}, {"0", "3"}}, {ry, {"0", "1"}}),
                     piece_json("D", swap, {{"0", "1"}, {"-1", "0"}}), piece_json("E", swap, {{"-1", "0"}, {"0", "-1"}}),
                     piece_json("F", swap, {{"0", "-1"}, {"1", "0"}})});
}

// Every claim of FloatLaw's contract, checked exactly: an ok result has finite values and
// bounds, its piece contains gamma, and |value - exact| <= bound in rationals; a refusal says why,
// and "overflow in the output" only when an exact output really lies beyond the double range.
void check_any(const Model& m, const FloatLaw::Result& r, const std::vector<double>& g) {
    Vector gamma;
    for (double x : g)
        gamma.emplace_back(x);
    const auto containing = m.pieces_containing(gamma);
    if (!r.ok) {
        REQUIRE_FALSE(r.error.empty());
        if (r.error == "gamma lies in no cone") {
            CHECK(containing.empty());
        } else {
            REQUIRE(r.error == "overflow in the output");
            REQUIRE_FALSE(containing.empty());
            const Vector exact = m.pieces()[containing.front()].Q * gamma;
            CHECK(std::any_of(exact.begin(), exact.end(), [](const Rational& x) { return std::isinf(nearest_double(x)); }));
        }
        return;
    }
    REQUIRE(std::find(containing.begin(), containing.end(), r.piece) != containing.end());
    const Vector exact = m.pieces()[r.piece].Q * gamma;
    const auto values = m.values_at(gamma);
    REQUIRE(std::find(values.begin(), values.end(), exact) != values.end());
    REQUIRE(r.value.size() == exact.size());
    REQUIRE(r.bound.size() == exact.size());
    for (std::size_t i = 0; i < exact.size(); ++i) {
        INFO("component " << i << ": value " << fuzz::hex(r.value[i]) << ", bound " << fuzz::hex(r.bound[i]));
        REQUIRE(std::isfinite(r.value[i]));
        REQUIRE(std::isfinite(r.bound[i]));
        REQUIRE(abs_of(Rational(r.value[i]) - exact[i]) <= Rational(r.bound[i]));
    }
}

double pow2(int e) { return std::ldexp(1.0, e); }

} // namespace

TEST_CASE("float evaluator: nearest_double saturates beyond the double range and rounds subnormals", "[float_eval]") {
    const double max = std::numeric_limits<double>::max(), tiny = std::numeric_limits<double>::denorm_min();
    CHECK(nearest_double(test::q(pow10_text(400))) == INFINITY);
    CHECK(nearest_double(test::q("-" + pow10_text(400))) == -INFINITY);
    const Rational midpoint = Rational(max) + Rational(pow2(970)); // halfway to 2^1024: ties overflow
    CHECK(nearest_double(midpoint) == INFINITY);
    CHECK(nearest_double(-midpoint) == -INFINITY);
    CHECK(nearest_double(midpoint - test::q(inv_pow10_text(9))) == max);
    CHECK(nearest_double(test::q(inv_pow10_text(400))) == 0);
    CHECK(nearest_double(Rational(tiny) / 2) == 0);                   // tie: to even (0)
    CHECK(nearest_double(Rational(tiny) * 3 / 2) == 2 * tiny);        // tie: to even (2 tiny)
    CHECK(nearest_double(Rational(tiny) / 2 + test::q(inv_pow10_text(400))) == tiny);
    CHECK(nearest_double(Rational(tiny) * 1000 + Rational(tiny) / 3) == 1000 * tiny);
    CHECK(nearest_double(-Rational(std::numeric_limits<double>::min()) * 3 / 4) == -0.75 * std::numeric_limits<double>::min());
    CHECK(nearest_double(test::q("1/3")) == 1.0 / 3);
    CHECK(upper_double(test::q("1/3")) == std::nextafter(1.0 / 3, 1.0));
    CHECK(upper_double(test::q(inv_pow10_text(400))) == tiny);
    CHECK(upper_double(test::q(pow10_text(400))) == INFINITY);
    CHECK(upper_double(test::q("-" + pow10_text(400))) == -max);
    CHECK(upper_double(Rational(0.5)) == 0.5);
}

TEST_CASE("float evaluator: a Q entry of 10^400 neither crashes nor returns a wrong value", "[float_eval]") {
    const Model m = model_of(quadrant_law("huge-entry", {{{"1", pow10_text(400)}, {"0", "1"}}, {{"1", "0"}, {"0", "1"}}}));
    const FloatLaw law(m);
    auto r = law.eval({1, 1}); // 1 + 10^400 is beyond the double range
    CHECK_FALSE(r.ok);
    CHECK(r.error == "overflow in the output");
    r = law.eval({1, 0}); // the huge entry multiplies an exact zero
    REQUIRE(r.ok);
    CHECK(r.value == std::vector<double>{1, 0});
    check_any(m, r, {1, 0});
    const std::vector<double> g = {1, std::numeric_limits<double>::denorm_min()}; // 10^400 2^-1074 ~ 5e76
    r = law.eval(g);
    REQUIRE(r.ok);
    CHECK(r.value[0] > 4e76);
    check_any(m, r, g);
}

TEST_CASE("float evaluator: entries below the double range count in the bound", "[float_eval]") {
    const Model m = model_of(quadrant_law("tiny-entry", {{{"0", inv_pow10_text(400)}, {"0", "1"}}}));
    const FloatLaw law(m);
    const std::vector<double> g = {0.5, 1e300}; // (Q gamma)_1 = 10^-400 * 1e300 ~ 1e-100
    const auto r = law.eval(g);
    REQUIRE(r.ok);
    check_any(m, r, g);
    CHECK(r.bound[0] >= 1e-101);
}

TEST_CASE("float evaluator: rays (10^200+1, 1) and (1, 10^200) do not fool the classification", "[float_eval]") {
    const Model m = model_of(thin_law(200));
    const FloatLaw law(m);
    // Slope 1e-201 lies below the ray (10^200+1, 1): piece B (doubles). R^-1's entry -1/det
    // ~ -10^-400 is 0 in double, and a filter that ignores that sees piece A.
    const std::vector<double> g = {1e300, 1e99};
    const auto r = law.eval(g);
    REQUIRE(r.ok);
    CHECK(m.pieces()[r.piece].name == "B");
    check_any(m, r, g);
    CHECK(std::fabs(r.value[0] - 2e300) <= 1e285);
}

TEST_CASE("float evaluator: adversarial laws and points, every result checked exactly", "[float_eval]") {
    const std::string huge = pow10_text(400), tiny = inv_pow10_text(400), big = pow10_text(300),
                      small = inv_pow10_text(300), sub = inv_pow10_text(320);
    std::vector<std::string> laws = {
        quadrant_law("quadrants-huge", {{{"1", huge}, {"0", "1"}},
                                        {{big, "-1"}, {tiny, big}},
                                        {{"-" + huge, tiny}, {small, "-7/3"}},
                                        {{sub, "0"}, {"1", "-" + sub}}}),
        quadrant_law("quadrants-300", {{{big, big}, {"-" + big, big}}, {{small, "1"}, {"1", "-" + small}}}),
        thin_law(100),
        thin_law(200),
        thin_law(300),
        thin_law(0, small, small), // tiny ray coordinates: (1, 10^-300) and (10^-300, 1)
        // c = 1 (two balls): the two half-lines.
        law_json("c1-huge", 2, {piece_json("approach", {{"-" + huge}}, {{"-1"}}), piece_json("separate", {{tiny}}, {{"1"}})}),
        law_json("c1-300", 2, {piece_json("approach", {{"-" + small}}, {{"-1"}}), piece_json("separate", {{big}}, {{"1"}})}),
    };
    { // c = 3 (four balls): the eight octants, entries cycling through the edge values.
        const std::vector<std::string> entries = {"1", huge, tiny, big, "-" + small, "-7/3", "0", sub, "-" + big, "1/3"};
        std::vector<std::string> pieces;
        for (int s = 0; s < 8; ++s) {
            std::vector<std::vector<std::string>> Q(3, std::vector<std::string>(3)), rays(3, std::vector<std::string>(3, "0"));
            for (int i = 0; i < 3; ++i) {
                rays[static_cast<std::size_t>(i)][static_cast<std::size_t>(i)] = (s >> i) & 1 ? "-1" : "1";
                for (int j = 0; j < 3; ++j)
                    Q[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
                        entries[static_cast<std::size_t>(s * 3 + i * 2 + j) % entries.size()];
            }
            pieces.push_back(piece_json("O" + std::to_string(s), Q, rays));
        }
        laws.push_back(law_json("c3-octants", 4, pieces));
    }
    std::mt19937_64 rng(2024);
    const double specials[] = {0.0, -0.0, std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::min(),
                               std::numeric_limits<double>::max(), 1.0, 3.0, 0.1, 1e300, 1e-300, 0x1p-1060};
    auto random_double = [&]() -> double {
        switch (rng() % 4) {
        case 0: { // any finite bit pattern
            for (;;) {
                const std::uint64_t bits = rng();
                double d;
                std::memcpy(&d, &bits, 8);
                if (std::isfinite(d))
                    return d;
            }
        }
        case 1: { // log-uniform over the whole range, subnormals included
            const int e = static_cast<int>(rng() % 2098) - 1074;
            const double d = std::ldexp(1.0 + static_cast<double>(rng() % (1ULL << 52)) * 0x1p-52, e);
            return (rng() & 1) ? -d : d;
        }
        case 2: { // subnormals
            const double d = static_cast<double>(rng() % (1ULL << 52)) * std::numeric_limits<double>::denorm_min();
            return (rng() & 1) ? -d : d;
        }
        default: {
            const double d = specials[rng() % std::size(specials)];
            return (rng() & 1) ? -d : d;
        }
        }
    };
    std::size_t exact_classifications = 0, exact_outputs = 0;
    for (const auto& text : laws) {
        const Model m = model_of(text);
        INFO("law " << m.law().name);
        const FloatLaw law(m);
        const std::size_t c = m.contacts();
        std::size_t ok = 0, refused = 0;
        for (int i = 0; i < 3000; ++i) {
            std::vector<double> g(c);
            if (i % 2 == 0) {
                for (auto& x : g)
                    x = random_double();
            } else {
                // On or a few ulps off a boundary ray (or a sum of two rays), at any scale.
                const auto& rays = m.rays();
                Vector point = rays[rng() % rays.size()];
                if (rng() % 3 == 0) {
                    const Vector& other = rays[rng() % rays.size()];
                    const Rational w(std::ldexp(1.0, static_cast<int>(rng() % 200) - 100));
                    for (std::size_t k = 0; k < c; ++k)
                        point[k] += w * other[k];
                }
                const Rational scale(std::ldexp(1.0, static_cast<int>(rng() % 2098) - 1074));
                for (std::size_t k = 0; k < c; ++k)
                    g[k] = nearest_double(point[k] * scale);
                const std::size_t k = rng() % c;
                for (int steps = static_cast<int>(rng() % 7) - 3; steps != 0; steps += steps > 0 ? -1 : 1)
                    g[k] = std::nextafter(g[k], steps > 0 ? INFINITY : -INFINITY);
                if (!std::all_of(g.begin(), g.end(), [](double x) { return std::isfinite(x); }))
                    continue;
            }
            std::string where;
            for (double x : g)
                where += fuzz::hex(x) + " ";
            INFO("gamma " << where);
            const auto r = law.eval(g);
            check_any(m, r, g);
            (r.ok ? ok : refused) += 1;
            exact_classifications += r.exact_fallback ? 1 : 0;
            exact_outputs += r.exact_output ? 1 : 0;
        }
        CHECK(ok > 1000);
        CHECK(refused < 1500);
    }
    CHECK(exact_classifications > 1000); // the boundary samples reach the exact fallback
    CHECK(exact_outputs > 100);          // and the 10^400 entries the exact output
}

TEST_CASE("float evaluator: eval --float --law exits 2 with one line when the evaluator refuses", "[float_eval][cli]") {
    const std::string path = "/tmp/impactcert-float-eval-huge.json";
    std::ofstream(path) << quadrant_law("huge-entry", {{{"1", pow10_text(400)}, {"0", "1"}}, {{"1", "0"}, {"0", "1"}}});
    auto run = test::run_cli("eval --float --law " + path + " 1 1");
    CHECK(run.status == 2);
    CHECK(run.err == "impactcert: input: overflow in the output\n");
    run = test::run_cli("eval --float --law " + path + " 1 0x1p-1074");
    CHECK(run.status == 0);
    CHECK(run.out.find("# piece Q1") != std::string::npos);
    std::remove(path.c_str());
    run = test::run_cli("eval --float --law '" + source_path("proofs/controls/missing-cone.json") + "' -- 1 -2");
    CHECK(run.status == 2);
    CHECK(run.err == "impactcert: input: gamma lies in no cone\n");
}
