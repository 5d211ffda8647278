// SPDX-License-Identifier: GPL-3.0-or-later
#include "exact/copositivity.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <functional>
#include <random>

using namespace impactcert;
using impactcert::test::q;
using impactcert::test::vec;

namespace {

Matrix sym(std::initializer_list<std::initializer_list<const char*>> rows) {
    std::vector<Vector> r;
    for (auto row : rows)
        r.push_back(vec(row));
    return Matrix::from_rows(r);
}

// Reassembles L diag(D) L^T.
Matrix ldlt(const LdlResult& f) {
    const std::size_t n = f.D.size();
    Matrix D(n, n);
    for (std::size_t i = 0; i < n; ++i)
        D(i, i) = f.D[i];
    return f.L * D * transpose(f.L);
}

} // namespace

TEST_CASE("PSD: LDL^T reproduces a semidefinite matrix exactly, singular ones included", "[copositivity]") {
    for (const Matrix& A : {sym({{"2", "-1"}, {"-1", "2"}}), sym({{"1", "1"}, {"1", "1"}}),
                            sym({{"0", "0", "0"}, {"0", "4", "2"}, {"0", "2", "1"}}),
                            sym({{"0", "0"}, {"0", "0"}})}) {
        const auto f = ldl_psd(A);
        REQUIRE(f.psd);
        CHECK(ldlt(f) == A);
        for (const auto& d : f.D)
            CHECK(sign_of(d) != Sign::negative);
    }
}

TEST_CASE("PSD: an indefinite matrix yields an exact negative direction", "[copositivity]") {
    for (const Matrix& A : {sym({{"1", "2"}, {"2", "1"}}), sym({{"0", "1"}, {"1", "0"}}),
                            sym({{"0", "0", "0"}, {"0", "0", "-3"}, {"0", "-3", "5"}}),
                            sym({{"1", "0"}, {"0", "-1/1000000000000"}})}) {
        const auto f = ldl_psd(A);
        REQUIRE_FALSE(f.psd);
        CHECK(sign_of(bilinear(f.witness, A, f.witness)) == Sign::negative);
    }
}

TEST_CASE("copositivity: cheap certificates come first", "[copositivity]") {
    CHECK(decide_copositivity(sym({{"1", "2"}, {"2", "0"}})).method == CopositivityMethod::nonnegative_entries);
    CHECK(decide_copositivity(sym({{"1", "-1"}, {"-1", "1"}})).method == CopositivityMethod::psd);
    // Copositive, neither non-negative nor PSD: P + N with N the positive off-diagonal part.
    const Matrix A = sym({{"1", "-1", "2"}, {"-1", "1", "3"}, {"2", "3", "0"}});
    const auto r = decide_copositivity(A);
    REQUIRE(r.copositive);
    REQUIRE(r.method == CopositivityMethod::psd_plus_nonnegative);
    CHECK(ldlt(r.ldl) + r.N == A);
}

TEST_CASE("copositivity: the Horn matrix is copositive and only the KKT enumeration proves it", "[copositivity]") {
    // Horn's matrix: copositive, but not PSD + non-negative (the classic 5x5 example).
    const Matrix horn = sym({{"1", "-1", "1", "1", "-1"},
                             {"-1", "1", "-1", "1", "1"},
                             {"1", "-1", "1", "-1", "1"},
                             {"1", "1", "-1", "1", "-1"},
                             {"-1", "1", "1", "-1", "1"}});
    const auto r = decide_copositivity(horn);
    CHECK(r.copositive);
    CHECK(r.method == CopositivityMethod::kkt_enumeration);
    CHECK(r.faces == 31);
    CHECK(to_string(r.minimum) == "0");
}

TEST_CASE("copositivity: a negative minimum is found exactly, with its minimiser", "[copositivity]") {
    // z^T A z on the simplex for A = [[1,-2],[-2,1]]: minimum -1/2 at (1/2, 1/2).
    const Matrix A = sym({{"1", "-2"}, {"-2", "1"}});
    const auto r = decide_copositivity(A);
    REQUIRE_FALSE(r.copositive);
    CHECK(to_string(r.minimum) == "-1/2");
    CHECK(r.witness == vec({"1/2", "1/2"}));
    const Vector inside = interior_witness(A, r.witness);
    for (const auto& x : inside)
        CHECK(sign_of(x) == Sign::positive);
    CHECK(sign_of(bilinear(inside, A, inside)) == Sign::negative);
}

TEST_CASE("copositivity: the decision agrees with exact sampling of the simplex on random matrices", "[copositivity]") {
    // Soundness in both directions on 300 random symmetric 3x3 and 4x4 integer matrices:
    // a sampled point with a negative value means "not copositive", and the reported minimum is
    // attained by the witness and is <= every sampled value.
    std::mt19937 rng(20261122);
    std::uniform_int_distribution<int> entry(-4, 6);
    for (int trial = 0; trial < 300; ++trial) {
        const std::size_t n = 3 + static_cast<std::size_t>(trial % 2);
        Matrix A(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i; j < n; ++j)
                A(i, j) = A(j, i) = entry(rng);
        const auto r = decide_copositivity(A);
        // Grid points of the simplex with denominator 6.
        const int d = 6;
        bool sampled_negative = false;
        std::vector<int> k(n, 0);
        std::function<void(std::size_t, int)> walk = [&](std::size_t i, int left) {
            if (i + 1 == n) {
                k[i] = left;
                Vector z(n);
                for (std::size_t a = 0; a < n; ++a)
                    z[a] = Rational(k[a], d);
                const Rational v = bilinear(z, A, z);
                if (sign_of(v) == Sign::negative)
                    sampled_negative = true;
                if (r.method == CopositivityMethod::kkt_enumeration)
                    REQUIRE(r.minimum <= v);
                return;
            }
            for (int x = 0; x <= left; ++x) {
                k[i] = x;
                walk(i + 1, left - x);
            }
        };
        walk(0, d);
        INFO("trial " << trial);
        if (sampled_negative)
            REQUIRE_FALSE(r.copositive);
        if (r.method == CopositivityMethod::kkt_enumeration) {
            // The reported minimum is attained by the witness, a point of the simplex.
            Rational sum;
            for (const auto& x : r.witness) {
                REQUIRE(sign_of(x) != Sign::negative);
                sum += x;
            }
            REQUIRE(sum == Rational(1));
            REQUIRE(bilinear(r.witness, A, r.witness) == r.minimum);
        }
        if (!r.copositive) {
            REQUIRE(sign_of(bilinear(r.witness, A, r.witness)) == Sign::negative);
            for (const auto& x : r.witness)
                REQUIRE(sign_of(x) != Sign::negative);
        }
    }
}

TEST_CASE("copositivity: the integer KKT faces give exactly GMP's candidates, overflow included", "[copositivity]") {
    // Lemma K3: a face solved in int64 (fraction-free, every division checked) has the same
    // unique solution as over GMP. Compared field by field on random forms that reach the KKT
    // enumeration: small integers, fractions, and entries near 2^43 whose larger faces leave
    // int64 (those faces are then eliminated over GMP integers within the same enumeration).
    std::mt19937 rng(20261125);
    std::uniform_int_distribution<int> small(-9, 9), kind(0, 9);
    std::size_t kkt = 0, overflowing = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const std::size_t n = 2 + static_cast<std::size_t>(trial % 6);
        Matrix A(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = i; j < n; ++j) {
                Rational v = small(rng);
                const int k = kind(rng);
                if (trial % 4 == 1 && k < 3)
                    v /= Rational(small(rng) == 0 ? 7 : 3 + std::abs(small(rng)));
                if (trial % 4 == 2 && k == 0) { // fits int64, but its faces' minors do not
                    v *= Rational(std::int64_t{1} << 40);
                    ++overflowing;
                }
                if (trial % 8 == 6 && k == 1) // beyond int64: the whole enumeration over GMP
                    v *= Rational(std::int64_t{1} << 40) * Rational(std::int64_t{1} << 30);
                A(i, j) = A(j, i) = v;
            }
        const auto fast = decide_copositivity(A, Limits{}.max_faces, true);
        const auto gmp = decide_copositivity(A, Limits{}.max_faces, false);
        INFO("trial " << trial);
        REQUIRE(fast.method == gmp.method);
        REQUIRE(fast.copositive == gmp.copositive);
        if (gmp.method != CopositivityMethod::kkt_enumeration)
            continue;
        ++kkt;
        CHECK(fast.faces == gmp.faces);
        CHECK(fast.minimum == gmp.minimum);
        CHECK(fast.witness == gmp.witness);
        REQUIRE(fast.candidates.size() == gmp.candidates.size());
        for (std::size_t c = 0; c < gmp.candidates.size(); ++c) {
            CHECK(fast.candidates[c].support == gmp.candidates[c].support);
            CHECK(fast.candidates[c].x == gmp.candidates[c].x);
            CHECK(fast.candidates[c].value == gmp.candidates[c].value);
        }
    }
    CHECK(kkt > 150);
    CHECK(overflowing > 20);
}
