// SPDX-License-Identifier: GPL-3.0-or-later
// verify --stream (src/prover/stream.hpp; proofs/README.md, "Streamed laws"): the same verdicts as
// verify() on every law both decide, witnesses re-validated on the expanded model, what the
// stream cannot decide undecided (never proved), and the same input errors.
#include "model/cradle.hpp"
#include "model/law_json.hpp"
#include "prover/stream.hpp"
#include "prover/stream_store.hpp"
#include "support.hpp"
#include "prover/verdict_output.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace impactcert;
using impactcert::test::revalidate;
using impactcert::test::run_cli;

namespace {

struct Agreement {
    std::size_t proved = 0, refuted = 0, undecided = 0;
};

// Every obligation the stream decides has verify()'s verdict, and every refutation's witness
// holds on the expanded model; the counts of each kind are returned for the caller to check.
Agreement require_agreement(const Law& law, const Limits& limits = {}) {
    const Model m(law, limits.max_pieces, limits.max_memory_mb);
    Limits quick = limits;
    quick.evidence = false;
    const VerifyReport full = verify(m, quick);
    const StreamResult s = verify_stream(law, quick);
    REQUIRE(s.pieces == m.pieces().size());
    REQUIRE(s.rays == m.rays().size());
    Agreement a;
    for (const char* id : kObligationIds) {
        INFO(id);
        const ObligationResult& x = full.at(id);
        const ObligationResult& y = s.report.at(id);
        CHECK(x.claimed == y.claimed);
        switch (y.verdict) {
        case Verdict::proved:
            CHECK(x.verdict == Verdict::proved);
            ++a.proved;
            break;
        case Verdict::refuted:
            CHECK(x.verdict == Verdict::refuted);
            revalidate(m, y);
            ++a.refuted;
            break;
        case Verdict::undecided: // never proved; verify() may decide it either way
            ++a.undecided;
            break;
        case Verdict::skipped:
            CHECK(x.verdict == Verdict::skipped);
            break;
        }
    }
    return a;
}

std::string temp_law(const std::string& name, const Law& law) {
    // In the temporary directory, never the directory the tests were started from.
    const std::string path = (std::filesystem::temp_directory_path() / ("impactcert-stream-test-" + name + ".json")).string();
    std::ofstream(path) << law_to_json(law).dump(2);
    return path;
}

} // namespace

TEST_CASE("stream: the cradles n = 2..7 (2..6 under the sanitizers) are proved as verify() proves them, piece for piece", "[stream]") {
#ifdef IMPACTCERT_SANITIZER_BUILD
    const std::size_t largest = 6;
#else
    const std::size_t largest = 7;
#endif
    for (std::size_t n = 2; n <= largest; ++n) { // n = 2: one contact, facets of no ray
        INFO("n = " << n);
        const Law law = cradle_law(n, CradleListing::representatives, true);
        const Agreement a = require_agreement(law);
        CHECK(a.proved == 12); // every claim: identities are not declared
        CHECK(a.refuted == 0);
        CHECK(a.undecided == 0);
        const StreamResult s = verify_stream(law);
        CHECK(s.report.exit_status() == 0);
        CHECK(s.images == n - 1); // the unit vectors: each ray goes to an axis
        CHECK(s.rays == (std::size_t{1} << n) - 2); // the non-empty proper subsets of balls
        CHECK(s.report.at("nonexpansive").checks == s.pieces); // one orbit: (representative, j) for every j
        CHECK(s.report.at("nonexpansive").method.find("by the symmetries") != std::string::npos);
    }
}

TEST_CASE("stream: negative controls are refuted with verify()'s witnesses or left undecided, never proved",
          "[stream]") {
    SECTION("the reversal with P' = I: (iii) fails at a (piece, symmetry) pair, and nothing is reduced") {
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.symmetries.back().P_prime = Matrix::identity(3);
        const Agreement a = require_agreement(law);
        const StreamResult s = verify_stream(law);
        REQUIRE(s.report.at("symmetries").verdict == Verdict::refuted);
        CHECK(s.report.at("symmetries").counterexample.contains("image_piece"));
        for (const char* id : {"fan", "P2", "energetic", "nonexpansive", "nonexpansive-lemma"})
            CHECK(s.report.at(id).verdict == Verdict::undecided);
        CHECK(a.refuted >= 1);
    }
    SECTION("Q = 2I on the representative: P2, energetic and the lemma refuted, nonexpansive undecided") {
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.pieces.front().Q = Rational(2) * Matrix::identity(3);
        law.single_impacts.clear();
        law.outcomes.clear();
        require_agreement(law);
        const StreamResult s = verify_stream(law);
        CHECK(s.report.at("symmetries").verdict == Verdict::proved);
        CHECK(s.report.at("fan").verdict == Verdict::proved);
        CHECK(s.report.at("P1").verdict == Verdict::proved);
        CHECK(s.report.at("P2").verdict == Verdict::refuted);
        CHECK(s.report.at("energetic").verdict == Verdict::refuted);
        CHECK(s.report.at("nonexpansive-lemma").verdict == Verdict::refuted);
        CHECK(s.report.at("nonexpansive").verdict == Verdict::undecided);
        CHECK(s.report.exit_status() == 1);
    }
    SECTION("Q = -I: P3, kinematic and kinetic refuted on a piece, with the one-piece model's witnesses") {
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.pieces.front().Q = Rational(-1) * Matrix::identity(3);
        law.single_impacts.clear();
        law.outcomes.clear();
        require_agreement(law);
        const StreamResult s = verify_stream(law);
        for (const char* id : {"P3", "kinematic", "kinetic"}) {
            INFO(id);
            REQUIRE(s.report.at(id).verdict == Verdict::refuted);
            CHECK(s.report.at(id).counterexample.contains("ray"));
        }
        CHECK(s.report.at("P2").verdict == Verdict::proved); // -I is an isometry
    }
    SECTION("a discontinuous law with two-piece orbits: P1 refuted on a shared ray, the lemma via P1") {
        // The 3-ball orderings, all listed, closed under the reversal alone; the sorted cone (fixed
        // by the reversal J) gets Q = [[2, 1], [1, 2]], which commutes with J: (iii) holds, and
        // its neighbours still send its rays to the axes.
        Law law = cradle_law(3, CradleListing::all, true);
        law.symmetries.erase(law.symmetries.begin(), law.symmetries.end() - 1);
        law.representatives_only = true;
        law.single_impacts.clear();
        law.outcomes.clear();
        bool found = false;
        for (auto& p : law.pieces)
            if (p.name == "u1<=u2<=u3") {
                p.Q = Matrix::from_rows({test::vec({"2", "1"}), test::vec({"1", "2"})});
                found = true;
            }
        REQUIRE(found);
        require_agreement(law);
        const StreamResult s = verify_stream(law);
        REQUIRE(s.report.at("symmetries").verdict == Verdict::proved);
        REQUIRE(s.report.at("P1").verdict == Verdict::refuted);
        CHECK(s.report.at("nonexpansive-lemma").verdict == Verdict::refuted);
        CHECK(s.report.at("nonexpansive-lemma").counterexample["via"] == "P1");
        CHECK(s.report.at("nonexpansive").verdict == Verdict::undecided);
    }
    SECTION("a gap (the reversal alone: two cones): the fan is undecided, not proved") {
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.symmetries.erase(law.symmetries.begin(), law.symmetries.end() - 1);
        law.single_impacts.clear();
        require_agreement(law);
        const StreamResult s = verify_stream(law);
        CHECK(s.pieces == 1); // the reversal fixes the sorted cone
        CHECK(s.report.at("fan").verdict == Verdict::undecided);
        CHECK(s.report.at("fan").limit.find("--stream") != std::string::npos);
        CHECK(s.report.at("P1").verdict != Verdict::proved);
        CHECK(s.report.at("kinematic").verdict != Verdict::proved);
        CHECK(s.report.exit_status() != 0);
    }
    SECTION("an overlap: a second listed cone contains the test point in its interior") {
        Law law = cradle_law(4, CradleListing::representatives, true);
        law.single_impacts.clear();
        law.outcomes.clear();
        PieceDecl extra{"overlap", Matrix::identity(3), std::vector<Vector>{test::vec({"1", "0", "0"}), test::vec({"0", "1", "0"}),
                                                                             test::vec({"1", "1", "2"})}};
        law.pieces.push_back(extra);
        require_agreement(law);
        const StreamResult s = verify_stream(law);
        REQUIRE(s.report.at("fan").verdict == Verdict::refuted);
        CHECK(s.report.at("fan").counterexample["interior_of"].size() >= 2);
    }
}

TEST_CASE("stream: limits, names and refusals are those of Model, in one line each", "[stream]") {
    const Law law = cradle_law(5, CradleListing::representatives, true);
    Limits few;
    few.max_pieces = 100;
    CHECK_THROWS_WITH(verify_stream(law, few), Catch::Contains("more than 100 pieces (raise it with --max-pieces)"));
    CHECK_THROWS_WITH(Model(law, 100), Catch::Contains("more than 100 pieces (raise it with --max-pieces)"));
    Limits tight;
    tight.max_memory_mb = 0;
    CHECK_THROWS_WITH(verify_stream(law, tight), Catch::Contains("raise it with --max-memory"));

    Law unknown = law;
    unknown.single_impacts.front().piece = "sorted.s9";
    CHECK_THROWS_WITH(verify_stream(unknown), Catch::Contains("$.single_impacts[0].piece: unknown piece \"sorted.s9\""));
    CHECK_THROWS_WITH(Model(unknown), Catch::Contains("$.single_impacts[0].piece: unknown piece \"sorted.s9\""));
    // A name reached by a path that did not generate it is unknown too: sorted.s1.s1 is sorted.
    unknown.single_impacts.front().piece = "sorted.s1.s1";
    CHECK_THROWS_AS(verify_stream(unknown), InputError);
    CHECK_THROWS_AS(Model(unknown), InputError);

    // A listed piece named like the piece a symmetry generates.
    Law taken = cradle_law(4, CradleListing::representatives, true);
    PieceDecl other = taken.pieces.front();
    other.name = "sorted.s1";
    other.rays = std::vector<Vector>{test::vec({"1", "0", "0"}), test::vec({"0", "1", "0"}), test::vec({"1", "1", "2"})};
    taken.pieces.push_back(other);
    CHECK_THROWS_WITH(Model(taken), Catch::Contains("generated piece name \"sorted.s1\" is taken"));
    CHECK_THROWS_WITH(verify_stream(taken), Catch::Contains("generated piece name \"sorted.s1\" is taken"));

    // Outside what the store holds: refused, never decided.
    CHECK_THROWS_AS(verify_stream(cradle_law(4, CradleListing::all, true)), StreamRefused);
    Law dotted = cradle_law(4, CradleListing::representatives, true);
    dotted.symmetries.front().name = "s.1";
    CHECK_THROWS_AS(verify_stream(dotted), StreamRefused);
    Law twice = cradle_law(4, CradleListing::representatives, true);
    twice.pieces.push_back(twice.pieces.front());
    twice.pieces.back().name = "again";
    CHECK_THROWS_AS(verify_stream(twice), StreamRefused);
}

TEST_CASE("stream: the CLI's --stream", "[stream][cli]") {
    const std::string path = temp_law("cradle6", cradle_law(6, CradleListing::representatives, true));
    const auto streamed = run_cli("verify --stream --json --law " + path);
    const auto full = run_cli("verify --json --law " + path);
    REQUIRE(streamed.status == 0);
    REQUIRE(full.status == 0);
    const Json a = Json::parse(streamed.out), b = Json::parse(full.out);
    CHECK(a["verdict"] == b["verdict"]);
    REQUIRE(a["obligations"].size() == 13); // (issue 33, 10g: an empty list compared nothing)
    REQUIRE(b["obligations"].size() == 13);
    for (std::size_t k = 0; k < a["obligations"].size(); ++k)
        CHECK(a["obligations"][k]["verdict"] == b["obligations"][k]["verdict"]);
    const auto table = run_cli("verify --stream --law " + path);
    CHECK(table.status == 0);
    CHECK(table.out.find("720 pieces as ids of 62 rays") != std::string::npos);

    const auto paper = run_cli("verify --stream");
    CHECK(paper.status == 3);
    CHECK(paper.err.find("--stream") != std::string::npos);
    CHECK(std::count(paper.err.begin(), paper.err.end(), '\n') == 1);
    const auto sharded = run_cli("verify --stream --shard 1/2 --law " + path);
    CHECK(sharded.status == 2);
    const auto limited = run_cli("verify --stream --max-pieces 10 --law " + path);
    CHECK(limited.status == 2);
    CHECK(limited.err.find(path + ": $.symmetries: the symmetries generate more than 10 pieces") != std::string::npos);
}

TEST_CASE("stream: the membership pass in threads gives the same report, byte for byte", "[stream]") {
    // 5,040 pieces: two and three ranges scanned in parallel; the fan, outcomes and counts merged
    // in piece order.
    // The outcome of the fully reversed ordering: its only piece is among the last generated
    // (the third range), so the pass must read every range.
    Law law = cradle_law(7, CradleListing::representatives, true);
    law.outcomes.push_back(OutcomeDecl{"reversed", test::vec({"7", "6", "5", "4", "3", "2", "1"}),
                                       test::vec({"1", "2", "3", "4", "5", "6", "7"})});
    Limits one, two, three;
    one.jobs = 1;
    two.jobs = 2;
    three.jobs = 3;
    const StreamResult single = verify_stream(law, one);
    REQUIRE(single.report.at("outcomes").verdict == Verdict::proved);
    const std::string a = verdict_json(single.report).dump();
    CHECK(verdict_json(verify_stream(law, two).report).dump() == a);
    CHECK(verdict_json(verify_stream(law, three).report).dump() == a);
    // A refuted fan (an overlapping listed cone and its orbit): the merged witness is the same.
    Law overlap = cradle_law(6, CradleListing::representatives, true);
    overlap.single_impacts.clear();
    overlap.outcomes.clear();
    std::vector<Vector> rays;
    for (std::size_t k = 0; k < 5; ++k)
        rays.push_back(unit_vector(5, k));
    rays.back() = test::vec({"1", "1", "1", "1", "2"});
    overlap.pieces.push_back(PieceDecl{"overlap", Matrix::identity(5), rays});
    const StreamResult s1 = verify_stream(overlap, one), s2 = verify_stream(overlap, two);
    REQUIRE(s1.report.at("fan").verdict == Verdict::refuted);
    CHECK(s1.report.at("fan").counterexample["interior_of"].size() >= 2);
    CHECK(verdict_json(s2.report).dump() == verdict_json(s1.report).dump());
}

TEST_CASE("stream: the symmetry expansion in threads stores exactly what one thread stores", "[stream]") {
    // 5,040 pieces in blocks of 4,096: the second block starts while pieces are still being
    // added; every record, the checks, the first failure and the orbits must be one thread's.
    // The listed pieces alone, as verify_stream gives them to the expansion.
    auto listed = [](Law law) {
        law.representatives_only = false;
        law.identities.clear();
        law.single_impacts.clear();
        law.outcomes.clear();
        law.claims.reset();
        return law;
    };
    auto same = [&](const Law& law, const Limits& one, const Limits& many) {
        const Model base_one(listed(law), one.max_pieces, one.max_memory_mb);
        const stream::Expansion a(law, base_one, one, nullptr), b(law, base_one, many, nullptr);
        REQUIRE(a.store.size() == b.store.size());
        const std::size_t c = a.c;
        for (std::size_t p = 0; p < a.store.size(); ++p) {
            INFO("piece " << p);
            REQUIRE(std::equal(a.store.rays(p), a.store.rays(p) + c, b.store.rays(p)));
            REQUIRE(std::equal(a.store.images(p), a.store.images(p) + c, b.store.images(p)));
            REQUIRE(a.store.parent(p) == b.store.parent(p));
            REQUIRE(a.store.generator(p) == b.store.generator(p));
        }
        CHECK(a.name(static_cast<stream::u32>(a.store.size() - 1)) == b.name(static_cast<stream::u32>(b.store.size() - 1)));
        CHECK(a.rays == b.rays);
        CHECK(a.images == b.images);
        CHECK(a.symmetry_checks == b.symmetry_checks);
        CHECK(a.representatives == b.representatives);
        REQUIRE(a.failure.has_value() == b.failure.has_value());
        if (a.failure) {
            CHECK(a.failure->piece == b.failure->piece);
            CHECK(a.failure->image_piece == b.failure->image_piece);
            CHECK(a.failure->symmetry == b.failure->symmetry);
            CHECK(a.failure->position == b.failure->position);
        }
        return std::make_pair(a.store.size(), a.failure.has_value());
    };
    Limits one, three;
    one.jobs = 1;
    three.jobs = 3;
#ifdef IMPACTCERT_SANITIZER_BUILD
    const std::size_t n = 6;
#else
    const std::size_t n = 7;
#endif
    const Law cradle = cradle_law(n, CradleListing::representatives, true);
    CHECK(same(cradle, one, three) == std::make_pair(std::size_t{n == 7 ? 5040u : 720u}, false));
    // Under --max-memory 8 the threads' blocks shrink (to 1/64 of the budget): several blocks, the
    // same store.
    Limits one_small = one, three_small = three;
    one_small.max_memory_mb = three_small.max_memory_mb = 8;
    CHECK(same(cradle, one_small, three_small).first == (n == 7 ? 5040u : 720u));
    // A refuted symmetry (the reversal with P' = I): the same first failure.
    Law wrong = cradle;
    wrong.symmetries.back().P_prime = Matrix::identity(n - 1);
    CHECK(same(wrong, one, three).second);
    // --max-pieces reached while the threads look ahead: the same message at the same piece.
    Limits small_one = one, small_three = three;
    small_one.max_pieces = small_three.max_pieces = 600;
    std::string e1, e3;
    const Model base(listed(cradle), 100000);
    try {
        stream::Expansion(cradle, base, small_one, nullptr);
    } catch (const InputError& e) {
        e1 = e.what();
    }
    try {
        stream::Expansion(cradle, base, small_three, nullptr);
    } catch (const InputError& e) {
        e3 = e.what();
    }
    CHECK(e1.find("--max-pieces") != std::string::npos);
    CHECK(e1 == e3);
}

namespace {

// The first input error of Model and of the stream on the same law: the same message.
std::string model_error(const Law& law, const Limits& limits = {}) {
    try {
        Model m(law, limits.max_pieces, limits.max_memory_mb);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

std::string stream_error(const Law& law, const Limits& limits = {}) {
    try {
        verify_stream(law, limits);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("stream: input errors come in Model's order, with Model's messages", "[stream]") {
    const Law cradle = cradle_law(4, CradleListing::representatives, true);
    auto same = [](const Law& law, const Limits& limits = {}) {
        const std::string m = model_error(law, limits);
        CHECK_FALSE(m.empty());
        CHECK(stream_error(law, limits) == m);
    };
    {   // an unknown identity piece before a wrong outcome
        Law law = cradle;
        law.identities.push_back(IdentityDecl{"nowhere", {"sorted"}});
        law.outcomes.front().u_minus.pop_back();
        same(law);
    }
    {   // a restitution out of range before a claim made twice
        Law law = cradle;
        law.single_impacts.front().restitution = Rational(2);
        law.claims = std::vector<std::string>{"fan", "fan"};
        same(law);
    }
    {   // an empty product
        Law law = cradle;
        law.identities.push_back(IdentityDecl{"sorted", {}});
        same(law);
    }
    {   // a listed name that a symmetry generates: at the moment it is generated
        Law law = cradle;
        PieceDecl other = law.pieces.front();
        other.name = "sorted.s1";
        other.rays = std::vector<Vector>{test::vec({"1", "0", "0"}), test::vec({"0", "1", "0"}), test::vec({"1", "1", "2"})};
        law.pieces.push_back(other);
        Limits three;
        three.max_pieces = 3;
        same(law, three);
        same(law);
    }
    {   // an input error of a later symmetry before a name that --stream refuses
        Law law = cradle;
        law.symmetries[0].name = "s.1";
        law.symmetries[1].P = Rational(2) * Matrix::identity(3);
        same(law);
    }
    {   // a listed name two steps down a path
        Law law = cradle;
        PieceDecl other = law.pieces.front();
        other.name = "sorted.s1.s2";
        other.rays = std::vector<Vector>{test::vec({"1", "0", "0"}), test::vec({"0", "1", "0"}), test::vec({"1", "1", "2"})};
        law.pieces.push_back(other);
        same(law);
    }
    {   // a name read through a listed name that has a "." itself: resolved as Model resolves it
        Law law = cradle;
        PieceDecl other = law.pieces.front();
        other.name = "sorted.x";
        other.rays = std::vector<Vector>{test::vec({"1", "0", "0"}), test::vec({"0", "1", "0"}), test::vec({"1", "1", "2"})};
        law.pieces.push_back(other);
        law.identities.push_back(IdentityDecl{"sorted.x.s1", {"sorted.x.s1"}});
        CHECK(model_error(law).empty());
        CHECK(stream_error(law).empty());
        law.identities.back().lhs = "sorted.x.s9";
        same(law);
    }
    {   // an empty piece name before missing symmetries
        Law law = cradle;
        law.pieces.front().name = "";
        law.symmetries.clear();
        same(law);
    }
    {   // a name far longer than any generated one: unknown, not a crash
        Law law = cradle;
        std::string deep = "sorted";
        for (int k = 0; k < 40000; ++k)
            deep += ".s1";
        law.identities.push_back(IdentityDecl{deep, {"sorted"}});
        same(law);
        // and a deep name within the length that does not exist: unknown too
        law.identities.back().lhs = "sorted.s1.s1.s1.s1.s1.s1.s1.s1.s1.s1.s1";
        same(law);
    }
    {   // a law listing every piece: validated first (exit 2), refused only when valid (exit 3)
        Law law = cradle_law(4, CradleListing::all, true);
        law.outcomes.front().u_plus.pop_back();
        same(law);
    }
}

TEST_CASE("stream: rational symmetries (P r = r' / 7), several orbits, and the second test points", "[stream]") {
    SECTION("a rational H-isometry of the 3-ball chain: rays scaled by 1/7, images by 7") {
        // P = P' = [[-3/7, -8/7], [-5/7, 3/7]] maps (1, 0) to (-3, -5)/7: s = 1/7.
        const Law law = parse_law_text(R"({"format": "impactcert-law/1", "name": "rational", "masses": ["1", "1", "1"],
            "contacts": "chain", "pieces_listed": "orbit-representatives",
            "pieces": [{"name": "A", "Q": [["1", "0"], ["0", "1"]], "rays": [["1", "0"], ["0", "1"]]},
                       {"name": "B", "Q": [["1", "0"], ["0", "1"]], "rays": [["0", "1"], ["-8", "3"]]},
                       {"name": "C", "Q": [["1", "0"], ["0", "1"]], "rays": [["-3", "-5"], ["1", "0"]]}],
            "symmetries": [{"name": "g", "P": [["-3/7", "-8/7"], ["-5/7", "3/7"]],
                            "P_prime": [["-3/7", "-8/7"], ["-5/7", "3/7"]]}]})",
                                       "rational");
        const Agreement a = require_agreement(law);
        CHECK(a.proved + a.refuted > 0);
        const StreamResult s = verify_stream(law);
        // Pinned (issue 33, 10f: only "decided" was asserted). The law is the identity on a fan of
        // four cones (three listed, one generated by g): a function, continuous, an isometry; the
        // identity does not reverse approaching contacts, so P3 and kinematic fail at the ray (-8, 3).
        CHECK(s.report.at("symmetries").verdict == Verdict::proved);
        for (const char* id : {"fan", "P1", "P2", "kinetic", "energetic", "nonexpansive", "nonexpansive-lemma"})
            CHECK(s.report.at(id).verdict == Verdict::proved);
        for (const char* id : {"P3", "kinematic"}) {
            CHECK(s.report.at(id).verdict == Verdict::refuted);
            CHECK(s.report.at(id).counterexample["ray"] == Json::array({"-8", "3"}));
        }
        CHECK(s.report.exit_status() == 1);
    }
    SECTION("the 3-ball orderings under the reversal alone: four orbits, the fan proved on all their facets") {
        Law law = cradle_law(3, CradleListing::all, true);
        law.symmetries.erase(law.symmetries.begin(), law.symmetries.end() - 1);
        law.representatives_only = true;
        const Agreement a = require_agreement(law);
        CHECK(a.undecided == 0);
        const StreamResult s = verify_stream(law);
        CHECK(s.report.at("fan").verdict == Verdict::proved);
        CHECK(s.report.at("nonexpansive").checks == 4 * 6); // four orbits x six pieces
        CHECK(s.report.exit_status() == 0);
    }
    SECTION("the first test point on another cone's boundary, the second inside it: an overlap") {
        // The quadrant and the cone of (1, 1), (-1, 2): p_1 = (1, 1) is a ray of the second,
        // p_2 = (1, 2) lies in both interiors.
        const Law law = parse_law_text(R"({"format": "impactcert-law/1", "name": "second-point", "masses": ["1", "1", "1"],
            "contacts": "chain", "pieces_listed": "orbit-representatives",
            "pieces": [{"name": "A", "Q": [["1", "0"], ["0", "1"]], "rays": [["1", "0"], ["0", "1"]]},
                       {"name": "B", "Q": [["1", "0"], ["0", "1"]], "rays": [["1", "1"], ["-1", "2"]]}],
            "symmetries": [{"name": "id", "P": [["1", "0"], ["0", "1"]], "P_prime": [["1", "0"], ["0", "1"]]}]})",
                                       "second-point");
        require_agreement(law);
        const StreamResult s = verify_stream(law);
        REQUIRE(s.report.at("fan").verdict == Verdict::refuted);
        CHECK(s.report.at("fan").counterexample["gamma"] == Json::array({"1", "2"}));
        CHECK(s.report.at("fan").checks == 2 * 2 + 2 * 4); // facets + two pieces x four points
    }
}
