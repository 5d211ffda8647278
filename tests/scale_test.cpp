// SPDX-License-Identifier: GPL-3.0-or-later
// scale_test.cpp -- issue 9: integer kernels (always the verdicts of GMP), declared symmetries
// (verified, refuted with witnesses, used only when proved), compact laws, derive cradle, and
// --jobs (the same output for any number of threads). Every certificate is re-checked.
#include "prover/certificate.hpp"
#include "checker.hpp"
#include "model/cradle.hpp"
#include "derive/derive.hpp"
#include "impactcert_check.hpp"
#include "exact/int_kernel.hpp"
#include "model/law_json.hpp"
#include "exact/pair_kernel.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <random>

using namespace impactcert;
using impactcert::test::check_certificate;
using impactcert::test::source_path;

namespace {

Model load(const std::string& relative) { return Model(load_law_file(source_path(relative))); }

using test::require_sound;

// The law as a function: primitive ray set (sorted) -> Q.
std::map<std::vector<Vector>, Matrix> cones_of(const Model& m) {
    std::map<std::vector<Vector>, Matrix> out;
    for (const auto& p : m.pieces()) {
        std::vector<Vector> rays;
        for (std::size_t k = 0; k < m.contacts(); ++k)
            rays.push_back(p.R.column(k));
        std::sort(rays.begin(), rays.end());
        out.emplace(rays, p.Q);
    }
    return out;
}

// Everything a verdict says, kernel or not, threads or not (the elapsed time aside).
void require_same(const VerifyReport& a, const VerifyReport& b) {
    REQUIRE(a.obligations.size() == b.obligations.size());
    for (std::size_t k = 0; k < a.obligations.size(); ++k) {
        const auto &x = a.obligations[k], &y = b.obligations[k];
        INFO(x.id);
        CHECK(x.verdict == y.verdict);
        CHECK(x.checks == y.checks);
        CHECK(x.method == y.method);
        CHECK(x.counterexample == y.counterexample);
        CHECK(x.limit == y.limit);
        CHECK(x.data == y.data);
    }
}

Limits with(bool kernels, bool evidence, unsigned jobs = 1) {
    Limits l;
    l.integer_kernels = kernels;
    l.evidence = evidence;
    l.jobs = jobs;
    return l;
}

// Laws whose pair forms take every route: A >= 0 (sort), PSD and PSD + N and KKT (derived
// inelastic chains, the controls), refutations (the controls).
std::vector<Model> kernel_laws() {
    std::vector<Model> laws;
    laws.emplace_back(paper_law());
    laws.push_back(load("proofs/newton4/law.json"));
    for (const char* c : {"discontinuous-isometric", "expansive-scaled", "missing-cone", "newton-simultaneous",
                          "perturbed-entry", "swapped-pieces"})
        laws.push_back(load(std::string("proofs/controls/") + c + ".json"));
    DeriveOptions o;
    o.masses = {Rational(1), Rational(2), Rational(3)};
    o.restitution = {Rational(1, 2), Rational(1)};
    laws.emplace_back(*derive_sequential(o).law);
    o.masses = {Rational(3), Rational(1), Rational(2), Rational(5)};
    o.restitution = {Rational(1), Rational(1), Rational(1)};
    laws.emplace_back(*derive_sequential(o).law);
    // Continuous inelastic laws (on the continuity curves of the (1, m, 1) family): P1 holds, so
    // the pair forms decide, and they take every route (a discontinuous law is refuted near
    // P1's ray before any pair form).
    o.masses = {Rational(1), Rational(1, 2), Rational(1)};
    o.restitution = {Rational(1, 2), Rational(1, 2)};
    laws.emplace_back(*derive_sequential(o).law);
    o.masses = {Rational(1), Rational(1, 3), Rational(1)};
    o.restitution = {Rational(1, 3), Rational(1, 3)};
    laws.emplace_back(*derive_sequential(o).law);
    return laws;
}

} // namespace

TEST_CASE("integer kernels: verdicts, counts, methods and witnesses are GMP's, the kernel forced off everywhere",
          "[scale][kernel]") {
    std::size_t methods_seen[4] = {0, 0, 0, 0};
    for (const Model& m : kernel_laws()) {
        INFO(m.law().name);
        const VerifyReport gmp = verify(m, with(false, false));
        require_same(verify(m, with(true, false)), gmp);
        // With evidence the kernel is also run and must agree pair by pair (ensure in the prover).
        require_same(verify(m, with(true, true)), verify(m, with(false, true)));
        // "copositive pair forms: 23 A>=0, 3 PSD, 3 PSD+N, 5 KKT": the counts of each route.
        const std::string method = gmp.at("nonexpansive").method;
        static const char* names[] = {" A>=0", " PSD,", " PSD+N", " KKT"};
        for (int k = 0; k < 4; ++k) {
            const auto at = method.find(names[k]);
            if (at == std::string::npos)
                continue;
            auto digits = at;
            while (digits > 0 && std::isdigit(static_cast<unsigned char>(method[digits - 1])))
                --digits;
            if (digits < at)
                methods_seen[k] += std::stoul(method.substr(digits, at - digits));
        }
    }
    // The set takes every route (else the comparison is weak).
    CHECK(methods_seen[0] > 0);
    CHECK(methods_seen[1] > 0);
    CHECK(methods_seen[2] > 0);
    CHECK(methods_seen[3] > 0);
    // And the kernel does decide (a kernel that always declined would pass the comparisons).
    const Model cradle(cradle_law(4, CradleListing::all, false));
    const PairKernel kernel(cradle, true);
    CHECK(kernel.pieces_in_kernel() == 24);
    PairKernel::Scratch scratch;
    for (std::size_t j = 0; j < 24; ++j)
        CHECK(kernel.decide(0, j, scratch) == CopositivityMethod::nonnegative_entries);
    CHECK_FALSE(PairKernel(cradle, false).decide(0, 1, scratch).has_value());
    DeriveOptions o;
    o.masses = {Rational(1), Rational(2), Rational(3)};
    o.restitution = {Rational(1, 2), Rational(1)};
    const Model derived(*derive_sequential(o).law);
    const PairKernel inelastic(derived, true);
    std::size_t psd = 0;
    for (std::size_t i = 0; i < derived.pieces().size(); ++i)
        for (std::size_t j = 0; j < derived.pieces().size(); ++j) {
            const auto method = inelastic.decide(i, j, scratch);
            psd += method && *method != CopositivityMethod::nonnegative_entries ? 1 : 0;
        }
    CHECK(psd > 0); // the kernel's PSD and PSD + N routes are taken
}

TEST_CASE("integer kernels: fraction-free PSD and determinant signs equal GMP's on random integer matrices",
          "[scale][kernel]") {
    std::mt19937_64 rng(20261123);
    std::uniform_int_distribution<int> small(-4, 4), size(1, 6);
    for (int trial = 0; trial < 3000; ++trial) {
        const std::size_t n = static_cast<std::size_t>(size(rng));
        // Symmetric: B^T B (PSD) or a random symmetric matrix, or a rank-deficient one.
        Matrix A(n, n), B(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                B(i, j) = small(rng);
        if (trial % 3 == 0)
            A = transpose(B) * B;
        else if (trial % 3 == 1)
            A = B + transpose(B);
        else {
            Matrix C = B;
            for (std::size_t i = 0; i < n; ++i)
                C(i, n - 1) = C(i, 0); // two equal columns
            A = transpose(C) * C;
        }
        std::vector<intk::i64> a(n * n), b(n * n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) {
                a[i * n + j] = intk::to_int_vector(Vector{A(i, j)}).value()[0];
                b[i * n + j] = intk::to_int_vector(Vector{B(i, j)}).value()[0];
            }
        const auto psd = int_psd(a, n);
        REQUIRE(psd.has_value());
        CHECK(*psd == ldl_psd(A).psd);
        const auto sign = intk::det_sign(b, n);
        REQUIRE(sign.has_value());
        CHECK(*sign == static_cast<int>(sign_of(determinant(B))));
    }
    // Overflow is reported, never wrapped: entries near 2^62 overflow the 2 x 2 minor.
    std::vector<intk::i64> big = {intk::i64{1} << 62, intk::i64{1} << 61, intk::i64{1} << 61, intk::i64{1} << 62};
    CHECK_FALSE(intk::det_sign(big, 2).has_value());
    big = {intk::i64{1} << 62, intk::i64{1} << 61, intk::i64{1} << 61, intk::i64{1} << 62};
    CHECK_FALSE(int_psd(big, 2).has_value());
}

TEST_CASE("integer kernels: the Gram tables find every entrywise non-negative pair form, and only those",
          "[scale][kernel]") {
    // A = B1^T H B1 - B2^T H B2 over GMP for every ordered pair, against the kernel's answer.
    auto check_law = [](const Model& m, bool expect_negative) {
        const PairKernel kernel(m, true);
        REQUIRE(kernel.gram_tables());
        PairKernel::Scratch scratch;
        const std::size_t c = m.contacts(), n = m.pieces().size();
        std::size_t negative = 0;
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j) {
                const Piece &a = m.pieces()[i], &b = m.pieces()[j];
                Matrix B1(c, 2 * c), B2(c, 2 * c);
                const Matrix QRa = a.Q * a.R, QRb = b.Q * b.R;
                for (std::size_t r = 0; r < c; ++r)
                    for (std::size_t k = 0; k < c; ++k) {
                        B1(r, k) = a.R(r, k);
                        B1(r, c + k) = -b.R(r, k);
                        B2(r, k) = QRa(r, k);
                        B2(r, c + k) = -QRb(r, k);
                    }
                const Matrix A = transpose(B1) * m.H() * B1 - transpose(B2) * m.H() * B2;
                bool entrywise = true;
                for (std::size_t x = 0; x < 2 * c; ++x)
                    for (std::size_t y = 0; y < 2 * c; ++y)
                        entrywise = entrywise && sign_of(A(x, y)) != Sign::negative;
                negative += entrywise ? 0 : 1;
                INFO(i << ", " << j);
                // The tables alone: every diagonal block of these laws is >= 0 (E = 0 for the
                // sort laws), so they answer every pair, and exactly.
                const auto tables = kernel.gram_nonnegative(i, j);
                REQUIRE(tables.has_value());
                CHECK(*tables == entrywise);
                const auto method = kernel.decide(i, j, scratch);
                CHECK((method == CopositivityMethod::nonnegative_entries) == entrywise);
            }
        CHECK((negative > 0) == expect_negative);
    };
    check_law(Model(cradle_law(4, CradleListing::all, false)), false);
    // Negative control: two columns of one piece's Q exchanged (images stay unit vectors, the
    // tables stay in use), so that some pair forms have negative entries.
    Law broken = cradle_law(4, CradleListing::all, false);
    Matrix& Q = broken.pieces[5].Q;
    for (std::size_t r = 0; r < 3; ++r)
        std::swap(Q(r, 0), Q(r, 2));
    check_law(Model(broken), true);
    // The paper's law: unit-vector images too, and every one of its 36 forms entrywise >= 0.
    check_law(Model(paper_law()), false);
    // Images that are not integral (a derived law with e = 1/2): no tables, the full kernel.
    DeriveOptions o;
    o.masses = {Rational(1), Rational(2), Rational(3)};
    o.restitution = {Rational(1, 2), Rational(1)};
    CHECK_FALSE(PairKernel(Model(*derive_sequential(o).law), true).gram_tables());
}

TEST_CASE("integer kernels: the fraction-free inverse equals GMP's, singular and overflowing matrices refused",
          "[scale][kernel]") {
    // intk::inverse (fraction-free Gauss-Jordan, every division checked) against the rational
    // Gauss-Jordan inverse, on random integer matrices: invertible, singular (two equal rows),
    // and with entries near 2^40 whose minors leave int64 (then nothing, never a wrong value).
    std::mt19937_64 rng(20261125);
    std::uniform_int_distribution<int> small(-5, 5), size(1, 9);
    std::size_t inverted = 0, singular = 0, overflow = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const std::size_t n = static_cast<std::size_t>(size(rng));
        Matrix A(n, n);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                A(i, j) = small(rng);
        if (trial % 5 == 1 && n > 1)
            for (std::size_t j = 0; j < n; ++j)
                A(n - 1, j) = A(0, j);
        if (trial % 5 == 2)
            for (std::size_t j = 0; j < n; ++j) { // row and column 0 near 2^40: 2 x 2 minors near 2^80
                A(0, j) = A(0, j) * Rational(std::int64_t{1} << 40) + 1;
                if (j > 0)
                    A(j, 0) = A(j, 0) * Rational(std::int64_t{1} << 40) + 3;
            }
        const auto gmp = inverse(A);
        const auto fast = intk::inverse(intk::to_int(A).value());
        if (fast) {
            REQUIRE(gmp);
            CHECK(fast->den > 0);
            CHECK(intk::to_matrix(*fast) == *gmp);
            ++inverted;
        } else if (!gmp) {
            ++singular;
        } else {
            ++overflow;
        }
    }
    CHECK(inverted > 1000);
    CHECK(singular > 200);
    CHECK(overflow > 20);
}

TEST_CASE("integer kernels: a law whose entries do not fit int64 falls back to GMP with the same verdicts",
          "[scale][kernel]") {
    Law law = paper_law();
    // Large rationals in the masses: H's common denominator exceeds int64.
    std::string m1 = "1" + std::string(25, '0') + "1"; // 10^26 + 1
    law.masses = {*parse_rational(m1), Rational(1), *parse_rational("1/" + m1)};
    law.claims.reset();
    law.identities.clear();
    law.single_impacts.clear();
    law.outcomes.clear();
    const Model m(law);
    const PairKernel kernel(m, true);
    CHECK(kernel.pieces_in_kernel() == 0);
    require_same(verify(m, with(true, false)), verify(m, with(false, false)));
}

TEST_CASE("symmetries: the cradle's relabelings and reversal are proved and reduce every pairwise check",
          "[scale][symmetries]") {
#ifdef IMPACTCERT_SANITIZER_BUILD
    // Under the sanitizers n = 3, 4: the checks of n = 5 (14,400 pair forms of the plain law) are
    // the same code on a larger law, and took 30 s there.
    for (std::size_t n : {3, 4}) {
#else
    for (std::size_t n : {3, 4, 5}) {
#endif
        INFO("n = " << n);
        const Model compact(cradle_law(n, CradleListing::representatives, true));
        const Model listed(cradle_law(n, CradleListing::all, true));
        const Model plain(cradle_law(n, CradleListing::all, false));
        // One law, three ways: the same cones and matrices.
        REQUIRE(cones_of(compact) == cones_of(plain));
        REQUIRE(cones_of(listed) == cones_of(plain));
        std::size_t factorial = 1;
        for (std::size_t k = 2; k <= n; ++k)
            factorial *= k;
        REQUIRE(compact.pieces().size() == factorial);
        const VerifyReport r = verify(compact);
        CHECK(r.passed());
        CHECK(r.at("symmetries").verdict == Verdict::proved);
        CHECK(r.at("nonexpansive").checks == factorial); // 1 orbit x n! pieces, not (n!)^2
        CHECK(r.at("nonexpansive").method.find("by the symmetries") != std::string::npos);
        CHECK(r.at("P3").checks == n - 1);              // P' = I or the reversal: orthant kept
        CHECK(r.at("kinetic").checks == factorial * (n - 1)); // not reducible: every piece
        const VerifyReport full = verify(plain);
        CHECK(full.passed());
        CHECK(full.at("nonexpansive").checks == factorial * factorial);
        require_sound(compact, r);
        require_sound(listed, verify(listed));
    }
}

TEST_CASE("derive cradle agrees with proofs/newton3, proofs/newton4 and derive sequential on equal masses",
          "[scale][cradle]") {
    // newton4: the very same pieces, names and rays.
    const Law listed4 = cradle_law(4, CradleListing::all, false);
    const Law newton4 = load_law_file(source_path("proofs/newton4/law.json"));
    REQUIRE(listed4.pieces.size() == newton4.pieces.size());
    for (std::size_t p = 0; p < newton4.pieces.size(); ++p) {
        CHECK(listed4.pieces[p].name == newton4.pieces[p].name);
        CHECK(listed4.pieces[p].Q == newton4.pieces[p].Q);
        CHECK(*listed4.pieces[p].rays == *newton4.pieces[p].rays);
    }
    // newton3 (the paper's table): the same cones and matrices.
    CHECK(cones_of(Model(cradle_law(3, CradleListing::representatives, true))) ==
          cones_of(Model(load_law_file(source_path("proofs/newton3/law.json")))));
    // derive sequential, equal masses, e = 1: every derived cone lies in a cradle cone with the
    // same matrix (derive may split a cone by the order of impacts; S is the same).
    for (std::size_t n : {3, 4, 5}) {
        INFO("n = " << n);
        DeriveOptions o;
        o.masses.assign(n, Rational(1));
        o.restitution.assign(n - 1, Rational(1));
        const Model derived(*derive_sequential(o).law);
        const Model cradle(cradle_law(n, CradleListing::representatives, true));
        for (const auto& piece : derived.pieces()) {
            const Vector centre = piece.R * Vector(n - 1, Rational(1));
            bool found = false;
            for (std::size_t q = 0; q < cradle.pieces().size() && !found; ++q)
                if (cradle.in_interior(q, centre)) {
                    found = true;
                    CHECK(cradle.pieces()[q].Q == piece.Q);
                    // Every ray of the derived cone lies in the cradle's cone q (the same cone).
                    for (std::size_t k = 0; k < n - 1; ++k) {
                        const auto holders = cradle.pieces_containing(piece.R.column(k));
                        CHECK(std::find(holders.begin(), holders.end(), q) != holders.end());
                    }
                }
            CHECK(found);
        }
    }
}

TEST_CASE("symmetries: negative controls are refuted with witnesses, and then nothing is reduced",
          "[scale][symmetries]") {
    SECTION("P' of the reversal wrong: Q_sigma(i) P != P' Q_i on a ray") {
        Law law = cradle_law(4, CradleListing::all, true);
        law.symmetries.back().P_prime = Matrix::identity(3);
        const Model m(law);
        const VerifyReport r = verify(m);
        REQUIRE(r.at("symmetries").verdict == Verdict::refuted);
        CHECK(r.at("symmetries").counterexample.contains("image_piece"));
        CHECK(r.at("nonexpansive").checks == 24 * 24); // no reduction
        CHECK(r.at("nonexpansive").verdict == Verdict::proved);
        require_sound(m, r);
    }
    SECTION("P not an H-isometry") {
        Law law = cradle_law(3, CradleListing::all, true);
        law.symmetries.front().P = Rational(2) * Matrix::identity(2);
        const Model m(law);
        const VerifyReport r = verify(m);
        REQUIRE(r.at("symmetries").verdict == Verdict::refuted);
        CHECK(r.at("symmetries").counterexample["matrix"] == "P");
        require_sound(m, r);
    }
    SECTION("an H-isometry that maps a cone onto no cone (reflection along (2, 1))") {
        Law law = paper_law();
        law.claims.reset();
        Matrix P(2, 2);
        P(0, 0) = Rational(-3, 7);
        P(0, 1) = Rational(-8, 7);
        P(1, 0) = Rational(-5, 7);
        P(1, 1) = Rational(3, 7);
        law.symmetries.push_back(SymmetryDecl{"reflection", P, P});
        const Model m(law);
        REQUIRE(transpose(P) * m.H() * P == m.H()); // an isometry indeed
        const VerifyReport r = verify(m);
        REQUIRE(r.at("symmetries").verdict == Verdict::refuted);
        CHECK(r.at("symmetries").counterexample.contains("image_rays"));
        CHECK(r.at("P2").checks == 6);
        require_sound(m, r);
    }
    SECTION("a compact law with a wrong generator: expanded all the same, checked without reduction") {
        // The reversal with P' = I: an isometry, so the law expands (r fixes the sorted cone and
        // generates nothing new), but Q_sorted J != I Q_sorted: refuted, and nothing is reduced.
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.symmetries.back().P_prime = Matrix::identity(3);
        const Model m(law);
        REQUIRE(m.pieces().size() == 24);
        const VerifyReport r = verify(m);
        REQUIRE(r.at("symmetries").verdict == Verdict::refuted);
        CHECK(r.at("symmetries").counterexample.contains("image_piece"));
        CHECK(r.at("nonexpansive").verdict == Verdict::proved);
        CHECK(r.at("nonexpansive").checks == 24 * 24);
        CHECK(r.at("nonexpansive").method.find("by the symmetries") == std::string::npos);
        require_sound(m, r);
        // A compact law whose generator is not an isometry is refused before generating.
        law.symmetries.front().P_prime = Rational(2) * Matrix::identity(3);
        CHECK_THROWS_WITH(Model(law), Catch::Contains("$.symmetries[0].P_prime: not an H-isometry"));
    }
    SECTION("valid symmetries of an expansive law: the reduced check still refutes it") {
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.pieces.front().Q = Rational(2) * Matrix::identity(3);
        law.single_impacts.clear();
        law.outcomes.clear();
        const Model m(law);
        const VerifyReport r = verify(m);
        REQUIRE(r.at("symmetries").verdict == Verdict::proved);
        CHECK(r.at("nonexpansive").verdict == Verdict::refuted);
        CHECK(r.at("energetic").verdict == Verdict::refuted);
        CHECK(r.at("P2").verdict == Verdict::refuted);
        require_sound(m, r);
    }
}

TEST_CASE("symmetries: law files are validated with paths, and compact laws are small", "[scale][symmetries]") {
    auto error_of = [](const std::string& text) {
        try {
            parse_law_text(text, "law.json");
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string head = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1","1","1"],
        "pieces": [{"name": "I", "Q": [["1","0"],["0","1"]]}], )";
    CHECK(error_of(head + R"("symmetries": [{"name": "s", "P": [["1","0"],["0","0"]], "P_prime": [["1","0"],["0","1"]]}]})") ==
          "law.json: $.symmetries[0].P: singular matrix (a symmetry maps the cones one to one)");
    CHECK(error_of(head + R"("symmetries": [{"name": "s", "P": [["1","0"]], "P_prime": [["1","0"],["0","1"]]}]})") ==
          "law.json: $.symmetries[0].P: expected a 2x2 matrix, got 1x2");
    CHECK(error_of(head + R"("symmetries": [{"name": "s", "P": [["1","0"],["0","1"]], "P_prime": [["1","0"],["0","1"]], "Q": 1}]})")
              .find("$.symmetries[0]") != std::string::npos);
    CHECK(error_of(head + R"("pieces_listed": "orbit-representatives"})") ==
          "law.json: $.pieces_listed: orbit representatives need \"symmetries\"");
    CHECK(error_of(head + R"("pieces_listed": "some"})").find("$.pieces_listed: expected") != std::string::npos);
    // A reflection (order 2) generates one piece.
    const std::string flip = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1","1"],
        "pieces": [{"name": "I", "Q": [["1"]]}], "symmetries": [{"name": "s", "P": [["-1"]], "P_prime": [["-1"]]}],
        "pieces_listed": "orbit-representatives"})";
    CHECK(Model(parse_law_text(flip, "law.json")).pieces().size() == 2);
    // A rotation of infinite order (3/5, 4/5; W = I and unit masses make H = I) would generate
    // pieces without end: stopped quickly by the depth of the search, one line, its path.
    const std::string rotation = R"({"format": "impactcert-law/1", "name": "x", "masses": ["1","1"],
        "contacts": {"W": [["1","0"],["0","1"]]},
        "pieces": [{"name": "I", "Q": [["1","0"],["0","1"]], "rays": [["1","0"],["0","1"]]}],
        "symmetries": [{"name": "s", "P": [["3/5","-4/5"],["4/5","3/5"]], "P_prime": [["3/5","-4/5"],["4/5","3/5"]]}],
        "pieces_listed": "orbit-representatives"})";
    // Refused before anything is generated (Lemma S0: det(xI - P) = x^2 - 6/5 x + 1).
    CHECK(error_of(rotation) == "law.json: $.symmetries[0].P: of infinite order: the coefficient of x^1 in det(xI - P) is "
                                "-6/5, not an integer, so the powers of P never return to I and generate pieces without "
                                "end (proofs/README.md, Lemma S0)");
    // Two reflections (order 2 each) whose product is that rotation: no generator is refused by
    // Lemma S0, and the expansion is stopped as soon as the numbers grow (long before the
    // 4,096-character name bound).
    std::string reflections = rotation;
    reflections.replace(reflections.find(R"("symmetries": [)"), std::string::npos,
                        R"("symmetries": [{"name": "s", "P": [["1","0"],["0","-1"]], "P_prime": [["1","0"],["0","-1"]]},
                           {"name": "t", "P": [["3/5","4/5"],["4/5","-3/5"]], "P_prime": [["3/5","4/5"],["4/5","-3/5"]]}],
                           "pieces_listed": "orbit-representatives"})");
    const std::string reflections_error = error_of(reflections);
    CHECK(reflections_error.rfind("law.json: $.symmetries: generated piece \"I.", 0) == 0);
    CHECK(reflections_error.find("the numbers grow (a symmetry of infinite order?)") != std::string::npos);
    // A shear is no isometry: generating from it is refused before anything is generated.
    std::string shear = rotation;
    shear.replace(shear.find(R"("P": [["3/5","-4/5"],["4/5","3/5"]])"), 35, R"("P": [["1","1"],["0","1"]])");
    CHECK(error_of(shear) == "law.json: $.symmetries[0].P: not an H-isometry (P^T H P != H): a compact law's symmetries must be");
    Law grow = cradle_law(5, CradleListing::representatives, true);
    CHECK_THROWS_WITH(Model(grow, 100), Catch::Contains("--max-pieces"));
    // The n = 8 law is a small file.
    CHECK(law_to_json(cradle_law(8, CradleListing::representatives, true)).dump().size() < 20000);
}

TEST_CASE("symmetries: Lemma S0, det(xI - P) by Newton's identities, and finite order read off it",
          "[scale][symmetries]") {
    // The polynomial against determinants of xI - A at c + 1 points (a second route).
    std::mt19937_64 rng(19);
    auto small = [&] { return Rational(static_cast<int>(rng() % 13) - 6, static_cast<int>(rng() % 5) + 1); };
    for (std::size_t c = 1; c <= 6; ++c)
        for (int trial = 0; trial < 30; ++trial) {
            Matrix A(c, c);
            for (std::size_t i = 0; i < c; ++i)
                for (std::size_t j = 0; j < c; ++j)
                    A(i, j) = small();
            const std::vector<Rational> a = characteristic_polynomial(A);
            REQUIRE(a.size() == c + 1);
            for (long x = -1; x <= static_cast<long>(c); ++x) {
                Matrix xI_A(c, c);
                for (std::size_t i = 0; i < c; ++i)
                    for (std::size_t j = 0; j < c; ++j)
                        xI_A(i, j) = (i == j ? Rational(x) : Rational(0)) - A(i, j);
                Rational value = 0;
                for (std::size_t k = 0; k <= c; ++k)
                    value = value * Rational(x) + a[k];
                CHECK(value == determinant(xI_A));
            }
        }
    // Finite order, by a second route: in GL(c, Q) for c <= 4 an element of finite order has
    // order at most 12 (1, 2, 3, 4, 5, 6, 8, 10 or 12), so P^k = I for some k <= 12 decides it.
    // The rule: every coefficient of det(xI - P) an integer.
    auto integral = [](const Matrix& P) {
        for (const auto& x : characteristic_polynomial(P))
            if (x.denominator() != 1)
                return false;
        return true;
    };
    auto finite_by_powers = [](const Matrix& P) {
        Matrix power = P;
        for (int k = 1; k <= 12; ++k, power = power * P)
            if (power == Matrix::identity(P.rows()))
                return true;
        return false;
    };
    std::size_t finite = 0, infinite = 0;
    auto require_rule = [&](const Matrix& P) {
        REQUIRE(transpose(P) * P == Matrix::identity(P.rows())); // an isometry of H = I
        const bool by_powers = finite_by_powers(P);
        CHECK(integral(P) == by_powers);
        ++(by_powers ? finite : infinite);
    };
    // Rotations and reflections of the Pythagorean triples (m^2 - n^2, 2mn, m^2 + n^2), in the
    // plane and with a third axis fixed or reversed.
    for (int m = 2; m <= 9; ++m)
        for (int n = 1; n < m; ++n) {
            const Rational x(m * m - n * n, m * m + n * n), y(2 * m * n, m * m + n * n);
            for (const Matrix& P2 : {Matrix::from_rows({{x, -y}, {y, x}}), Matrix::from_rows({{x, y}, {y, -x}})}) {
                require_rule(P2);
                for (int sign : {1, -1}) {
                    Matrix P3(3, 3);
                    for (std::size_t i = 0; i < 2; ++i)
                        for (std::size_t j = 0; j < 2; ++j)
                            P3(i, j) = P2(i, j);
                    P3(2, 2) = Rational(sign);
                    require_rule(P3);
                }
            }
        }
    // Every signed permutation of 2 and 3 axes (finite order), and the rotations by a quarter turn.
    for (std::size_t c : {2u, 3u}) {
        std::vector<std::size_t> perm(c);
        for (std::size_t i = 0; i < c; ++i)
            perm[i] = i;
        do {
            for (unsigned signs = 0; signs < (1u << c); ++signs) {
                Matrix P(c, c);
                for (std::size_t i = 0; i < c; ++i)
                    P(perm[i], i) = Rational((signs >> i) & 1 ? -1 : 1);
                require_rule(P);
            }
        } while (std::next_permutation(perm.begin(), perm.end()));
    }
    CHECK(finite >= 2 * 8 + 6 * 8);
    CHECK(infinite >= 40);
    // In R^4: two planar rotations whose traces cancel (3/5 + 3/5 - 3/5 - 3/5 = 0): an integer
    // trace, but det(xI - P) = x^4 + 14/25 x^2 + 1. With the rotation by pi - theta replaced by
    // a quarter turn, a rotation of infinite order beside one of order 4; with both quarter
    // turns, order 4.
    auto block = [](const Matrix& a, const Matrix& b) {
        Matrix P(4, 4);
        for (std::size_t i = 0; i < 2; ++i)
            for (std::size_t j = 0; j < 2; ++j) {
                P(i, j) = a(i, j);
                P(i + 2, j + 2) = b(i, j);
            }
        return P;
    };
    const Matrix theta = Matrix::from_rows({{Rational(3, 5), Rational(-4, 5)}, {Rational(4, 5), Rational(3, 5)}});
    const Matrix pi_minus_theta = Matrix::from_rows({{Rational(-3, 5), Rational(-4, 5)}, {Rational(4, 5), Rational(-3, 5)}});
    const Matrix quarter = Matrix::from_rows({{Rational(0), Rational(-1)}, {Rational(1), Rational(0)}});
    const Matrix p4 = block(theta, pi_minus_theta);
    const auto coefficients = characteristic_polynomial(p4);
    CHECK(coefficients == std::vector<Rational>{Rational(1), Rational(0), Rational(14, 25), Rational(0), Rational(1)});
    require_rule(p4);
    require_rule(block(theta, quarter));
    require_rule(block(quarter, quarter));
    CHECK_FALSE(integral(p4));
    CHECK(integral(block(quarter, quarter)));
    // The order-6 rotation of the hexagonal lattice is an isometry of its metric, not of I.
    const Matrix hex = Matrix::from_rows({{Rational(0), Rational(-1)}, {Rational(1), Rational(1)}});
    CHECK(integral(hex));
    CHECK(finite_by_powers(hex));
}

TEST_CASE("jobs: the verdict, the evidence and the certificate do not depend on the number of threads",
          "[scale][jobs]") {
    for (const char* path : {"proofs/controls/perturbed-entry.json", "proofs/controls/expansive-scaled.json",
                             "proofs/newton4/law.json"}) {
        INFO(path);
        const Model m = load(path);
        const VerifyReport one = verify(m, with(true, true, 1));
        const VerifyReport three = verify(m, with(true, true, 3));
        require_same(one, three);
        CHECK(certificate_text(make_certificate(m, one)) == certificate_text(make_certificate(m, three)));
    }
    const Model m(cradle_law(5, CradleListing::all, false));
    require_same(verify(m, with(true, false, 1)), verify(m, with(true, false, 2)));
}

TEST_CASE("cli: derive cradle writes a compact law that verifies, and rejects bad options", "[scale][cli]") {
    const std::string out = "/tmp/impactcert-test-cradle5.json";
    auto run = test::run_cli("derive cradle --balls 5 -o " + out);
    REQUIRE(run.status == 0);
    CHECK(run.err.find("1 pieces listed, 120 in all, 5 symmetries") != std::string::npos);
    run = test::run_cli("verify --law " + out + " --jobs 2");
    CHECK(run.status == 0);
    CHECK(run.out.find("verdict: proved (12/12 claimed obligations proved") != std::string::npos);
    const std::string cert = "/tmp/impactcert-test-cradle5.cert.json";
    REQUIRE(test::run_cli("certify --law " + out + " -o " + cert).status == 0);
    const auto checked = impactcert_check::check_text(test::read_file(cert));
    CHECK(checked.status == impactcert_check::kVerified);
    std::remove(out.c_str());
    std::remove(cert.c_str());
    for (const char* bad : {"derive cradle --balls 1", "derive cradle --balls 13", "derive cradle --balls 4 --no-symmetries",
                            "derive cradle --balls 4 --pieces some", "verify --jobs 0"}) {
        INFO(bad);
        const auto r = test::run_cli(bad);
        CHECK(r.status == 2);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
}

TEST_CASE("symmetries: the checker holds reduced certificates to the reduced lists, and no other",
          "[scale][symmetries][certificate]") {
    const Model m(cradle_law(4, CradleListing::representatives, true));
    const Json cert = make_certificate(m, verify(m));
    REQUIRE(check_certificate(cert).status == impactcert_check::kVerified);
    {
        // The checker's --max-pieces: expanding beyond it is undecided, with the option named.
        impactcert_check::detail::Limits few;
        few.max_pieces = 10;
        const auto outcome = impactcert_check::check_text(cert.dump(), few);
        CHECK(outcome.status == impactcert_check::kUndecided);
        CHECK(outcome.message.find("--max-pieces") != std::string::npos);
    }
    auto index_of = [&](const std::string& id) {
        for (std::size_t k = 0; k < cert["obligations"].size(); ++k)
            if (cert["obligations"][k]["id"] == id)
                return k;
        throw std::logic_error("no obligation " + id);
    };
    auto refused = [&](const Json& forged, const std::string& reason) {
        const auto outcome = check_certificate(forged);
        INFO(outcome.message);
        CHECK(outcome.status != impactcert_check::kVerified);
        CHECK(outcome.message.find(reason) != std::string::npos);
    };
    {
        // P3 listed for every piece, as without symmetries: more than the orbit representatives.
        Json forged = cert;
        Json& images = forged["obligations"][index_of("P3")]["data"]["images"];
        for (std::size_t p = 1; p < m.pieces().size(); ++p)
            for (std::size_t k = 0; k < 3; ++k) {
                const Vector r = m.pieces()[p].R.column(k);
                images.push_back(Json{{"piece", m.pieces()[p].name}, {"ray", to_json(r)}, {"image", to_json(m.pieces()[p].Q * r)}});
            }
        refused(forged, "too many entries");
    }
    {
        Json forged = cert;
        forged["obligations"][index_of("nonexpansive")]["data"].erase("first_pieces");
        refused(forged, "first_pieces");
    }
    {
        Json forged = cert;
        forged["obligations"][index_of("symmetries")]["data"]["orbit_representatives"] = Json::array({"sorted.s1"});
        refused(forged, "are not the least pieces of the orbits");
    }
    {
        Json forged = cert;
        forged["obligations"][index_of("symmetries")]["data"]["symmetries"][0]["permutation"][3] = 4;
        refused(forged, "permutation of the pieces");
    }
    {
        // A pair list cut short: every ordered pair must be covered by a checked representative.
        Json forged = cert;
        forged["obligations"][index_of("nonexpansive")]["data"]["pairs"].erase(23);
        refused(forged, "is incomplete");
    }
    {
        // The symmetries said refuted (with a made-up witness) although they hold.
        Json forged = cert;
        Json& o = forged["obligations"][index_of("symmetries")];
        o["verdict"] = "refuted";
        o["counterexample"] = Json{{"symmetry", "s1"}, {"matrix", "P"}, {"gamma", Json::array({"1", "0", "0"})},
                                   {"lhs", "1"}, {"rhs", "1"}};
        forged["verdict"] = "refuted";
        refused(forged, "every symmetry holds");
    }
}

TEST_CASE("impactcert-check --jobs: every fixture and certificate gets the same outcome and message with 3 threads",
          "[scale][jobs][certificate]") {
    namespace fs = std::filesystem;
    std::size_t compared = 0;
    for (const char* dir : {"tests/certificates/valid", "tests/certificates/fail", "proofs/controls", "proofs/cradle4"})
        for (const auto& entry : fs::directory_iterator(source_path(dir))) {
            const std::string path = entry.path().string();
            if (path.find("certificate") == std::string::npos && std::string(dir).find("tests/") == std::string::npos)
                continue;
            INFO(path);
            const std::string text = test::read_file(path);
            impactcert_check::detail::Limits one, three;
            three.jobs = 3;
            const auto a = impactcert_check::check_text(text, one), b = impactcert_check::check_text(text, three);
            CHECK(a.status == b.status);
            CHECK(a.message == b.message);
            ++compared;
        }
    CHECK(compared > 40);
    // A forged pair deep in a list: the first failure in order is reported, whatever the threads.
    const Model m(cradle_law(4, CradleListing::all, false));
    Json cert = make_certificate(m, verify(m));
    for (std::size_t k = 0; k < cert["obligations"].size(); ++k)
        if (cert["obligations"][k]["id"] == "nonexpansive") {
            cert["obligations"][k]["data"]["pairs"][400]["certificate"]["method"] = "psd-ldlt";
            cert["obligations"][k]["data"]["pairs"][500]["piece_b"] = "x";
        }
    impactcert_check::detail::Limits three;
    three.jobs = 3;
    const auto a = impactcert_check::check_text(cert.dump(), impactcert_check::detail::Limits{});
    const auto b = impactcert_check::check_text(cert.dump(), three);
    CHECK(a.status != impactcert_check::kVerified);
    CHECK(a.message.find("pairs[400]") != std::string::npos);
    CHECK(a.message == b.message);
}
