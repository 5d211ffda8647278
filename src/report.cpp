#include "report.hpp"

#include "certificate.hpp"
#include "law_json.hpp"
#include "verdict_output.hpp"

#include <cmath>
#include <cstdio>
#include <string_view>

namespace impactcert {

namespace {

const char* const kPalette[] = {"#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#b07aa1",
                                "#76b7b2", "#edc948", "#9c755f", "#ff9da7", "#bab0ac"};

std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", x);
    return buf;
}

struct Dir {
    double x, y; // unit vector
};

Dir direction(const Vector& v) {
    const double x = mpq_get_d(v[0].mpq()), y = mpq_get_d(v[1].mpq());
    const double n = std::hypot(x, y);
    return {x / n, y / n};
}

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

std::string cones_svg(const Model& model) {
    if (model.contacts() != 2)
        return "";
    const auto& pieces = model.pieces();
    const std::size_t P = pieces.size(), cols = 3, rows = (P + cols - 1) / cols;
    const double main = 380, cell = 130, width = main + 20 + cols * cell,
                 height = std::max(main, 30 + rows * cell) + 10;
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + fmt(width) + "\" height=\"" +
                    fmt(height) + "\" viewBox=\"0 0 " + fmt(width) + " " + fmt(height) +
                    "\" font-family=\"sans-serif\" role=\"img\" aria-label=\"cones of " + xml_escape(model.law().name) +
                    "\">\n";
    s += "<title>" + xml_escape(model.law().name) + ": the cones C_i in the (gamma1-, gamma2-) plane and their images "
         "Q_i C_i</title>\n";
    // Main panel: the cones.
    const double cx = main / 2, cy = main / 2 + 10, r = 160;
    s += "<defs><clipPath id=\"main\"><rect x=\"" + fmt(cx - r) + "\" y=\"" + fmt(cy - r) + "\" width=\"" +
         fmt(2 * r) + "\" height=\"" + fmt(2 * r) + "\"/></clipPath>\n";
    for (std::size_t p = 0; p < P; ++p) {
        const double x0 = main + 20 + static_cast<double>(p % cols) * cell, y0 = 30 + static_cast<double>(p / cols) * cell;
        s += "<clipPath id=\"img" + std::to_string(p) + "\"><rect x=\"" + fmt(x0 + 5) + "\" y=\"" + fmt(y0 + 5) +
             "\" width=\"" + fmt(cell - 10) + "\" height=\"" + fmt(cell - 10) + "\"/></clipPath>\n";
    }
    s += "</defs>\n";
    s += "<text x=\"" + fmt(cx) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"14\">cones C_i in the (&#947;1-, "
         "&#947;2-) plane</text>\n";
    s += "<rect x=\"" + fmt(cx - r) + "\" y=\"" + fmt(cy - r) + "\" width=\"" + fmt(2 * r) + "\" height=\"" +
         fmt(2 * r) + "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
    for (std::size_t p = 0; p < P; ++p) {
        const auto [a, b] = ccw(pieces[p].R.column(0), pieces[p].R.column(1));
        s += wedge(direction(a), direction(b), cx, cy, r, kPalette[p % 10], "main", 0.55);
    }
    s += "<line x1=\"" + fmt(cx - r) + "\" y1=\"" + fmt(cy) + "\" x2=\"" + fmt(cx + r) + "\" y2=\"" + fmt(cy) +
         "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
    s += "<line x1=\"" + fmt(cx) + "\" y1=\"" + fmt(cy - r) + "\" x2=\"" + fmt(cx) + "\" y2=\"" + fmt(cy + r) +
         "\" stroke=\"#888\" stroke-dasharray=\"4 3\"/>\n";
    for (const auto& ray : model.rays())
        s += ray_line(direction(ray), cx, cy, r, "main");
    for (std::size_t p = 0; p < P; ++p) {
        const auto [a, b] = ccw(pieces[p].R.column(0), pieces[p].R.column(1));
        const Dir da = direction(a), db = direction(b);
        Dir mid{da.x + db.x, da.y + db.y};
        const double n = std::hypot(mid.x, mid.y);
        mid = {mid.x / n, mid.y / n};
        s += "<text x=\"" + fmt(cx + mid.x * r * 0.62) + "\" y=\"" + fmt(cy - mid.y * r * 0.62 + 5) +
             "\" text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\" class=\"cone-label\">" +
             xml_escape(pieces[p].name) + "</text>\n";
    }
    s += "<text x=\"" + fmt(cx + r - 4) + "\" y=\"" + fmt(cy - 6) + "\" text-anchor=\"end\" font-size=\"12\">&#947;1-</text>\n";
    s += "<text x=\"" + fmt(cx + 6) + "\" y=\"" + fmt(cy - r + 14) + "\" font-size=\"12\">&#947;2-</text>\n";

    // Small panels: the image of each cone.
    s += "<text x=\"" + fmt(main + 20 + cols * cell / 2) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"14\">"
         "images Q_i C_i in the (&#947;1+, &#947;2+) plane</text>\n";
    for (std::size_t p = 0; p < P; ++p) {
        const double x0 = main + 20 + static_cast<double>(p % cols) * cell, y0 = 30 + static_cast<double>(p / cols) * cell;
        const double icx = x0 + cell / 2, icy = y0 + cell / 2, ir = cell / 2 - 5;
        const std::string clip = "img" + std::to_string(p);
        s += "<rect x=\"" + fmt(x0 + 5) + "\" y=\"" + fmt(y0 + 5) + "\" width=\"" + fmt(cell - 10) + "\" height=\"" +
             fmt(cell - 10) + "\" fill=\"#fafafa\" stroke=\"#999\"/>\n";
        const Vector u = pieces[p].Q * pieces[p].R.column(0), v = pieces[p].Q * pieces[p].R.column(1);
        const Rational area = u[0] * v[1] - u[1] * v[0];
        if (sign_of(area) != Sign::zero) {
            const auto [a, b] = ccw(u, v);
            s += wedge(direction(a), direction(b), icx, icy, ir, kPalette[p % 10], clip, 0.7);
        }
        for (const Vector* w : {&u, &v})
            if (!is_zero(*w))
                s += ray_line(direction(*w), icx, icy, ir, clip);
        s += "<line x1=\"" + fmt(x0 + 5) + "\" y1=\"" + fmt(icy) + "\" x2=\"" + fmt(x0 + cell - 5) + "\" y2=\"" +
             fmt(icy) + "\" stroke=\"#888\" stroke-dasharray=\"3 3\"/>\n";
        s += "<line x1=\"" + fmt(icx) + "\" y1=\"" + fmt(y0 + 5) + "\" x2=\"" + fmt(icx) + "\" y2=\"" +
             fmt(y0 + cell - 5) + "\" stroke=\"#888\" stroke-dasharray=\"3 3\"/>\n";
        s += "<text x=\"" + fmt(x0 + 10) + "\" y=\"" + fmt(y0 + cell - 10) + "\" font-size=\"12\" class=\"image-label\">" +
             xml_escape("Q_" + pieces[p].name + " C_" + pieces[p].name) + "</text>\n";
    }
    s += "</svg>\n";
    return s;
}

namespace {

std::string matrix_text(const Matrix& m) {
    std::string s = "[";
    for (std::size_t i = 0; i < m.rows(); ++i) {
        s += i ? ", [" : "[";
        for (std::size_t j = 0; j < m.cols(); ++j)
            s += (j ? ", " : "") + to_string(m(i, j));
        s += "]";
    }
    return s + "]";
}

std::string rays_text(const Piece& p) {
    std::string s;
    for (std::size_t k = 0; k < p.R.cols(); ++k)
        s += (k ? ", " : "") + to_string(p.R.column(k));
    return s;
}

std::size_t claimed_count(const VerifyReport& r, bool proved_only) {
    std::size_t n = 0;
    for (const auto& o : r.obligations)
        n += (o.claimed && (!proved_only || o.verdict == Verdict::proved)) ? 1 : 0;
    return n;
}

std::string law_hash(const Model& m) { return sha256_hex(law_to_json(m.law()).dump()); }

} // namespace

std::string report_markdown(const Model& model, const VerifyReport& report) {
    std::string s = "# impactcert report: " + md_escape(report.law) + "\n\n";
    s += std::string("**Verdict: ") + report.verdict() + "** — " +
         std::to_string(claimed_count(report, true)) + " of " + std::to_string(claimed_count(report, false)) +
         " claimed obligations proved. " + std::to_string(model.balls()) + " balls, " +
         std::to_string(model.contacts()) + (model.contacts() == 1 ? " contact, " : " contacts, ") +
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
    s += "\n## The law\n\n| piece | rays | Q |\n|---|---|---|\n";
    for (const auto& p : model.pieces())
        s += "| " + md_escape(p.name) + " | " + rays_text(p) + " | `" + matrix_text(p.Q) + "` |\n";
    s += "\nH = G^-1 = `" + matrix_text(model.H()) + "`. Every check is exact (GMP rationals); the reductions "
         "are argued in proofs/README.md.\n";
    return s;
}

std::string report_html(const Model& model, const VerifyReport& report) {
    const std::string verdict = report.verdict();
    const char* colour = verdict == "proved" ? "#1a7f37" : verdict == "refuted" ? "#cf222e" : "#9a6700";
    std::string s = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>impactcert: " +
                    xml_escape(report.law) + "</title>\n<style>\n"
                    "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\n"
                    "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;text-align:left}\n"
                    "th{background:#f0f0f0}.proved{color:#1a7f37;font-weight:bold}.refuted{color:#cf222e;font-weight:bold}\n"
                    ".skipped{color:#777}.badge{display:inline-block;padding:4px 12px;border-radius:4px;color:#fff}\n"
                    "pre{background:#f6f8fa;padding:8px;overflow-x:auto}code{font-size:90%}\n"
                    "</style>\n</head>\n<body>\n";
    s += "<h1>impactcert report: " + xml_escape(report.law) + "</h1>\n";
    s += std::string("<p><span class=\"badge\" style=\"background:") + colour + "\">" + verdict + "</span> " + std::to_string(claimed_count(report, true)) + " of " +
         std::to_string(claimed_count(report, false)) + " claimed obligations proved; " +
         std::to_string(model.balls()) + " balls, " + std::to_string(model.contacts()) + " contacts, " +
         std::to_string(model.pieces().size()) + " pieces. Law SHA-256 <code>" + law_hash(model) + "</code>.</p>\n";
    if (model.contacts() == 2)
        s += "<figure>\n" + cones_svg(model) +
             "<figcaption>Left: the cones of the law in the plane of pre-impact contact velocities (compare "
             "Leine &amp; Winandy, Fig. 1(b)); black lines are the boundary rays. Right: each cone's image under "
             "its matrix.</figcaption>\n</figure>\n";
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
    s += "<h2>The law</h2>\n<table>\n<tr><th>piece</th><th>rays</th><th>Q</th></tr>\n";
    for (const auto& p : model.pieces())
        s += "<tr><td>" + xml_escape(p.name) + "</td><td>" + xml_escape(rays_text(p)) + "</td><td><code>" +
             xml_escape(matrix_text(p.Q)) + "</code></td></tr>\n";
    s += "</table>\n<p>H = G<sup>-1</sup> = <code>" + xml_escape(matrix_text(model.H())) +
         "</code>. Every check is exact (GMP rationals); the reductions are argued in proofs/README.md.</p>\n";
    s += "</body>\n</html>\n";
    return s;
}

} // namespace impactcert
