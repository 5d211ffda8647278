// fan.hpp -- does the set of cones form a fan that covers R^c exactly once?
//
// Contract (proofs/README.md, obligation `fan`):
//   - check_fan_planar (c = 2 only): sorts the distinct rays by angle with exact orientation
//     predicates; between two angularly consecutive rays lies an open sector that no ray cuts,
//     so the number of cones containing it is constant there; one exact test direction per
//     sector must be covered by exactly one cone.
//   - check_fan_facets (any c): every facet (c-1 rays) of every cone is the facet of exactly one
//     other cone, the two on opposite sides of the facet's hyperplane, and one generic point (on
//     no facet hyperplane) lies in exactly one cone.
// Both return a witness on failure: a point covered k != 1 times, or a facet and its defect.
#pragma once

#include "law.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

struct FanResult {
    bool proved = false;
    std::size_t checks = 0;
    std::string method; // "angular-sectors" or "facet-matching"
    // Failure witness, one of:
    std::optional<Vector> point;          // a gamma covered covering.size() != 1 times
    std::vector<std::size_t> covering;    //   the pieces whose interior contains it
    std::optional<std::size_t> piece;     // a piece with a defective facet ...
    std::vector<Vector> facet;            //   the facet's rays
    std::vector<std::size_t> neighbours;  //   the other pieces having that facet
    std::string reason;                   // one line, human readable
    // Certificate data (what was checked), whichever the verdict:
    std::vector<Vector> rays_by_angle;    // planar: the distinct rays, sorted by angle
    std::vector<Vector> sector_points;    // planar: one direction inside each sector
    struct Facet {
        std::vector<Vector> rays;         // the facet's c-1 rays (sorted by ray id)
        std::vector<std::size_t> pieces; // the pieces having it
    };
    std::vector<Facet> facets;            // facet method: every facet with its pieces
    std::optional<Vector> generic_point;  // facet method: the point covered exactly once
};

FanResult check_fan_planar(const Model& model);
FanResult check_fan_facets(const Model& model);
// The method of SPEC section 3 for this dimension: planar for c = 2, facets otherwise.
FanResult check_fan(const Model& model);

} // namespace impactcert
