// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/verdict_output.hpp"

#include "base/junit.hpp"

#include <cstdio>

namespace impactcert {

Json verdict_json(const VerifyReport& report) {
    Json out;
    out["format"] = kVerdictFormat;
    out["law"] = report.law;
    out["verdict"] = report.verdict();
    Json list = Json::array();
    for (const auto& o : report.obligations) {
        Json item;
        item["id"] = o.id;
        item["claimed"] = o.claimed;
        item["verdict"] = to_string(o.verdict);
        item["checks"] = o.checks;
        if (o.verdict == Verdict::refuted)
            item["counterexample"] = o.counterexample;
        if (o.verdict == Verdict::undecided)
            item["limit"] = o.limit;
        list.push_back(std::move(item));
    }
    out["obligations"] = list;
    return out;
}

namespace {

// Milliseconds with microsecond resolution, for display only (never part of a verdict).
std::string milliseconds(std::chrono::nanoseconds t) {
    const long long us = std::chrono::duration_cast<std::chrono::microseconds>(t).count();
    char buf[32];
    std::snprintf(buf, sizeof buf, "%lld.%03lld ms", us / 1000, us % 1000);
    return buf;
}


std::string pad(std::string s, std::size_t width) {
    if (s.size() < width)
        s.append(width - s.size(), ' ');
    return s;
}

std::string pad_left(std::string s, std::size_t width) {
    if (s.size() < width)
        s.insert(0, width - s.size(), ' ');
    return s;
}

} // namespace

std::string xml_escape(const std::string& s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const char ch = s[i];
        // UTF-8 of U+FFFE, U+FFFF (EF BF BE/BF) and of the surrogates (ED A0..BF xx): not XML 1.0
        // characters either (a law named "x\uFFFEy" made every SVG invalid).
        const auto byte = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
        if ((byte(i) == 0xEF && byte(i + 1) == 0xBF && (byte(i + 2) == 0xBE || byte(i + 2) == 0xBF)) ||
            (byte(i) == 0xED && byte(i + 1) >= 0xA0 && byte(i + 1) <= 0xBF && byte(i + 2) >= 0x80 && byte(i + 2) <= 0xBF)) {
            out += "&#65533;";
            i += 2;
            continue;
        }
        switch (ch) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        case '\t': case '\n': case '\r': out += ch; break;
        default:
            // XML 1.0 has no other control characters, not even as references: U+FFFD.
            if (static_cast<unsigned char>(ch) < 0x20 || ch == '\x7f')
                out += "&#65533;";
            else
                out += ch;
        }
    }
    return out;
}

std::string shortened(const std::string& text, std::size_t limit) {
    if (text.size() <= limit)
        return text;
    std::size_t end = limit;
    while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80)
        --end;
    return text.substr(0, end) + "...";
}

std::string system_words(const Model& model) {
    const std::size_t n = model.balls(), c = model.normals(), t = model.tangents().size();
    const bool chain = !model.law().W && !model.law().M && !model.has_friction();
    const auto& vnames = model.law().velocity_names;
    const auto& cnames = model.law().contact_names;
    // A list of names in parentheses, up to 8 of them, each cut at 40 bytes (on a UTF-8 boundary)
    // and control characters blanked: the names come from the file. Callers escape the line for
    // Markdown or HTML.
    auto listed = [](const std::vector<std::string>& names) {
        if (names.empty() || names.size() > 8)
            return std::string();
        std::string s;
        for (std::string name : names) {
            if (name.size() > 40)
                name = shortened(name, 37);
            for (char& ch : name)
                if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f)
                    ch = ' ';
            s += (s.empty() ? " (" : ", ") + name;
        }
        return s + ")";
    };
    // Bodies of a scene: velocities named BODY.vx, BODY.vy, BODY.omega.
    std::vector<std::string> bodies;
    bool scene = !vnames.empty() && vnames.size() % 3 == 0;
    for (std::size_t b = 0; scene && b < vnames.size() / 3; ++b) {
        const std::string& vx = vnames[3 * b];
        const std::string body = vx.size() > 3 ? vx.substr(0, vx.size() - 3) : "";
        scene = !body.empty() && vx == body + ".vx" && vnames[3 * b + 1] == body + ".vy" && vnames[3 * b + 2] == body + ".omega";
        bodies.push_back(body);
    }
    std::string s;
    if (scene)
        s = std::to_string(bodies.size()) + (bodies.size() == 1 ? " body" : " bodies") + listed(bodies) + ", " +
            std::to_string(n) + " velocities, ";
    else
        s = std::to_string(n) + (chain ? (n == 1 ? " ball" : " balls") : (n == 1 ? " velocity" : " velocities")) +
            listed(vnames) + ", ";
    s += std::to_string(c) + (c == 1 ? " contact" : " contacts") + listed(cnames);
    if (t)
        s += " with " + std::to_string(t) + (t == 1 ? " friction tangent" : " friction tangents");
    if (model.redundant()) { // the law's coordinates: the columns kept, 1-based (normals, then tangents)
        std::string kept;
        for (const std::size_t k : model.basis())
            kept += (kept.empty() ? "" : ", ") + (k < c ? "N" + std::to_string(k + 1) : "T" + std::to_string(k - c + 1));
        s += ", on " + std::to_string(model.basis().size()) + " of " + std::to_string(c + t) + " columns (" + kept + ")";
    }
    return s;
}

std::string coordinate_svg(const Model& model, std::size_t k) {
    if (model.redundant()) // coordinate k is the velocity of basis column basis()[k]
        k = model.basis()[k];
    if (!model.has_friction())
        return "&#947;<tspan baseline-shift=\"sub\" font-size=\"75%\">" + std::to_string(k + 1) + "</tspan>";
    const bool normal = k < model.normals();
    return "&#947;<tspan baseline-shift=\"sub\" font-size=\"75%\">" + std::string(normal ? "N" : "T") +
           std::to_string(normal ? k + 1 : k - model.normals() + 1) + "</tspan>";
}

std::string verdict_table(const VerifyReport& report, const Model& model) {
    std::string table = verdict_table(report, model.balls(), model.contacts(), model.pieces().size());
    const std::string old_head = table.substr(0, table.find('\n'));
    const std::string head = "impactcert verify: " + report.law + " (" + system_words(model) + ", " +
                             std::to_string(model.pieces().size()) + " pieces)";
    return head + table.substr(old_head.size());
}

namespace {
// A right-aligned column, with a blank before a value as wide as the column (400 M checks, a
// verification of minutes) so that neighbouring columns never run together.
std::string column(const std::string& s, std::size_t width) {
    return s.size() >= width ? " " + s : pad_left(s, width);
}
} // namespace

std::string verdict_table(const VerifyReport& report, std::size_t balls, std::size_t contacts, std::size_t pieces) {
    std::string out = "impactcert verify: " + report.law + " (" + std::to_string(balls) +
                      " balls, " + std::to_string(contacts) + (contacts == 1 ? " contact, " : " contacts, ") +
                      std::to_string(pieces) + " pieces)\n";
    out += "  " + pad("obligation", 20) + pad("claimed", 9) + pad("verdict", 9) +
           pad_left("checks", 8) + pad_left("time", 13) + "   method\n";
    std::chrono::nanoseconds total{0};
    std::size_t claimed = 0, proved = 0;
    for (const auto& o : report.obligations) {
        total += o.elapsed;
        claimed += o.claimed ? 1 : 0;
        proved += (o.claimed && o.verdict == Verdict::proved) ? 1 : 0;
        out += "  " + pad(o.id, 20) + pad(o.claimed ? "yes" : "no", 9) + pad(to_string(o.verdict), 9) +
               column(std::to_string(o.checks), 8) + column(milliseconds(o.elapsed), 13) + "   " +
               o.method + "\n";
        if (o.verdict == Verdict::refuted)
            out += "      counterexample: " + o.counterexample.dump() + "\n";
        if (o.verdict == Verdict::undecided)
            out += "      limit: " + o.limit + "\n";
    }
    out += "verdict: " + std::string(report.verdict()) + " (" +
           std::to_string(proved) + "/" + std::to_string(claimed) +
           " claimed obligations proved, " + milliseconds(total) + ")\n";
    return out;
}

std::string verdict_junit(const VerifyReport& report) {
    JunitSuite suite{"impactcert verify " + report.law, {}};
    for (const auto& o : report.obligations) {
        JunitCase c;
        c.classname = "impactcert." + report.law;
        c.name = o.id;
        c.time = o.elapsed;
        const bool failed = o.claimed && o.verdict != Verdict::proved;
        if (failed) {
            const std::string witness = o.verdict == Verdict::undecided ? o.limit : o.counterexample.dump();
            c.kind = JunitCase::Kind::failed;
            c.type = to_string(o.verdict);
            c.message = o.id + " " + to_string(o.verdict) + ": " + witness;
            c.text = witness;
        } else if (!o.claimed || o.verdict == Verdict::skipped) {
            c.kind = JunitCase::Kind::skipped;
            c.message = o.verdict == Verdict::skipped ? "nothing declared to check"
                                                      : std::string("not claimed; ") + to_string(o.verdict) +
                                                            (o.verdict == Verdict::refuted     ? ": " + o.counterexample.dump()
                                                             : o.verdict == Verdict::undecided ? ": " + o.limit
                                                                                               : std::string());
        }
        suite.cases.push_back(std::move(c));
    }
    return junit_xml(suite);
}

} // namespace impactcert
