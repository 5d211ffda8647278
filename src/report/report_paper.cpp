// SPDX-License-Identifier: GPL-3.0-or-later
// report_paper.cpp -- what a report gives a paper: LaTeX tables of a law and of its verdicts, and
// standalone figures (SVG and PDF).
#include "report/report.hpp"

#include "report/figure.hpp"
#include "exact/rational.hpp"
#include "report/report_draw.hpp"

#include <cstdio>
#include <filesystem>

namespace impactcert {
namespace {

constexpr std::size_t kTabularRows = 40; // more pieces: longtable, which breaks across pages

// Text for \texttt{} and comments: LaTeX's special characters escaped, control characters '?',
// and every character beyond ASCII as its code point, "[U+03B3]" (pdflatex stops at a Unicode
// character its fonts do not set up; the table must compile whatever the names).
std::string tex_escape(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const char ch = s[i];
        const auto u = static_cast<unsigned char>(ch);
        if (u >= 0x80) {
            // A UTF-8 sequence (nlohmann-json hands over valid UTF-8): its code point.
            const std::size_t n = u >= 0xF0 ? 4 : u >= 0xE0 ? 3 : u >= 0xC0 ? 2 : 1;
            unsigned long cp = n == 4 ? (u & 0x07u) : n == 3 ? (u & 0x0Fu) : n == 2 ? (u & 0x1Fu) : u;
            for (std::size_t k = 1; k < n && i + k < s.size(); ++k)
                cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3Fu);
            i += n - 1;
            char buf[24];
            std::snprintf(buf, sizeof buf, "[U+%04lX]", cp);
            out += buf;
            continue;
        }
        switch (ch) {
        case '\\': out += "\\textbackslash{}"; break;
        case '{': out += "\\{"; break;
        case '}': out += "\\}"; break;
        case '$': out += "\\$"; break;
        case '&': out += "\\&"; break;
        case '#': out += "\\#"; break;
        case '_': out += "\\_"; break;
        case '%': out += "\\%"; break;
        case '^': out += "\\textasciicircum{}"; break;
        case '~': out += "\\textasciitilde{}"; break;
        default: out += (u < 0x20 || u == 0x7f) ? '?' : ch;
        }
    }
    return out;
}

std::string tex_number(const Rational& q) {
    const std::string text = to_string(q);
    const auto slash = text.find('/');
    if (slash == std::string::npos)
        return text;
    const bool negative = text[0] == '-';
    return std::string(negative ? "-" : "") + "\\frac{" + text.substr(negative ? 1 : 0, slash - (negative ? 1 : 0)) + "}{" +
           text.substr(slash + 1) + "}";
}

std::string tex_matrix(const Matrix& m) {
    std::string s = "\\begin{pmatrix}";
    for (std::size_t i = 0; i < m.rows(); ++i) {
        for (std::size_t j = 0; j < m.cols(); ++j)
            s += (j ? " & " : "") + tex_number(m(i, j));
        s += i + 1 < m.rows() ? " \\\\ " : "";
    }
    return s + "\\end{pmatrix}";
}

std::string tex_column(const Vector& v) {
    std::string s = "\\begin{pmatrix}";
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? " \\\\ " : "") + tex_number(v[i]);
    return s + "\\end{pmatrix}";
}

std::string header(const Model& model, const std::string& what, const std::string& packages) {
    std::string s = "% SPDX-License-Identifier: MIT\n% " + what + " of the law \"" + tex_escape(model.law().name) +
                    "\", written by impactcert " + IMPACTCERT_VERSION + " (report).\n% Needs \\usepackage{" + packages + "}";
    if (model.contacts() > 10)
        s += "; matrices wider than 10 columns need \\setcounter{MaxMatrixCols}{" + std::to_string(model.contacts()) + "}";
    return s + ".\n";
}

} // namespace

std::string law_latex(const Model& model) {
    const auto& pieces = model.pieces();
    const bool long_table = pieces.size() > kTabularRows;
    std::string s = header(model, "The pieces", long_table ? "amsmath,booktabs,longtable" : "amsmath,booktabs");
    s += "% One row per piece: the cone C_i spanned by its rays, and Q_i with gamma+ = Q_i gamma- on C_i.\n";
    const std::string env = long_table ? "longtable" : "tabular";
    s += "\\begin{" + env + "}{lcc}\n\\toprule\nPiece & Rays of $C_i$ & $Q_i$ \\\\\n\\midrule\n";
    if (long_table)
        s += "\\endhead\n";
    for (const auto& p : pieces) {
        std::string rays;
        for (std::size_t k = 0; k < p.R.cols(); ++k)
            rays += (k ? ",\\ " : "") + tex_column(p.R.column(k));
        s += "\\texttt{" + tex_escape(p.name) + "} & $" + rays + "$ & $" + tex_matrix(p.Q) + "$ \\\\\n";
    }
    return s + "\\bottomrule\n\\end{" + env + "}\n";
}

std::string verdicts_latex(const Model& model, const VerifyReport& report, const WorstCase* worst) {
    std::string s = header(model, "The obligations and their verdicts", "booktabs");
    s += "\\begin{tabular}{llrl}\n\\toprule\nObligation & Claimed & Exact checks & Verdict \\\\\n\\midrule\n";
    for (const auto& o : report.obligations)
        s += "\\texttt{" + tex_escape(o.id) + "} & " + (o.claimed ? "yes" : "no") + " & " + std::to_string(o.checks) + " & " +
             to_string(o.verdict) + " \\\\\n";
    s += std::string("\\midrule\n\\multicolumn{4}{l}{Gate: ") + report.verdict() + "} \\\\\n";
    if (worst) // report --worst-case: one row per bound, the value as the report gives it
        for (const auto& line : worst_case_words(*worst, model)) {
            // The quantity in mathematics, the rest as text.
            std::string text = tex_escape(line);
            for (const auto& [plain, math] : {std::pair<std::string, std::string>{"sup T+/T-", "$\\sup T^+/T^-$"},
                                              {tex_escape("Lipschitz^2 in H"), "$L^2$ in $H$"}})
                if (text.rfind(plain, 0) == 0)
                    text = math + text.substr(plain.size());
            s += "\\multicolumn{4}{l}{\\small " + text + "} \\\\\n";
        }
    return s + "\\bottomrule\n\\end{tabular}\n";
}

std::vector<std::string> write_report_figures(const Model& model, const VerifyReport& report, const std::string& dir,
                                              bool bare) {
    const std::size_t c = model.contacts();
    std::string why_not;
    const bool planes = planes_svg_fits(model, &why_not);
    if (c != 2 && c != 3 && !planes)
        return {};
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    bool refuted = false; // a counterexample drawn: claimed obligations only (cones_svg)
    for (const auto& o : report.obligations)
        refuted = refuted || (o.verdict == Verdict::refuted && o.claimed);
    const std::string name = model.law().name;
    // A legend of the cones' colours where each colour names one cone (the palette has 7 hues);
    // the sphere of a law with 3 contacts numbers its cones and has its own key.
    std::vector<LegendItem> cones;
    const auto colours = draw::piece_colours(model);
    if (model.pieces().size() <= 7)
        for (std::size_t p = 0; p < model.pieces().size(); ++p)
            cones.push_back({colours[p], model.pieces()[p].name, LegendItem::Shape::square});
    std::vector<std::string> written;
    auto add = [&](const std::string& stem, const std::string& svg) {
        for (auto& path : write_figure(dir + "/" + stem, svg))
            written.push_back(std::move(path));
    };
    // With friction the pieces are named by contact modes: the key goes with every caption.
    auto caption = [&](const char* base) {
        return std::string(base) + (model.has_friction() ? std::string(" ") + kModeKey : std::string());
    };
    auto figure = [&](const std::string& title, const std::string& text, const std::string& drawing,
                      const std::vector<LegendItem>& legend) {
        return bare ? standalone_figure("", "", drawing, legend) : standalone_figure(title, text, drawing, legend);
    };
    if (c == 2 || c == 3) {
        std::vector<LegendItem> legend = c == 3 ? std::vector<LegendItem>{} : cones;
        if (refuted)
            legend.push_back({"#000000", "counterexample", LegendItem::Shape::dot});
        add("cones", figure(name + ": the cones of the law", caption(c == 2 ? kConesCaption2 : kConesCaption3),
                                       cones_svg(model, &report), legend));
    }
    if (c == 2) {
        std::vector<LegendItem> legend = {{"#000000", "‖γ⁻‖_H = 1", LegendItem::Shape::dashed},
                                          {"#000000", "S(γ⁻) and the ratio, coloured by cone", LegendItem::Shape::line}};
        legend.insert(legend.end(), cones.begin(), cones.end());
        add("unit-circle", figure(name + ": S along the unit circle of the metric H", caption(kUnitCircleCaption),
                                             unit_circle_svg(model), legend));
    }
    if (planes) {
        std::vector<LegendItem> legend = {{"#000000", "‖γ⁻‖_H = 1", LegendItem::Shape::dashed},
                                          {"#000000", "‖S(γ⁻)‖_H / ‖γ⁻‖_H", LegendItem::Shape::line},
                                          {"#dddddd", "no cone in a sector", LegendItem::Shape::square}};
        legend.insert(legend.end(), cones.begin(), cones.end());
        add("planes", figure(name + (model.has_friction() ? ": the law on the planes of two contact coordinates"
                                                                     : ": the law on the planes of two contacts"),
                                        caption(kPlanesCaption),
                                        planes_svg(model), legend));
    }
    return written;
}

} // namespace impactcert
