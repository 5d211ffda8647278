#include "fan.hpp"
#include "law_json.hpp"
#include "paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

using namespace impactcert;
using impactcert::test::source_path;
using impactcert::test::vec;

namespace {

Law two_d_law(std::vector<std::pair<const char*, std::vector<Vector>>> cones) {
    Law law;
    law.name = "fan-fixture";
    law.masses = vec({"1", "1", "1"});
    for (auto& [name, rays] : cones)
        law.pieces.push_back(PieceDecl{name, Matrix::identity(2), rays});
    return law;
}

} // namespace

TEST_CASE("fan: the paper's six cones cover the plane exactly once", "[fan]") {
    const Model m(paper_law());
    const auto planar = check_fan_planar(m);
    CHECK(planar.proved);
    CHECK(planar.checks == 36); // six sectors, six cones each
    CHECK(check_fan_facets(m).proved);
}

TEST_CASE("fan: the planar and the facet method agree on every 2-contact law we ship", "[fan]") {
    for (const char* name : {"newton3/law", "controls/perturbed-entry", "controls/swapped-pieces",
                             "controls/missing-cone", "controls/newton-simultaneous",
                             "controls/discontinuous-isometric", "controls/expansive-scaled"}) {
        INFO(name);
        const Model m(load_law_file(source_path(std::string("proofs/") + name + ".json")));
        CHECK(check_fan_planar(m).proved == check_fan_facets(m).proved);
    }
}

TEST_CASE("fan: a gap is found with an uncovered direction", "[fan]") {
    // Three quadrants only: the fourth quadrant is uncovered.
    const Model m(two_d_law({{"Q1", {vec({"1", "0"}), vec({"0", "1"})}},
                             {"Q2", {vec({"0", "1"}), vec({"-1", "0"})}},
                             {"Q3", {vec({"-1", "0"}), vec({"0", "-1"})}}}));
    const auto r = check_fan_planar(m);
    REQUIRE_FALSE(r.proved);
    REQUIRE(r.point);
    CHECK(m.pieces_containing(*r.point).empty());
    CHECK_FALSE(check_fan_facets(m).proved);
}

TEST_CASE("fan: overlapping cones are found with a doubly covered direction", "[fan]") {
    // Q1 and Q2 plus a cone spanning (1,1)..(-1,1) on top of them, plus the lower half.
    const Model m(two_d_law({{"Q1", {vec({"1", "0"}), vec({"0", "1"})}},
                             {"Q2", {vec({"0", "1"}), vec({"-1", "0"})}},
                             {"top", {vec({"1", "1"}), vec({"-1", "1"})}},
                             {"Q3", {vec({"-1", "0"}), vec({"0", "-1"})}},
                             {"Q4", {vec({"0", "-1"}), vec({"1", "0"})}}}));
    const auto r = check_fan_planar(m);
    REQUIRE_FALSE(r.proved);
    REQUIRE(r.point);
    CHECK(r.covering.size() == 2);
    CHECK_FALSE(check_fan_facets(m).proved);
}

TEST_CASE("fan: a cone counted twice around the origin is a double cover, not a fan", "[fan]") {
    // Six cones that wind around the origin twice: every cone spans less than pi (135 degrees,
    // the last 45), consecutive cones share a ray on opposite sides, and the chain closes after
    // two full turns. Every facet matches, so only the covering count can catch it.
    const Model m(two_d_law({{"a", {vec({"1", "0"}), vec({"-1", "1"})}},
                             {"b", {vec({"-1", "1"}), vec({"0", "-1"})}},
                             {"c", {vec({"0", "-1"}), vec({"1", "1"})}},
                             {"d", {vec({"1", "1"}), vec({"-1", "0"})}},
                             {"e", {vec({"-1", "0"}), vec({"1", "-1"})}},
                             {"f", {vec({"1", "-1"}), vec({"1", "0"})}}}));
    const auto planar = check_fan_planar(m);
    REQUIRE_FALSE(planar.proved);
    CHECK(planar.covering.size() == 2);
    const auto facets = check_fan_facets(m);
    REQUIRE_FALSE(facets.proved);
    REQUIRE(facets.point);
    CHECK(facets.covering.size() == 2);
}

TEST_CASE("fan: the 4-ball sorting law's 24 cones form a fan in R^3", "[fan]") {
    const Model m(test::sorting_law(4));
    REQUIRE(m.pieces().size() == 24);
    const auto r = check_fan_facets(m);
    CHECK(r.proved);
    CHECK(r.method == "facet-matching");
}

TEST_CASE("fan: dropping one of the 24 cones in R^3 leaves unmatched facets", "[fan]") {
    Law law = test::sorting_law(4);
    law.pieces.erase(law.pieces.begin() + 7);
    const auto r = check_fan_facets(Model(law));
    REQUIRE_FALSE(r.proved);
    CHECK(r.reason.find("no other cone") != std::string::npos);
    CHECK(r.facet.size() == 2);
}
