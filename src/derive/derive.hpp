// SPDX-License-Identifier: GPL-3.0-or-later
// derive.hpp -- impact laws derived from the mechanics (SPEC section 7).
//
// Contract: derive_sequential(options) computes, exactly, the sequential impact law of a system
// (a chain of n balls, with walls, or any system of section 8): starting from gamma-, while a contact approaches apply the two-ball impact at the
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

#include "model/law.hpp"
#include "model/system.hpp"

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace impactcert {

enum class ImpactRule { most_negative, left_first, right_first };

// A derivation whose numbers outgrow `max_bits` (bits of the numerator plus the denominator of
// one matrix entry) stops: exit 3, undecided, naming --max-bits. Words are bounded by
// --max-impacts; this bounds the size of what each impact multiplies (restitution 10^-1000 makes
// every entry thousands of digits longer per impact).
// Progress of a long derivation: the phase ("regions", "merge", "pieces") and a count, now and
// then (the CLI shows it on a terminal).
using DeriveProgress = std::function<void(const char* phase, std::size_t done, std::size_t total)>;

struct DeriveLimit : std::runtime_error {
    using std::runtime_error::runtime_error;
};
inline constexpr std::size_t kDefaultMaxBits = 65536;
// --max-memory of derive: megabytes of the regions and pieces a derivation holds (PPL's count of
// each polyhedron, the numbers of each map and ray); undecided (exit 3) beyond it, checked as
// they grow.
inline constexpr std::size_t kDefaultDeriveMemoryMb = 2048;
std::size_t entry_bits(const Matrix& m); // the largest numerator-plus-denominator bit length

// The system (a chain by its masses, or any system: system.hpp), then the process.
struct DeriveOptions : System {
    std::vector<Rational> restitution; // one per contact, each in [0, 1]
    ImpactRule rule = ImpactRule::most_negative;
    std::size_t max_impacts = 100;     // longest word allowed
    std::size_t max_bits = kDefaultMaxBits;
    std::size_t max_memory_mb = kDefaultDeriveMemoryMb;
    std::vector<OutcomeDecl> outcomes_override; // non-empty: declare these instead of the simulated ones
    bool polyhedral = false; // two contacts by PPL polyhedra too (the tests compare it with the sectors)
    DeriveProgress progress;  // optional
};

struct DeriveResult {
    std::optional<Law> law;            // the derived law, or ...
    std::optional<Vector> not_finite;  // ... a gamma- whose sequence exceeds max_impacts
    std::string word;                  // the first max_impacts + 1 impacts at not_finite
    std::size_t regions = 0;           // word regions found
    std::size_t max_word = 0;          // longest word
    std::size_t peak_bytes = 0;        // the most the regions and pieces held (--max-memory's count)
    std::size_t pieces = 0;            // the pieces written (a streamed derivation)
    // With friction: a gamma- where the written regions do not tile (a gap or an overlap of two
    // different maps: the fan's witness), and the fan's reason.
    std::optional<Vector> not_a_function;
    std::string not_a_function_reason;
};

// With friction (SPEC section 9) each impact is the one-contact Newton law with friction of the
// picked contact (derive_sequential_friction.cpp); the rules compare the normals only.
DeriveResult derive_sequential(const DeriveOptions& options);
// The same law streamed to a file (derive sequential --stream; derive_stream.cpp): the regions
// spilled to bucket files by their map as the words are explored (only the cells waiting are held),
// then each bucket's regions merged and triangulated and their pieces written, the identities
// after them. Memory grows with the exploration's frontier and the largest bucket, not with the
// law. The file is the in-memory law's text with the pieces and identities in another order
// (buckets, not words); whole or absent (OutputFile). The spill files live in a directory made
// beside `path` and are removed on every way out but a kill. Frictionless systems of three
// contacts or more (the others are small: derive_sequential). `pieces` in the result counts the
// pieces written; `law` stays empty.
inline constexpr std::size_t kStreamBuckets = 64;
DeriveResult derive_sequential_streamed(const DeriveOptions& options, const std::string& path,
                                        std::size_t buckets = kStreamBuckets);
DeriveResult derive_sequential_friction(const DeriveOptions& options, const Mechanics& mech);
// The same process in body velocities, without G: each step the one-contact law solved by its
// modes (simulate_newton_friction on the contact's columns). Nothing beyond `limit` impacts or
// where a step has no single answer.
std::optional<Vector> simulate_sequential_friction(const Mechanics& m, const std::vector<Rational>& restitution,
                                                   ImpactRule rule, Vector u, std::size_t limit);

// The contacts the sequential process applies at gamma- (exact simulation on contact velocities
// with G), at most `limit` of them; the second value is true when it stopped (gamma >= 0).
std::pair<std::vector<std::size_t>, bool> sequential_word(const System& system,
                                                          const std::vector<Rational>& restitution,
                                                          ImpactRule rule, const Vector& gamma,
                                                          std::size_t limit);

// The independent simulation in ball velocities: for a chain given by its masses, the two-ball
// collision formulas (momentum kept, relative velocity reversed with factor e); for any other
// system, the impulse of contact k applied through M^-1 and W's column k (never G or Q^(k)).
// The same rule on the contact velocities W^T u. Nothing when it needs more than `limit` impacts.
std::optional<Vector> simulate_balls(const System& system, const std::vector<Rational>& restitution,
                                     ImpactRule rule, Vector u, std::size_t limit);
std::optional<Vector> simulate_balls(const std::vector<Rational>& masses,
                                     const std::vector<Rational>& restitution, ImpactRule rule,
                                     Vector u, std::size_t limit);

ImpactRule parse_rule(const std::string& text); // InputError on an unknown rule
const char* to_string(ImpactRule rule);

// A word as the law names its pieces: "none", "121"; with more than nine contacts "1-12-3".
std::string word_text(const std::vector<std::size_t>& word, std::size_t contacts);

// ---- Order independence (`derive sequential --rule any`), derive_order.cpp.
//
// The sequential process with every admissible order: at each step any approaching contact
// (gamma_k < 0) may take the next impact. The admissible words are found by cutting cones
// (PPL, not necessarily closed, exact): the cell of a word w = k1..kL is the set of gamma- where
// (A_{i-1} gamma-)_{k_i} < 0 for every i (A_i the map of the first i letters), its final cell
// adds A_L gamma- >= 0. The result does not depend on the order exactly when every two final
// cells with different maps meet only where the maps agree; otherwise a point of their
// intersection where they differ is the witness (proofs/README.md, "Order independence").
struct OrderWitness {
    Vector gamma_minus;                      // primitive integer
    std::vector<std::size_t> word_a, word_b; // two admissible words (contacts from 0)
    Vector gamma_a, gamma_b;                 // their gamma+ (different)
};
struct OrderResult {
    std::optional<OrderWitness> witness;  // the result depends on the order, or ...
    std::optional<Vector> not_finite;     // ... an admissible order longer than max_impacts here
    std::vector<std::size_t> long_word;   // that order's first max_impacts + 1 letters
    std::size_t words = 0;                // admissible words with a non-empty final cell
    std::size_t max_word = 0;             // the longest of them
    std::size_t pairs = 0;                // pairs of final cells with different maps compared
    bool independent() const { return !witness && !not_finite; }
};
inline constexpr std::size_t kDefaultMaxWords = 20000;
// The work is bounded by max_words: at most that many cells are walked, and at most
// kPairsPerWord * max_words pairs of final cells are compared (each pair first by an exact
// separation test, then, if not separated, by intersection); beyond either, DeriveLimit naming
// --max-words (undecided). The rule of `options` is ignored.
inline constexpr std::size_t kPairsPerWord = 100;
OrderResult order_independence(const DeriveOptions& options, std::size_t max_words = kDefaultMaxWords);
// The witness re-checked by simulation (no cones): each word admissible at gamma- (its contact
// approaching at every step), ending with gamma >= 0 at the listed gamma+, and the two differ.
bool order_witness_holds(const System& system, const std::vector<Rational>& restitution, const OrderWitness& w);

// ---- The classical simultaneous laws (SPEC section 8), derive_classical.cpp.

enum class RestitutionOn { all, approaching };
RestitutionOn parse_restitution_on(const std::string& text); // InputError naming --restitution-on

struct ClassicalOptions : System {
    std::vector<Rational> restitution; // one per contact, each in [0, 1]
    RestitutionOn on = RestitutionOn::all; // Newton only
    std::size_t max_bits = kDefaultMaxBits;
    std::size_t max_memory_mb = kDefaultDeriveMemoryMb;
    std::vector<OutcomeDecl> outcomes_override;
};

// Contacts allowed, by kind: the regions are 2^c complementary cones (Newton, all), 4^c orthant and
// cone pairs (approaching: 37 s and 1.1 GB at c = 8), 4^c active-set pairs with many non-simplicial
// cells (Poisson: 33,426 pieces, 16 s, 0.5 GB at c = 6).
inline constexpr std::size_t kMaxNewtonContacts = 8, kMaxApproachingContacts = 7, kMaxPoissonContacts = 5;

// Pieces named by active sets: Newton "free" (no impulse), "J13" (contacts 1 and 3 carry an
// impulse), with --restitution-on approaching "J13/e1" (restitution applied at contact 1 only,
// where J13 alone means at all of J); Poisson "C13.E3" (compression set, expansion set).
Law derive_newton(const ClassicalOptions& options);
Law derive_poisson(const ClassicalOptions& options);

// ---- The Newton-type law with Coulomb friction (SPEC section 9), derive_friction.cpp.
//
// The system has friction (its tangents' mu and e_T are the system's; restitution: one per
// normal contact). Every contact mode (open; closed, and per tangent stick or slip either way)
// is a polyhedral cone in (gamma-, Lambda); the law is a function exactly when no two modes
// (a mode with itself included) admit one gamma- with two impulses (proofs/README.md, "Friction",
// Lemma U), decided on the generators of the pair cones; the regions of the modes with an
// invertible system then give the pieces, and their fan decides that every gamma- has a
// solution. Otherwise `not_a_function`: an exact gamma- with two solutions (their modes,
// impulses and gamma+), or one with none.
struct NotAFunction {
    Vector gamma_minus;
    bool none = false;             // no solution at gamma_minus (else two)
    std::string mode_a, mode_b;
    Vector lambda_a, lambda_b, gamma_a, gamma_b;
    // In body velocities: a u- with W^T u- = gamma_minus, and u+ = u- + M^-1 W Lambda for each
    // impulse (the Newton law on dependent columns; empty otherwise).
    Vector u_minus, u_a, u_b;
    bool frictionless = false; // the Newton law of frictionless dependent columns
};
struct FrictionResult {
    std::optional<Law> law;
    std::optional<NotAFunction> not_a_function;
    std::size_t modes = 0, pairs = 0, regions = 0;
};
// Modes enumerated at most by default (pairs compared: about its square over two); beyond
// max_modes, DeriveLimit naming --max-modes (undecided).
inline constexpr std::size_t kMaxFrictionModes = 400;
struct FrictionOptions : ClassicalOptions {
    DeriveProgress progress;
    std::size_t max_modes = kMaxFrictionModes;
};
FrictionResult derive_newton_friction(const FrictionOptions& options);
// Every solution at gamma- (distinct gamma+), by the modes with an invertible system (the
// modes that found them appended to modes_found, when given).
std::vector<Vector> newton_friction_solutions(const Mechanics& m, const std::vector<Rational>& restitution,
                                              RestitutionOn on, const Vector& gamma_minus,
                                              std::string* modes_found = nullptr);
// In body velocities, without G: u+ when exactly one mode with an invertible system gives a
// solution (distinct u+), else nothing.
std::optional<Vector> simulate_newton_friction(const Mechanics& m, const std::vector<Rational>& restitution,
                                               RestitutionOn on, const Vector& u_minus);

// Independent solutions in ball velocities: the LCPs solved by enumerating active sets over the
// rationals (M (u+ - u-) = W_J Lambda_J, W_J^T u+ = -E rho_J, Lambda_J >= 0, the rest
// non-negative). G positive definite: exactly one solution, whatever active set finds it.
Vector simulate_newton(const Mechanics& m, const std::vector<Rational>& restitution, RestitutionOn on,
                       const Vector& u_minus);
Vector simulate_poisson(const Mechanics& m, const std::vector<Rational>& restitution, const Vector& u_minus);

} // namespace impactcert
