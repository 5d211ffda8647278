// SPDX-License-Identifier: GPL-3.0-or-later
// derive_planar.hpp -- internal to derive.cpp: the sequential process of a system with two
// contacts, by sectors of the plane (proofs/README.md, "Planar derivation").
//
// Contract: the same regions, words, merges, pieces and names as the general path (PPL
// polyhedra, derive_regions.hpp), computed with integers only:
//   - a region is a convex cone of the plane kept as a counter-clockwise chain of integer rays
//     (two rays: a pointed sector; three: a half-plane; or the whole plane); cutting it by a
//     half-plane a . x >= 0 keeps the rays where a . g >= 0 and adds the direction of the line
//     a . x = 0 where the sign changes between neighbours: no polyhedral library, no gcd;
//   - the map of a word is an integer matrix Z with a positive denominator D (M = Z / D), never
//     reduced while the process runs (the signs of the rows of Z are those of M); each impact
//     multiplies by the integer matrix d_k Q^(k). Reduced once per region, for the law;
//   - the limits are the general path's: --max-bits on the reduced entries (checked exactly
//     when a cheap bound exceeds it), --max-impacts with the same witness.
// Time: linear in the number of tree nodes times the size of their numbers (the law's size),
// where the general path pays for PPL's normalisations of every constraint system.
#pragma once

#include "derive/derive.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert::derive_detail {

struct PlanarRegion {
    std::vector<Vector> chain; // counter-clockwise rays (primitive); empty: the whole plane
    Matrix M;                  // gamma+ = M gamma- (reduced)
    std::vector<std::size_t> key;
    std::string name;
};

struct PlanarResult {
    std::vector<PlanarRegion> regions;     // in discovery order
    std::optional<std::vector<Vector>> too_long_cell; // a cell whose word exceeds max_impacts: its rays
    std::vector<std::size_t> too_long_word;          // that word (max_impacts + 1 letters)
};

// Qk: the two impact matrices; names: word -> piece name.
PlanarResult planar_regions(const std::vector<Matrix>& Qk, ImpactRule rule, std::size_t max_impacts,
                            std::size_t max_bits, const std::function<std::string(const std::vector<std::size_t>&)>& names);

struct PlanarPiece {
    std::string name;
    std::size_t region; // index into the merged regions
};

// Sorts by key, merges regions with one matrix whose union is convex (the first keeps its name),
// cuts a non-pointed region by the quadrants (NAME.1, ...), appends the pieces to law.pieces.
std::vector<PlanarPiece> add_planar_pieces(std::vector<PlanarRegion>& regions, Law& law);

} // namespace impactcert::derive_detail
