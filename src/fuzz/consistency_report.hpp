// SPDX-License-Identifier: GPL-3.0-or-later
// consistency_report.hpp -- a consistency run as `impactcert fuzz --masses|--system` and the
// library (impactcert::api::fuzz_consistency) set it up and report it: the options parsed into a
// plan (the reference law derived or read), the properties checked, and the impactcert-fuzz/1
// JSON report of consistency mode.
//
// Contract:
//   - plan_consistency: the command line's checks and messages, in its order (--require,
//     --range, [between], --restitution, --max-ulps, --max-rel-error, [between], the dimension,
//     --reference); a
//     reference by name is derived here (approaching, newton, poisson; with friction the Newton
//     law with Coulomb friction, refused where it is not a function), a file is read and must
//     have the system's M and W. The plan's options point at its own reference law.
//   - checked_properties: which properties the run checks (momentum only in ball velocities,
//     nondeterminism only for a separate process).
//   - consistency_report_json: docs/formats.md's consistency-mode object, given the run's summary,
//     the implementation's description, an effort sweep (null: none) and its standard error.
#pragma once

#include "base/json.hpp"
#include "fuzz/consistency.hpp"
#include "fuzz/fuzz_impl.hpp"
#include "model/law.hpp"
#include "model/system.hpp"
#include "prover/worst_case.hpp"

#include <array>
#include <functional>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::fuzz {

struct ConsistencyRequest {
    System system;
    std::function<System()> system_source;            // when set, the system is made by it, after --require and --range
    bool velocities = false;
    bool max_ulps_given = false;                      // refused: there is no exact law to count ulps against
    std::optional<double> max_rel_error;              // else 1e-9
    std::optional<std::vector<Rational>> restitution; // --restitution: one value, or one per contact
    std::optional<std::string> restitution_text;      // or as the option's text (parsed here, in order)
    std::string cone;                                 // --cone: "" or box (each tangent bounded), circular
    std::string reference;                            // "": none; approaching, newton, poisson, or a law file
    bool reference_given = false;                     // given, even as an empty text
    std::vector<std::string> require;                 // --require's items
    std::string range;                                // --range LO..HI ("": the default)
    std::uint64_t seed = 1, samples = 1000000;
    double seconds = 0;
    unsigned jobs = 1;
    std::size_t keep = 10;
};

struct ConsistencyPlan {
    System system;
    Mechanics mech;
    double R = 1e-9;
    std::string R_text;                // R as --max-rel-error prints it
    std::unique_ptr<Model> reference;  // --reference
    std::string reference_name;        // as the report names it
    ConsistencyOptions options;        // options.reference is reference.get()
};

// `between` (optional) is called after the options (--require, --range) and after the tolerance
// (--restitution, --max-ulps, --max-rel-error): the command line checks its own options there, so
// that its messages come in the order they always came.
enum class PlanStage { options, tolerance };
ConsistencyPlan plan_consistency(const ConsistencyRequest& request,
                                 const std::function<void(PlanStage)>& between = {});

std::array<bool, kProperties> checked_properties(const ConsistencyPlan& plan, bool nondeterminism);

Json finding_json(const Finding& f);
// The coverage line (text, JSON and JUnit alike), and what the checked inputs never had.
std::string coverage_text(const ConsistencySummary& sum);
std::vector<std::string> coverage_gaps(const ConsistencySummary& sum);
// With a reference law and energy gains found: its exact sup T+/T- (laws of at most 14 contacts
// and 20,000 faces, frictionless), else nothing.
std::optional<LawBound> reference_supremum(const ConsistencySummary& sum, const ConsistencyPlan& plan);

Json consistency_report_json(const ConsistencySummary& sum, const ConsistencyPlan& plan, const std::string& implementation,
                             const std::array<bool, kProperties>& checked, const std::optional<LawBound>& reference_sup,
                             const Json& effort, const std::optional<StderrSummary>& stderr_summary);

} // namespace impactcert::fuzz
