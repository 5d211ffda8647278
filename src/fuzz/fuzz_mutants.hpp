// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_mutants.hpp -- the gate's own strength: the configured law-mode fuzz run against planted
// bugs (mutants) of the law's plain double evaluation (`impactcert fuzz --mutants N`).
//
// Contract:
//   - The plain evaluation (Mutation::Op::none, the control) is what a careful engine writes for
//     a cone-wise linear law: `if (gamma in cone 0) ... else if (gamma in cone 1) ... else` the
//     last piece, y = Q_p gamma (each row summed left to right). A cone test is t_k >= -a_k with
//     t = R_p^-1 gamma in double and a_k = 2^-46 sum_j |R_p^-1(k,j) gamma_j| + 2^-1069, more than
//     the rounding of t_k, so rounding never pushes a point out of its own cone (it may accept a
//     point a relative 2^-46 outside, where a continuous law's pieces agree to that order).
//     Contact velocities only.
//   - A mutation changes one thing of that program, modelled on bugs found in real solvers:
//     dead-zone (|gamma_i| < tau treated as 0), slow-contact (|gamma_i| < r |gamma|_inf treated
//     as 0), facet-flip (one cone test reversed), facet-drop (one cone test missing: a missing
//     clamp), sign (one entry of one Q_p negated), formula (piece p computes piece q's formula),
//     separating (restitution 1/2 applied to contact i when it separates), float32 (every
//     operation in single precision), naive-norm (gamma scaled by sqrt(sum gamma_i^2) and back:
//     overflow and underflow), flush-subnormal (subnormal inputs and outputs read as 0) and
//     constant-digits (every entry of every Q_p rounded to 6 significant digits).
//   - Equivalent mutants are recognised only when the mutated program computes, for every finite
//     input, the same doubles as the control up to the sign of a zero (a zero entry negated, a
//     formula swapped for an identical one, constants that already have 6 digits). They are
//     listed and never run or counted.
//   - A witness of a mutant is an input where the mutant's answer is outside the gate's tolerance
//     and the control's is inside, both decided by a second route (exact_violation:
//     Model::values_at on rationals and the tolerance's definition in rationals, not the
//     fuzzer's reference).
//   - A kill is the gate failing the mutant (Summary::fails) with a confirmed witness among its
//     examples of the class that failed it, evaluated again. A survivor is searched for a witness
//     beyond the gate's sampling (the law's probes at scales 2^-1070 .. 2^1020, moderate ones
//     first, and with one slow component). The kill rate is killed / (killed + survivors with a
//     witness); survivors without one, and those whose only witnesses are extreme inputs a gate
//     with --allow extreme accepts, are listed apart.
#pragma once

#include "fuzz/fuzz.hpp"

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace impactcert::fuzz {

struct Mutation {
    enum class Op {
        none, dead_zone, slow_contact, facet_flip, facet_drop, sign, formula, separating,
        float32, naive_norm, flush_subnormal, constant_digits
    };
    Op op = Op::none;
    std::size_t p = 0, q = 0, i = 0, j = 0; // piece, other piece or row, entry
    double param = 0;                       // tau or r
    std::string id() const;                 // e.g. "facet-flip:3:1" (--mutant ID)
    std::string what(const Model& model) const;
};

// --mutant ID, checked against the law (piece, row and entry indices in range). Throws InputError.
Mutation parse_mutation(std::string_view id, const Model& model);

struct MutantSite {
    Mutation mutation;
    std::string equivalent; // non-empty: why the mutated program computes the control's doubles
};

// Every mutation of this law, grouped by operator, each group in a seeded order.
std::vector<MutantSite> enumerate_mutants(const Model& model, std::uint64_t seed);
// n of them, one operator after another in turn (every operator before any is taken twice).
std::vector<MutantSite> select_mutants(const std::vector<MutantSite>& all, std::size_t n);

// The plain evaluation with one mutation (Op::none: the control), contact velocities.
std::unique_ptr<Implementation> plain_law(const Model& model, const Mutation& mutation);

// Whether y is outside the options' tolerance (--max-ulps or --max-rel-error) around every value
// of the law at x, decided on rationals from Model::values_at (the second route). `what` gets a
// line saying why. A point in no cone is no violation.
// With `velocities`, x and y are ball velocities u-, u+ (the values are the law's u+, the metric M).
bool exact_violation(const Model& model, const Options& options, const double* x, const double* y,
                     std::string* what = nullptr, bool velocities = false);

struct MutantResult {
    MutantSite site;
    enum class Status { killed, survived, equivalent, unconfirmed } status = Status::survived;
    std::uint64_t samples = 0;      // the gate's samples on this mutant
    double seconds = 0;
    std::uint64_t kill_index = 0;   // the sample of the witness (killed)
    std::string kill_kind;          // its generator
    std::vector<double> witness, output; // a confirmed witness (killed, or survived: found by search)
    bool witness_extreme = false;   // the witness is at an extreme input (extreme_input)
    std::string witness_what;       // exact_violation's line
};

struct MutantsReport {
    Summary control;
    std::vector<MutantResult> mutants;
    std::size_t enumerated = 0; // mutations of this law in all
    std::size_t killed = 0, survived_witness = 0, survived_unknown = 0, equivalent = 0, unconfirmed = 0,
                extreme_only = 0; // survivors whose only witnesses are extreme (allowed by the gate)
    bool measured() const { return killed + survived_witness > 0; } // some mutant shown different
    double kill_rate() const {
        const std::size_t d = killed + survived_witness;
        return d ? static_cast<double>(killed) / static_cast<double>(d) : 0.0;
    }
};

// progress(done, total) after each mutant.
MutantsReport run_mutants(const Options& options, const LawReference& reference, const Properties& properties,
                          std::size_t count, const std::function<void(std::size_t, std::size_t)>& progress);

} // namespace impactcert::fuzz
