// SPDX-License-Identifier: GPL-3.0-or-later
// report.hpp -- human-readable reports of a verification.
//
// Contract:
//   - report_markdown: fits a CI job summary (GitHub's $GITHUB_STEP_SUMMARY): the verdict, a
//     table of the obligations, every counterexample, and the law's pieces.
//   - report_html: one self-contained page (inline CSS and SVG, no script, no external
//     resource) with the same content and, for c = 2 and c = 3, the picture of the cones.
//   - cones_svg: for c = 2, an SVG redrawing Leine & Winandy's Figure 1(b): the cones in the
//     (gamma1-, gamma2-) plane, labelled, with their boundary rays, and beside it one small panel
//     per piece showing its image Q_i C_i. For c = 3 the cones on the unit sphere, in two
//     orthographic hemispheres, each labelled. With a report, every refuted obligation's
//     counterexample is drawn (a point, or a pair and its segment). Empty for other c. Valid XML.
//   - Names come from the law file and are untrusted: Markdown escapes them (one line, every
//     character that could end a table cell or start a heading, link, fence or HTML tag
//     backslash-escaped; fenced JSON writes ` < > & as \u escapes); HTML and SVG escape them
//     as XML (control characters become U+FFFD).
// Drawing coordinates are doubles (presentation only; no verdict depends on them).
#pragma once

#include "obligations.hpp"

#include <string>

namespace impactcert {

std::string cones_svg(const Model& model, const VerifyReport* report = nullptr);
std::string report_markdown(const Model& model, const VerifyReport& report);
std::string report_html(const Model& model, const VerifyReport& report);

} // namespace impactcert
