// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "base/errors.hpp"
#include "report/figure.hpp"
#include "report/report.hpp"
#include "prover/verdict_output.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <cctype>
#include <cstdio>
#include <vector>

using namespace impactcert;
using impactcert::test::source_path;

namespace {

// A small XML well-formedness check: balanced, properly nested tags; quoted attributes with no
// raw '<' or '&'; character data with only the five predefined or numeric entities. Returns
// the element names in document order, or throws std::runtime_error naming the offset.
std::vector<std::string> xml_elements(const std::string& x) {
    std::vector<std::string> open, seen;
    auto fail = [&](std::size_t at, const std::string& why) {
        throw std::runtime_error("offset " + std::to_string(at) + ": " + why);
    };
    auto check_entities = [&](std::size_t from, std::size_t to) {
        for (std::size_t i = from; i < to; ++i) {
            if (x[i] == '<')
                fail(i, "raw '<'");
            if (x[i] != '&')
                continue;
            const auto semi = x.find(';', i);
            if (semi == std::string::npos || semi > to)
                fail(i, "unterminated entity");
            const std::string e = x.substr(i + 1, semi - i - 1);
            const bool named = e == "amp" || e == "lt" || e == "gt" || e == "quot" || e == "apos";
            const bool numeric = e.size() > 1 && e[0] == '#' &&
                                 std::all_of(e.begin() + 1, e.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); });
            if (!named && !numeric)
                fail(i, "unknown entity &" + e + ";");
        }
    };
    std::size_t i = 0;
    while (i < x.size()) {
        const auto lt = x.find('<', i);
        check_entities(i, lt == std::string::npos ? x.size() : lt);
        if (lt == std::string::npos)
            break;
        if (x.compare(lt, 4, "<!--") == 0) {
            i = x.find("-->", lt) + 3;
            continue;
        }
        if (x.compare(lt, 2, "<?") == 0) {
            i = x.find("?>", lt) + 2;
            continue;
        }
        const auto gt = x.find('>', lt);
        if (gt == std::string::npos)
            fail(lt, "unterminated tag");
        std::string tag = x.substr(lt + 1, gt - lt - 1);
        if (!tag.empty() && tag[0] == '/') {
            const std::string name = tag.substr(1);
            if (open.empty() || open.back() != name)
                fail(lt, "mismatched </" + name + ">");
            open.pop_back();
        } else {
            const bool self_closing = !tag.empty() && tag.back() == '/';
            if (self_closing)
                tag.pop_back();
            std::size_t k = 0;
            while (k < tag.size() && !std::isspace(static_cast<unsigned char>(tag[k])))
                ++k;
            const std::string name = tag.substr(0, k);
            if (name.empty())
                fail(lt, "empty tag name");
            // Attributes: name="value" pairs.
            while (k < tag.size()) {
                while (k < tag.size() && std::isspace(static_cast<unsigned char>(tag[k])))
                    ++k;
                if (k == tag.size())
                    break;
                const auto eq = tag.find('=', k);
                if (eq == std::string::npos || eq + 1 >= tag.size() || tag[eq + 1] != '"')
                    fail(lt, "attribute without a quoted value in <" + name + ">");
                const auto close = tag.find('"', eq + 2);
                if (close == std::string::npos)
                    fail(lt, "unterminated attribute value");
                check_entities(lt + 1 + eq + 2, lt + 1 + close);
                k = close + 1;
            }
            seen.push_back(name);
            if (!self_closing)
                open.push_back(name);
        }
        i = gt + 1;
    }
    if (!open.empty())
        fail(x.size(), "unclosed <" + open.back() + ">");
    return seen;
}

std::size_t count(const std::string& hay, const std::string& needle) {
    std::size_t n = 0;
    for (auto at = hay.find(needle); at != std::string::npos; at = hay.find(needle, at + 1))
        ++n;
    return n;
}

} // namespace

TEST_CASE("report: the SVG of the paper's law is well-formed XML with six labelled cones and six images", "[report]") {
    const Model m(paper_law());
    const std::string svg = cones_svg(m);
    std::vector<std::string> elements;
    REQUIRE_NOTHROW(elements = xml_elements(svg));
    REQUIRE(elements.front() == "svg");
    CHECK(std::count(elements.begin(), elements.end(), "polygon") == 12); // 6 cones + 6 images
    for (const char* name : {"I", "IIa", "IIb", "III", "IVb", "IVa"})
        CHECK(svg.find("class=\"cone-label\">" + std::string(name) + "</text>") != std::string::npos);
    CHECK(count(svg, "class=\"image-label\"") == 6);
}

TEST_CASE("report: the XML checker itself rejects broken markup", "[report]") {
    CHECK_THROWS(xml_elements("<svg><g></svg></g>"));
    CHECK_THROWS(xml_elements("<svg><text>a < b</text></svg>"));
    CHECK_THROWS(xml_elements("<svg width=3></svg>"));
    CHECK_THROWS(xml_elements("<svg><text>&nbsp;</text></svg>"));
    CHECK_THROWS(xml_elements("<svg>"));
    CHECK_NOTHROW(xml_elements("<svg a=\"1\"><text>&#947;1 &amp; 2</text><rect/></svg>"));
}

TEST_CASE("report: markdown lists every obligation and every counterexample", "[report]") {
    const Model m(load_law_file(source_path("proofs/controls/missing-cone.json")));
    const VerifyReport r = verify(m);
    const std::string md = report_markdown(m, r);
    CHECK(md.find("**Verdict: refuted**") != std::string::npos);
    for (const auto& o : r.obligations)
        CHECK(md.find("| `" + o.id + "` |") != std::string::npos);
    CHECK(count(md, "```json") == 4); // fan, kinematic, nonexpansive, nonexpansive-lemma
    CHECK(md.find("\"gamma\": [") != std::string::npos);
}

TEST_CASE("report: the HTML page is self-contained and embeds the SVG for c = 2 and c = 3", "[report]") {
    const Model paper(paper_law());
    const std::string html = report_html(paper, verify(paper));
    CHECK(html.find("<svg") != std::string::npos);
    CHECK(html.find("src=") == std::string::npos);   // no external resources
    CHECK(html.find("href=") == std::string::npos);
    CHECK(html.find("<script") == std::string::npos);
    const Model four(load_law_file(source_path("proofs/newton4/law.json")));
    const std::string four_html = report_html(four, verify(four));
    CHECK(four_html.find("<svg") != std::string::npos);
    // Every one of the 24 cones is numbered on the sphere and named in its key.
    for (std::size_t k = 0; k < four.pieces().size(); ++k) {
        const std::string number = std::to_string(k + 1);
        CHECK(four_html.find("class=\"cone-label\">" + number + "</text>") != std::string::npos);
        CHECK(four_html.find(">" + number + "  " + xml_escape(four.pieces()[k].name) + "</text>") != std::string::npos);
    }
    const Model five(test::sorting_law(5));
    CHECK(cones_svg(five).empty()); // c = 4: no picture
}

TEST_CASE("report: impactcert report writes both files and exits 0 even for a refuted law", "[report][cli]") {
    const std::string dir = "/tmp/impactcert-report-test";
    const auto run = test::run_cli("report --law '" + source_path("proofs/controls/expansive-scaled.json") + "' -o " + dir);
    CHECK(run.status == 0);
    CHECK(test::read_file(dir + "/report.md").find("# impactcert report: control-expansive-scaled") == 0);
    CHECK(test::read_file(dir + "/report.html").find("<!DOCTYPE html>") == 0);
    std::remove((dir + "/report.md").c_str());
    std::remove((dir + "/report.html").c_str());
}

namespace {

// The sorting law of three balls with hostile names everywhere a name can go, and a wrong
// declared outcome (so that a counterexample carries the outcome's name).
Model hostile_law() {
    Law law = test::sorting_law(3);
    law.name = "evil|law\n# pwned <img src=x onerror=alert(1)> `tick` ```fence";
    const char* names[] = {"a|b", "line\nbreak", "```", "<script>alert(1)</script>", "# heading", "[link](http://x) *em* _u_ $x$ \x01"};
    for (std::size_t p = 0; p < law.pieces.size(); ++p)
        law.pieces[p].name = names[p % std::size(names)] + std::to_string(p);
    law.outcomes.push_back(OutcomeDecl{"out|come\n```\n<b>x</b>", test::vec({"1", "0", "0"}), test::vec({"0", "1", "0"})});
    return Model(law);
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::size_t from = 0;
    for (auto nl = text.find('\n'); nl != std::string::npos; nl = text.find('\n', from)) {
        out.push_back(text.substr(from, nl - from));
        from = nl + 1;
    }
    out.push_back(text.substr(from));
    return out;
}

std::size_t unescaped_pipes(const std::string& line) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < line.size(); ++i)
        n += (line[i] == '|' && (i == 0 || line[i - 1] != '\\')) ? 1 : 0;
    return n;
}

} // namespace

TEST_CASE("report: names cannot rewrite the markdown (tables, headings, fences, HTML)", "[report]") {
    const Model m = hostile_law();
    const VerifyReport r = verify(m);
    const std::string md = report_markdown(m, r);
    INFO(md);
    const auto lines = lines_of(md);
    // Only the title is a heading of level 1, and it is one line.
    CHECK(lines.front().rfind("# impactcert report: ", 0) == 0);
    for (std::size_t i = 1; i < lines.size(); ++i)
        CHECK(lines[i].rfind("# ", 0) != 0);
    // No raw HTML, no control characters.
    for (std::size_t i = md.find('<'); i != std::string::npos; i = md.find('<', i + 1))
        CHECK((i > 0 && md[i - 1] == '\\')); // every '<' escaped: no HTML tag
    CHECK(md.find('\x01') == std::string::npos);
    // Fences alternate ```json / ``` and nothing inside a fence starts one.
    bool in_fence = false;
    for (const auto& line : lines) {
        if (line.rfind("```", 0) != 0) {
            if (in_fence)
                CHECK(line.find("```") == std::string::npos);
            continue;
        }
        CHECK(line == (in_fence ? "```" : "```json"));
        in_fence = !in_fence;
    }
    CHECK_FALSE(in_fence);
    // The law table: one row per piece, four cell separators in every row.
    const auto header = std::find(lines.begin(), lines.end(), "| piece | rays | Q |");
    REQUIRE(header != lines.end());
    std::size_t rows = 0;
    for (auto it = header + 2; it != lines.end() && !it->empty(); ++it, ++rows)
        CHECK(unescaped_pipes(*it) == 4);
    CHECK(rows == m.pieces().size());
    // The outcome's counterexample still names it, in JSON that means the same (\u escapes).
    CHECK(md.find(R"("outcome": "out|come\n\u0060\u0060\u0060\n\u003cb\u003ex\u003c/b\u003e")") != std::string::npos);
}

TEST_CASE("report: the HTML page and its SVG escape hostile names", "[report]") {
    const Model m = hostile_law();
    const std::string html = report_html(m, verify(m));
    CHECK(html.find("<script") == std::string::npos);
    CHECK(html.find("<img") == std::string::npos);
    CHECK(html.find("<b>") == std::string::npos);
    CHECK(html.find('\x01') == std::string::npos); // not even valid as a character reference in XML
    CHECK(html.find("&lt;script&gt;") != std::string::npos);
    std::vector<std::string> elements;
    REQUIRE_NOTHROW(elements = xml_elements(cones_svg(m)));
    CHECK(std::count(elements.begin(), elements.end(), "polygon") == 12);
}

TEST_CASE("report: counterexamples are drawn on the cone picture (c = 2 and c = 3)", "[report]") {
    const Model m(load_law_file(source_path("proofs/controls/newton-simultaneous.json")));
    const VerifyReport r = verify(m);
    const std::string svg = cones_svg(m, &r);
    std::size_t marks = 0;
    for (auto at = svg.find("class=\"counterexample\""); at != std::string::npos;
         at = svg.find("class=\"counterexample\"", at + 1))
        ++marks;
    std::size_t expected = 0;
    for (const auto& o : r.obligations)
        if (o.verdict == Verdict::refuted)
            expected += o.counterexample.contains("gamma_a") ? 2 : (o.counterexample.contains("gamma") || o.counterexample.contains("ray")) ? 1 : 0;
    CHECK(marks == expected);
    CHECK(marks >= 3);
    CHECK(svg.find("<line x1=") != std::string::npos);
    CHECK(cones_svg(m).find("counterexample") == std::string::npos); // none without a report
    const Model gap(load_law_file(source_path("tests/laws/gap-newton4-missing-cone.json")));
    const VerifyReport rg = verify(gap);
    CHECK(cones_svg(gap, &rg).find("class=\"counterexample\"") != std::string::npos);
}

#include "derive/derive.hpp"

#include <cmath>

namespace {

// The start tags that contain `marker`, with the value of attribute `name` in each (no regex: GCC 12
// warns inside <regex> under the sanitizer build).
std::vector<double> attribute_of_tags(const std::string& svg, const std::string& marker, const std::string& name) {
    std::vector<double> out;
    for (auto at = svg.find(marker); at != std::string::npos; at = svg.find(marker, at + 1)) {
        const auto open = svg.rfind('<', at);
        const auto attr = svg.find(" " + name + "=\"", open);
        REQUIRE(attr != std::string::npos);
        REQUIRE(attr < at);
        out.push_back(std::stod(svg.substr(attr + name.size() + 3)));
    }
    return out;
}

} // namespace

TEST_CASE("report: a law of many thin cones stays legible (metric H, labels where they fit, hover, filter)", "[report]") {
    // A heavy ball against a light one at a wall: in gamma coordinates the cones squeeze against one line.
    DeriveOptions o;
    static_cast<System&>(o) = chain_system({Rational(1), Rational(100)}, Walls::left);
    o.restitution = {Rational(1), Rational(1)};
    o.rule = ImpactRule::left_first;
    const DeriveResult d = derive_sequential(o);
    REQUIRE(d.law);
    const Model m(*d.law);
    REQUIRE(m.pieces().size() > 40);
    const std::string svg = cones_svg(m);
    REQUIRE_NOTHROW(xml_elements(svg));
    // Labels only where they fit: far fewer than the pieces, and no two on top of each other.
    const std::vector<double> xs = attribute_of_tags(svg, "class=\"cone-label\"", "x"),
                              ys = attribute_of_tags(svg, "class=\"cone-label\"", "y");
    REQUIRE(xs.size() == ys.size());
    std::vector<std::pair<double, double>> labels;
    for (std::size_t i = 0; i < xs.size(); ++i)
        labels.push_back({xs[i], ys[i]});
    CHECK(labels.size() < m.pieces().size() / 2);
    for (std::size_t i = 0; i < labels.size(); ++i)
        for (std::size_t j = i + 1; j < labels.size(); ++j)
            CHECK(std::hypot(labels[i].first - labels[j].first, labels[i].second - labels[j].second) > 12);
    // Every piece is still named: on hover (its word, rays and matrix), in the cone panel and the strip.
    for (const auto& p : m.pieces()) {
        CHECK(count(svg, "<title>" + xml_escape(p.name) + ": rays ") == 2);
        CHECK(count(svg, "<title>image of " + xml_escape(p.name) + ": rays ") == 1);
    }
    CHECK(count(svg, "class=\"image-label\"") == 0); // one panel of images, not a thumbnail per piece
    CHECK(count(svg, "class=\"cone-band\"") == m.pieces().size());
    // In the metric H the bands of the strip have room: the thinnest is wider than a pixel.
    double thinnest = 1e9;
    for (auto at = svg.find("<g class=\"cone-band\">"); at != std::string::npos; at = svg.find("<g class=\"cone-band\">", at + 1)) {
        const auto rect = svg.find("<rect ", at);
        const auto width = svg.find(" width=\"", rect);
        REQUIRE(width != std::string::npos);
        thinnest = std::min(thinnest, std::stod(svg.substr(width + 8)));
    }
    CHECK(thinnest > 1.0);
    // The page's table can be filtered, one row per piece.
    // Drawing leaves the law alone (regression: the drawing scaled shared GMP values in place, so
    // the Model's rays and H changed and verify then threw on a non-symmetric H).
    CHECK(law_to_json(m.law()).dump() == law_to_json(*d.law).dump());
    const Model fresh(*d.law);
    CHECK(m.H() == fresh.H());
    for (std::size_t p = 0; p < m.pieces().size(); ++p)
        CHECK(m.pieces()[p].R == fresh.pieces()[p].R);
    const std::string html = report_html(m, verify(m));
    CHECK(html.find("id=\"filter\"") != std::string::npos);
    CHECK(count(html, "<tr class=\"piece\">") == m.pieces().size());
    // The paper's law keeps every label and thumbnail (six cones of 60 degrees in the metric H).
    const Model paper(paper_law());
    const std::string small = cones_svg(paper);
    CHECK(count(small, "class=\"cone-label\"") == 6);
    CHECK(count(small, "class=\"strip-label\"") == 6);
}

TEST_CASE("report: colour-blind-safe colours, a sentence for c >= 4, a summary-only markdown for large laws",
          "[report]") {
    // Okabe-Ito hues; none of the old red/green pair, counterexamples in black.
    const Model missing(load_law_file(source_path("proofs/controls/missing-cone.json")));
    const std::string html = report_html(missing, verify(missing));
    for (const char* old : {"#d00", "#cf222e", "#2da44e", "#1a7f37", "#4e79a7", "#e15759", "#59a14f"})
        CHECK(html.find(old) == std::string::npos);
    CHECK(html.find("#E69F00") != std::string::npos);
    CHECK(html.find("class=\"counterexample\"") != std::string::npos);
    CHECK(html.find("fill=\"#000\" stroke=\"#fff\" class=\"counterexample\"") != std::string::npos);
    // c = 4 (five balls, 120 pieces): the plane view (six planes), which the markdown points to;
    // the markdown lists no piece (more than 100) and stays small, the HTML lists them all.
    const Model five(test::sorting_law(5));
    const VerifyReport r5 = verify(five);
    const std::string md = report_markdown(five, r5), html5 = report_html(five, r5);
    CHECK(count(html5, "<g class=\"plane\">") == 6);
    CHECK(html5.find("No plane view") == std::string::npos);
    CHECK(md.find("on each plane of two contacts (figures/planes.svg)") != std::string::npos);
    CHECK(md.find("120 pieces: too many for a job summary") != std::string::npos);
    CHECK(md.find("| piece | rays | Q |") == std::string::npos);
    CHECK(md.size() < 8000);
    CHECK(count(html5, "<tr class=\"piece\">") == 120);
    // Negative control: a law of at most 100 pieces keeps its table in the markdown.
    const Model paper(paper_law());
    const std::string md3 = report_markdown(paper, verify(paper));
    CHECK(md3.find("| piece | rays | Q |") != std::string::npos);
    CHECK(md3.find("too many for a job summary") == std::string::npos);
    CHECK(md3.find("No picture") == std::string::npos);
}

TEST_CASE("figures: a converter that hangs is killed at its deadline with what it started, and no PDF is left",
          "[report][figures]") {
    const std::string dir = "/tmp/impactcert-figure-deadline";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir + "/bin");
    {
        std::ofstream fake(dir + "/bin/rsvg-convert");
        fake << "#!/bin/sh\nsleep 31.25\n"; // a child of the shell: killed with its process group
    }
    {
        // One that closes its output at once and goes on: its exit is awaited within the deadline.
        std::ofstream fake(dir + "/bin/closes-and-sleeps");
        fake << "#!/bin/sh\nexec >&-\nsleep 31.25\n";
    }
    std::filesystem::permissions(dir + "/bin/rsvg-convert", std::filesystem::perms::owner_all);
    const std::string path = std::getenv("PATH") ? std::getenv("PATH") : "/usr/bin:/bin";
    ::setenv("PATH", (dir + "/bin:" + path).c_str(), 1);
    const auto start = std::chrono::steady_clock::now();
    std::string error;
    try {
        write_figure(dir + "/x", standalone_figure("t", "", "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"></svg>\n", {}), 1);
    } catch (const InputError& e) {
        error = e.what();
    }
    CHECK(error == dir + "/x.pdf: the converter did not finish in 1 s");
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(20));
    std::filesystem::rename(dir + "/bin/closes-and-sleeps", dir + "/bin/rsvg-convert");
    std::filesystem::permissions(dir + "/bin/rsvg-convert", std::filesystem::perms::owner_all);
    error.clear();
    try {
        write_figure(dir + "/y", standalone_figure("t", "", "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"10\" height=\"10\"></svg>\n", {}), 1);
    } catch (const InputError& e) {
        error = e.what();
    }
    ::setenv("PATH", path.c_str(), 1);
    CHECK(error == dir + "/y.pdf: the converter did not finish in 1 s");
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(20));
    std::vector<std::string> left;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
        left.push_back(entry.path().filename().string());
    std::sort(left.begin(), left.end());
    CHECK(left == std::vector<std::string>{"bin", "x.svg", "y.svg"});
    std::filesystem::remove_all(dir);
    // Nothing of it is left running: no process's command line is "sleep 31.25".
    bool left_running = false;
    for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
        std::ifstream cmdline(entry.path() / "cmdline", std::ios::binary);
        const std::string text((std::istreambuf_iterator<char>(cmdline)), std::istreambuf_iterator<char>());
        left_running = left_running || text == std::string("sleep\0" "31.25\0", 12);
    }
    CHECK_FALSE(left_running);
}
