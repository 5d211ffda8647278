// SPDX-License-Identifier: GPL-3.0-or-later
// Polynomials over Q (upoly.hpp): determinants of pencils against a direct expansion, Sturm
// counts and isolation against polynomials built from known roots.
#include "exact/upoly.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace impactcert;
using impactcert::test::q;

namespace {
UPoly from_roots(const std::vector<Rational>& roots, const Rational& lead = Rational(1)) {
    UPoly p = make_poly({lead});
    for (const auto& r : roots) {
        std::vector<Rational> next(p.c.size() + 1, Rational(0));
        for (std::size_t i = 0; i < p.c.size(); ++i) {
            next[i + 1] += p.c[i];
            next[i] -= r * p.c[i];
        }
        p = make_poly(next);
    }
    return p;
}
} // namespace

TEST_CASE("polynomials: Sturm counts and isolation find every root, multiple ones once", "[upoly]") {
    const UPoly p = from_roots({q("1"), q("2"), q("3")});
    CHECK(count_roots(p, q("0"), q("10")) == 3);
    CHECK(count_roots(p, q("1"), q("2")) == 2); // closed at both ends
    CHECK(count_roots(p, q("3/2"), q("5/2")) == 1);
    CHECK(count_roots(p, q("3"), q("3")) == 1);
    CHECK(count_roots(p, q("4"), q("5")) == 0);
    CHECK(count_roots_above(p, q("2")) == 1);
    CHECK(count_roots_above(p, q("0")) == 3);
    const auto iv = isolate(p);
    REQUIRE(iv.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(iv[i].lo <= Rational(static_cast<long>(i + 1)));
        CHECK(Rational(static_cast<long>(i + 1)) <= iv[i].hi);
    }
    // Multiple and close roots, a negative leading coefficient.
    const UPoly m = from_roots({q("1/3"), q("1/3"), q("1/3") + q("1/1000000"), q("-7"), q("-7")}, q("-5"));
    const auto im = isolate(m);
    REQUIRE(im.size() == 3);
    CHECK(count_roots(m, q("-100"), q("100")) == 3);
    CHECK(rational_root(m, refine(m, im[1], q("1/1000000000000")), 64) == q("1/3"));
    CHECK(square_free(m).degree() == 3);
    // Irrational roots: x^2 - 2.
    const UPoly two = make_poly({q("-2"), q("0"), q("1")});
    const auto it = isolate(two);
    REQUIRE(it.size() == 2);
    const auto r = refine(two, it[1], q("1/1000000000000"));
    CHECK(r.lo * r.lo < q("2"));
    CHECK(q("2") < r.hi * r.hi);
    CHECK(!rational_root(two, r, 64));
    // Random polynomials with known rational roots: every root inside exactly one interval.
    std::mt19937_64 rng(5);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<Rational> roots;
        const int n = 1 + static_cast<int>(rng() % 6);
        for (int i = 0; i < n; ++i)
            roots.push_back(Rational(static_cast<long>(rng() % 41) - 20, static_cast<long>(1 + rng() % 7)));
        long lead = static_cast<long>(rng() % 9) - 4;
        if (lead == 0)
            lead = 3;
        const UPoly f = from_roots(roots, Rational(lead));
        const auto ivs = isolate(f);
        std::vector<Rational> distinct = roots;
        std::sort(distinct.begin(), distinct.end());
        distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
        REQUIRE(ivs.size() == distinct.size());
        for (std::size_t i = 0; i < ivs.size(); ++i) {
            CHECK(ivs[i].lo <= distinct[i]);
            CHECK(distinct[i] <= ivs[i].hi);
            CHECK(count_roots(f, ivs[i].lo, ivs[i].hi) == 1);
        }
    }
}

TEST_CASE("polynomials: det(P - x N) by interpolation equals the determinant at other points", "[upoly]") {
    std::mt19937_64 rng(7);
    for (int trial = 0; trial < 50; ++trial) {
        const std::size_t k = 1 + rng() % 5;
        Matrix P(k, k), N(k, k);
        for (std::size_t i = 0; i < k; ++i)
            for (std::size_t j = 0; j < k; ++j) {
                P(i, j) = Rational(static_cast<long>(rng() % 21) - 10, static_cast<long>(1 + rng() % 5));
                N(i, j) = Rational(static_cast<long>(rng() % 21) - 10);
            }
        const UPoly d = pencil_determinant(P, N);
        CHECK(d.degree() <= static_cast<int>(k));
        for (const char* x : {"-7/3", "1/2", "11", "-1000"})
            CHECK(evaluate(d, q(x)) == determinant(P - q(x) * N));
    }
}

TEST_CASE("polynomials: a root at zero beside irrational ones", "[upoly]") {
    const UPoly p = make_poly({q("0"), q("-9/5"), q("701/50"), q("-122/5")});
    const auto iv = isolate(p);
    REQUIRE(iv.size() == 3);
    CHECK(iv[0].lo == q("0"));
    CHECK(iv[0].hi == q("0"));
    CHECK(iv[2].lo <= q("381/1000"));
    CHECK(q("380/1000") <= iv[2].hi);
}
