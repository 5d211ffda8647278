// derive.hpp -- impact laws derived from the mechanics (SPEC section 7).
//
// Contract: derive_sequential(options) computes, exactly, the sequential impact law of a chain of
// n balls: starting from gamma-, while a contact approaches apply the two-ball impact at the
// contact the rule picks, Q^(k)(e_k) = I - (1+e_k) G e_k e_k^T / G_kk. The map is linear on
// each region where the word (the contacts in order of application) is fixed; every region is a
// polyhedral cone, the conjunction of the sign conditions met along the word. The regions are
// computed with the Parma Polyhedra Library (exact, GMP); a region that is not a simplicial cone
// is triangulated (a pulling triangulation of its extreme rays over its facets). The result is
// a valid impactcert-law/1 with pieces named by their words (`none`, `1`, `21`, `121`;
// triangulation parts `121.1`, `121.2`), the single impacts (one-letter words), the
// factorisations (each piece the product of its letters, first impact rightmost) and the
// classical outcomes computed by a separate simulation in ball velocities (two-ball collision
// formulas with the masses, no G), declared only where every piece containing gamma- agrees.
// Bad parameters are an InputError; a region whose word would exceed max_impacts gives a
// NotFinite result with an exact gamma- inside it (its sequence is longer than the bound).
#pragma once

#include "law.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

enum class ImpactRule { most_negative, left_first, right_first };

struct DeriveOptions {
    std::vector<Rational> masses;      // n >= 2, all > 0
    std::vector<Rational> restitution; // one per contact (c = n-1), each in [0, 1]
    ImpactRule rule = ImpactRule::most_negative;
    std::size_t max_impacts = 100;     // longest word allowed
};

struct DeriveResult {
    std::optional<Law> law;            // the derived law, or ...
    std::optional<Vector> not_finite;  // ... a gamma- whose sequence exceeds max_impacts
    std::string word;                  // the first max_impacts + 1 impacts at not_finite
    std::size_t regions = 0;           // word regions found
    std::size_t max_word = 0;          // longest word
};

DeriveResult derive_sequential(const DeriveOptions& options);

// The contacts the sequential process applies at gamma- (exact simulation on contact velocities
// with G), at most `limit` of them; the second value is true when it stopped (gamma >= 0).
std::pair<std::vector<std::size_t>, bool> sequential_word(const std::vector<Rational>& masses,
                                                          const std::vector<Rational>& restitution,
                                                          ImpactRule rule, const Vector& gamma,
                                                          std::size_t limit);

// The independent simulation in ball velocities: two-ball collision formulas with the masses,
// the same rule on the contact velocities u_{k+1} - u_k. Nothing when it needs more than
// `limit` impacts.
std::optional<Vector> simulate_balls(const std::vector<Rational>& masses,
                                     const std::vector<Rational>& restitution, ImpactRule rule,
                                     Vector u, std::size_t limit);

ImpactRule parse_rule(const std::string& text); // InputError on an unknown rule
const char* to_string(ImpactRule rule);

} // namespace impactcert
