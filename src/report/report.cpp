// SPDX-License-Identifier: GPL-3.0-or-later
#include "report/report.hpp"

#include "prover/certificate.hpp"
#include "model/law_json.hpp"
#include "exact/rational.hpp"
#include "report/report_draw.hpp"
#include "prover/verdict_output.hpp"

#include <array>
#include <climits>
#include <cmath>
#include <map>
#include <cstdio>
#include <string_view>

namespace impactcert {

namespace {

using namespace draw;


// A wedge from direction a counter-clockwise to b (angle < pi), centred at (cx, cy) with
// radius r (drawn long and clipped by the panel).
std::string wedge(Dir a, Dir b, double cx, double cy, double r, const std::string& fill, const std::string& clip,
                  double opacity) {
    Dir mid{a.x + b.x, a.y + b.y};
    const double n = std::hypot(mid.x, mid.y);
    mid = n > 1e-12 ? Dir{mid.x / n, mid.y / n} : Dir{-a.y, a.x};
    auto pt = [&](Dir d, double scale) { return fmt(cx + d.x * r * scale) + "," + fmt(cy - d.y * r * scale); };
    return "<polygon points=\"" + fmt(cx) + "," + fmt(cy) + " " + pt(a, 3) + " " + pt(mid, 3) + " " + pt(b, 3) +
           "\" fill=\"" + fill + "\" fill-opacity=\"" + fmt(opacity) + "\" clip-path=\"url(#" + clip + ")\"/>\n";
}

std::string ray_line(Dir d, double cx, double cy, double r, const std::string& clip) {
    return "<line x1=\"" + fmt(cx) + "\" y1=\"" + fmt(cy) + "\" x2=\"" + fmt(cx + d.x * r * 3) + "\" y2=\"" +
           fmt(cy - d.y * r * 3) + "\" stroke=\"#222\" stroke-width=\"1.5\" clip-path=\"url(#" + clip + ")\"/>\n";
}

// The counter-clockwise order of two rays spanning an angle < pi.
std::pair<Vector, Vector> ccw(const Vector& a, const Vector& b) {
    const Rational d = a[0] * b[1] - a[1] * b[0];
    return sign_of(d) == Sign::negative ? std::make_pair(b, a) : std::make_pair(a, b);
}

std::string verdict_word(const ObligationResult& o) { return to_string(o.verdict); }


// Text from a law (names) or a method in Markdown: one line (control characters become
// blanks) with every character that Markdown, GitHub's tables, HTML or math could act on
// backslash-escaped, so a name can neither end a table cell, start a heading or a fence, nor
// inject HTML.
std::string md_escape(const std::string& s) {
    std::string out;
    for (char ch : s) {
        const auto u = static_cast<unsigned char>(ch);
        if (u < 0x20 || u == 0x7f)
            out += ' ';
        else if (std::string_view("\\`*_[]<>|#!&~$").find(ch) != std::string_view::npos)
            out += std::string("\\") + ch;
        else
            out += ch;
    }
    return out;
}

// JSON for a fenced code block: the characters that could close the fence or look like HTML
// are written as \u escapes (they occur only inside JSON strings, so the JSON means the same).
std::string md_json(const Json& j) {
    std::string out;
    for (char ch : j.dump(2)) {
        switch (ch) {
        case '`': out += "\\u0060"; break;
        case '<': out += "\\u003c"; break;
        case '>': out += "\\u003e"; break;
        case '&': out += "\\u0026"; break;
        default: out += ch;
        }
    }
    return out;
}

} // namespace

namespace {


} // namespace

namespace {


// The cones unrolled on a strip: the H-angle from -pi to pi left to right, one band per cone with
// its name where it fits and everything on hover; ticks at the axes and the tie.
std::string angle_strip(const Model& model, double x0, double y0, double width) {
    const double pi = std::acos(-1.0), height = 34;
    auto at = [&](double angle) { return x0 + (angle + pi) / (2 * pi) * width; };
    std::string s = "<text x=\"" + fmt(x0) + "\" y=\"" + fmt(y0 - 6) + "\" font-size=\"12\">cones unrolled by "
                    "their angle in the metric H, -180&#176; to 180&#176; (hover: word, rays, matrix)</text>\n";
    s += "<rect x=\"" + fmt(x0) + "\" y=\"" + fmt(y0) + "\" width=\"" + fmt(width) + "\" height=\"" + fmt(height) +
         "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
    const auto& pieces = model.pieces();
    const auto colours = piece_colours(model);
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        const auto [ra, rb] = ccw(pieces[p].R.column(0), pieces[p].R.column(1));
        const double a = h_angle(model.H(), ra), d = span(a, h_angle(model.H(), rb));
        std::vector<std::pair<double, double>> bands;
        if (a + d <= pi)
            bands.push_back({a, a + d});
        else {
            bands.push_back({a, pi});
            bands.push_back({-pi, a + d - 2 * pi});
        }
        s += "<g class=\"cone-band\"><title>" + xml_escape(piece_title(pieces[p])) + "</title>";
        for (const auto& [lo, hi] : bands)
            s += "<rect x=\"" + fmt(at(lo)) + "\" y=\"" + fmt(y0) + "\" width=\"" + fmt(std::max(at(hi) - at(lo), 0.6)) +
                 "\" height=\"" + fmt(height) + "\" fill=\"" + colours[p] + "\" fill-opacity=\"0.7\" stroke=\"#fff\" stroke-width=\"0.5\"/>";
        s += "</g>\n";
        for (const auto& [lo, hi] : bands)
            if ((at(hi) - at(lo)) >= 7.0 * static_cast<double>(pieces[p].name.size()) + 4)
                s += "<text x=\"" + fmt((at(lo) + at(hi)) / 2) + "\" y=\"" + fmt(y0 + height / 2 + 4) +
                     "\" text-anchor=\"middle\" font-size=\"11\" class=\"strip-label\">" + xml_escape(pieces[p].name) + "</text>\n";
    }
    const std::string g1 = coordinate_svg(model, 0), g2 = coordinate_svg(model, 1);
    const std::string p1 = "+" + g1, p2 = "+" + g2, m1 = "-" + g1, m2 = "-" + g2;
    const std::vector<std::pair<Vector, const char*>> ticks = {
        {{Rational(1), Rational(0)}, p1.c_str()}, {{Rational(0), Rational(1)}, p2.c_str()},
        {{Rational(-1), Rational(0)}, m1.c_str()}, {{Rational(0), Rational(-1)}, m2.c_str()},
        {{Rational(-1), Rational(-1)}, "tie"}};
    // Ticks left to right; a label closer than 30 px to the previous one goes one row lower.
    std::vector<std::pair<double, const char*>> placed;
    for (const auto& [v, label] : ticks)
        placed.push_back({at(h_angle(model.H(), v)), label});
    std::sort(placed.begin(), placed.end());
    double last = -1e9;
    int row = 0;
    for (const auto& [x, label] : placed) {
        row = x - last < 30 ? row + 1 : 0;
        last = x;
        s += "<line x1=\"" + fmt(x) + "\" y1=\"" + fmt(y0 + height) + "\" x2=\"" + fmt(x) + "\" y2=\"" +
             fmt(y0 + height + 5 + 10 * row) + "\" stroke=\"#444\"/><text x=\"" + fmt(x) + "\" y=\"" +
             fmt(y0 + height + 16 + 10 * row) + "\" text-anchor=\"middle\" font-size=\"10\">" + label + "</text>\n";
    }
    return s;
}

} // namespace

std::string cones_svg(const Model& model, const VerifyReport* report) {
    if (model.contacts() == 3)
        return draw::sphere_svg(model, report);
    if (model.contacts() != 2)
        return "";
    const auto& pieces = model.pieces();
    const auto colours = piece_colours(model);
    const Matrix& H = model.H();
    // Up to 12 pieces: one thumbnail per image; more: all images in one panel (hover for names).
    const std::size_t P = pieces.size(), cols = 3;
    const bool thumbnails = P <= 12;
    const std::size_t rows = thumbnails ? (P + cols - 1) / cols : 0;
    const double main = 380, cell = 130, width = main + 20 + (thumbnails ? static_cast<double>(cols) * cell : main),
                 panels = std::max(main, 30 + static_cast<double>(rows) * cell), strip_y = panels + 34,
                 height = strip_y + 90;
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(width) + "\" height=\"" +
                    fmt(height) + "\" viewBox=\"0 0 " + fmt(width) + " " + fmt(height) +
                    "\" font-family=\"sans-serif\" role=\"img\" aria-label=\"cones of " + xml_escape(model.law().name) +
                    "\">\n";
    s += "<title>" + xml_escape(model.law().name) + ": the cones C_i and their images Q_i C_i, drawn in the "
         "kinetic-energy metric H = G^-1</title>\n";
    // Main panel: the cones, in coordinates where H is the Euclidean metric.
    const double cx = main / 2, cy = main / 2 + 10, r = 160;
    s += "<defs><clipPath id=\"main\"><rect x=\"" + fmt(cx - r) + "\" y=\"" + fmt(cy - r) + "\" width=\"" +
         fmt(2 * r) + "\" height=\"" + fmt(2 * r) + "\"/></clipPath>\n";
    if (thumbnails)
        for (std::size_t p = 0; p < P; ++p) {
            const double x0 = main + 20 + static_cast<double>(p % cols) * cell, y0 = 30 + static_cast<double>(p / cols) * cell;
            s += "<clipPath id=\"img" + std::to_string(p) + "\"><rect x=\"" + fmt(x0 + 5) + "\" y=\"" + fmt(y0 + 5) +
                 "\" width=\"" + fmt(cell - 10) + "\" height=\"" + fmt(cell - 10) + "\"/></clipPath>\n";
        }
    else
        s += "<clipPath id=\"images\"><rect x=\"" + fmt(main + 20 + cx - r) + "\" y=\"" + fmt(cy - r) +
             "\" width=\"" + fmt(2 * r) + "\" height=\"" + fmt(2 * r) + "\"/></clipPath>\n";
    s += "</defs>\n";
    const std::string g1 = coordinate_svg(model, 0), g2 = coordinate_svg(model, 1);
    s += "<text x=\"" + fmt(cx) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"14\">cones C_i, pre-impact "
         "(" + g1 + "-, " + g2 + "-), metric H</text>\n";
    auto axes = [&](double ox, double oy, double rr, const char* x_label, const char* y_label, const std::string& clip) {
        std::string t = "<rect x=\"" + fmt(ox - rr) + "\" y=\"" + fmt(oy - rr) + "\" width=\"" + fmt(2 * rr) +
                        "\" height=\"" + fmt(2 * rr) + "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
        // The coordinate axes of gamma, drawn where they lie in the metric H (dashed).
        for (const Vector& axis : {Vector{Rational(1), Rational(0)}, Vector{Rational(0), Rational(1)}}) {
            const Dir d = h_direction(H, axis);
            t += "<line x1=\"" + fmt(ox - d.x * rr * 3) + "\" y1=\"" + fmt(oy + d.y * rr * 3) + "\" x2=\"" +
                 fmt(ox + d.x * rr * 3) + "\" y2=\"" + fmt(oy - d.y * rr * 3) +
                 "\" stroke=\"#888\" stroke-dasharray=\"4 3\" clip-path=\"url(#" + clip + ")\"/>\n";
        }
        const Dir dx = h_direction(H, {Rational(1), Rational(0)}), dy = h_direction(H, {Rational(0), Rational(1)});
        t += "<text x=\"" + fmt(ox + dx.x * rr * 0.9) + "\" y=\"" + fmt(oy - dx.y * rr * 0.9 - 6) +
             "\" text-anchor=\"end\" font-size=\"12\">" + x_label + "</text>\n";
        // Close axes (a heavy and a light ball: the quadrant is a thin wedge in H): the second label below its line.
        const bool close = std::fabs(dx.x * dy.y - dx.y * dy.x) < 0.3 && dx.x * dy.x + dx.y * dy.y > 0;
        t += "<text x=\"" + fmt(ox + dy.x * rr * (close ? 0.6 : 0.9) + 6) + "\" y=\"" +
             fmt(oy - dy.y * rr * (close ? 0.6 : 0.9) + (close ? 16 : 4)) + "\" font-size=\"12\">" + y_label + "</text>\n";
        return t;
    };
    s += axes(cx, cy, r, (g1 + "-").c_str(), (g2 + "-").c_str(), "main");
    for (std::size_t p = 0; p < P; ++p) {
        const auto [a, b] = ccw(pieces[p].R.column(0), pieces[p].R.column(1));
        s += "<g><title>" + xml_escape(piece_title(pieces[p])) + "</title>" +
             wedge(h_direction(H, a), h_direction(H, b), cx, cy, r, colours[p], "main", 0.55) + "</g>\n";
    }
    for (const auto& ray : model.rays())
        s += ray_line(h_direction(H, ray), cx, cy, r, "main");
    // Labels only where they fit: the wedge's opening at 62% of the radius must hold the name.
    for (std::size_t p = 0; p < P; ++p) {
        const auto [a, b] = ccw(pieces[p].R.column(0), pieces[p].R.column(1));
        const double aa = h_angle(H, a), opening = span(aa, h_angle(H, b));
        if (opening * r * 0.62 < 9.0 * static_cast<double>(pieces[p].name.size()) + 6 && opening < 0.9)
            continue;
        const double mid = aa + opening / 2;
        s += "<text x=\"" + fmt(cx + std::cos(mid) * r * 0.62) + "\" y=\"" + fmt(cy - std::sin(mid) * r * 0.62 + 5) +
             "\" text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\" class=\"cone-label\">" +
             xml_escape(pieces[p].name) + "</text>\n";
    }
    // Counterexamples: a point in its direction, a pair as a segment at a common scale, both in
    // the metric H: each point at its H-angle and at its H-length relative to the longest
    // (sqrt of an exact ratio of quadratic forms), so any scale stays finite.
    std::map<std::pair<long, long>, int> labels;
    for (const auto& mk : marked_points(report, 2)) {
        std::vector<Rational> norms;
        Rational longest(0);
        for (const auto& pt : mk.exact) {
            norms.push_back(bilinear(pt, H, pt));
            longest = std::max(longest, norms.back());
        }
        if (sign_of(longest) != Sign::positive)
            continue;
        std::vector<std::pair<double, double>> shown;
        for (std::size_t i = 0; i < mk.exact.size(); ++i) {
            const double a = h_angle(H, mk.exact[i]), len = std::sqrt(display_double(norms[i] / longest));
            shown.push_back({cx + std::cos(a) * len * r * 0.85, cy - std::sin(a) * len * r * 0.85});
        }
        s += marks_svg(shown, mk.id, labels);
    }

    // The images.
    if (thumbnails) {
        s += "<text x=\"" + fmt(main + 20 + static_cast<double>(cols) * cell / 2) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"14\">"
             "images Q_i C_i (" + g1 + "+, " + g2 + "+), metric H</text>\n";
        for (std::size_t p = 0; p < P; ++p) {
            const double x0 = main + 20 + static_cast<double>(p % cols) * cell, y0 = 30 + static_cast<double>(p / cols) * cell;
            const double icx = x0 + cell / 2, icy = y0 + cell / 2, ir = cell / 2 - 5;
            const std::string clip = "img" + std::to_string(p);
            s += axes(icx, icy, ir, "", "", clip);
            const Vector u = pieces[p].Q * pieces[p].R.column(0), v = pieces[p].Q * pieces[p].R.column(1);
            const Rational area = u[0] * v[1] - u[1] * v[0];
            if (sign_of(area) != Sign::zero) {
                const auto [a, b] = ccw(u, v);
                s += "<g><title>" + xml_escape("image of " + pieces[p].name) + "</title>" +
                     wedge(h_direction(H, a), h_direction(H, b), icx, icy, ir, colours[p], clip, 0.7) + "</g>\n";
            }
            for (const Vector* w : {&u, &v})
                if (!is_zero(*w))
                    s += ray_line(h_direction(H, *w), icx, icy, ir, clip);
            s += "<text x=\"" + fmt(x0 + 10) + "\" y=\"" + fmt(y0 + cell - 10) + "\" font-size=\"12\" class=\"image-label\">" +
                 xml_escape("Q_" + pieces[p].name + " C_" + pieces[p].name) + "</text>\n";
        }
    } else {
        const double icx = main + 20 + cx;
        s += "<text x=\"" + fmt(icx) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"14\">all images Q_i C_i "
             "(" + g1 + "+, " + g2 + "+), metric H (hover)</text>\n";
        s += axes(icx, cy, r, (g1 + "+").c_str(), (g2 + "+").c_str(), "images");
        for (std::size_t p = 0; p < P; ++p) {
            const Vector u = pieces[p].Q * pieces[p].R.column(0), v = pieces[p].Q * pieces[p].R.column(1);
            const Rational area = u[0] * v[1] - u[1] * v[0];
            if (sign_of(area) == Sign::zero)
                continue;
            const auto [a, b] = ccw(u, v);
            s += "<g><title>" + xml_escape("image of " + piece_title(pieces[p])) + "</title>" +
                 wedge(h_direction(H, a), h_direction(H, b), icx, cy, r, colours[p], "images", 0.45) + "</g>\n";
        }
    }
    s += angle_strip(model, 20, strip_y, width - 40);
    s += "</svg>\n";
    return s;
}

namespace {

std::size_t claimed_count(const VerifyReport& r, bool proved_only) {
    std::size_t n = 0;
    for (const auto& o : r.obligations)
        n += (o.claimed && (!proved_only || o.verdict == Verdict::proved)) ? 1 : 0;
    return n;
}

std::string law_hash(const Model& m) { return sha256_hex(law_to_json(m.law()).dump()); }

} // namespace

std::vector<std::string> worst_case_words(const WorstCase& w, const Model& model) {
    std::vector<std::string> out;
    auto one = [&](const char* what, const LawBound& b, const char* where) {
        if (!b.decided) {
            out.push_back(std::string(what) + ": undecided (" + b.limit + ")");
            return;
        }
        std::string point;
        for (const auto& e : b.pieces[b.top].point)
            point += (point.empty() ? "" : ", ") + to_string(e);
        out.push_back(std::string(what) + " = " + value_text(b.value) + (b.value.exact ? ", attained" : ", approached") +
                      " in piece " + model.pieces()[b.pieces[b.top].piece].name + " at " + where + " (" + point + ")");
    };
    one("sup T+/T-", w.energy, "gamma- =");
    if (w.lipschitz)
        one("Lipschitz^2 in H", *w.lipschitz, "direction");
    else
        out.push_back("Lipschitz^2 in H: not computed (fan and P1 are not both proved: no continuous tiling)");
    return out;
}

std::string report_markdown(const Model& model, const VerifyReport& report, const WorstCase* worst) {
    std::string s = "# impactcert report: " + md_escape(report.law) + "\n\n";
    s += std::string("**Verdict: ") + report.verdict() + "** — " +
         std::to_string(claimed_count(report, true)) + " of " + std::to_string(claimed_count(report, false)) +
         " claimed obligations proved. " + md_escape(system_words(model)) + ", " +
         std::to_string(model.pieces().size()) + " pieces; law SHA-256 `" + law_hash(model) + "`.\n\n";
    s += "| obligation | claimed | verdict | exact checks | method |\n|---|---|---|---:|---|\n";
    for (const auto& o : report.obligations) {
        const char* mark = o.verdict == Verdict::proved      ? "✅"
                           : o.verdict == Verdict::refuted   ? "❌"
                           : o.verdict == Verdict::undecided ? "❔"
                                                             : "➖";
        s += "| `" + o.id + "` | " + (o.claimed ? "yes" : "no") + " | " + mark + " " + verdict_word(o) + " | " +
             std::to_string(o.checks) + " | " + md_escape(o.method) + " |\n";
    }
    bool any = false;
    for (const auto& o : report.obligations) {
        if (o.verdict != Verdict::refuted)
            continue;
        if (!any)
            s += "\n## Counterexamples\n";
        any = true;
        s += "\n### `" + o.id + "`\n\n```json\n" + md_json(o.counterexample) + "\n```\n";
    }
    for (const auto& o : report.obligations)
        if (o.verdict == Verdict::undecided)
            s += "\n`" + o.id + "` is undecided: " + md_escape(o.limit) + "\n";
    if (worst) {
        s += "\n## Worst case (exact)\n\n";
        for (const auto& line : worst_case_words(*worst, model))
            s += "- " + md_escape(line) + "\n";
    }
    // A law of more than 100 pieces: the summary only (GitHub's job summary stops at 1 MiB; a
    // 1,775-piece law made 791 KB); every piece is in report.html.
    constexpr std::size_t kPiecesInMarkdown = 100;
    if (model.pieces().size() > kPiecesInMarkdown) {
        s += "\n## The law\n\n" + std::to_string(model.pieces().size()) + " pieces: too many for a job summary; every "
             "piece, its rays and its matrix are in report.html (with a filter).\n";
    } else {
        s += "\n## The law\n\n| piece | rays | Q |\n|---|---|---|\n";
        for (const auto& p : model.pieces())
            s += "| " + md_escape(p.name) + " | " + rays_text(p) + " | `" + matrix_text(p.Q) + "` |\n";
    }
    if (model.contacts() >= 4) {
        std::string why_not;
        if (planes_svg_fits(model, &why_not))
            s += "\nreport.html draws the " + std::to_string(model.contacts()) + "-dimensional law on each plane of two "
                 + std::string(model.has_friction() ? "contact coordinates (normal gamma_N and tangential gamma_T)" : "contacts") +
                 " (figures/planes.svg).\n";
        else
            s += "\nNo picture in report.html: " + md_escape(why_not) + ".\n";
    }
    s += std::string(model.redundant() ? "\nH = G_B^-1 (G_B = W_B^T M^-1 W_B of the basis columns) = `" : "\nH = G^-1 = `") +
         matrix_text(model.H()) + "`. Every check is exact (GMP rationals); the reductions "
         "are argued in proofs/README.md.\n";
    return s;
}

std::string report_html(const Model& model, const VerifyReport& report, const WorstCase* worst) {
    const std::string verdict = report.verdict();
    const char* colour = verdict == "proved" ? "#007a5a" : verdict == "refuted" ? "#b34700" : "#8a5a00"; // Okabe-Ito hues, darkened for white text
    std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>impactcert: " +
                    xml_escape(report.law) + "</title>\n<style>\n"
                    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\n"
                    "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}\n"
                    "th{background:#f0f0f0}.proved{color:#007a5a;font-weight:bold}.refuted{color:#b34700;font-weight:bold}\n"
                    ".skipped{color:#777}.badge{display:inline-block;padding:4px 12px;border-radius:4px;color:#fff}\n"
                    "pre{background:#f6f8fa;padding:8px;overflow-x:auto}code{font-size:90%}\n"
                    "</style>\n</head>\n<body>\n";
    s += "<h1>impactcert report: " + xml_escape(report.law) + "</h1>\n";
    s += std::string("<p><span class=\"badge\" style=\"background:") + colour + "\">" + verdict + "</span> " + std::to_string(claimed_count(report, true)) + " of " +
         std::to_string(claimed_count(report, false)) + " claimed obligations proved; " +
         xml_escape(system_words(model)) + ", " + std::to_string(model.pieces().size()) + " pieces. Law SHA-256 <code>" +
         law_hash(model) + "</code>.</p>\n";
    if (model.contacts() == 2)
        s += "<figure>\n" + cones_svg(model, &report) +
             "<figcaption>Left: the cones of the law in the plane of pre-impact contact velocities (compare "
             "Leine &amp; Winandy, Fig. 1(b)), drawn in the kinetic-energy metric H = G<sup>-1</sup>, where an elastic "
             "impact is a reflection and thin cones open up (dashed: the coordinate axes); black lines are the "
             "boundary rays; black dots: counterexamples (a point in its direction, a pair joined at a common scale). "
             "Right: each cone's image under its matrix. Below: the cones unrolled by angle. Names are written "
             "where they fit; hover any cone for its word, rays and matrix.</figcaption>\n</figure>\n";
    if (model.contacts() == 3)
        s += "<figure>\n" + cones_svg(model, &report) +
             "<figcaption>" + std::string(kConesCaption3) + " Hover a cone for its name, rays and matrix." +
             (model.has_friction() ? std::string(" ") + kModeKey : std::string()) + "</figcaption>\n</figure>\n";
    if (model.contacts() == 2)
        s += "<figure>\n" + unit_circle_svg(model) + "<figcaption>" + kUnitCircleCaption +
             (model.has_friction() ? std::string(" ") + kModeKey : std::string()) + "</figcaption>\n</figure>\n";
    if (model.contacts() >= 3) {
        std::string why_not;
        const std::string planes = planes_svg(model, &why_not);
        if (!planes.empty())
            s += "<figure>\n" + planes + "<figcaption>" + kPlanesCaption +
                 (model.has_friction() ? std::string(" ") + kModeKey : std::string()) + "</figcaption>\n</figure>\n";
        else
            s += "<p>" + xml_escape("No plane view: " + why_not) + ". The table of pieces below can be filtered.</p>\n";
    }
    if (worst) {
        s += "<h2>Worst case (exact)</h2>\n<ul>\n";
        for (const auto& line : worst_case_words(*worst, model))
            s += "<li>" + xml_escape(line) + "</li>\n";
        s += "</ul>\n";
    }
    s += "<h2>Obligations</h2>\n<table>\n<tr><th>obligation</th><th>claimed</th><th>verdict</th><th>exact "
         "checks</th><th>method</th></tr>\n";
    for (const auto& o : report.obligations)
        s += "<tr><td><code>" + xml_escape(o.id) + "</code></td><td>" + (o.claimed ? "yes" : "no") +
             "</td><td class=\"" + verdict_word(o) + "\">" + verdict_word(o) + "</td><td>" +
             std::to_string(o.checks) + "</td><td>" + xml_escape(o.method) + "</td></tr>\n";
    s += "</table>\n";
    bool any = false;
    for (const auto& o : report.obligations) {
        if (o.verdict != Verdict::refuted)
            continue;
        if (!any)
            s += "<h2>Counterexamples</h2>\n";
        any = true;
        s += "<h3><code>" + xml_escape(o.id) + "</code></h3>\n<pre>" + xml_escape(o.counterexample.dump(2)) + "</pre>\n";
    }
    for (const auto& o : report.obligations)
        if (o.verdict == Verdict::undecided)
            s += "<p><code>" + xml_escape(o.id) + "</code> is undecided: " + xml_escape(o.limit) + "</p>\n";
    s += "<h2>The law</h2>\n<p><input id=\"filter\" type=\"search\" size=\"50\" placeholder=\"filter the " +
         std::to_string(model.pieces().size()) + " pieces: a word, a ray or a matrix entry\" "
         "oninput=\"var q=this.value;document.querySelectorAll('#pieces tr.piece').forEach(function(r){"
         "r.style.display=r.textContent.indexOf(q)>=0?'':'none';});\"></p>\n<table id=\"pieces\">\n"
         "<tr><th>piece</th><th>rays</th><th>Q</th></tr>\n";
    for (const auto& p : model.pieces())
        s += "<tr class=\"piece\"><td>" + xml_escape(p.name) + "</td><td>" + xml_escape(rays_text(p)) + "</td><td><code>" +
             xml_escape(matrix_text(p.Q)) + "</code></td></tr>\n";
    s += std::string(model.redundant() ? "</table>\n<p>H = G<sub>B</sub><sup>-1</sup> (the basis columns) = <code>"
                                       : "</table>\n<p>H = G<sup>-1</sup> = <code>") +
         xml_escape(matrix_text(model.H())) +
         "</code>. Every check is exact (GMP rationals); the reductions are argued in proofs/README.md.</p>\n";
    s += "</body>\n</html>\n";
    return s;
}

} // namespace impactcert
