// SPDX-License-Identifier: GPL-3.0-or-later
// tiling.hpp -- the checker's own decisions about sets of simplicial cones (proofs/README.md,
// "fan"): the chambers of a central hyperplane arrangement (counted, and enumerated by the
// prover's deletion-restriction rule), the walls recursion that decides a tiling, and the
// planar orientation tests.
//
// Contract: exact (linalg.hpp); canonical_chamber_points is bounded by `budget` (rejects) and
// by --max-chambers (ChamberSteps: Undecided), counted as the prover counts its steps.
#pragma once

#include "linalg.hpp"
#include "reading.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace impactcert_check::detail {

// The number of chambers of the arrangement of `normals` in R^d; more than `cap` once over it.
std::size_t count_chambers(const std::vector<Vec>& normals, std::size_t d, std::size_t cap);

// The prover's count of chamber-enumeration steps (src/prover/fan.cpp, charge): one per call and one
// per point of a restriction; more than --max-chambers of them and the prover gives up.
struct ChamberSteps {
    std::size_t done, max;
    std::string path;
    void charge() {
        if (++done > max)
            undecided("--max-chambers", path,
                      "the facet arrangement needs more than " + std::to_string(max) + " chamber-enumeration steps");
    }
};

// One point per chamber, in the prover's canonical order (tiling.cpp).
std::vector<Vec> canonical_chamber_points(const std::vector<Vec>& normals, std::size_t d, std::size_t& budget,
                                          ChamberSteps& steps);

// A cone of a signed family: its rays and integer weight.
struct WCone {
    std::vector<Vec> rays;
    long w = 0;
};

// The first point (1, t, t^2, ...) of the moment curve, t = 1, 2, ..., off every hyperplane.
Vec first_generic(const std::vector<Vec>& normals, std::size_t d);

// Whether sum w_i [x in int C_i] = target at every generic x of R^d (tiling.cpp).
bool walls_balance(const std::vector<WCone>& in, std::size_t d, long target);

// c = 2: the sign of det(a, b), and whether x comes before y counter-clockwise from a.
int sign_det2(const Vec& a, const Vec& b);
bool ccw_before(const Vec& a, const Vec& x, const Vec& y);

} // namespace impactcert_check::detail
