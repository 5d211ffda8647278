// SPDX-License-Identifier: GPL-3.0-or-later
#include "sweep/sweep.hpp"
#include "sweep/sweep_point.hpp"
#include "sweep/threshold.hpp"

#include "report/figure.hpp"
#include "exact/exact_conditions.hpp"

#include "base/errors.hpp"
#include "base/json.hpp"
#include "model/law_json.hpp"
#include "prover/obligations.hpp"
#include "base/output_file.hpp"
#include "prover/verdict_output.hpp"
#include "prover/certificate.hpp"
#include "prover/shard.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace impactcert {

namespace {

// The sweep's column for order independence (sweep.csv header, the phase map's title).
constexpr const char* kOrderColumn = "order-independent";

using sweep_detail::is_name;
using sweep_detail::number;

// Okabe & Ito (colour-blind safe): bluish green, vermillion, grey, orange; proved, refuted,
// skipped, undecided.
const char* kColour[] = {"#009E73", "#D55E00", "#BBBBBB", "#E69F00"};

std::string colour_of(const std::string& verdict) {
    if (verdict == "proved")
        return kColour[0];
    if (verdict == "refuted")
        return kColour[1];
    if (verdict == "skipped")
        return kColour[2];
    if (verdict == "undecided")
        return kColour[3];
    return "#24292f"; // no finite law
}

std::string csv_field(const std::string& s) {
    if (s.find_first_of(",\"\n") == std::string::npos)
        return s;
    std::string out = "\"";
    for (char ch : s)
        out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return out + "\"";
}

struct Point {
    std::vector<Rational> values; // one per parameter
};

} // namespace

// The sweep's inputs, in the order sweep.json and the parts write them: masses, restitution,
// rule, max_impacts, parameters with their grid values.
void put_inputs(Json& j, const SweepSpec& spec) {
    if (spec.system) {
        // The file's document as read (parse_system_text reads it again when parts are merged).
        j["system"] = Json::parse(spec.system_text);
        j["law"] = to_string(spec.law);
        j["restitution_on"] = spec.on == RestitutionOn::all ? "all" : "approaching";
    }
    if (spec.thresholds)
        j["threshold_digits"] = spec.threshold_digits;
    j["masses"] = spec.masses;
    j["restitution"] = spec.restitution;
    j["rule"] = to_string(spec.rule);
    j["max_impacts"] = spec.max_impacts;
    j["max_words"] = spec.max_words;
    Json params = Json::array();
    for (const auto& p : spec.parameters) {
        Json values = Json::array();
        for (const auto& v : p.values)
            values.push_back(to_string(v));
        params.push_back(Json{{"name", p.name}, {"values", values}});
    }
    j["parameters"] = params;
}

namespace {

// Order independence at a point (derive.hpp, `--rule any`): proved, refuted with the witness (two
// admissible words, or an admissible order longer than --max-impacts), or undecided at a limit.
Json order_entry(const DeriveOptions& o, std::size_t max_words) {
    try {
        const OrderResult r = order_independence(o, max_words);
        if (r.not_finite)
            return Json{{"verdict", "refuted"},
                        {"counterexample",
                         Json{{"gamma", to_json(*r.not_finite)}, {"word", word_text(r.long_word, o.restitution.size()) + "..."}}}};
        if (r.witness) {
            const std::size_t c = o.restitution.size();
            return Json{{"verdict", "refuted"},
                        {"counterexample",
                         Json{{"gamma", to_json(r.witness->gamma_minus)},
                              {"words", Json::array({word_text(r.witness->word_a, c), word_text(r.witness->word_b, c)})},
                              {"gamma_plus", Json::array({to_json(r.witness->gamma_a), to_json(r.witness->gamma_b)})}}}};
        }
        return Json{{"verdict", "proved"}};
    } catch (const DeriveLimit& e) {
        return Json{{"verdict", "undecided"}, {"limit", e.what()}};
    }
}

// Derive and verify one grid point.
Json evaluate(const SweepSpec& spec, const Point& point) {
    Json out;
    Json at = Json::object();
    for (std::size_t p = 0; p < spec.parameters.size(); ++p)
        at[spec.parameters[p].name] = to_string(point.values[p]);
    out["point"] = at;
    sweep_detail::PointLaw d = sweep_detail::law_at(spec, point.values);
    out["derive"] = d.derive;
    if (d.derive != "ok") {
        out[sweep_detail::detail_key(d.derive)] = d.detail;
        return out;
    }
    out["pieces"] = d.law->pieces.size();
    out["max_word"] = d.max_word;
    const Model model(*d.law);
    const VerifyReport r = verify(model, spec.limits);
    Json obligations = Json::object();
    for (const auto& ob : r.obligations) {
        Json item = Json{{"verdict", to_string(ob.verdict)}};
        if (ob.verdict == Verdict::refuted)
            item["counterexample"] = ob.counterexample;
        if (ob.verdict == Verdict::undecided)
            item["limit"] = ob.limit;
        obligations[ob.id] = item;
    }
    out["obligations"] = obligations;
    // Every admissible order: a frictionless sequential law's question (a simultaneous law has
    // no order of impacts; with friction the process is not offered).
    out["order"] = d.sequential ? order_entry(*d.sequential, spec.max_words) : Json{{"verdict", "skipped"}};
    return out;
}

// x rounded down to `digits` decimals, as text (exact: integer arithmetic).
std::string decimal_text(const Rational& x, int digits) {
    mpz_class scale = 1;
    for (int i = 0; i < digits; ++i)
        scale *= 10;
    mpz_class q;
    const mpz_class num = mpz_class(mpq_numref(x.mpq())) * scale;
    mpz_fdiv_q(q.get_mpz_t(), num.get_mpz_t(), mpq_denref(x.mpq()));
    const bool negative = q < 0;
    if (negative)
        q = -q;
    std::string t = q.get_str();
    if (digits > 0) {
        if (t.size() <= static_cast<std::size_t>(digits))
            t.insert(0, static_cast<std::size_t>(digits) + 1 - t.size(), '0');
        t.insert(t.size() - static_cast<std::size_t>(digits), ".");
    }
    return (negative ? "-" : "") + t;
}

// A grid value for an axis tick: an integer as it is, else three decimals without trailing zeros;
// beyond 10^6 or below 10^-3, four significant digits with an exponent ("1e+50000": a tick of a
// grid up to 10^100000 was a label of 50,001 digits, which a PDF converter took minutes to lay out).
std::string tick_text(const Rational& v) {
    const Rational a = abs_of(v);
    if (sign_of(v) != Sign::zero && (a >= Rational(1000000) || a < Rational(1, 1000)))
        return readable_text(v, 4);
    if (v.denominator() == CGAL::Gmpz(1))
        return to_string(v);
    std::string t = decimal_text(v, 3);
    while (!t.empty() && t.back() == '0')
        t.pop_back();
    if (!t.empty() && t.back() == '.')
        t.pop_back();
    return t;
}

// The exact continuity conditions of the sweep's family (exact_conditions.hpp), when it is a
// three-ball chain under most-negative; curves with the crossings of every line, checks at the
// rational crossings of grid lines.
struct SweepConditions {
    ConditionFamily family;
    ConditionsResult result;
};

SweepConditions sweep_conditions(const SweepSpec& spec) {
    SweepConditions c;
    c.family.masses = spec.masses;
    c.family.restitution = spec.restitution;
    c.family.max_impacts = spec.max_impacts;
    for (const auto& p : spec.parameters)
        c.family.parameters.push_back({p.name, p.values});
    if (spec.system || spec.law != SweepLaw::sequential) {
        c.result.why_not = "computed for the sequential law of a three-ball chain only";
        return c;
    }
    if (spec.rule != ImpactRule::most_negative) {
        c.result.why_not = "the rule is not most-negative (index rules have no tie jump)";
        return c;
    }
    c.result = continuity_conditions(c.family);
    return c;
}

// Where the derived laws conserve energy (P2), exactly: a sequential law conserves energy iff
// every contact's restitution is 1 (an impact at contact k loses (1 - e_k^2) gamma_k^2 / (2 G_kk),
// and every contact of a chain takes the first impact on an open set of gamma-: proofs/README.md,
// "Where continuity holds"). So: everywhere, nowhere, or where each restitution parameter is 1.
Json energy_condition(const SweepSpec& spec) {
    if (spec.system || spec.law != SweepLaw::sequential)
        return Json{{"holds", "not computed"}, {"why", "computed for the sequential law of a chain only"}};
    std::vector<std::string> lines;
    for (const auto& e : spec.restitution) {
        bool is_parameter = false;
        for (const auto& p : spec.parameters)
            is_parameter = is_parameter || p.name == e;
        if (is_parameter) {
            if (std::find(lines.begin(), lines.end(), e + " = 1") == lines.end())
                lines.push_back(e + " = 1");
        } else if (number(e, "--restitution") != Rational(1)) {
            return Json{{"holds", "nowhere"}, {"why", "restitution " + e + " < 1"}};
        }
    }
    if (lines.empty())
        return Json{{"holds", "everywhere"}};
    std::string where;
    for (const auto& l : lines)
        where += (where.empty() ? "" : " and ") + l;
    return Json{{"holds", "where " + where}};
}

// A law on a continuity curve, derived and verified at its exact point: the verdicts the curve
// predicts (P1, nonexpansive) and the order column.
Json check_at(const SweepSpec& spec, const Point& at) {
    const Json r = evaluate(spec, at);
    Json check;
    check["point"] = r["point"];
    check["derive"] = r["derive"];
    if (r["derive"] == "ok") {
        check["P1"] = r["obligations"]["P1"]["verdict"];
        check["nonexpansive"] = r["obligations"]["nonexpansive"]["verdict"];
        check["order-independent"] = r["order"]["verdict"];
    }
    return check;
}

// A parameter value's horizontal (or vertical) position on a map: the grid values sit at the
// cells' centres, values between them linearly in between; tenths of a pixel, exact.
Rational map_position(const std::vector<Rational>& values, const Rational& v, int cell) {
    // A grid may run either way (--vary m=2..1/2:3).
    const bool down = values.size() > 1 && values.back() < values.front();
    std::size_t i = 0;
    while (i + 2 < values.size() && (down ? v < values[i + 1] : values[i + 1] < v))
        ++i;
    Rational t(0);
    if (values.size() > 1 && values[i + 1] != values[i])
        t = (v - values[i]) / (values[i + 1] - values[i]);
    return (Rational(static_cast<long>(i)) + t) * Rational(cell) + Rational(cell, 2);
}

// Round-number ticks for an axis over the grid's values: on a log grid 1, 2, 5 times powers of
// ten (only the powers when that gives more than eight), on a linear one multiples of 1, 2, 2.5 or
// 5 times a power of ten, the finest step with at most eight ticks; each placed where it falls
// between the grid values (map_position). Fewer than two: the grid values themselves (as before).
std::vector<Rational> round_ticks(const std::vector<Rational>& values, bool log) {
    // The fallback: every k-th grid value and the last (at most about eight), as before.
    auto grid_ticks = [&values]() {
        std::vector<Rational> g;
        const std::size_t k = std::max<std::size_t>(1, (values.size() + 7) / 8);
        for (std::size_t i = 0; i < values.size(); ++i)
            if (i % k == 0 || i + 1 == values.size())
                g.push_back(values[i]);
        return g;
    };
    std::vector<Rational> out;
    if (values.size() < 2)
        return grid_ticks();
    const Rational lo = *std::min_element(values.begin(), values.end()), hi = *std::max_element(values.begin(), values.end());
    if (!(lo < hi))
        return grid_ticks();
    const Rational ten(10);
    // Grids of any scale are allowed (10^-100000..): beyond 60 decades from 1 or across the grid,
    // the grid values themselves (no loop over the decades in between).
    constexpr int kDecades = 60;
    // The power of ten 10^k <= x < 10^(k+1) (x > 0), when |k| < kDecades.
    auto decade_of = [&ten](const Rational& x) -> std::optional<Rational> {
        Rational t(1);
        for (int steps = 0; t > x || t * ten <= x; ++steps) {
            if (steps >= kDecades)
                return std::nullopt;
            t = t > x ? t / ten : t * ten;
        }
        return t;
    };
    if (log && sign_of(lo) == Sign::positive) {
        const auto start = decade_of(lo);
        if (!start)
            return grid_ticks();
        const Rational& t = *start;
        for (const bool powers_only : {false, true}) {
            out.clear();
            int decades = 0;
            for (Rational d = t; d <= hi && ++decades < kDecades; d *= ten)
                for (const long c : {1L, 2L, 5L})
                    if ((!powers_only || c == 1) && lo <= Rational(c) * d && Rational(c) * d <= hi)
                        out.push_back(Rational(c) * d);
            if (out.size() <= 8)
                break;
        }
    } else {
        const auto span_decade = decade_of(hi - lo);
        if (!span_decade)
            return grid_ticks();
        Rational decade = *span_decade / Rational(100); // start fine, grow until at most eight ticks
        bool done = false;
        for (int guard = 0; guard < 12 && !done; ++guard, decade *= ten)
            for (const Rational& m : {Rational(1), Rational(2), Rational(5, 2), Rational(5)}) {
                const Rational step = m * decade;
                // the multiples of step in [lo, hi]
                Rational first = lo / step;
                mpz_t c;
                mpz_init(c);
                mpz_cdiv_q(c, mpq_numref(first.mpq()), mpq_denref(first.mpq()));
                Rational k;
                mpq_set_z(k.mpq(), c);
                mpz_clear(c);
                std::vector<Rational> ticks;
                for (Rational v = k * step; v <= hi && ticks.size() <= 8; v += step)
                    ticks.push_back(v);
                if (ticks.size() <= 8) {
                    out = std::move(ticks);
                    done = true;
                    break;
                }
            }
    }
    if (out.size() < 2 || out.size() > 8)
        return grid_ticks();
    return out;
}

std::string curve_label(const ConditionCurve& curve) {
    return "after the tie: " + curve.word_a + " / " + curve.word_b + " (" + std::to_string(curve.word_a.size()) + " and " +
           std::to_string(curve.word_b.size()) + " impacts): " + curve.polynomial + " = 0";
}

std::string svg_map(const SweepSpec& spec, const std::vector<Json>& results, const std::string& id,
                    const SweepConditions* conditions = nullptr) {
    const int cell = 22, margin = 60;
    const std::size_t n0 = spec.parameters[0].values.size();
    const std::size_t n1 = spec.parameters.size() > 1 ? spec.parameters[1].values.size() : 1;
    const int width = margin + static_cast<int>(n0) * cell + 20, height = static_cast<int>(n1) * cell + 46;
    std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" +
                    std::to_string(height) + "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    for (std::size_t i = 0; i < n0; ++i)
        for (std::size_t j = 0; j < n1; ++j) {
            const Json& r = results[i * n1 + j];
            std::string verdict = "no finite law", detail;
            if (r["derive"] == "ok") {
                const Json& o = id == kOrderColumn ? r["order"] : r["obligations"][id];
                verdict = o["verdict"].get<std::string>();
                if (o.contains("counterexample"))
                    detail = " " + o["counterexample"].dump();
                if (o.contains("limit"))
                    detail = " " + o["limit"].get<std::string>();
            } else if (r["derive"] == "undecided") {
                verdict = "undecided";
                detail = " derivation beyond a limit: " + r["limit"].get<std::string>();
            } else if (r["derive"] == "not-a-function") {
                verdict = "no law";
                detail = " (not a function) " + r["not_a_function"].dump();
            } else {
                detail = " gamma- = " + r["not_finite"]["gamma"].dump() + " needs more than " +
                         std::to_string(spec.max_impacts) + " impacts";
            }
            std::string where;
            for (auto it = r["point"].begin(); it != r["point"].end(); ++it)
                where += (where.empty() ? "" : ", ") + it.key() + " = " + it.value().get<std::string>();
            const int x = margin + static_cast<int>(i) * cell;
            const int y = 10 + static_cast<int>(n1 - 1 - j) * cell;
            s += "<rect x=\"" + std::to_string(x) + "\" y=\"" + std::to_string(y) + "\" width=\"" +
                 std::to_string(cell - 1) + "\" height=\"" + std::to_string(cell - 1) + "\" fill=\"" +
                 colour_of(verdict) + "\"><title>" + xml_escape(where + ": " + verdict + detail) + "</title></rect>\n";
        }
    if (conditions && conditions->result.computed) {
        // The continuity set: dots at the certified crossings of every grid and drawing line.
        std::vector<std::pair<Rational, Rational>> labels;
        for (const auto& curve : conditions->result.curves) {
            if (curve.isolated) {
                for (const auto& at : curve.points) {
                    const Rational px = Rational(margin) + map_position(spec.parameters[0].values, at[0], cell);
                    Rational py = Rational(10 + cell / 2);
                    if (at.size() > 1)
                        py = Rational(10 + static_cast<int>(n1) * cell) - map_position(spec.parameters[1].values, at[1], cell);
                    s += "<circle cx=\"" + decimal_text(px, 1) + "\" cy=\"" + decimal_text(py, 1) +
                         "\" r=\"3\" fill=\"#ffffff\" stroke=\"#000000\"><title>" +
                         xml_escape("after the tie: " + curve.word_a + " / " + curve.word_b +
                                    ": an isolated point where the jump vanishes") + "</title></circle>\n";
                }
                continue;
            }
            if (curve.whole_cell)
                continue;
            // White dots with a black rim: seen on every cell colour, the dark "no finite law" too.
            s += "<g fill=\"#ffffff\" stroke=\"#000000\" stroke-width=\"0.7\"><title>" + xml_escape(curve_label(curve)) + "</title>\n";
            std::optional<std::pair<Rational, Rational>> label_at;
            for (const auto& x : curve.crossings) {
                const Rational mid = (x.lo + x.hi) / Rational(2);
                const Rational v0 = x.varies == 0 ? mid : x.at;
                const Rational px = Rational(margin) + map_position(spec.parameters[0].values, v0, cell);
                Rational py = Rational(10 + cell / 2);
                if (spec.parameters.size() > 1) {
                    const Rational v1 = x.varies == 1 ? mid : x.at;
                    py = Rational(10 + static_cast<int>(n1) * cell) -
                         map_position(spec.parameters[1].values, v1, cell);
                }
                // Large: a rational point on a grid line, derived and verified (sweep.json "checks").
                s += "<circle cx=\"" + decimal_text(px, 1) + "\" cy=\"" + decimal_text(py, 1) + "\" r=\"" +
                     (x.exact && x.grid_line ? "3" : "1.6") + "\"/>";
                if (!label_at || py < label_at->second)
                    label_at = std::make_pair(px, py);
            }
            s += "</g>\n";
            // The curve's label, its impact count after the tie, at its highest dot, where no other
            // label is within 12 pixels (the rest on hover).
            bool room = label_at.has_value();
            for (const auto& [lx, ly] : labels)
                room = room && (abs_of(lx - label_at->first) > Rational(12) || abs_of(ly - label_at->second) > Rational(12));
            if (room) {
                labels.push_back(*label_at);
                s += "<text x=\"" + decimal_text(label_at->first + Rational(4), 1) + "\" y=\"" +
                     decimal_text(label_at->second - Rational(2), 1) + "\" font-size=\"10\" fill=\"#000000\" stroke=\"#ffffff\" stroke-width=\"2.5\" paint-order=\"stroke\" class=\"curve-label\">" +
                     std::to_string(curve.word_a.size()) + "</text>\n";
            }
        }
    }
    // Axes with round-number ticks (at most eight per axis), exact values on hover.
    const auto& p0 = spec.parameters[0];
    const int bottom = 10 + static_cast<int>(n1) * cell;
    for (const Rational& v : round_ticks(p0.values, p0.log)) {
        const std::string x = decimal_text(Rational(margin) + map_position(p0.values, v, cell), 1);
        s += "<line x1=\"" + x + "\" y1=\"" + std::to_string(bottom) + "\" x2=\"" + x + "\" y2=\"" + std::to_string(bottom + 4) +
             "\" stroke=\"#444\"/><text x=\"" + x + "\" y=\"" + std::to_string(bottom + 14) +
             "\" text-anchor=\"middle\" font-size=\"9\"><title>" + xml_escape(p0.name + " = " + to_string(v)) + "</title>" +
             xml_escape(tick_text(v)) + "</text>\n";
    }
    s += "<text x=\"" + std::to_string(margin + static_cast<int>(n0) * cell / 2) + "\" y=\"" +
         std::to_string(bottom + 28) + "\" text-anchor=\"middle\" font-weight=\"bold\">" + xml_escape(p0.name) + "</text>\n";
    if (spec.parameters.size() > 1) {
        const auto& p1 = spec.parameters[1];
        for (const Rational& v : round_ticks(p1.values, p1.log)) {
            const Rational yr = Rational(10 + static_cast<int>(n1) * cell) - map_position(p1.values, v, cell);
            const std::string y = decimal_text(yr, 1), y3 = decimal_text(yr + Rational(3), 1);
            s += "<line x1=\"" + std::to_string(margin - 4) + "\" y1=\"" + y + "\" x2=\"" + std::to_string(margin) + "\" y2=\"" + y +
                 "\" stroke=\"#444\"/><text x=\"" + std::to_string(margin - 6) + "\" y=\"" + y3 +
                 "\" text-anchor=\"end\" font-size=\"9\"><title>" + xml_escape(p1.name + " = " + to_string(v)) + "</title>" +
                 xml_escape(tick_text(v)) + "</text>\n";
        }
        s += "<text x=\"4\" y=\"" + std::to_string(10 + static_cast<int>(n1) * cell / 2) + "\" font-weight=\"bold\">" +
             xml_escape(p1.name) + "</text>\n";
    }
    return s + "</svg>\n";
}

// Whole or absent (output_file.hpp): a killed run leaves the previous file or none.
void write(const std::string& path, const std::string& text) { write_file(path, text); }

} // namespace

SweepParameter parse_vary(const std::string& text) {
    const auto eq = text.find('=');
    const auto dots = text.find("..");
    const auto colon = text.find(':', dots == std::string::npos ? 0 : dots);
    if (eq == std::string::npos || dots == std::string::npos || colon == std::string::npos || dots < eq)
        throw InputError("--vary: \"" + text + "\": expected NAME=LO..HI:COUNT[:log]");
    SweepParameter p;
    p.name = text.substr(0, eq);
    if (!is_name(p.name))
        throw InputError("--vary: \"" + p.name + "\" is not a parameter name (letters, digits, _)");
    const Rational lo = number(text.substr(eq + 1, dots - eq - 1), "--vary " + p.name);
    const Rational hi = number(text.substr(dots + 2, colon - dots - 2), "--vary " + p.name);
    std::string rest = text.substr(colon + 1);
    bool log = false;
    if (rest.size() > 4 && rest.substr(rest.size() - 4) == ":log") {
        log = true;
        rest = rest.substr(0, rest.size() - 4);
    }
    if (rest.empty() || rest.size() > 5 || !std::all_of(rest.begin(), rest.end(), [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)); }))
        throw InputError("--vary " + p.name + ": COUNT must be an integer from 1 to 10000, got \"" + rest + "\"");
    const std::size_t count = std::stoul(rest);
    if (count < 1 || count > 10000)
        throw InputError("--vary " + p.name + ": COUNT must be an integer from 1 to 10000, got " + rest);
    if (log && (sign_of(lo) != Sign::positive || sign_of(hi) != Sign::positive))
        throw InputError("--vary " + p.name + ": a log grid needs LO > 0 and HI > 0");
    p.lo = lo;
    p.hi = hi;
    p.count = count;
    p.log = log;
    return p;
}

void run_sweep(SweepSpec spec, const std::string& dir, const std::function<void(std::size_t, std::size_t)>& progress) {
    if (spec.parameters.empty() || spec.parameters.size() > 2)
        throw InputError("--vary: give one or two parameters");
    for (std::size_t a = 0; a < spec.parameters.size(); ++a)
        for (std::size_t b = a + 1; b < spec.parameters.size(); ++b)
            if (spec.parameters[a].name == spec.parameters[b].name)
                throw InputError("--vary: parameter \"" + spec.parameters[a].name + "\" given twice");
    if (spec.thresholds && spec.parameters.size() != 1)
        throw InputError("--thresholds: give exactly one --vary parameter");
    if (spec.thresholds && (spec.threshold_digits < 1 || spec.threshold_digits > 100))
        throw InputError("--threshold-digits: expected 1 to 100");
    auto check = [&](const std::string& name, const Rational& x, bool mass) {
        if (mass && sign_of(x) != Sign::positive)
            throw InputError("--masses: " + name + " = " + to_string(x) + " is not a positive mass");
        if (!mass && (sign_of(x) == Sign::negative || x > Rational(1)))
            throw InputError("--restitution: " + name + " = " + to_string(x) + " is outside [0, 1]");
    };
    if (!spec.system) {
        // Every input is validated before any work (bad input is exit 2 with one line): the
        // names, the constants, then the size of the grid, then each parameter's values.
        sweep_detail::validate_parameters(spec);
        for (const auto* list : {&spec.masses, &spec.restitution})
            for (const auto& item : *list)
                if (!is_name(item))
                    check(item, number(item, list == &spec.masses ? "--masses" : "--restitution"), list == &spec.masses);
        if (spec.masses.size() < 2)
            throw InputError("--masses: a chain needs at least two balls");
        if (spec.restitution.size() != 1 && spec.restitution.size() != spec.masses.size() - 1)
            throw InputError("--restitution: expected one value or one per contact (" + std::to_string(spec.masses.size() - 1) + ")");
    }
    std::size_t total = 1;
    for (const auto& p : spec.parameters)
        total *= p.count; // at most 10,000^2: no overflow
    if (total > spec.max_points)
        throw SweepLimit("the grid has " + std::to_string(total) + " points, more than " + std::to_string(spec.max_points) +
                         " (raise it with --max-points)");
    std::vector<SweepParameter> gridded = spec.parameters;
    for (auto& p : gridded) {
        p.values = grid_values(p);
        if (!spec.system)
            for (const auto& x : p.values) {
                for (const auto& m : spec.masses)
                    if (m == p.name)
                        check(p.name, x, true);
                for (const auto& e : spec.restitution)
                    if (e == p.name)
                        check(p.name, x, false);
            }
    }
    spec.parameters = gridded;
    if (spec.system)
        sweep_detail::validate_parameters(spec); // names, contacts and every grid value
    const auto& params = spec.parameters;
    std::vector<Point> points;
    const std::size_t n1 = params.size() > 1 ? params[1].values.size() : 1;
    for (const auto& v0 : params[0].values)
        for (std::size_t j = 0; j < n1; ++j) {
            Point pt;
            pt.values.push_back(v0);
            if (params.size() > 1)
                pt.values.push_back(params[1].values[j]);
            points.push_back(pt);
        }
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());

    // A shard evaluates its own points only (k mod N = K - 1), in the same order.
    std::vector<std::size_t> mine;
    for (std::size_t k = 0; k < points.size(); ++k)
        if (!spec.shard || owns(*spec.shard, k))
            mine.push_back(k);
    std::vector<Json> results(points.size());
    const unsigned jobs = std::max(1u, std::min<unsigned>(spec.jobs, static_cast<unsigned>(std::max<std::size_t>(1, mine.size()))));
    if (jobs == 1) {
        for (std::size_t m = 0; m < mine.size(); ++m) {
            results[mine[m]] = evaluate(spec, points[mine[m]]);
            if (progress)
                progress(m + 1, mine.size());
        }
    } else {
        // Worker processes (PPL is not thread-safe): worker w takes the points k = w mod jobs,
        // writes one JSON line per point to its part file and one byte per point to a pipe.
        // The part files are created (and must be writable) before any worker starts.
        for (unsigned w = 0; w < jobs; ++w) {
            const std::string path = dir + "/.sweep-part-" + std::to_string(w);
            std::ofstream part(path, std::ios::binary | std::ios::trunc);
            if (!part)
                throw InputError(path + ": cannot write a worker's part file");
        }
        int fds[2];
        if (pipe(fds) != 0)
            throw std::runtime_error("sweep: cannot create a pipe");
        std::vector<pid_t> workers;
        for (unsigned w = 0; w < jobs; ++w) {
            const pid_t pid = fork();
            if (pid == 0) {
                close(fds[0]);
                std::ofstream part(dir + "/.sweep-part-" + std::to_string(w), std::ios::binary);
                int status = 0;
                try {
                    for (std::size_t m = w; m < mine.size(); m += jobs) {
                        const std::size_t k = mine[m];
                        part << k << "\t" << evaluate(spec, points[k]).dump() << "\n";
                        part.flush();
                        if (!part) {
                            status = 2; // the part file cannot be written (a full disk)
                            break;
                        }
                        const char one = '.';
                        if (::write(fds[1], &one, 1) != 1)
                            status = 1;
                    }
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "impactcert: sweep worker: %s\n", e.what());
                    status = 4;
                }
                close(fds[1]);
                std::_Exit(status);
            }
            if (pid < 0)
                throw std::runtime_error("sweep: cannot start a worker process");
            workers.push_back(pid);
        }
        close(fds[1]);
        std::size_t done = 0;
        char buf[256];
        for (ssize_t got; (got = read(fds[0], buf, sizeof buf)) > 0;) {
            done += static_cast<std::size_t>(got);
            if (progress)
                progress(done, mine.size());
        }
        close(fds[0]);
        bool lost_write = false, failed = false;
        for (auto pid : workers) {
            int status = 0;
            waitpid(pid, &status, 0);
            lost_write = lost_write || (WIFEXITED(status) && WEXITSTATUS(status) == 2);
            failed = failed || !WIFEXITED(status) || (WEXITSTATUS(status) != 0 && WEXITSTATUS(status) != 2);
        }
        if (failed)
            throw std::runtime_error("sweep: a worker process failed");
        if (lost_write)
            throw InputError(dir + ": cannot write a worker's part file (disk full?)");
        for (unsigned w = 0; w < jobs; ++w) {
            const std::string path = dir + "/.sweep-part-" + std::to_string(w);
            std::ifstream part(path, std::ios::binary);
            std::string line;
            while (std::getline(part, line)) {
                const auto tab = line.find('\t');
                std::size_t k = points.size();
                try {
                    k = std::stoul(line.substr(0, tab));
                    if (k >= points.size())
                        throw std::out_of_range("index");
                    results[k] = Json::parse(line.substr(tab + 1));
                } catch (const std::exception&) {
                    throw InputError(path + ": a worker's part file was changed or cut short while the sweep ran");
                }
            }
            std::filesystem::remove(path, ec);
        }
    }

    for (const std::size_t k : mine)
        if (!results[k].is_object())
            throw InputError(dir + ": the result of grid point " + std::to_string(k + 1) + " is missing from the part files");
    if (spec.shard) {
        write_sweep_part(spec, results, mine, dir);
        return;
    }
    write_sweep_outputs(spec, results, dir);
}

namespace {

// What identifies a run: every input that can change a verdict (not --jobs).
Json run_json(const SweepSpec& spec) {
    Json run;
    put_inputs(run, spec);
    run["limits"] = Json{{"max_faces", spec.limits.max_faces},     {"max_chambers", spec.limits.max_chambers},
                         {"max_subsets", spec.limits.max_subsets}, {"max_pieces", spec.limits.max_pieces},
                         {"max_memory", spec.limits.max_memory_mb}};
    return run;
}

std::string part_digest(const Json& part) {
    Json body = part;
    body.erase("sha256");
    return sha256_hex(body.dump());
}

} // namespace

std::string sweep_part_path(const std::string& dir, const Shard& shard) {
    return dir + "/sweep.part-" + std::to_string(shard.index + 1) + "-of-" + std::to_string(shard.count) + ".json";
}

void write_sweep_part(const SweepSpec& spec, const std::vector<Json>& results, const std::vector<std::size_t>& mine,
                      const std::string& dir) {
    Json part;
    part["format"] = kSweepPartFormat;
    part["shard"] = Json{{"index", spec.shard->index + 1}, {"count", spec.shard->count}};
    part["run"] = run_json(spec);
    Json points = Json::array();
    for (const std::size_t k : mine) {
        Json entry = Json{{"index", k}};
        for (auto it = results[k].begin(); it != results[k].end(); ++it)
            entry[it.key()] = it.value();
        points.push_back(std::move(entry));
    }
    part["points"] = std::move(points);
    part["sha256"] = part_digest(part);
    write(sweep_part_path(dir, *spec.shard), part.dump(1) + "\n");
}

namespace {

// A point's result as write_sweep_outputs reads it; InputError naming the place otherwise.
void check_point_shape(const Json& r, const std::string& where, bool friction) {
    auto fail = [&](const std::string& what) { throw InputError(where + "." + what); };
    if (!r.contains("point") || !r["point"].is_object())
        fail("point: expected an object");
    for (auto it = r["point"].begin(); it != r["point"].end(); ++it)
        if (!it.value().is_string())
            fail("point." + it.key() + ": expected a string");
    if (!r.contains("derive") || !r["derive"].is_string())
        fail("derive: expected a string");
    const std::string derive = r["derive"].get<std::string>();
    if (derive != "ok" && derive != "not-finite" && derive != "not-a-function" && derive != "undecided")
        fail("derive: expected ok, not-finite, not-a-function or undecided");
    // Exactly the keys a single run writes for this kind of point.
    const std::vector<std::string> keys = derive == "ok" ? std::vector<std::string>{"point", "derive", "pieces", "max_word", "obligations", "order"}
                                                         : std::vector<std::string>{"point", "derive", sweep_detail::detail_key(derive)};
    for (auto it = r.begin(); it != r.end(); ++it)
        if (std::find(keys.begin(), keys.end(), it.key()) == keys.end())
            fail(it.key() + ": not written for a point whose derivation is " + derive);
    for (const auto& key : keys)
        if (!r.contains(key))
            fail(key + ": missing");
    if (derive != "ok")
        return;
    for (const char* key : {"pieces", "max_word"})
        if (!r.contains(key) || !r[key].is_number_unsigned())
            fail(std::string(key) + ": expected a non-negative integer");
    if (!r.contains("obligations") || !r["obligations"].is_object())
        fail("obligations: expected an object");
    // A verdict is one of the four words a run writes (a part's hash is no proof of origin: it
    // is recomputed by anyone, and a verdict is written into sweep.csv and sweep.html as is).
    auto verdict_word = [](const Json& v) {
        return v.is_string() && (v == "proved" || v == "refuted" || v == "undecided" || v == "skipped");
    };
    for (const char* id : obligation_ids(friction))
        if (!r["obligations"].contains(id) || !r["obligations"][id].is_object() ||
            !r["obligations"][id].contains("verdict") || !verdict_word(r["obligations"][id]["verdict"]))
            fail(std::string("obligations.") + id + ".verdict: expected proved, refuted, undecided or skipped");
    if (!r["order"].is_object() || !r["order"].contains("verdict") || !verdict_word(r["order"]["verdict"]))
        fail("order.verdict: expected proved, refuted, undecided or skipped");
}

} // namespace

void merge_sweep_parts(const std::vector<std::string>& paths, const std::string& dir, std::size_t max_points) {
    if (paths.empty())
        throw InputError("--merge: no part files given");
    std::vector<Json> parts;
    for (const auto& path : paths) {
        const std::string text = read_file_text(path);
        Json part;
        try {
            part = Json::parse(text);
        } catch (const Json::exception&) {
            throw InputError(path + ": not JSON (a sweep part, " + std::string(kSweepPartFormat) + ")");
        }
        if (!part.is_object() || part.value("format", "") != kSweepPartFormat)
            throw InputError(path + ": $.format: not an " + std::string(kSweepPartFormat) + " document");
        for (const char* key : {"shard", "run", "points", "sha256"})
            if (!part.contains(key))
                throw InputError(path + ": $." + key + ": missing");
        if (!part["sha256"].is_string() || part["sha256"] != part_digest(part))
            throw InputError(path + ": $.sha256: does not match the part's content (changed or cut short)");
        if (!part["shard"].is_object() || !part["shard"].contains("index") || !part["shard"].contains("count") ||
            !part["shard"]["index"].is_number_unsigned() || !part["shard"]["count"].is_number_unsigned())
            throw InputError(path + ": $.shard: expected {\"index\": K, \"count\": N}");
        if (!part["run"].is_object() || !part["points"].is_array())
            throw InputError(path + ": $.run / $.points: expected an object and an array");
        parts.push_back(std::move(part));
    }
    // One run, every shard exactly once.
    const Json& run = parts[0]["run"];
    const Json count = parts[0]["shard"]["count"];
    if (!count.is_number_unsigned() || count.get<std::size_t>() != parts.size())
        throw InputError(paths[0] + ": $.shard.count: the run has " + count.dump() + " shards, " +
                         std::to_string(parts.size()) + " parts given");
    const std::size_t n = count.get<std::size_t>();
    std::vector<int> seen(n, -1);
    for (std::size_t p = 0; p < parts.size(); ++p) {
        if (parts[p]["run"] != run)
            throw InputError(paths[p] + ": $.run: a part of another run (masses, restitution, rule, grid or limits differ)");
        if (parts[p]["shard"]["count"] != count)
            throw InputError(paths[p] + ": $.shard.count: " + parts[p]["shard"]["count"].dump() + " shards, not " + count.dump());
        const Json& index = parts[p]["shard"]["index"];
        if (!index.is_number_unsigned() || index.get<std::size_t>() < 1 || index.get<std::size_t>() > n)
            throw InputError(paths[p] + ": $.shard.index: expected 1.." + std::to_string(n));
        const std::size_t k = index.get<std::size_t>() - 1;
        if (seen[k] >= 0)
            throw InputError(paths[p] + ": $.shard.index: shard " + std::to_string(k + 1) + " also given by " + paths[seen[k]]);
        seen[k] = static_cast<int>(p);
    }
    // The run's grid, then every point exactly where its shard owns it.
    SweepSpec spec;
    try {
        if (run.contains("system")) {
            spec.system_text = run.at("system").dump();
            spec.system_origin = paths[0] + ": $.run.system";
            spec.system = parse_system_text(spec.system_text, spec.system_origin);
            spec.law = parse_sweep_law(run.at("law").get<std::string>());
            spec.on = parse_restitution_on(run.at("restitution_on").get<std::string>());
        }
        if (run.contains("threshold_digits")) {
            spec.thresholds = true;
            spec.threshold_digits = run.at("threshold_digits").get<std::size_t>();
            if (spec.threshold_digits < 1 || spec.threshold_digits > 100)
                throw InputError(paths[0] + ": $.run.threshold_digits: expected 1 to 100");
        }
        spec.masses = run.at("masses").get<std::vector<std::string>>();
        spec.restitution = run.at("restitution").get<std::vector<std::string>>();
        // The run's limits: the merged outputs' own derivations (continuity checks, thresholds)
        // are decided under them, as the shards' were.
        const Json& limits = run.at("limits");
        spec.limits.max_faces = limits.at("max_faces").get<std::size_t>();
        spec.limits.max_chambers = limits.at("max_chambers").get<std::size_t>();
        spec.limits.max_subsets = limits.at("max_subsets").get<std::size_t>();
        spec.limits.max_pieces = limits.at("max_pieces").get<std::size_t>();
        spec.limits.max_memory_mb = limits.at("max_memory").get<std::size_t>();
        spec.rule = parse_rule(run.at("rule").get<std::string>());
        spec.max_impacts = run.at("max_impacts").get<std::size_t>();
        spec.max_words = run.at("max_words").get<std::size_t>();
        for (const auto& pj : run.at("parameters")) {
            SweepParameter param;
            param.name = pj.at("name").get<std::string>();
            for (const auto& v : pj.at("values"))
                param.values.push_back(number(v.get<std::string>(), "$.run.parameters"));
            param.count = param.values.size();
            spec.parameters.push_back(param);
        }
    } catch (const Json::exception&) {
        throw InputError(paths[0] + ": $.run: not a sweep's description");
    }
    if (spec.parameters.empty() || spec.parameters.size() > 2)
        throw InputError(paths[0] + ": $.run.parameters: one or two parameters");
    if (spec.thresholds && spec.parameters.size() != 1)
        throw InputError(paths[0] + ": $.run.threshold_digits: thresholds need exactly one parameter");
    std::size_t total = 1;
    for (const auto& p : spec.parameters) {
        if (p.values.empty() || p.values.size() > 10000)
            throw InputError(paths[0] + ": $.run.parameters: " + p.name + " needs 1 to 10000 values, has " +
                             std::to_string(p.values.size()));
        total *= p.values.size(); // at most 10,000^2: no overflow
    }
    if (total > max_points)
        throw SweepLimit("the merged grid has " + std::to_string(total) + " points, more than " +
                         std::to_string(max_points) + " (raise it with --max-points)");
    std::vector<Json> results(total);
    const std::size_t n1 = spec.parameters.size() > 1 ? spec.parameters[1].values.size() : 1;
    for (std::size_t p = 0; p < parts.size(); ++p) {
        const Shard shard{parts[p]["shard"]["index"].get<std::size_t>() - 1, n};
        const Json& points = parts[p]["points"];
        std::size_t expected = shard.index;
        for (std::size_t e = 0; e < points.size(); ++e, expected += n) {
            const std::string where = paths[p] + ": $.points[" + std::to_string(e) + "]";
            if (!points[e].is_object() || !points[e].contains("index") || !points[e]["index"].is_number_unsigned() ||
                points[e]["index"].get<std::size_t>() != expected || expected >= total)
                throw InputError(where + ".index: expected grid point " + std::to_string(expected) + " (shard " +
                                 std::to_string(shard.index + 1) + " of " + std::to_string(n) + " owns k mod " +
                                 std::to_string(n) + " = " + std::to_string(shard.index) + ")");
            // The point's coordinates are the grid's at its index.
            const std::size_t i0 = expected / n1, i1 = expected % n1;
            Json at = Json::object();
            at[spec.parameters[0].name] = to_string(spec.parameters[0].values[i0]);
            if (spec.parameters.size() > 1)
                at[spec.parameters[1].name] = to_string(spec.parameters[1].values[i1]);
            if (points[e].value("point", Json()) != at)
                throw InputError(where + ".point: is not the grid point at index " + std::to_string(expected));
            Json result = points[e];
            result.erase("index");
            check_point_shape(result, where, sweep_friction(spec));
            results[expected] = std::move(result);
        }
        if (expected < total)
            throw InputError(paths[p] + ": $.points: grid point " + std::to_string(expected) + " of shard " +
                             std::to_string(shard.index + 1) + " is missing");
    }
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    write_sweep_outputs(spec, results, dir);
}

void write_sweep_outputs(const SweepSpec& spec, const std::vector<Json>& results, const std::string& dir) {
    const std::vector<const char*> ids = obligation_ids(sweep_friction(spec));
    // sweep.csv
    std::string csv;
    for (const auto& p : spec.parameters)
        csv += csv_field(p.name) + ",";
    for (const char* id : ids)
        csv += std::string(id) + ",";
    csv += std::string(kOrderColumn) + ",pieces,max_word,derive\n";
    for (const auto& r : results) {
        for (auto it = r["point"].begin(); it != r["point"].end(); ++it)
            csv += csv_field(it.value().get<std::string>()) + ",";
        const bool ok = r["derive"] == "ok";
        for (const char* id : ids)
            csv += (ok ? r["obligations"][id]["verdict"].get<std::string>() : std::string()) + ",";
        csv += (ok ? r["order"]["verdict"].get<std::string>() : std::string()) + ",";
        csv += (ok ? std::to_string(r["pieces"].get<std::size_t>()) : std::string()) + "," +
               (ok ? std::to_string(r["max_word"].get<std::size_t>()) : std::string()) + "," +
               r["derive"].get<std::string>() + "\n";
    }
    write(dir + "/sweep.csv", csv);

    // The exact conditions (P1 only; see proofs/README.md, "Where continuity holds").
    const SweepConditions conditions = sweep_conditions(spec);
    Json exact = Json::object();
    exact["computed"] = conditions.result.computed;
    if (!conditions.result.computed) {
        exact["why_not"] = conditions.result.why_not;
    } else {
        exact["cells"] = conditions.result.cells;
        exact["cells_not_computed"] = conditions.result.cells_not_computed;
        Json curves = Json::array();
        std::set<std::vector<std::string>> checked;
        for (const auto& curve : conditions.result.curves) {
            Json c;
            c["words"] = Json::array({curve.word_a, curve.word_b});
            c["impacts"] = Json::array({curve.word_a.size(), curve.word_b.size()});
            if (curve.whole_cell) {
                c["whole_cell"] = true;
                curves.push_back(c);
                continue;
            }
            if (curve.isolated) {
                // Coprime jump components: continuity only at isolated points, not computed; the
                // probe points where both vanish, derived and verified.
                c["isolated"] = "the two components of the jump have no common factor: continuity holds at most at "
                                "isolated points (not computed); listed: grid points and points between them where both vanish";
                Json points = Json::array(), checks = Json::array();
                for (const auto& at_values : curve.points) {
                    checks.push_back(check_at(spec, Point{at_values}));
                    points.push_back(checks.back()["point"]);
                }
                c["points"] = points;
                c["checks"] = checks;
                curves.push_back(c);
                continue;
            }
            c["polynomial"] = curve.polynomial;
            c["degree"] = curve.degree;
            Json crossings = Json::array(), checks = Json::array();
            for (const auto& x : curve.crossings) {
                if (!x.grid_line)
                    continue;
                Json item;
                if (spec.parameters.size() > 1)
                    item["line"] = spec.parameters[1 - x.varies].name + " = " + to_string(x.at);
                item["root"] = spec.parameters[x.varies].name;
                item["in"] = Json::array({to_string(x.lo), to_string(x.hi)});
                item["approx"] = decimal_text(x.lo, 6);
                if (x.along)
                    item["along"] = true; // the whole grid line lies on the curve; one of its grid points
                if (x.exact) {
                    item["exact"] = to_string(*x.exact);
                    // A law exactly on the curve: derived and verified at the rational point.
                    Point at;
                    at.values.assign(spec.parameters.size(), Rational(0));
                    at.values[x.varies] = *x.exact;
                    if (spec.parameters.size() > 1)
                        at.values[1 - x.varies] = x.at;
                    std::vector<std::string> key;
                    for (const auto& v : at.values)
                        key.push_back(to_string(v));
                    if (checked.insert(key).second)
                        checks.push_back(check_at(spec, at));
                }
                crossings.push_back(item);
            }
            c["grid_crossings"] = crossings;
            c["checks"] = checks;
            curves.push_back(c);
        }
        exact["curves"] = curves;
    }

    // sweep.json
    Json doc;
    doc["format"] = "impactcert-sweep/1";
    put_inputs(doc, spec);
    doc["points"] = results;
    doc["exact_conditions"] = Json{{"P1", exact}, {"P2", energy_condition(spec)}};
    Json thresholds;
    if (spec.thresholds) {
        thresholds = find_thresholds(spec, results, spec.threshold_progress);
        doc["thresholds"] = thresholds;
    }
    write(dir + "/sweep.json", doc.dump(1) + "\n");

    // sweep.html
    std::string title = spec.system ? "impactcert sweep: " + spec.system->name + ", the " + to_string(spec.law) + " law"
                                    : "impactcert sweep: masses " + [&] {
        std::string s;
        for (const auto& m : spec.masses)
            s += (s.empty() ? "" : ",") + m;
        return s;
    }() + ", restitution " + [&] {
        std::string s;
        for (const auto& e : spec.restitution)
            s += (s.empty() ? "" : ",") + e;
        return s;
    }() + ", rule " + to_string(spec.rule);
    if (!spec.system && spec.law != SweepLaw::sequential)
        title += ", the " + std::string(to_string(spec.law)) + " law";
    std::string html = "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
                       xml_escape(title) + "</title>\n<style>\nbody{font-family:sans-serif;margin:2em;color:#222}"
                       ".maps{display:flex;flex-wrap:wrap;gap:18px}.map{border:1px solid #ddd;padding:6px}"
                       ".map h3{margin:2px 0 6px;font-size:14px}.key span{display:inline-block;width:12px;height:12px;"
                       "margin:0 4px 0 12px;vertical-align:middle}\n</style>\n</head>\n<body>\n<h1>" +
                       xml_escape(title) + "</h1>\n<p>One phase map per obligation; every cell is a derived law at an "
                       "exact grid point (hover for the point and the witness).</p>\n<p class=\"key\">"
                       "<span style=\"background:#009E73\"></span>proved<span style=\"background:#D55E00\"></span>refuted"
                       "<span style=\"background:#E69F00\"></span>undecided<span style=\"background:#BBBBBB\"></span>skipped"
                       "<span style=\"background:#24292f\"></span>no finite law</p>\n<div class=\"maps\">\n";
    for (const char* id : ids) {
        const bool overlay = std::string(id) == "P1" || std::string(id) == "nonexpansive";
        html += "<div class=\"map\"><h3>" + std::string(id) + (overlay && conditions.result.computed ? " (white dots: where P1 holds exactly)" : "") +
                "</h3>\n" + svg_map(spec, results, id, overlay ? &conditions : nullptr) + "</div>\n";
    }
    html += "<div class=\"map\"><h3>" + std::string(kOrderColumn) +
            " (every admissible order, whatever the rule)</h3>\n" + svg_map(spec, results, kOrderColumn) + "</div>\n";
    html += "</div>\n";
    if (conditions.result.computed) {
        html += "<h2>Where P1 holds exactly</h2>\n<p>Continuity holds where the jump at the tie gamma- = (-1, -1) "
                "vanishes: on each cell of fixed words after the tie, the zero set of the polynomial below (white dots: "
                "certified crossings of the grid lines and of " + std::to_string(conditions.result.subdivisions - 1) +
                " lines between them; large dots: rational points on grid lines, derived and verified; numbers: "
                "impacts after the tie). " +
                std::to_string(conditions.result.cells) + " cells found, " +
                std::to_string(conditions.result.cells_not_computed) + " beyond " +
                std::to_string(ConditionFamily{}.max_word) + " impacts not computed.</p>\n<ul>\n";
        for (const auto& curve : conditions.result.curves) {
            std::size_t grid = 0;
            for (const auto& x : curve.crossings)
                grid += x.grid_line;
            if (curve.isolated) {
                html += "<li>" + xml_escape("after the tie: " + curve.word_a + " / " + curve.word_b +
                                            ": no common curve; continuity at most at isolated points (not computed), " +
                                            std::to_string(curve.points.size()) + " found among the grid and probe points") +
                        "</li>\n";
                continue;
            }
            html += "<li>" + (curve.whole_cell ? xml_escape("after the tie: " + curve.word_a + " / " + curve.word_b + ": the whole cell") : xml_escape(curve_label(curve))) +
                    (curve.whole_cell ? std::string() : " (" + std::to_string(grid) + " grid-line crossings)") + "</li>\n";
        }
        html += "</ul>\n";
    } else {
        html += "<p>Exact conditions not computed: " + xml_escape(conditions.result.why_not) + ".</p>\n";
    }
    if (spec.thresholds) {
        html += "<h2>Thresholds along " + xml_escape(spec.parameters[0].name) +
                "</h2>\n<p>Each change of a verdict between neighbouring grid points, enclosed by exact bisection "
                "(the law derived and decided at both ends: proved); for energetic, the boundary's polynomial found by "
                "exact interpolation, with its only root in the enclosure (found, not proved: proofs/README.md, "
                "\"Thresholds along a parameter\"; sweep.json has every number).</p>\n<ul>\n";
        for (const auto& t : thresholds) {
            std::string line = t["column"].get<std::string>() + ": " + t["below"].get<std::string>() + " at " +
                               t["in"][0].get<std::string>() + ", " + t["above"].get<std::string>() + " at " +
                               t["in"][1].get<std::string>() + " (" + spec.parameters[0].name + " ~ " +
                               t["approx"].get<std::string>() + ")";
            if (t.contains("stopped"))
                line += "; stopped: " + t["stopped"].get<std::string>();
            if (t.contains("boundary") && t["boundary"].contains("polynomial"))
                line += "; the root of " + t["boundary"]["polynomial"].get<std::string>() + " (piece " +
                        t["boundary"]["piece"].get<std::string>() + ")";
            html += "<li>" + xml_escape(line) + "</li>\n";
        }
        html += "</ul>\n";
    }
    html += "</body>\n</html>\n";
    write(dir + "/sweep.html", html);

    // figures/: one standalone figure per map (SVG, and PDF with rsvg-convert), for papers.
    std::error_code ec;
    std::filesystem::create_directories(dir + "/figures", ec);
    if (ec)
        throw InputError(dir + "/figures: cannot create directory: " + ec.message());
    std::vector<LegendItem> legend = {{colour_of("proved"), "proved", LegendItem::Shape::square},
                                      {colour_of("refuted"), "refuted", LegendItem::Shape::square},
                                      {colour_of("undecided"), "undecided", LegendItem::Shape::square},
                                      {colour_of("skipped"), "skipped", LegendItem::Shape::square},
                                      {colour_of(""), spec.system ? "no law (not finite, or not a function)" : "no finite law", LegendItem::Shape::square}};
    std::vector<std::string> maps(ids.begin(), ids.end());
    maps.push_back(kOrderColumn);
    for (const auto& id : maps) {
        const bool overlay = (id == "P1" || id == "nonexpansive") && conditions.result.computed;
        std::vector<LegendItem> items = legend;
        if (overlay)
            items.push_back({"#ffffff", "P1 holds exactly (certified crossings)", LegendItem::Shape::dot});
        const std::string caption = id == kOrderColumn
                                        ? "Whether every admissible order of the impacts gives the same law, at each grid point."
                                        : "The obligation " + id + " of the law derived at each grid point (proofs/README.md).";
        write_figure(dir + "/figures/" + id, standalone_figure(id + ": " + title, caption,
                                                              svg_map(spec, results, id, overlay ? &conditions : nullptr), items));
    }
}

} // namespace impactcert
