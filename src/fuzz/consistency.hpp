// SPDX-License-Identifier: GPL-3.0-or-later
// consistency.hpp -- consistency of a black-box impact map (SPEC section 8): `fuzz` with a system
// (--masses, --walls, --system) and no --law.
//
// Contract:
//   - The implementation maps u- to u+ (velocities) or gamma- to gamma+ (contact velocities).
//     Samples are a pure function of (seed, index); every input has at least one approaching
//     contact (gamma-_k < 0, decided exactly) and components that are 0 or have a magnitude in
//     [range_lo, range_hi].
//   - Every property is decided exactly on the returned doubles (as rationals: a finite double
//     is a dyadic rational; a non-finite output is its own violation), beyond the relative
//     tolerance R of proofs/README.md ("Consistency of black-box impact maps"): with |.| the
//     metric of the input space (M for ball velocities, H for contact velocities) and s = |x-|,
//       kinematic   gamma+_k < 0 and (gamma+_k)^2 > R^2 G_kk s^2 (normals k)
//       kinetic     Lambda_k < 0 and Lambda_k^2 > R^2 H_kk s^2, Lambda = H (gamma+ - gamma-) (normals)
//       friction_cone  |Lambda_T| - mu Lambda_N > R s (sqrt H_TT + mu sqrt H_NN)
//       coulomb     xi_T = gamma_T+ + e_T gamma_T- beyond R s sqrt G_TT on one side, and the friction
//                   beyond R s (sqrt H_TT + mu sqrt H_NN) from the bound that opposes that slip
//     A contact with a friction polygon (the system's facets a_j, vertices v_j): friction_cone
//     a_j . Lambda_T - mu Lambda_N beyond t (sqrt(a_j^T H_TT a_j) + mu sqrt H_NN), coulomb
//     (Lambda_T - mu Lambda_N v_j) . xi_T beyond its bound (consistency.cpp, polygon_friction).
//     With the circular cone (--cone circular: |Lambda_T| <= mu Lambda_N over the tangents of one
//     contact, Lambda_T = -mu Lambda_N xi_T / |xi_T| where it slips; proofs/README.md, "Consistency
//     with a circular friction cone"), per rough contact, with t = R s + A:
//       friction_cone  |Lambda_T| - mu Lambda_N > t (sqrt tr H_TT + mu sqrt H_NN)
//       coulomb     rho = Lambda_T . xi_T + mu Lambda_N |xi_T| > t |xi_T| (sqrt tr H_TT + mu sqrt H_NN)
//                   + 2 mu L t sqrt tr G_TT, or |Lambda_T ^ xi_T| > t |xi_T| sqrt tr H_TT + mu L t sqrt tr G_TT
//                   (L = max(Lambda_N + t sqrt H_NN, 0); both are 0 at every answer of Coulomb's law,
//                   sliding or sticking), decided exactly (P + Q sqrt(S) > 0)
//       momentum    (velocities) r = du - M^-1 W Lambda, |r|_M^2 > R^2 s^2: a velocity change
//                   outside the range of M^-1 W (lost or created momentum of a free chain)
//       energy      |x+|^2 > (1 + R)^2 s^2
//       nonexpansive (pairs, on request) |y_a - y_b| > |a - b| + R (|a| + |b|)
//       continuity   (close pairs, on request) |y_a - y_b| > 1024 |a - b| + R (|a| + |b|)
//     Every R s above is R s + A, A = sqrt(d trace X) 2^-1074, the allowance for underflow (an
//     output component may be one subnormal ulp off whatever its scale: proofs/README.md).
//     An output within R s + A of a consistent one never violates any of them (the README's lemma),
//     so every violation reported is one of the map itself, reproduced exactly by its replay.
//       restitution (frictionless, the restitution given) where exactly one normal contact k
//                   approaches and the single impact at k leaves every other contact not
//                   approaching -- every impact law then gives gamma+_k = -e_k gamma-_k --
//                   (gamma+_k + e_k gamma-_k)^2 > (R s + A)^2 G_kk;
//                   with friction (Newton's law with Coulomb friction): where an approaching
//                   contact k pushes, Lambda_N,k^2 > (R s + A)^2 H_kk, the same inequality
//       reference   (with --reference) |y - y*| > R s + A, y* the reference law's exact answer
//   - The probe: the input at rest is evaluated once before the samples; an answer that moves
//     (beyond the underflow allowance), a non-finite one, a crash, a hang or a malformed answer
//     there is the finding `at-rest`, with its replay.
//   - nondeterministic: an implementation run as a process that answers the same input
//     differently (fuzz_impl.hpp, ImplStatus::nondeterministic) is its own finding, with both
//     answers; the rest of that batch is not checked (its answers cannot be trusted to be in step).
//   - The summary has, per property, the count and the worst case (largest violation relative to
//     the sample's scale) with exact figures and a replay command.
#pragma once

#include "fuzz/fuzz_impl.hpp"
#include "fuzz/fuzz_reference.hpp"
#include "model/law.hpp"
#include "model/system.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::fuzz {

// friction_cone and coulomb: systems with friction only (SPEC section 9).
enum class Property : std::size_t {
    kinematic, kinetic, friction_cone, coulomb, restitution, momentum, energy, nonexpansive, continuity, at_rest,
    nondeterministic, non_finite, reference, count
};
inline constexpr std::size_t kProperties = static_cast<std::size_t>(Property::count);
const char* property_id(Property p);    // "kinematic", "kinetic", "momentum", "energy", ...
const char* property_title(Property p); // "negative contact velocity", "energy gain", ...

// The friction of a contact with several tangents: each tangent bounded by mu Lambda_N on its own
// (the box, ODE's dContactApprox1: the laws impactcert derives), or the circular cone (Jolt,
// MuJoCo's elliptic cone, Siconos's fc3d), checked by consistency fuzzing only.
enum class Cone { box, circular };

struct ConsistencyOptions {
    std::uint64_t seed = 1;
    std::uint64_t samples = 100000;
    double seconds = 0; // > 0: stop after this long
    unsigned jobs = 1;
    double max_rel_error = 1e-9;
    double range_lo = 1e-3, range_hi = 1e3;
    bool velocities = true;
    bool nonexpansive = false, continuity = false; // --require
    std::vector<Rational> restitution; // --restitution: one per normal contact; empty: not checked
    Cone cone = Cone::box;             // --cone
    const Model* reference = nullptr;  // --reference: the exact law the implementation means to compute
    std::size_t keep = 10;
    std::string replay_prefix; // "impactcert eval --float --masses ... --impl-cmd ..."
};

struct Finding {
    Property property = Property::energy;
    std::uint64_t index = 0;
    double score = 0;           // the violation relative to the scale (for ordering)
    std::string detail;         // the figures as decimals: "T- = 1, T+ = ~1.3333333333333333 (+33.3%)"
    // The same figures exactly (rational text), for --json: {"T-", "1"}, {"T+", "4/3"}.
    std::vector<std::pair<std::string, std::string>> exact;
    std::vector<double> input, input_b, output, output_b;
    std::string replay;
    // With a reference law (--reference; SPEC section 8, "Diagnosis"): 1 law-level (the exact law
    // breaks the property at this input too: more iterations will not help), 2 solver-level (it
    // does not: the answer is `off` the law's, relative to |x| in the metric), 0 not classified
    // (a pair property, or an input outside the law's cones).
    int level = 0;
    double off = 0;
    // kinetic, friction_cone, coulomb: at an input where momentum fails, so that Lambda is the
    // projection of a velocity change not made of contact impulses (a consequence of that finding).
    bool projection = false;
};

struct PropertyCount {
    std::uint64_t count = 0;
    std::optional<Finding> worst;
    std::uint64_t law = 0, solver = 0;   // by level, with a reference law
    std::uint64_t projections = 0;       // findings marked `projection`
    std::optional<Finding> worst_solver; // the solver-level finding furthest off the law
};

inline constexpr std::size_t kCoveragePieces = 2000;

struct ConsistencySummary {
    std::uint64_t samples = 0, pairs = 0, skipped = 0;
    double seconds = 0;
    // Coverage of the checked inputs: the patterns of approaching normal contacts met (of
    // 2^normals - 1; patterns 0 beyond 20 contacts), the decades of their largest components, and
    // with a reference law of at most kCoveragePieces pieces its pieces with an approaching
    // direction, and those whose cone held one (0 of 0 for a larger reference).
    std::uint64_t patterns_hit = 0, patterns = 0, reference_pieces_hit = 0, reference_pieces = 0, decades = 0;
    int decade_lo = 0, decade_hi = 0;
    std::array<PropertyCount, kProperties> properties;
    std::uint64_t crashed = 0, hung = 0, malformed = 0, refused = 0;
    std::vector<Finding> examples; // the first `keep` by sample index
    std::uint64_t violations() const;
};

// The exact checks of one sample (or pair), for the run and for replays.
class ConsistencyChecker {
  public:
    ConsistencyChecker(const Mechanics& m, bool velocities, double max_rel_error,
                       std::vector<Rational> restitution = {}, Cone cone = Cone::box);
    std::size_t dim() const;
    // Findings for one input/output (each property at most once).
    std::vector<Finding> check(const double* x, const double* y) const;
    // The same on exact vectors (no input/output doubles in the findings); with no_tolerance,
    // R = 0 and no underflow allowance: whether the exact answer y itself breaks a property.
    std::vector<Finding> check_exact(const Vector& x, const Vector& y, bool no_tolerance) const;
    // Findings for a pair (nonexpansive and/or continuity).
    std::vector<Finding> check_pair(const double* a, const double* ya, const double* b, const double* yb,
                                    bool nonexpansive, bool continuity) const;
    // True when some contact approaches at x (exact).
    bool approaching(const double* x) const;
    // Bit k set when normal contact k < 64 approaches at x (exact); gamma- into `gamma` if given.
    std::uint64_t approach_pattern(const double* x, Vector* gamma = nullptr) const;
    // The probe (SPEC section 8, "Diagnosis", at-rest): the answer y to the input at rest must be
    // at rest, |y| <= A (the underflow allowance); a finding otherwise (a non-finite y too).
    std::optional<Finding> at_rest(const double* y) const;
    // reference (with --reference): the answer y farther from the reference law's exact answer
    // at x than the tolerance, |y - y*| > R s + A in the metric of the input space (y* the law's
    // value nearest y where it has several); nothing where x lies in no cone of the law.
    std::optional<Finding> reference(const double* x, const double* y, const Model& law) const;
    // The same input x answered y1, then y2 (nondeterministic).
    Finding nondeterministic(const double* x, const double* y1, const std::vector<double>& y2) const;
    bool checks_restitution() const { return !e_.empty(); }

  private:
    const Mechanics& m_;
    bool velocities_;
    double R_;
    Rational A_; // the underflow allowance, sqrt(d trace X) 2^-1074
    std::vector<Rational> e_; // the restitution per normal contact (empty: not checked)
    Cone cone_;
    // The circular cone's friction_cone and coulomb findings (check_exact).
    void circular_friction(const Vector& lambda, const Vector& gm, const Vector& gp, const Rational& tol, const Rational& s2,
                           std::vector<Finding>& out) const;
    // The same for the contacts with a friction polygon (the system's facets).
    void polygon_friction(const Vector& lambda, const Vector& gm, const Vector& gp, const Rational& tol, const Rational& s2,
                          std::vector<Finding>& out) const;
};

ConsistencySummary run_consistency(const Mechanics& m, const ConsistencyOptions& options, const Implementation& impl,
                                   const std::function<void(std::uint64_t)>& progress);

// The sample of (seed, index): a point, and for pairs its partner (options say which). Even
// indices 2k take the k-th member of the structured families while they last (structured_input),
// the others are random.
void consistency_sample(const Mechanics& m, const ConsistencyOptions& options, std::uint64_t index, double* a,
                        double* b, bool& pair, bool& close);

// The k-th structured input of dimension d (k < structured_count(d)), in units s (a power of two
// in the run's --range): in order, one moving component (+-1), two (every pair, values +-1, +-2),
// ties (a run of consecutive components at 1, one other at -1), everything approaching (the
// decreasing ramps d-1..0 times 1 and 2, and 0..d-1 negated), then small integers (every vector
// of -3..3 on three consecutive components, the rest 0). Entries are small integers: the caller
// scales them (entries within -3..3 except the ramps). Proofs/README.md, "Consistency of black-box impact maps", says why these first.
std::size_t structured_count(std::size_t d);
void structured_input(std::size_t d, std::size_t k, std::vector<int>& out);

// A finite double as an exact rational; nothing for NaN or an infinity.
std::optional<Rational> exact_of(double x);

// --range LO..HI: 0 < LO <= HI, finite (InputError naming --range).
std::pair<double, double> parse_range(const std::string& text);

} // namespace impactcert::fuzz
