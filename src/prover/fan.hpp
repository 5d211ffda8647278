// SPDX-License-Identifier: GPL-3.0-or-later
// fan.hpp -- do the cones tile R^c, is S a function on R^c, and where do two cones meet?
//
// Contract (proofs/README.md, obligations `fan` and `P1`, argues each step):
//   - check_fan decides exactly whether the cones tile R^c (union R^c, interiors pairwise
//     disjoint; they need not meet face to face):
//       c = 2: method `angular-sectors`: one direction inside each open sector between angularly
//              consecutive rays; the count of cones containing it is constant on the sector.
//       c != 2: method `facet-matching` (fast path): every facet shared by exactly one other cone
//              on the opposite side, and one generic point covered once. When it does not
//              apply, method `walls`: the count of cones is 1 at one generic point and does not
//              change across any facet hyperplane (the facets in it cancel, recursively in
//              dimension c-1): a complete decision of tilings, proved without enumerating
//              chambers. When that fails, method `chambers`: one point in every chamber of the
//              arrangement of all facet hyperplanes (chamber_points), for the witness and for
//              check_domain; the count is constant on each chamber.
//     Every test point lies on no cone boundary, so "in a closed cone" and "in its interior"
//     agree there; `covering` lists the interiors containing each point, and the first point
//     covered k != 1 times is the witness (k = 0: a gap, k >= 2: an overlap).
//   - check_domain: from a complete list of test points, whether S is a function on R^c (no gap,
//     and overlapping interiors carry equal matrices); otherwise the first point where S is
//     undefined or two-valued on an open set.
//   - intersection_rays: the extreme rays of C_i ∩ C_j (a pointed cone), sorted.
// Limits: LimitExceeded (limits.hpp) before the chamber enumeration or the intersection work
// exceeds its limit.
#pragma once

#include "model/law.hpp"
#include "base/limits.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

struct FanResult {
    bool proved = false;
    bool fast_path = false;    // proved by sectors or by facet matching: a fan meeting face to face
    std::size_t checks = 0;
    std::string method;        // "angular-sectors", "facet-matching", "walls", "unmatched-facet" or "chambers"
    std::vector<Vector> rays_by_angle; // angular-sectors: the distinct rays, sorted by angle
    struct Facet {
        std::vector<Vector> rays;         // the facet's c-1 rays (in ray-id order)
        std::vector<std::size_t> pieces;  // the pieces having it
    };
    std::vector<Facet> facets;         // facet-matching: every facet with its pieces
    std::vector<Vector> hyperplanes;   // walls, chambers: the distinct facet hyperplanes (normals)
    // angular-sectors: one direction per sector; facet-matching, walls: the generic point;
    // chambers: one point per chamber. None lies on a facet hyperplane.
    std::vector<Vector> test_points;
    std::vector<std::vector<std::size_t>> covering; // the interiors containing each test point
    std::optional<std::size_t> failing;             // first test point covered != 1 times
};

FanResult check_fan(const Model& model, const Limits& limits);
// The facets with one cone that check_fan tries for a gap point (the checker's bound too).
inline constexpr std::size_t kMaxGapCandidates = 64;

struct DomainResult {
    bool function = true;                // S is defined and single-valued off the boundaries
    std::optional<Vector> point;         // otherwise: in no cone, or interior to two cones ...
    std::vector<std::size_t> interior_of; // ... the interiors containing it
    std::string reason;
};

// `fan` must come from check_fan; when it is proved S is a function.
DomainResult check_domain(const Model& model, const FanResult& fan);

// The extreme rays of C_i ∩ C_j (primitive, sorted); empty when the cones meet only in 0.
// `subsets` counts the constraint subsets examined.
std::vector<Vector> intersection_rays(const Model& model, std::size_t i, std::size_t j,
                                      std::size_t& subsets);
// The pairs i < j with Q_i != Q_j of cones having facets in one hyperplane, on opposite sides:
// when the cones tile R^c, every (c-1)-dimensional piece of common boundary is between such a
// pair, so P1 needs only these.
std::vector<std::pair<std::size_t, std::size_t>> wall_pairs(const Model& model);
// Constraint subsets intersection_rays examines for one pair: C(2c, c-1).
std::size_t intersection_subsets(std::size_t c);

// One point in every chamber of the central arrangement {x in R^d : n.x = 0}, n in `normals`
// (distinct canonical lines, see canonical_line), none on a hyperplane, one per chamber, in a
// deterministic order. `steps` counts the work; LimitExceeded beyond `max_steps`.
std::vector<Vector> chamber_points(const std::vector<Vector>& normals, std::size_t d,
                                   std::size_t max_steps, std::size_t& steps);

// The distinct facet hyperplanes of all cones, as sorted canonical normals.
std::vector<Vector> facet_hyperplanes(const Model& model);

} // namespace impactcert
