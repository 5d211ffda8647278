// SPDX-License-Identifier: GPL-3.0-or-later
// derive_regions.hpp -- internal to the derivations (derive.cpp, derive_classical.cpp): from
// polyhedral regions with one linear map each to the pieces of a law file.
//
// Contract:
//   - A Region is a polyhedral cone (PPL, exact) with the matrix of the map on it, a sort key
//     (the word of the sequential process, the active sets of a classical law) and a name.
//   - add_region_pieces: regions with one matrix whose union is convex are merged (the first by
//     key keeps its name); a region that is not pointed is cut by the orthants, then every part
//     is triangulated (pulling triangulation of its extreme rays over its facets); a region of
//     one simplicial cone keeps its name, parts are named NAME.1, NAME.2, ... Returns, per
//     piece written, the region it came from (index into the sorted, merged list).
//   - The PPL rounding guard must be held while any of this runs (PplScope).
#pragma once

#include "derive/derive.hpp"
#include "model/law.hpp"

#define PPL_NO_AUTOMATIC_INITIALIZATION
#include <ppl.hh>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::derive_detail {

namespace PPL = Parma_Polyhedra_Library;

struct Region {
    PPL::C_Polyhedron cone;
    Matrix M;                      // gamma+ = M gamma- on the region
    std::vector<std::size_t> key;  // sort key (the word)
    std::string name;
};

// The memory budget of a derivation (--max-memory): the bytes of the regions and pieces it holds
// (PPL's count of a polyhedron, the numbers of a map, a word, a piece's rays), added as they are
// made and removed as they are dropped; DeriveLimit naming --max-memory as soon as they exceed it.
class RegionBudget {
  public:
    explicit RegionBudget(std::size_t max_mb);
    static std::size_t bytes_of(const Region& r);
    void add(std::size_t bytes, const char* what);
    void remove(std::size_t bytes) { held_ -= std::min(held_, bytes); }
    std::size_t held() const { return held_; }
    std::size_t peak() const { return peak_; }
  private:
    std::size_t max_bytes_, held_ = 0, peak_ = 0;
};

// PPL initialised once per process, and its rounding mode set while an instance lives.
class PplScope {
  public:
    PplScope();
    ~PplScope();
    PplScope(const PplScope&) = delete;
    PplScope& operator=(const PplScope&) = delete;
};

// The linear form a . x with integer coefficients (a positive multiple of a).
PPL::Linear_Expression form(const Vector& a);
// A generator's integer coefficients on the c space dimensions (its divisor not applied).
Vector generator_vector(const PPL::Generator& g, std::size_t c);
// A constraint's integer coefficients a (it reads a . x >= 0, > 0 or = 0: every cell here is a
// cone), or nothing for a tautology (PPL's 1 > 0 of a not-necessarily-closed polyhedron).
std::optional<Vector> constraint_vector(const PPL::Constraint& k, std::size_t c);
// The constraint a . x >= 0 (a != 0).
PPL::Constraint nonneg(const Vector& a);
// A region: the intersection of {a . x >= 0} for the given a (zero vectors are ignored).
PPL::C_Polyhedron cone_of(std::size_t c, const std::vector<Vector>& constraints);
bool full_dimensional(const PPL::C_Polyhedron& p, std::size_t c);
// A point of the interior direction: the sum of the extreme rays.
Vector interior_point(const PPL::C_Polyhedron& p, std::size_t c);

struct WrittenPiece {
    std::string name;
    std::size_t region; // index into the merged regions
};

// Regions with one matrix whose interiors overlap (a degenerate LCP: restitution 0 makes several
// active sets give the same cell and map) become disjoint: in key order, a region inside an
// earlier one of the same matrix is dropped, and one that overlaps it partly is replaced by the
// full-dimensional parts of its difference, R \ A = union_i (R ∩ {a_i <= 0} ∩ {a_j >= 0, j < i})
// over A's facet constraints a_i >= 0. The union and the map on it are unchanged.
void remove_overlaps(std::vector<Region>& regions, std::size_t c);

// The regions of one map (sorted by key) merged where the union of two is convex: the first pair
// (a, b), a < b, that merges is merged into a's place, until none does (proofs/README.md,
// "Derivation", merging). The merged region keeps the first key and name.
void merge_group(std::vector<Region>& group, std::size_t c);
// A region's pieces: cut by the orthants first when it is not pointed, then triangulated; one
// simplicial cone keeps the region's name, parts are NAME.1, NAME.2, ...
std::vector<PieceDecl> region_pieces(const Region& region, std::size_t c);
// The text that tells maps apart (their rows, canonical).
std::string map_key(const Matrix& M);

// Sorts by key, merges, triangulates; appends pieces to law.pieces. `regions` is replaced by
// the merged list (indices of WrittenPiece::region refer to it).
// `budget`, when given, holds the regions already; the pieces written are added to it.
// `merge` false: no region is merged, so that every piece lies in the region of one key.
std::vector<WrittenPiece> add_region_pieces(std::vector<Region>& regions, std::size_t c, Law& law,
                                           const DeriveProgress& progress = {}, RegionBudget* budget = nullptr,
                                           bool merge = true);

// The laws with friction (derive_friction.cpp, derive_sequential_friction.cpp): whether the
// pieces written tile R^d, decided by the `fan` of the law; a point where they do not (the fan's
// witness, with its reason), or nothing. DeriveLimit when the fan is undecided.
struct TilingDefect {
    Vector gamma;
    std::string reason;
};
std::optional<TilingDefect> tiling_defect(const Law& law);
// The outcomes u- = -e_i and +e_i of every coordinate, each where `simulate` gives one u+.
std::vector<OutcomeDecl> unit_velocity_outcomes(std::size_t n,
                                                const std::function<std::optional<Vector>(const Vector&)>& simulate);

// Shared by the derivations. DeriveLimit when an entry of m has more than max_bits bits.
void check_bits(const Matrix& m, std::size_t max_bits, const std::string& what);
std::string list_text(const std::vector<Rational>& xs); // "1,2,1/2"
std::string system_text(const System& s);              // for descriptions
// The classical experiments of a cradle (one ball in from the left, ...) in n ball velocities.
std::vector<OutcomeDecl> classical_experiments(std::size_t n);
// Declares `override_outcomes` when given, else the experiments whose simulated u+ every piece
// containing gamma- reproduces (simulate: u- -> u+, or nothing).
void declare_outcomes(Law& law, const std::vector<OutcomeDecl>& override_outcomes,
                      const std::function<std::optional<Vector>(const Vector&)>& simulate);
// The same, one piece at a time (a streamed derivation holds no list of pieces).
class OutcomeTracker {
  public:
    OutcomeTracker(const Law& head, const std::function<std::optional<Vector>(const Vector&)>& simulate);
    void add(const PieceDecl& piece);
    std::vector<OutcomeDecl> outcomes() const;

  private:
    struct Track {
        OutcomeDecl experiment; // u_plus: the simulation's
        Vector gamma;           // W^T u-
        bool agree = true, inside_any = false;
    };
    Mechanics mech_;
    std::vector<Track> tracks_;
};

// ---- The sequential law (derive.cpp), shared with its streamed form (derive_stream.cpp).

// InputError unless the process is valid: one restitution in [0, 1] per contact, --max-impacts >= 1.
void validate(const DeriveOptions& options, std::size_t contacts);
// The law's head: name, description, system (no pieces, no declarations).
Law law_header(const DeriveOptions& options, std::size_t n);
// The words of the sequential process, depth first: each final region (key = word, name, map,
// cone) handed to `found`, or the first gamma- whose word exceeds max_impacts (with that word).
// The cells waiting are counted against `budget`; what `found` keeps is the caller's to count.
struct Explored {
    std::optional<Vector> not_finite;
    std::string word;
    std::size_t regions = 0, max_word = 0;
};
Explored explore_words(const DeriveOptions& options, const std::vector<Matrix>& Qk, RegionBudget& budget,
                       const std::function<void(Region&&)>& found);
// Declarations from the pieces: the single impacts (contact -> a piece of its one-letter word),
// the factorisation of a piece of a word of two letters or more (nothing when a letter has no
// piece), and the simulation the outcomes are declared by.
std::vector<SingleImpactDecl> single_impacts_of(const std::map<std::size_t, std::string>& letter_piece,
                                                const std::vector<Rational>& restitution);
std::optional<IdentityDecl> identity_of(const std::string& name, const std::vector<std::size_t>& word,
                                        const std::map<std::size_t, std::string>& letter_piece);
std::function<std::optional<Vector>(const Vector&)> outcome_simulation(const DeriveOptions& options);
// Stable sort by key (shorter words first, then lexicographic).
void sort_by_key(std::vector<Region>& regions);

} // namespace impactcert::derive_detail
