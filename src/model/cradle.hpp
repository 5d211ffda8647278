// SPDX-License-Identifier: GPL-3.0-or-later
// cradle.hpp -- the N-ball equal-mass elastic cradle law, S = sort (SPEC section 6,
// `impactcert derive cradle`), with its symmetries declared (proofs/README.md, "Symmetries").
//
// Contract: cradle_law(n, listing, symmetries) for 2 <= n <= 12 returns a valid law of n unit
// masses in a chain: one cone per ordering of the ball velocities (n! in all). The cone of the
// ordering u_a1 <= ... <= u_an is spanned by the contact velocities of the step velocities
// that are 1 on the k fastest balls (k = n-1, ..., 1), and Q sends each of these rays to its
// sorted step, i.e. to e_k. The symmetries are the swaps s1..s(n-1) of adjacent balls
// (P = the induced map on contact velocities, P' = I, since sort(pi u) = sort(u)) and the
// reversal r (u -> -reversed u: P = P' = the reversal of the contacts).
//   - Listing::representatives: one piece, "sorted" (the identity ordering), closed under the
//     symmetries by Model (pieces "sorted.s1", "sorted.s1.s2", ...); requires symmetries.
//   - Listing::all: every ordering, named "u1<=u2<=...<=un", in lexicographic order of the
//     ordering (the pieces of proofs/newton3 and proofs/newton4).
// Both declare the single impacts (the swap of balls k, k+1 is the two-ball impact at contact
// k with e = 1) and the classical outcomes, computed by sorting.
#pragma once

#include "model/law.hpp"

#include <cstddef>

namespace impactcert {

enum class CradleListing { representatives, all };

Law cradle_law(std::size_t n, CradleListing listing, bool symmetries);

} // namespace impactcert
