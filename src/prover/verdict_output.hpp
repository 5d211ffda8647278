// SPDX-License-Identifier: GPL-3.0-or-later
// verdict_output.hpp -- the three ways a VerifyReport leaves the program.
//
// Contract:
//   - verdict_json: `impactcert-verdict/1` exactly as SPEC section 4; deterministic (no times).
//   - verdict_table: a human table, one line per obligation (claimed, verdict, checks, time),
//     each refutation's counterexample underneath, the gate verdict last.
//   - verdict_junit: JUnit XML, one testcase per obligation; a claimed refutation is a <failure>
//     carrying the counterexample, an unclaimed or skipped obligation is <skipped> with the
//     reason. CI systems (GitLab, Jenkins, GitHub test reporters) read this shape.
#pragma once

#include "prover/obligations.hpp"

#include <string>

namespace impactcert {

inline constexpr const char* kVerdictFormat = "impactcert-verdict/1";

Json verdict_json(const VerifyReport& report);
// The law's system as it is: "3 balls, 2 contacts" for a chain of balls; otherwise its
// velocities and contacts, and with friction its tangents ("2 velocities, 1 contact with 1
// friction tangent").
std::string system_words(const Model& model);
// The name of contact coordinate k (0-based) in a figure's text: gamma1.. without friction;
// gammaN1.., gammaT1.. with it (HTML/SVG: the letter as an entity, the index as a subscript).
std::string coordinate_svg(const Model& model, std::size_t k);
std::string verdict_table(const VerifyReport& report, const Model& model);
std::string verdict_table(const VerifyReport& report, std::size_t balls, std::size_t contacts, std::size_t pieces);
std::string verdict_junit(const VerifyReport& report);

// At most `limit` bytes of text, cut at a UTF-8 character boundary, with "..." after it when cut.
std::string shortened(const std::string& text, std::size_t limit);

// Escapes & < > " ' for XML/HTML text and attribute values; what XML 1.0 cannot hold (control
// characters but tab and newlines, U+FFFE, U+FFFF, encoded surrogates) becomes U+FFFD.
std::string xml_escape(const std::string& s);

} // namespace impactcert
