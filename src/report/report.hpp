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

#include "prover/obligations.hpp"
#include "prover/worst_case.hpp"

#include <string>
#include <vector>

namespace impactcert {

std::string cones_svg(const Model& model, const VerifyReport* report = nullptr);

// S along the unit circle of the metric H (report_planes.cpp), drawn so that this circle is round:
//   - unit_circle_svg (c = 2): the cones as light sectors, the circle |gamma-|_H = 1 dashed and its
//     image S(gamma-) as a curve coloured by cone (outside the circle T+ > T-). Empty otherwise.
//   - planes_svg (c >= 3): small multiples, one panel per plane of two contacts i < j (the other
//     components 0): a ring of the cones met in each direction of the plane, found exactly from
//     R^-1 (grey where no cone meets it in a sector), and the curve |S(gamma-)|_H / |gamma-|_H
//     along the unit circle of H restricted to the plane (dashed: 1). Empty beyond 10 contacts or
//     2 * 10^7 sign tests, with the reason in *why_not.
std::string unit_circle_svg(const Model& model);
std::string planes_svg(const Model& model, std::string* why_not = nullptr);
bool planes_svg_fits(const Model& model, std::string* why_not = nullptr); // planes_svg draws

// Laws with friction: the key to the contact modes in their pieces' names.
inline constexpr const char* kModeKey =
    "Piece names give the contact modes, one token per contact: o open, c closed (frictionless), and per tangent "
    "s stick, f slip forward, b slip backward (docs/derive.md, \"Friction\").";
inline constexpr const char* kUnitCircleCaption =
    "S along the unit circle of the metric H (dashed: ‖γ⁻‖_H = 1, unit pre-impact kinetic energy of the "
    "contacts). Left: the image S(γ⁻), coloured by the cone of γ⁻. Right: the ratio ‖S(γ⁻)‖_H / ‖γ⁻‖_H in the "
    "direction of γ⁻; outside the dashed circle T⁺ > T⁻. Shaded: the cones; grey lines: the contact axes, all "
    "drawn in the metric H.";
inline constexpr const char* kPlanesCaption =
    "The law on each plane of two contacts (the other components 0), drawn in the metric H restricted to the "
    "plane. Ring: the cone met in each direction (grey: no cone meets the plane there in a sector). Curve: "
    "‖S(γ⁻)‖_H / ‖γ⁻‖_H along the unit circle; dashed: 1, outside it T⁺ > T⁻.";

// LaTeX tables for papers (report_tex.cpp): the pieces (rays and Q, exact fractions; longtable
// beyond 40 pieces) and the obligations with their verdicts. Names are escaped for \texttt.
std::string law_latex(const Model& model);
std::string verdicts_latex(const Model& model, const VerifyReport& report, const WorstCase* worst = nullptr);

// Standalone figures into dir (created; figure.hpp): cones (c = 2, 3), unit-circle (c = 2) and
// planes (when planes_svg draws), each STEM.svg and, with rsvg-convert, STEM.pdf, with a title,
// a caption and a legend (bare: the legend alone, without title and caption). Returns the paths
// written; none when there is no picture.
std::vector<std::string> write_report_figures(const Model& model, const VerifyReport& report, const std::string& dir,
                                              bool bare = false);


inline constexpr const char* kConesCaption2 =
    "The cones in the plane of pre-impact contact velocities (compare Leine & Winandy, Fig. 1(b)), drawn in the "
    "metric H = G^-1, where an elastic impact is a reflection; black lines: boundary rays; black dots: "
    "counterexamples. Right: each cone's image under its matrix. Below: the cones unrolled by angle.";
inline constexpr const char* kConesCaption3 =
    "The cones on the unit sphere of pre-impact contact velocities, in two orthographic hemispheres (seen from "
    "(1,1,1) and from (-1,-1,-1)); edges are great-circle arcs. Each cone is numbered where it shows best (inside "
    "it, or by a leader line) and named in the key (laws of up to 120 cones); neighbouring cones have different colours; black dots: "
    "counterexamples.";
// With `worst` (report --worst-case): the law's exact worst case too.
std::string report_markdown(const Model& model, const VerifyReport& report, const WorstCase* worst = nullptr);
std::string report_html(const Model& model, const VerifyReport& report, const WorstCase* worst = nullptr);
// The worst case in words, one line per bound ("sup T+/T- = 4/3, attained in piece ... at ...").
std::vector<std::string> worst_case_words(const WorstCase& w, const Model& model);

} // namespace impactcert
