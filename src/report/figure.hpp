// SPDX-License-Identifier: GPL-3.0-or-later
// figure.hpp -- standalone figures for papers: one SVG per drawing, with its title and legend,
// and the same figure as PDF.
//
// Contract:
//   - standalone_figure: wraps a drawing (an SVG document whose first tag has width and height in
//     pixels) into one SVG document with a white background, a title, an optional caption line
//     wrapped to the drawing's width, and a legend row (squares, dots, lines), sized to hold all
//     of them and scalable (viewBox). An empty title and caption give the drawing and its legend
//     alone (report --bare-figures: a paper sets title and caption in LaTeX). The title is cut at 120 bytes and legend labels at 40
//     ("..."), whatever the names in the law file.
//     Every text is escaped as XML. The result is valid XML.
//   - write_figure(stem, svg): writes STEM.svg and, when `rsvg-convert` (Debian: librsvg2-bin) is
//     found on PATH, STEM.pdf converted from it (vector, one page of the figure's size). Both are
//     whole or absent (output_file.hpp): the PDF is read from the converter's standard output
//     into a temporary file renamed at the end, and is not written when the converter fails,
//     writes more than 256 MiB or runs for more than converter_seconds (it is then killed, with
//     everything in its process group). Returns the paths written. Without the converter it returns the
//     SVG alone and pdf_unavailable_reason() says why (the caller prints it once, as a note).
//     A converter that fails is an InputError naming the figure.
#pragma once

#include <string>
#include <vector>

namespace impactcert {

struct LegendItem {
    enum class Shape { square, dot, line, dashed };
    std::string colour; // "#009E73": a square, a line or a dot (with a black rim) of it
    std::string label;
    Shape shape = Shape::square;
};

std::string standalone_figure(const std::string& title, const std::string& caption, const std::string& drawing,
                              const std::vector<LegendItem>& legend);

std::vector<std::string> write_figure(const std::string& stem, const std::string& svg, int converter_seconds = 120);

// Empty when PDFs can be written; else one sentence for a note on stderr.
std::string pdf_unavailable_reason();

} // namespace impactcert
