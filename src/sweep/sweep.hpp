// SPDX-License-Identifier: GPL-3.0-or-later
// sweep.hpp -- derive + verify over a grid of parameters (SPEC section 6, `impactcert sweep`).
//
// Contract: the masses and restitution lists may name parameters ("1,m,1", "e"); each named
// parameter takes the values of its --vary grid, NAME=LO..HI:COUNT[:log]: COUNT exact rationals
// from LO to HI, evenly spaced, or (log) the rationals k/1000 nearest below the geometric points
// LO (HI/LO)^(i/(COUNT-1)) found by exact bisection (endpoints exact). At most two parameters.
// Every grid point is derived (derive_sequential) and, when the law is finite, verified; the
// verdicts are data. run_sweep writes DIR/sweep.csv, DIR/sweep.json and DIR/sweep.html (one
// phase map per obligation, an SVG strip or grid, each cell's tooltip the exact point and
// witness). Bad specifications are InputError. `jobs` worker processes share the points;
// the output does not depend on their number.
// A system or scene file (--system, --scene) takes the place of the chain: its parameters are
// mu (every friction coefficient), muK (contact K's), e (every normal restitution), eK, or names
// used in --restitution; the law is sequential, newton or poisson (--law). With --thresholds and
// one parameter, every change of a verdict between neighbouring grid points is enclosed exactly
// (threshold.hpp).
#pragma once

#include "derive/derive.hpp"
#include "base/json.hpp"
#include "base/limits.hpp"
#include "prover/shard.hpp"

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace impactcert {

struct SweepParameter {
    std::string name;
    Rational lo, hi;
    std::size_t count = 0;
    bool log = false;
    std::vector<Rational> values; // filled by run_sweep once the inputs are validated (grid_values)
};

// A limit of the sweep exceeded before any work (exit 3, naming the option).
struct SweepLimit : std::runtime_error {
    using std::runtime_error::runtime_error;
};

enum class SweepLaw { sequential, newton, poisson };
SweepLaw parse_sweep_law(const std::string& text); // InputError naming --law
const char* to_string(SweepLaw law);

struct SweepSpec {
    std::vector<std::string> masses;      // items: numbers or parameter names (a chain)
    // ... or a system or scene file (--system/--scene): its text, where it came from, and the
    // system it describes (parse_system_text); masses is then empty.
    std::string system_text, system_origin;
    std::optional<System> system;
    SweepLaw law = SweepLaw::sequential;  // --law
    RestitutionOn on = RestitutionOn::all; // --restitution-on (newton)
    std::vector<std::string> restitution; // one item (every contact) or one per contact
    ImpactRule rule = ImpactRule::most_negative;
    std::size_t max_impacts = 100;
    std::size_t max_words = 2000; // --max-words: the order column's budget per point (derive.hpp)
    std::vector<SweepParameter> parameters; // one or two
    Limits limits;
    unsigned jobs = 1;
    std::size_t max_points = 100000; // --max-points: grid points in all
    std::optional<Shard> shard;      // --shard K/N: only the points k with k mod N = K - 1 (shard.hpp)
    bool thresholds = false;         // --thresholds (one parameter): threshold.hpp
    std::size_t threshold_digits = 10; // --threshold-digits: enclosures at most 10^-D wide
    std::function<void(const std::string&)> threshold_progress; // optional: each change as it is narrowed
};
// Whether the sweep's laws have friction (a system with friction declarations): their verdicts
// then include `coulomb` (obligation_ids(true)).
bool sweep_friction(const SweepSpec& spec);

// NAME=LO..HI:COUNT[:log]
// Syntax only (no grid yet): NAME=LO..HI:COUNT[:log].
SweepParameter parse_vary(const std::string& text);
// The grid: COUNT points from LO to HI, evenly spaced, or with :log geometrically spaced rationals
// with enough significant decimal digits to be distinct (at least 3), computed from the exponents
// (time linear in the digits of LO and HI, positive at any scale); the ends exact.
std::vector<Rational> grid_values(const SweepParameter& p);

// Writes the three files and figures/ (one standalone figure per map, SVG and PDF: figure.hpp)
// into dir; `progress(done, total)` now and then. With a shard: only the
// shard's points, into its part file (sweep_part_path), nothing else.
void run_sweep(SweepSpec spec, const std::string& dir,
               const std::function<void(std::size_t, std::size_t)>& progress);

// DIR/sweep.part-K-of-N.json: format impactcert-sweep-part/1, the shard, the run (every input
// that can change a verdict), the shard's points with their grid index, and the SHA-256 of the rest.
std::string sweep_part_path(const std::string& dir, const Shard& shard);
void write_sweep_part(const SweepSpec& spec, const std::vector<Json>& results, const std::vector<std::size_t>& mine,
                      const std::string& dir);
// sweep --merge: parts of one run (same run, same N), every shard exactly once, each holding
// exactly its points in order, at the grid's coordinates, intact (digest); then the three files
// as a single run writes them. InputError naming the part and the place otherwise.
// A merged grid larger than max_points is refused before any allocation (SweepLimit, exit 3).
void merge_sweep_parts(const std::vector<std::string>& paths, const std::string& dir, std::size_t max_points);
void write_sweep_outputs(const SweepSpec& spec, const std::vector<Json>& results, const std::string& dir);
void put_inputs(Json& j, const SweepSpec& spec); // masses ... parameters, as sweep.json writes them

} // namespace impactcert
