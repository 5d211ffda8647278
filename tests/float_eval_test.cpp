#include "float_eval.hpp"
#include "fuzz.hpp"
#include "law_json.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
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
    for (std::uint64_t i = 0; i < 100000; ++i) {
        const auto s = fuzz::make_sample(5, i);
        const std::vector<double> g = {s.a.g[0], s.a.g[1]};
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
    CHECK(fallbacks > 1000); // boundary samples need the exact classification
    CHECK(fallbacks < 50000); // the filter decides the rest
}

TEST_CASE("float evaluator: the 4-ball law (c = 3), bound holds exactly, ties classified exactly", "[float_eval]") {
    const Model m(load_law_file(source_path("proofs/newton4/law.json")));
    const FloatLaw law(m);
    std::mt19937_64 rng(8);
    std::uniform_int_distribution<int> small(-3, 3);
    std::uniform_real_distribution<double> real(-10, 10);
    std::size_t fallbacks = 0;
    for (int i = 0; i < 20000; ++i) {
        std::vector<double> g(3);
        for (auto& x : g)
            x = (i % 2) ? small(rng) * 0.5 : real(rng); // half on ties (cone boundaries)
        const auto r = law.eval(g);
        check_bound(m, r, g);
        fallbacks += r.exact_fallback ? 1 : 0;
    }
    CHECK(fallbacks > 1000);
}

TEST_CASE("float evaluator: non-finite input and overflow are reported, not returned", "[float_eval]") {
    const Model m(load_law_file(source_path("proofs/controls/expansive-scaled.json")));
    const FloatLaw law(m);
    CHECK_FALSE(law.eval({std::nan(""), 1.0}).ok);
    const auto r = law.eval({1e308, 1e308}); // doubling 1e308 overflows
    CHECK_FALSE(r.ok);
    CHECK(r.error == "overflow in the output");
}
