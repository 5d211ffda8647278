// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_report.hpp -- what a law-mode fuzz run reports, shared by `impactcert fuzz` and the
// library (impactcert::api::fuzz): the properties a law's proof licenses, the coverage line, the
// tolerance as its option, and the impactcert-fuzz/1 JSON report.
//
// Contract:
//   - law_facts(model, velocities): the fuzzer's dimension limits (InputError), then the
//     obligations that license each checked property, decided by verify without evidence.
//   - report_json: docs/formats.md's impactcert-fuzz/1 object for a finished run; `stderr` is
//     the implementation's collected standard error, when it is a process.
#pragma once

#include "base/json.hpp"
#include "fuzz/fuzz.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::fuzz {

struct LawFacts {
    bool continuous_tiling = false;
    Properties properties;
};
LawFacts law_facts(const Model& model, bool velocities);

std::string count_text(std::uint64_t n); // "12345", "1.2M"
// The coverage line (text, JSON and JUnit alike) and what the run did not test.
std::string coverage_text(const Summary& sum);
std::vector<std::string> untested(const Summary& sum, const Options& o);
std::string tolerance_text(const Options& o); // "--max-ulps 4", "--max-rel-error 1e-12", ...

Json report_json(const Summary& sum, const Options& options, const Properties& properties,
                 const std::string& law_name, const std::string& implementation, bool velocities,
                 const std::optional<StderrSummary>& stderr_summary);

} // namespace impactcert::fuzz
