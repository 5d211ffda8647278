// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/law_json.hpp"
#include "prover/obligations.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <set>

using namespace impactcert;
using impactcert::test::q;
using impactcert::test::source_path;
using impactcert::test::vec;

namespace {

std::set<std::string> refuted_ids(const VerifyReport& r) {
    std::set<std::string> out;
    for (const auto& o : r.obligations)
        if (o.verdict == Verdict::refuted)
            out.insert(o.id);
    return out;
}

Vector sorted(Vector u) {
    std::sort(u.begin(), u.end());
    return u;
}

// u+ from the law through the impact equations, for a point where S is single-valued.
Vector law_in_velocities(const Model& m, const Vector& u) {
    const Vector gamma = m.contact_velocities(u);
    const auto values = m.values_at(gamma);
    REQUIRE(values.size() == 1);
    return m.post_impact_velocities(u, gamma, values.front());
}

Law four_ball_law() {
    Law law = test::sorting_law(4);
    // Two-ball impacts: only contact k approaches, so sorting swaps balls k and k+1.
    law.single_impacts = {{"u2<=u1<=u3<=u4", 1, Rational(1)},
                          {"u1<=u3<=u2<=u4", 2, Rational(1)},
                          {"u1<=u2<=u4<=u3", 3, Rational(1)}};
    law.outcomes = {{"one ball in", vec({"1", "0", "0", "0"}), vec({"0", "0", "0", "1"})},
                    {"two balls in", vec({"1", "1", "0", "0"}), vec({"0", "0", "1", "1"})},
                    {"three balls in", vec({"1", "1", "1", "0"}), vec({"0", "1", "1", "1"})},
                    {"all reversed", vec({"2", "1", "0", "-1"}), vec({"-1", "0", "1", "2"})}};
    return law;
}

} // namespace

TEST_CASE("paper's law: every obligation of the SPEC is proved", "[obligations]") {
    const Model m(paper_law());
    const VerifyReport r = verify(m);
    REQUIRE(r.obligations.size() == kObligationIds.size());
    for (const auto& o : r.obligations) {
        INFO(o.id << " " << o.counterexample.dump());
        if (o.id == "symmetries") { // the paper declares none
            CHECK_FALSE(o.claimed);
            CHECK(o.verdict == Verdict::skipped);
            continue;
        }
        CHECK(o.claimed);
        CHECK(o.verdict == Verdict::proved);
        CHECK(o.checks > 0);
    }
    CHECK(r.passed());
    // The finite checks are the ones the reductions call for.
    CHECK(r.at("P1").checks == 6);     // six shared rays
    CHECK(r.at("P2").checks == 6);     // six pieces
    CHECK(r.at("P3").checks == 12);    // two rays per piece
    CHECK(r.at("identities").checks == 4);
    CHECK(r.at("single-impacts").checks == 2);
    CHECK(r.at("nonexpansive").checks >= 36); // 36 ordered pairs, one certificate or 15 faces each
}

TEST_CASE("paper's law: S is 'sort the ball velocities' on 10,201 rational points, every cone boundary included",
          "[obligations]") {
    const Model m(paper_law());
    std::size_t points = 0, on_boundary = 0;
    for (int a = -50; a <= 50; ++a)
        for (int b = -50; b <= 50; ++b) {
            // gamma = (a/7, b/7 + a/11): the lines g1 = 0, g2 = 0 and g1 + g2 = 0 are all hit.
            const Vector gamma = {Rational(a, 7), Rational(b, 7)};
            const Vector u = {Rational(0), gamma[0], gamma[0] + gamma[1]};
            INFO("u- = " << to_string(u));
            REQUIRE(law_in_velocities(m, u) == sorted(u));
            ++points;
            on_boundary += m.pieces_containing(gamma).size() > 1 ? 1 : 0;
        }
    CHECK(points == 10201);
    CHECK(on_boundary == 301); // three lines of 101 points through the origin, origin counted once
}

TEST_CASE("paper's law: the sort law of 3 balls, built from first principles, is the paper's table", "[obligations]") {
    const Model paper(paper_law()), sort3(test::sorting_law(3));
    REQUIRE(sort3.pieces().size() == 6);
    for (const auto& p : paper.pieces()) {
        INFO(p.name);
        bool found = false;
        for (const auto& s : sort3.pieces()) {
            std::vector<Vector> a = {p.R.column(0), p.R.column(1)}, b = {s.R.column(0), s.R.column(1)};
            std::sort(a.begin(), a.end());
            std::sort(b.begin(), b.end());
            if (a == b) {
                found = true;
                CHECK(p.Q == s.Q);
            }
        }
        CHECK(found);
    }
}

TEST_CASE("negative controls: each is refuted on exactly the obligations its note states", "[obligations][controls]") {
    // Derivations by hand are in each file's note; the sets here are those notes.
    const std::vector<std::pair<std::string, std::set<std::string>>> controls = {
        {"perturbed-entry", {"P1", "P2", "P3", "kinematic", "kinetic", "identities", "nonexpansive", "nonexpansive-lemma"}},
        {"swapped-pieces", {"P1", "P3", "kinematic", "kinetic", "identities", "single-impacts", "nonexpansive",
                            "nonexpansive-lemma"}},
        {"missing-cone", {"fan", "kinematic", "nonexpansive", "nonexpansive-lemma"}},
        {"newton-simultaneous", {"P1", "P3", "kinematic", "nonexpansive", "nonexpansive-lemma", "outcomes"}},
        {"discontinuous-isometric", {"P1", "kinetic", "nonexpansive", "nonexpansive-lemma"}},
        {"expansive-scaled", {"P2", "energetic", "identities", "single-impacts", "nonexpansive", "nonexpansive-lemma",
                              "outcomes"}},
        {"symmetry-wrong-reversal", {"symmetries"}},
        {"symmetric-expansive", {"P2", "energetic", "nonexpansive", "nonexpansive-lemma"}},
    };
    for (const auto& [name, expected] : controls) {
        INFO("control " << name);
        const Model m(load_law_file(source_path("proofs/controls/" + name + ".json")));
        const VerifyReport r = verify(m);
        CHECK_FALSE(r.passed());
        CHECK(refuted_ids(r) == expected);
        for (const auto& o : r.obligations) {
            if (o.verdict == Verdict::refuted)
                test::revalidate(m, o);
            else
                CHECK(o.counterexample.is_null());
        }
    }
}

TEST_CASE("negative controls: the simultaneous Newton law sends (1,0,0) to (-1/3,2/3,2/3)", "[obligations][controls]") {
    const Model m(load_law_file(source_path("proofs/controls/newton-simultaneous.json")));
    const Vector u = vec({"1", "0", "0"});
    const Vector gamma = m.contact_velocities(u);
    const auto& III = m.pieces()[m.piece_index("III")];
    CHECK(m.post_impact_velocities(u, gamma, III.Q * gamma) == vec({"-1/3", "2/3", "2/3"}));
    // Energy is conserved all the same: 1/2 |u|^2 = 1/2 before and after.
    const Vector after = m.post_impact_velocities(u, gamma, III.Q * gamma);
    CHECK(dot(after, after) == dot(u, u));
}

TEST_CASE("negative controls: the expansive law is caught by copositivity, not by a discontinuity", "[obligations][controls]") {
    const Model m(load_law_file(source_path("proofs/controls/expansive-scaled.json")));
    const VerifyReport r = verify(m);
    CHECK(r.at("P1").verdict == Verdict::proved);
    CHECK(r.at("fan").verdict == Verdict::proved);
    const auto& ne = r.at("nonexpansive");
    REQUIRE(ne.verdict == Verdict::refuted);
    CHECK_FALSE(ne.counterexample.contains("via"));
    test::revalidate(m, ne);
}

TEST_CASE("gate: only claimed obligations decide the verdict - the others are still reported", "[obligations]") {
    Law law = load_law_file(source_path("proofs/controls/perturbed-entry.json"));
    law.claims = std::vector<std::string>{"fan", "energetic", "outcomes"};
    const VerifyReport r = verify(Model(law));
    CHECK(r.passed());
    CHECK(r.at("P2").verdict == Verdict::refuted);
    CHECK_FALSE(r.at("P2").claimed);
    law.claims->push_back("P2");
    CHECK_FALSE(verify(Model(law)).passed());
}

TEST_CASE("gate: undeclared identities, single impacts and outcomes are skipped, not proved", "[obligations]") {
    const VerifyReport r = verify(Model(test::sorting_law(3)));
    for (const char* id : {"identities", "single-impacts", "outcomes"}) {
        CHECK(r.at(id).verdict == Verdict::skipped);
        CHECK_FALSE(r.at(id).claimed);
    }
    CHECK(r.passed());
}

TEST_CASE("4-ball law (c = 3, 24 cones): every obligation is proved", "[obligations][c3]") {
    const Model m(four_ball_law());
    REQUIRE(m.contacts() == 3);
    REQUIRE(m.pieces().size() == 24);
    const VerifyReport r = verify(m);
    for (const auto& o : r.obligations) {
        INFO(o.id << " " << o.counterexample.dump());
        if (o.id == "identities" || o.id == "symmetries")
            CHECK(o.verdict == Verdict::skipped);
        else
            CHECK(o.verdict == Verdict::proved);
    }
    CHECK(r.at("fan").method == "facet-matching");
    CHECK(r.passed());
}

TEST_CASE("4-ball law: S is 'sort the ball velocities' on random rational points and on ties", "[obligations][c3]") {
    const Model m(four_ball_law());
    std::mt19937 rng(4);
    std::uniform_int_distribution<int> num(-6, 6), den(1, 4);
    for (int trial = 0; trial < 3000; ++trial) {
        Vector u(4);
        for (auto& x : u)
            x = Rational(num(rng), den(rng)); // small range: many ties, i.e. cone boundaries
        INFO("u- = " << to_string(u));
        REQUIRE(law_in_velocities(m, u) == sorted(u));
    }
}

TEST_CASE("4-ball law: a perturbed piece is refuted with re-validated witnesses", "[obligations][c3]") {
    Law law = four_ball_law();
    law.outcomes.clear();
    law.single_impacts.clear();
    law.claims.reset();
    auto& piece = law.pieces[5];
    piece.Q(0, 0) += Rational(1, 10);
    const Model m(law);
    const VerifyReport r = verify(m);
    CHECK_FALSE(r.passed());
    for (const char* id : {"P1", "P2", "nonexpansive", "nonexpansive-lemma"})
        CHECK(r.at(id).verdict == Verdict::refuted);
    CHECK(r.at("fan").verdict == Verdict::proved);
    for (const auto& o : r.obligations)
        if (o.verdict == Verdict::refuted)
            test::revalidate(m, o);
}

TEST_CASE("nonexpansive: a continuous law that expands inside one cone is refuted with interior points", "[obligations]") {
    // Paper's law with piece I stretched along gamma_2 and IIa, IVa... simplest: a single linear
    // map on the whole plane split into four quadrant cones, expanding in one direction.
    Law law;
    law.name = "linear-stretch";
    law.masses = vec({"1", "1", "1"});
    const Matrix stretch = Matrix::from_rows({vec({"1", "0"}), vec({"0", "3/2"})});
    const std::vector<std::vector<Vector>> quadrants = {{vec({"1", "0"}), vec({"0", "1"})},
                                                        {vec({"0", "1"}), vec({"-1", "0"})},
                                                        {vec({"-1", "0"}), vec({"0", "-1"})},
                                                        {vec({"0", "-1"}), vec({"1", "0"})}};
    for (std::size_t k = 0; k < 4; ++k)
        law.pieces.push_back(PieceDecl{"q" + std::to_string(k + 1), stretch, quadrants[k]});
    const Model m(law);
    const VerifyReport r = verify(m);
    CHECK(r.at("fan").verdict == Verdict::proved);
    CHECK(r.at("P1").verdict == Verdict::proved);
    REQUIRE(r.at("nonexpansive").verdict == Verdict::refuted);
    REQUIRE(r.at("nonexpansive-lemma").verdict == Verdict::refuted);
    test::revalidate(m, r.at("nonexpansive"));
    test::revalidate(m, r.at("nonexpansive-lemma"));
}

TEST_CASE("4-ball law: proofs/newton4/law.json is the law built from first principles", "[obligations][c3]") {
    const Law file = load_law_file(source_path("proofs/newton4/law.json"));
    Law built = four_ball_law();
    built.name = file.name;
    CHECK(law_to_json(file).dump() == law_to_json(built).dump());
    CHECK(verify(Model(file)).passed());
}
