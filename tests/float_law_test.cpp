// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/fuzz.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <impactcert/float_law.hpp>

#include <cmath>
#include <cstring>
#include <limits>

using namespace impactcert;

TEST_CASE("float law: hand-checked values on every cone and boundary", "[float]") {
    struct Case {
        double g1, g2, e1, e2;
    };
    // gamma- -> gamma+ for unit balls; by the sort rule, u = (0, g1, g1+g2) sorted.
    const Case cases[] = {
        {1, 2, 1, 2},     {-1, 3, 1, 2},   {-3, 1, 1, 2},  {-1, -2, 2, 1},
        {1, -3, 2, 1},    {3, -1, 2, 1},   {-1, 0, 0, 1},  {0, -1, 1, 0},
        {-1, 1, 1, 0},    {1, -1, 0, 1},   {0, 0, 0, 0},   {-0.0, -0.0, 0, 0},
    };
    for (const auto& c : cases) {
        double out[2];
        fp::S(c.g1, c.g2, out);
        INFO(c.g1 << ", " << c.g2);
        CHECK(out[0] == c.e1);
        CHECK(out[1] == c.e2);
    }
}

TEST_CASE("float law: the branch-free batch form equals the scalar form and never returns -0", "[float]") {
    std::vector<double> g1, g2;
    for (std::uint64_t i = 0; i < test::samples(200000); ++i) {
        const auto s = fuzz::make_paper_sample(7, i);
        g1.push_back(s.a[0]);
        g2.push_back(s.a[1]);
    }
    std::vector<double> o1(g1.size()), o2(g1.size());
    fp::S_batch(g1.data(), g2.data(), o1.data(), o2.data(), g1.size());
    for (std::size_t i = 0; i < g1.size(); ++i) {
        double out[2];
        fp::S(g1[i], g2[i], out);
        INFO(fuzz::hex(g1[i]) << " " << fuzz::hex(g2[i]));
        REQUIRE(fuzz::ulp_distance(out[0], o1[i]) == 0); // +0 and -0 count as equal
        REQUIRE(fuzz::ulp_distance(out[1], o2[i]) == 0);
        REQUIRE_FALSE(std::signbit(o1[i]));
        REQUIRE_FALSE(std::signbit(o2[i]));
    }
}

TEST_CASE("float law: correctly rounded against the naive GMP reference on 300,000 samples", "[float]") {
    // The naive path (exact rationals, rounding by exact comparison) is the reference for both
    // the float law and the fast TwoSum reference of the fuzzer.
    const Model paper(paper_law());
    for (std::uint64_t i = 0; i < test::samples(300000); ++i) {
        const auto s = fuzz::make_paper_sample(11, i);
        const double g1 = s.a[0], g2 = s.a[1];
        double out[2];
        fp::S(g1, g2, out);
        const auto naive = fuzz::reference_naive(paper, g1, g2);
        const auto fast = fuzz::reference_fast(g1, g2);
        INFO(s.kind << " " << fuzz::hex(g1) << " " << fuzz::hex(g2));
        REQUIRE(fuzz::ulp_distance(out[0], naive.value[0]) == 0);
        REQUIRE(fuzz::ulp_distance(out[1], naive.value[1]) == 0);
        REQUIRE(fuzz::ulp_distance(fast.value[0], naive.value[0]) == 0);
        REQUIRE(fuzz::ulp_distance(fast.value[1], naive.value[1]) == 0);
        if (i % 16 == 0) {
            // TwoSum's value + residual is the exact result.
            const Vector gamma = {Rational(g1), Rational(g2)};
            const Vector exact = paper.pieces()[paper.pieces_containing(gamma).front()].Q * gamma;
            REQUIRE(Rational(fast.value[0]) + Rational(fast.residual[0]) == exact[0]);
            REQUIRE(Rational(fast.value[1]) + Rational(fast.residual[1]) == exact[1]);
        }
    }
}

TEST_CASE("float law: the extremes of the double range stay finite and exact", "[float]") {
    const double big = std::numeric_limits<double>::max(), tiny = std::numeric_limits<double>::denorm_min();
    double out[2];
    fp::S(big, -big, out); // IVa/IVb boundary: (0, big)
    CHECK(out[0] == 0);
    CHECK(out[1] == big);
    fp::S(-big, big, out);
    CHECK(out[0] == big);
    CHECK(out[1] == 0);
    fp::S(-big, -big, out); // III: (big, big), no sum formed
    CHECK(out[0] == big);
    CHECK(out[1] == big);
    fp::S(tiny, -2 * tiny, out); // IVb: (-(g1+g2), g1) = (tiny, tiny)
    CHECK(out[0] == tiny);
    CHECK(out[1] == tiny);
    CHECK_FALSE(fp::S_checked(std::nan(""), 1, out));
    CHECK_FALSE(fp::S_checked(1, -std::numeric_limits<double>::infinity(), out));
}

TEST_CASE("float law: equal-mass ball velocities are sorted exactly", "[float]") {
    double u[3] = {3, -0.5, 1e-300};
    fp::sort_velocities(u);
    CHECK(u[0] == -0.5);
    CHECK(u[1] == 1e-300);
    CHECK(u[2] == 3);
    // Agrees with the law in contact velocities: gamma+ = W^T sort(u).
    for (std::uint64_t i = 0; i < 20000; ++i) {
        const auto s = fuzz::make_paper_sample(3, i);
        double v[3] = {0, s.a[0], s.a[0] + s.a[1]};
        if (!std::isfinite(v[2]))
            continue;
        const double before[3] = {v[0], v[1], v[2]};
        fp::sort_velocities(v);
        CHECK(v[0] <= v[1]);
        CHECK(v[1] <= v[2]);
        // A permutation of the input, not just some sorted triple.
        CHECK(std::is_permutation(v, v + 3, before));
    }
}
