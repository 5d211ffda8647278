// cli_main.cpp -- the `impactcert` command (SPEC section 6).
//
// Exit status: 0 success / every claim proved; 1 a claim refuted; 2 bad input or usage.
// Every error is one line on stderr: "impactcert: <place>: <reason>".
#include "certificate.hpp"
#include "cradle.hpp"
#include "derive.hpp"
#include "float_eval.hpp"
#include "fuzz.hpp"
#include "law_json.hpp"
#include "obligations.hpp"
#include "paper_law.hpp"
#include "report.hpp"
#include "smt.hpp"
#include "sweep.hpp"
#include "verdict_output.hpp"

#include <CLI/CLI.hpp>
#include <impactcert/float_law.hpp>

#include <dlfcn.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

namespace impactcert {
namespace {

constexpr int kExitProved = 0;
constexpr int kExitRefuted = 1;
constexpr int kExitBadInput = 2;

Model load_model(const std::string& law_path, std::size_t max_pieces = Limits{}.max_pieces) {
    return law_path.empty() ? Model(paper_law(), max_pieces) : load_model_file(law_path, max_pieces);
}

constexpr int kExitUndecided = 3;
constexpr int kExitInternal = 4;

// Progress on a terminal for runs over a second: one line on stderr, rewritten in place.
class TerminalProgress {
  public:
    TerminalProgress() : enabled_(isatty(2) != 0), start_(std::chrono::steady_clock::now()) {}
    ~TerminalProgress() {
        if (shown_)
            std::fprintf(stderr, "\r\033[K");
    }
    TerminalProgress(const TerminalProgress&) = delete;
    TerminalProgress& operator=(const TerminalProgress&) = delete;
    Progress callback() {
        if (!enabled_)
            return {};
        return [this](const std::string& id, const std::string& status) {
            const auto now = std::chrono::steady_clock::now();
            if (now - start_ < std::chrono::seconds(1) || now - last_ < std::chrono::milliseconds(200))
                return;
            last_ = now;
            shown_ = true;
            std::fprintf(stderr, "\r\033[Kimpactcert: %s %s", id.c_str(), status.c_str());
            std::fflush(stderr);
        };
    }

  private:
    bool enabled_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_{};
};

VerifyReport verify_with_progress(const Model& model, const Limits& limits) {
    TerminalProgress progress;
    return verify(model, limits, progress.callback());
}

int run_verify(const std::string& law_path, bool json, const std::string& junit_path, const Limits& limits) {
    const Model model = load_model(law_path, limits.max_pieces);
    Limits no_evidence = limits;
    no_evidence.evidence = false; // a verdict needs no certificate
    const VerifyReport report = verify_with_progress(model, no_evidence);
    if (json)
        std::cout << verdict_json(report).dump(2) << "\n";
    else
        std::cout << verdict_table(report, model);
    if (!junit_path.empty()) {
        std::ofstream out(junit_path, std::ios::binary);
        out << verdict_junit(report);
        if (!out)
            throw InputError(junit_path + ": cannot write the JUnit report");
    }
    return report.exit_status();
}

int run_certify(const std::string& law_path, const std::string& out_path, const Limits& limits) {
    const Model model = load_model(law_path, limits.max_pieces);
    // The header names the top verdict: a first pass without evidence gives it; the second
    // writes each obligation as it is decided (one obligation's evidence in memory at a time).
    Limits quick = limits;
    quick.evidence = false;
    const VerifyReport first = verify_with_progress(model, quick);
    std::ofstream out(out_path, std::ios::binary);
    if (!out)
        throw InputError(out_path + ": cannot write the certificate");
    CertificateWriter writer(out, model, first.verdict());
    TerminalProgress progress;
    const VerifyReport report =
        verify_streaming(model, limits, progress.callback(), [&](ObligationResult& r) { writer.add(r); });
    writer.finish();
    out.close();
    if (!out)
        throw InputError(out_path + ": cannot write the certificate");
    for (std::size_t k = 0; k < report.obligations.size(); ++k) {
        const auto &a = first.obligations.at(k), &b = report.obligations[k];
        if (a.verdict != b.verdict || a.checks != b.checks || a.method != b.method || a.counterexample != b.counterexample)
            throw std::logic_error("certify: the two passes disagree on " + a.id);
    }
    std::cerr << "impactcert: wrote " << out_path << " (" << report.law << ": " << report.verdict() << ")\n";
    return report.exit_status();
}

void write_file(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
    out.close();
    if (!out)
        throw InputError(path + ": cannot write");
}

int run_report(const std::string& law_path, const std::string& dir, const Limits& limits) {
    const Model model = load_model(law_path, limits.max_pieces);
    const VerifyReport report = verify_with_progress(model, limits);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    write_file(dir + "/report.md", report_markdown(model, report));
    write_file(dir + "/report.html", report_html(model, report));
    std::cout << dir << "/report.md\n" << dir << "/report.html\n";
    return kExitProved; // a report is written whatever the verdict
}

// A comma-separated list of command-line numbers ("1,m,1" has no names here: see sweep).
std::vector<Rational> number_list(const std::string& option, const std::string& text) {
    std::vector<Rational> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        std::string why;
        const auto x = parse_cli_number(item, &why);
        if (!x)
            throw InputError(option + ": \"" + item + "\" is not a number" + (why.empty() ? "" : " (" + why + ")"));
        out.push_back(*x);
        if (comma == std::string::npos)
            return out;
        start = comma + 1;
    }
}

struct DeriveArgs {
    std::string masses, restitution = "1", rule = "most-negative", out;
    std::size_t max_impacts = 100;
};

int run_derive_sequential(const DeriveArgs& a) {
    DeriveOptions o;
    o.masses = number_list("--masses", a.masses);
    o.restitution = number_list("--restitution", a.restitution);
    if (o.restitution.size() == 1 && o.masses.size() > 2)
        o.restitution.assign(o.masses.size() - 1, o.restitution[0]);
    o.rule = parse_rule(a.rule);
    o.max_impacts = a.max_impacts;
    const DeriveResult r = derive_sequential(o);
    if (r.not_finite) {
        std::cerr << "impactcert: derive: no finite law: gamma- = " << to_string(*r.not_finite) << " needs more than "
                  << o.max_impacts << " impacts (word " << r.word << "...)\n";
        return kExitRefuted;
    }
    // The canonical law, with the derivation's description after the name.
    const Json canonical = law_to_json(*r.law);
    Json law;
    for (auto it = canonical.begin(); it != canonical.end(); ++it) {
        law[it.key()] = it.value();
        if (it.key() == "name")
            law["description"] = r.law->description;
    }
    const std::string text = law.dump(2) + "\n";
    if (a.out.empty()) {
        std::cout << text;
    } else {
        write_file(a.out, text);
        std::cerr << "impactcert: wrote " << a.out << " (" << r.law->pieces.size() << " pieces, " << r.regions
                  << " regions, longest word " << r.max_word << ")\n";
    }
    return kExitProved;
}

struct CradleArgs {
    std::size_t balls = 0;
    std::string pieces = "representatives", out;
    bool no_symmetries = false;
};

int run_derive_cradle(const CradleArgs& a) {
    if (a.pieces != "representatives" && a.pieces != "all")
        throw InputError("--pieces: expected representatives or all, got \"" + a.pieces + "\"");
    if (a.pieces == "all" && a.balls > 8)
        throw InputError("--pieces all: at most 8 balls (40,320 listed pieces); larger laws are written compactly");
    const Law law = cradle_law(a.balls, a.pieces == "all" ? CradleListing::all : CradleListing::representatives,
                               !a.no_symmetries);
    std::size_t cones = 1; // n! (not generated here: verify and certify expand the law)
    for (std::size_t k = 2; k <= a.balls; ++k)
        cones *= k;
    const Json canonical = law_to_json(law);
    Json out;
    for (auto it = canonical.begin(); it != canonical.end(); ++it) {
        out[it.key()] = it.value();
        if (it.key() == "name")
            out["description"] = law.description;
    }
    const std::string text = out.dump(2) + "\n";
    if (a.out.empty()) {
        std::cout << text;
    } else {
        write_file(a.out, text);
        std::cerr << "impactcert: wrote " << a.out << " (" << law.pieces.size() << " pieces listed, " << cones
                  << " in all, " << law.symmetries.size() << " symmetries)\n";
    }
    return kExitProved;
}

struct SweepArgs {
    std::string masses, restitution = "1", rule = "most-negative", out;
    std::vector<std::string> vary;
    std::size_t max_impacts = 100;
    unsigned jobs = 1;
};

std::vector<std::string> items(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');)
        out.push_back(item);
    if (!text.empty() && text.back() == ',')
        out.push_back("");
    return out;
}

int run_sweep_command(const SweepArgs& a, const Limits& limits) {
    SweepSpec spec;
    spec.masses = items(a.masses);
    spec.restitution = items(a.restitution);
    spec.rule = parse_rule(a.rule);
    spec.max_impacts = a.max_impacts;
    spec.limits = limits;
    spec.jobs = a.jobs;
    for (const auto& v : a.vary)
        spec.parameters.push_back(parse_vary(v));
    const bool tty = isatty(2) != 0;
    const auto start = std::chrono::steady_clock::now();
    run_sweep(spec, a.out, [&](std::size_t done, std::size_t total) {
        if (tty && std::chrono::steady_clock::now() - start > std::chrono::seconds(1))
            std::fprintf(stderr, "\r\033[Kimpactcert: sweep %zu/%zu points", done, total);
    });
    if (tty)
        std::fprintf(stderr, "\r\033[K");
    std::cout << a.out << "/sweep.csv\n" << a.out << "/sweep.json\n" << a.out << "/sweep.html\n";
    return kExitProved; // the verdicts are data
}

int run_smt(const std::string& law_path, const std::string& dir) {
    const Model model = load_model(law_path);
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    for (const auto& problem : smt_problems(model)) {
        const std::string path = dir + "/" + problem.id + ".smt2";
        std::ofstream out(path, std::ios::binary);
        out << problem.script;
        out.close();
        if (!out)
            throw InputError(path + ": cannot write");
        std::cout << path << "\n";
    }
    return kExitProved;
}

// Splits on white space and commas; parentheses and brackets are decoration.
std::vector<std::string> tokens_of(const std::string& text) {
    std::vector<std::string> out;
    std::string cur;
    for (char ch : text) {
        if (ch == ' ' || ch == '\t' || ch == ',' || ch == '(' || ch == ')' || ch == '[' ||
            ch == ']' || ch == '\r' || ch == '\n') {
            if (!cur.empty())
                out.push_back(cur);
            cur.clear();
        } else {
            cur += ch;
        }
    }
    if (!cur.empty())
        out.push_back(cur);
    return out;
}

std::string line_of(const Vector& v) {
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i)
        s += (i ? " " : "") + to_string(v[i]);
    return s;
}

// One point: c contact velocities, or n ball velocities with --velocities.
std::string evaluate_point(const Model& model, const Vector& x, bool velocities, const std::string& where) {
    const Vector gamma = velocities ? model.contact_velocities(x) : x;
    const auto values = model.values_at(gamma);
    if (values.empty())
        throw InputError(where + ": gamma- = " + to_string(gamma) + " lies in no cone of law " +
                         model.law().name);
    std::string out;
    for (std::size_t k = 0; k < values.size(); ++k) {
        const Vector shown = velocities ? model.post_impact_velocities(x, gamma, values[k]) : values[k];
        out += (k ? " | " : "") + line_of(shown);
    }
    return out;
}

// Finite doubles from text: decimals correctly rounded (strtod), hex floats exactly.
double parse_double(const std::string& text, const std::string& where) {
    char* end = nullptr;
    errno = 0;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size())
        throw InputError(where + ": " + text + ": not a number");
    if (!std::isfinite(d))
        throw InputError(where + ": " + text + ": not a finite double (NaN and infinities are outside the domain)");
    return d;
}

struct FuzzArgs {
    std::string law_path, impl_spec, impl_cmd, junit;
    bool velocities = false, json = false;
    bool impl_given = false, impl_cmd_given = false; // given, even as an empty string
    std::optional<std::uint64_t> max_ulps;
    std::optional<double> max_rel_error;
    double timeout = 10;
    fuzz::Options options;
};

// The implementation under test: --impl, --impl-cmd, or the built-in float law.
std::unique_ptr<fuzz::Implementation> make_impl(const FuzzArgs& a, const Model& model, std::size_t dim) {
    if (a.impl_given && a.impl_cmd_given)
        throw InputError("--impl and --impl-cmd: give one implementation");
    if (a.impl_given && a.impl_spec.empty())
        throw InputError("--impl: empty (expected LIB.so:SYMBOL)");
    if (a.impl_cmd_given && a.impl_cmd.empty())
        throw InputError("--impl-cmd: empty command");
    if (!(a.timeout > 0 && std::isfinite(a.timeout)))
        throw InputError("--impl-timeout: must be a finite number of seconds > 0");
    if (!a.impl_spec.empty())
        return fuzz::load_symbol(a.impl_spec, dim, dim);
    if (!a.impl_cmd.empty())
        return fuzz::command(a.impl_cmd, dim, dim, a.timeout);
    if (a.law_path.empty())
        return fuzz::builtin_paper(a.velocities);
    if (a.velocities)
        throw InputError("--velocities --law: the built-in float law takes contact velocities; test an "
                         "implementation in ball velocities with --impl or --impl-cmd");
    return fuzz::builtin_float_law(model);
}

// What `verify` proves of the law decides what the fuzzer may check (and whether one piece per
// point is enough: a continuous tiling).
struct LawFacts {
    bool continuous_tiling = false;
    fuzz::Properties properties;
};

LawFacts law_facts(const Model& model) {
    static const std::vector<std::string> ids = {"fan", "P1", "kinematic", "energetic", "nonexpansive-lemma"};
    const VerifyReport report = verify(model, Limits{}, {}, &ids);
    auto proved = [&](const char* id) { return report.at(id).verdict == Verdict::proved; };
    LawFacts f;
    f.continuous_tiling = proved("fan") && proved("P1");
    f.properties.nonnegative = proved("kinematic");
    f.properties.energy = proved("energetic");
    f.properties.nonexpansive = proved("nonexpansive-lemma");
    return f;
}

std::vector<double> parse_doubles(const std::vector<std::string>& toks) {
    std::vector<double> x;
    for (const auto& t : toks)
        x.push_back(parse_double(t, "input"));
    return x;
}

int run_eval_float(const FuzzArgs& a, const std::vector<std::vector<std::string>>& points) {
    if (a.impl_given || a.impl_cmd_given) {
        // An implementation against the exact law, point by point (the fuzzer's replays).
        const Model model = load_model(a.law_path);
        const LawFacts facts = law_facts(model);
        const fuzz::LawReference reference(model, a.velocities, facts.continuous_tiling);
        auto impl = make_impl(a, model, reference.in_dim());
        for (const auto& toks : points) {
            const auto x = parse_doubles(toks);
            std::printf("%s", fuzz::explain(reference, impl.get(), x.data()).c_str());
        }
        return kExitProved;
    }
    if (!a.law_path.empty()) {
        // Any law file: the general float evaluator, with its error bound.
        if (a.velocities)
            throw InputError("--float --law --velocities: the built-in float law takes contact velocities");
        const Model model = load_model(a.law_path);
        const FloatLaw law(model);
        for (const auto& toks : points) {
            const auto x = parse_doubles(toks);
            const auto r = law.eval(x);
            if (!r.ok)
                throw InputError("input: " + r.error);
            std::string line, bound;
            for (std::size_t i = 0; i < r.value.size(); ++i) {
                line += (i ? " " : "") + fuzz::hex(r.value[i]);
                bound += " " + fuzz::hex(r.bound[i]);
            }
            std::printf("%s  # piece %s, |error| <=%s%s%s\n", line.c_str(), model.pieces()[r.piece].name.c_str(),
                        bound.c_str(), r.exact_fallback ? ", classified exactly" : "",
                        r.exact_output ? ", computed exactly" : "");
        }
        return kExitProved;
    }
    for (const auto& toks : points) {
        auto x = parse_doubles(toks);
        if (a.velocities) {
            fp::sort_velocities(x.data());
            std::printf("%a %a %a\n", x[0], x[1], x[2]);
            continue;
        }
        double law[2];
        fp::S(x[0], x[1], law);
        std::printf("%a %a\n", law[0], law[1]);
    }
    return kExitProved;
}

std::string count_text(std::uint64_t n) {
    char buf[32];
    if (n >= 1000000)
        std::snprintf(buf, sizeof buf, "%.1fM", static_cast<double>(n) / 1e6);
    else
        std::snprintf(buf, sizeof buf, "%llu", static_cast<unsigned long long>(n));
    return buf;
}

std::string fuzz_junit(const fuzz::Summary& sum, const std::string& target) {
    struct Case {
        const char* name;
        std::uint64_t count;
    };
    const Case cases[] = {{"accuracy", sum.inaccurate - sum.non_finite},
                          {"classification", sum.misclassified},
                          {"non-finite outputs", sum.non_finite},
                          {"negative contact velocities", sum.negative},
                          {"energy", sum.energy},
                          {"non-expansivity", sum.nonexpansive},
                          {"implementation failures", sum.crashed + sum.hung + sum.malformed + sum.refused}};
    std::size_t failures = 0;
    for (const auto& c : cases)
        failures += c.count ? 1 : 0;
    std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites>\n";
    x += "  <testsuite name=\"impactcert fuzz: " + xml_escape(target) + "\" tests=\"" + std::to_string(std::size(cases)) +
         "\" failures=\"" + std::to_string(failures) + "\">\n";
    for (const auto& c : cases) {
        x += "    <testcase classname=\"impactcert.fuzz\" name=\"" + std::string(c.name) + "\"";
        if (!c.count) {
            x += "/>\n";
            continue;
        }
        std::string first;
        for (const auto& v : sum.examples)
            if (first.empty())
                first = v.what + "; replay: " + v.replay;
        x += ">\n      <failure message=\"" + std::to_string(c.count) + " violation(s) in " + std::to_string(sum.samples) +
             " samples\">" + xml_escape(first) + "</failure>\n    </testcase>\n";
    }
    return x + "  </testsuite>\n</testsuites>\n";
}

int run_fuzz(FuzzArgs a) {
    if (!(a.options.seconds >= 0 && std::isfinite(a.options.seconds)))
        throw InputError("--seconds: must be a finite number >= 0");
    if (!a.junit.empty() && !std::ofstream(a.junit)) // before the run, not after it
        throw InputError("--junit " + a.junit + ": cannot write");
    const Model model = load_model(a.law_path);
    if (a.max_ulps && a.max_rel_error)
        throw InputError("--max-ulps and --max-rel-error: give one tolerance");
    if (a.max_rel_error && !(*a.max_rel_error >= 0 && std::isfinite(*a.max_rel_error)))
        throw InputError("--max-rel-error: must be a finite number >= 0");
    const LawFacts facts = law_facts(model);
    const fuzz::LawReference reference(model, a.velocities, facts.continuous_tiling);
    const auto impl = make_impl(a, model, reference.in_dim());
    fuzz::Options& options = a.options;
    if (a.max_rel_error) {
        options.tolerance = fuzz::Tolerance::relative;
        options.max_rel_error = *a.max_rel_error;
    } else if (a.max_ulps) {
        options.tolerance = fuzz::Tolerance::ulps;
        options.max_ulps = *a.max_ulps;
    } else {
        options.tolerance = impl->states_bound() ? fuzz::Tolerance::stated_bound : fuzz::Tolerance::ulps;
    }
    options.replay_prefix = "impactcert eval --float";
    if (!a.law_path.empty())
        options.replay_prefix += " --law " + fuzz::shell_quote(a.law_path);
    if (a.velocities)
        options.replay_prefix += " --velocities";
    const bool tty = !a.json && isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    auto progress = [&](std::uint64_t done) {
        if (!tty)
            return;
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        double frac = options.samples ? static_cast<double>(done) / static_cast<double>(options.samples) : 1.0;
        if (options.seconds > 0)
            frac = std::max(frac, secs / options.seconds);
        frac = std::min(frac, 1.0);
        const int width = 30, filled = static_cast<int>(frac * width);
        std::fprintf(stderr, "\r[%s%s] %3.0f%% %s samples, %.2f M/s ", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                     std::string(static_cast<std::size_t>(width - filled), '.').c_str(), frac * 100, count_text(done).c_str(),
                     secs > 0 ? static_cast<double>(done) / secs / 1e6 : 0.0);
    };
    const fuzz::Summary sum = fuzz::run(options, reference, *impl, facts.properties, progress);
    if (tty)
        std::fprintf(stderr, "\r\033[K");
    const double rate = sum.seconds > 0 ? static_cast<double>(sum.samples) / sum.seconds : 0;
    const std::string target = impl->describe();
    const std::string space = a.velocities ? "ball velocities" : "contact velocities";
    const std::string tolerance =
        options.tolerance == fuzz::Tolerance::relative ? "--max-rel-error " + [&] {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.3g", options.max_rel_error);
            return std::string(buf);
        }()
        : options.tolerance == fuzz::Tolerance::ulps   ? "--max-ulps " + std::to_string(options.max_ulps)
                                                       : "the implementation's stated bound";
    auto hexes = [](const std::vector<double>& v) {
        Json j = Json::array();
        for (double x : v)
            j.push_back(fuzz::hex(x));
        return j;
    };
    if (!a.junit.empty()) {
        std::ofstream f(a.junit);
        f << fuzz_junit(sum, target);
        if (!f)
            throw InputError("--junit " + a.junit + ": cannot write");
    }
    if (a.json) {
        Json j;
        j["format"] = "impactcert-fuzz/1";
        j["law"] = model.law().name;
        j["space"] = space;
        j["implementation"] = target;
        j["tolerance"] = tolerance;
        j["seed"] = options.seed;
        j["jobs"] = options.jobs;
        j["samples"] = sum.samples;
        j["pairs"] = sum.pairs;
        j["seconds"] = sum.seconds;
        j["samples_per_second"] = rate;
        j["reference_through_gmp"] = sum.slow;
        j["outside_every_cone"] = sum.outside;
        j["max_error_ulps"] = sum.max_ulps;
        j["max_relative_error"] = sum.max_rel_error;
        j["checked_properties"] = {{"nonnegative", facts.properties.nonnegative}, {"energy", facts.properties.energy},
                                   {"nonexpansive", facts.properties.nonexpansive}};
        j["violations"] = {{"outside_tolerance", sum.inaccurate}, {"classification", sum.misclassified},
                           {"non_finite", sum.non_finite}, {"negative_output", sum.negative},
                           {"energy", sum.energy}, {"nonexpansive", sum.nonexpansive},
                           {"crashed", sum.crashed}, {"hung", sum.hung}, {"malformed", sum.malformed},
                           {"refused", sum.refused}};
        Json examples = Json::array();
        for (const auto& v : sum.examples) {
            Json e = {{"index", v.index}, {"what", v.what}, {"generator", v.kind}, {"input", hexes(v.input)}};
            if (!v.input_b.empty())
                e["input_b"] = hexes(v.input_b);
            e["output"] = hexes(v.output);
            e["expected"] = hexes(v.expected);
            e["replay"] = v.replay;
            examples.push_back(e);
        }
        j["examples"] = examples;
        j["verdict"] = sum.violations() ? "violations" : "no violation";
        std::cout << j.dump(2) << "\n";
    } else {
        auto u = [](std::uint64_t x) { return static_cast<unsigned long long>(x); };
        std::string ulps;
        for (auto e : sum.max_ulps)
            ulps += (ulps.empty() ? "" : ", ") + std::to_string(e);
        std::printf("impactcert fuzz: %s vs the exact law %s, in %s (seed %llu, %u job%s)\n", target.c_str(),
                    model.law().name.c_str(), space.c_str(), u(options.seed), options.jobs, options.jobs == 1 ? "" : "s");
        std::printf("  tolerance                      %s\n", tolerance.c_str());
        std::printf("  samples                        %llu (%llu close pairs; %llu reference points through GMP)\n",
                    u(sum.samples), u(sum.pairs), u(sum.slow));
        std::printf("  time                           %.2f s (%.2f M samples/s, %.2f M/s per job)\n", sum.seconds,
                    rate / 1e6, rate / 1e6 / std::max(1u, options.jobs));
        std::printf("  max error                      %s ulp per component; %.3g relative (normwise)\n", ulps.c_str(),
                    sum.max_rel_error);
        std::printf("  outside the tolerance          %llu (classification: %llu, non-finite: %llu)\n", u(sum.inaccurate),
                    u(sum.misclassified), u(sum.non_finite));
        std::printf("  negative contact velocities    %llu%s\n", u(sum.negative), facts.properties.nonnegative ? "" : " (not checked: not proved for this law)");
        std::printf("  energy increases               %llu%s\n", u(sum.energy), facts.properties.energy ? "" : " (not checked: not proved for this law)");
        std::printf("  non-expansivity violations     %llu%s\n", u(sum.nonexpansive), facts.properties.nonexpansive ? "" : " (not checked: not proved for this law)");
        std::printf("  implementation failures        %llu crashed, %llu hung, %llu malformed, %llu refused\n",
                    u(sum.crashed), u(sum.hung), u(sum.malformed), u(sum.refused));
        if (sum.outside)
            std::printf("  points in no cone (skipped)    %llu\n", u(sum.outside));
        for (const auto& v : sum.examples) {
            std::string in, out, ex;
            for (double x : v.input)
                in += " " + fuzz::hex(x);
            if (!v.input_b.empty())
                in += " |";
            for (double x : v.input_b)
                in += " " + fuzz::hex(x);
            for (double x : v.output)
                out += " " + fuzz::hex(x);
            for (double x : v.expected)
                ex += " " + fuzz::hex(x);
            std::printf("  violation at sample %llu (%s): %s\n    input%s -> output%s, exact%s\n    replay: %s\n",
                        u(v.index), v.kind.c_str(), v.what.c_str(), in.c_str(), out.empty() ? " (none)" : out.c_str(),
                        ex.empty() ? " (none)" : ex.c_str(), v.replay.c_str());
        }
        std::printf("verdict: %s\n", sum.violations() ? "violations found" : "no violation");
    }
    return sum.violations() ? kExitRefuted : kExitProved;
}

int run_eval(const std::string& law_path, bool velocities, const std::vector<std::string>& args, bool as_float,
             FuzzArgs float_args) {
    if ((float_args.impl_given || float_args.impl_cmd_given) && !as_float)
        throw InputError("--impl and --impl-cmd need --float");
    if (as_float) {
        float_args.law_path = law_path;
        float_args.velocities = velocities;
        const Model dims = load_model(law_path);
        const std::size_t dim = velocities ? dims.balls() : dims.contacts();
        std::vector<std::vector<std::string>> points;
        std::vector<std::string> toks;
        for (const auto& a : args)
            for (auto& t : tokens_of(a))
                toks.push_back(t);
        if (args.empty()) {
            std::string line;
            for (std::size_t lineno = 1; std::getline(std::cin, line); ++lineno) {
                const auto lt = tokens_of(line);
                if (lt.empty() || lt.front().front() == '#')
                    continue;
                if (lt.size() != dim)
                    throw InputError("stdin:" + std::to_string(lineno) + ": expected " + std::to_string(dim) +
                                     " numbers, got " + std::to_string(lt.size()));
                points.push_back(lt);
            }
        } else {
            if (toks.empty() || toks.size() % dim != 0)
                throw InputError("arguments: expected a multiple of " + std::to_string(dim) + " numbers, got " +
                                 std::to_string(toks.size()));
            for (std::size_t i = 0; i < toks.size(); i += dim)
                points.emplace_back(toks.begin() + static_cast<std::ptrdiff_t>(i),
                                    toks.begin() + static_cast<std::ptrdiff_t>(i + dim));
        }
        return run_eval_float(float_args, points);
    }
    const Model model = load_model(law_path);
    const std::size_t dim = velocities ? model.balls() : model.contacts();
    auto read_point = [&](const std::vector<std::string>& toks, std::size_t first, const std::string& where) {
        Vector x;
        for (std::size_t i = first; i < first + dim; ++i) {
            std::string why;
            auto r = parse_cli_number(toks[i], &why);
            if (!r)
                throw InputError(where + ": " + toks[i] + ": " + why);
            x.push_back(*r);
        }
        return x;
    };
    if (!args.empty()) {
        std::vector<std::string> toks;
        for (const auto& a : args)
            for (auto& t : tokens_of(a))
                toks.push_back(t);
        if (toks.empty() || toks.size() % dim != 0)
            throw InputError("arguments: expected a multiple of " + std::to_string(dim) + " numbers (" +
                             (velocities ? "ball" : "contact") + " velocities), got " +
                             std::to_string(toks.size()));
        for (std::size_t first = 0; first < toks.size(); first += dim)
            std::cout << evaluate_point(model, read_point(toks, first, "arguments"), velocities,
                                        "arguments")
                      << "\n";
        return kExitProved;
    }
    std::string line;
    for (std::size_t lineno = 1; std::getline(std::cin, line); ++lineno) {
        const auto toks = tokens_of(line);
        if (toks.empty() || toks.front().front() == '#')
            continue;
        const std::string where = "stdin:" + std::to_string(lineno);
        if (toks.size() != dim)
            throw InputError(where + ": expected " + std::to_string(dim) + " numbers, got " +
                             std::to_string(toks.size()));
        std::cout << evaluate_point(model, read_point(toks, 0, where), velocities, where) << "\n";
    }
    return kExitProved;
}

} // namespace
} // namespace impactcert

int main(int argc, char** argv) {
    using namespace impactcert;
    CLI::App app{"impactcert: exact proofs for cone-wise linear impact laws"};
    app.set_version_flag("--version", std::string("impactcert ") + IMPACTCERT_VERSION);
    app.require_subcommand(1);

    std::string law_path, junit_path, out_path;
    bool json = false, velocities = false, as_float = false;
    FuzzArgs fuzz_args, eval_float_args;
    fuzz::Options& fuzz_options = fuzz_args.options;
    fuzz_options.jobs = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::string> eval_args;
    DeriveArgs derive_args;
    SweepArgs sweep_args;
    sweep_args.jobs = std::max(1u, std::thread::hardware_concurrency());

    auto* verify_cmd = app.add_subcommand("verify", "decide every proof obligation; exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input");
    verify_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    verify_cmd->add_flag("--json", json, "print the impactcert-verdict/1 JSON instead of the table");
    verify_cmd->add_option("--junit", junit_path, "also write a JUnit XML report to this file");

    auto* certify_cmd = app.add_subcommand("certify", "write the impactcert-certificate/1 JSON; exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input");
    certify_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    certify_cmd->add_option("-o,--output", out_path, "certificate file to write")->required();

    auto* report_cmd = app.add_subcommand("report", "write report.md (CI job summary) and a self-contained report.html with a picture of the cones");
    report_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    report_cmd->add_option("-o,--output", out_path, "directory to write report.md and report.html into")->required();

    auto* smt_cmd = app.add_subcommand("smt", "write one SMT-LIB2 file per universal claim (the claim negated: unsat = holds)");
    smt_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    smt_cmd->add_option("-o,--output", out_path, "directory to write the .smt2 files into")->required();

    auto* eval_cmd = app.add_subcommand("eval", "evaluate S exactly at points given as arguments or stdin lines");
    eval_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    eval_cmd->add_flag("--velocities", velocities, "points are ball velocities u- (print u+)");
    eval_cmd->add_flag("--float", as_float, "evaluate the float law in double (inputs read with strtod; output in hex, %a)");
    eval_cmd->add_option("--impl", eval_float_args.impl_spec, "with --float: run LIB.so:SYMBOL and show its output against the correctly rounded exact value");
    eval_cmd->add_option("--impl-cmd", eval_float_args.impl_cmd, "with --float: the same for a command (see fuzz --impl-cmd)");
    eval_cmd->add_option("--impl-timeout", eval_float_args.timeout, "seconds to wait for --impl-cmd's answer")->check(CLI::PositiveNumber);
    eval_cmd->add_option("points", eval_args, "numbers: rationals (-3/4), decimals (0.1, 2.5e-3), hex floats (0x1.8p-3)");

    auto* derive_cmd = app.add_subcommand("derive", "derive an impact law from the mechanics (SPEC section 7)");
    derive_cmd->require_subcommand(1);
    auto* sequential_cmd = derive_cmd->add_subcommand("sequential", "the sequential impact law of a chain; exit 0 law written, 1 no finite law (with a witness), 2 bad input");
    sequential_cmd->add_option("--masses", derive_args.masses, "ball masses M1,M2,... (rationals, > 0)")->required();
    sequential_cmd->add_option("--restitution", derive_args.restitution, "E for every contact, or E1,...,E(n-1), each in [0, 1]")->capture_default_str();
    sequential_cmd->add_option("--rule", derive_args.rule, "which approaching contact impacts first: most-negative, left-first or right-first")->capture_default_str();
    sequential_cmd->add_option("--max-impacts", derive_args.max_impacts, "longest impact sequence allowed")->capture_default_str();
    sequential_cmd->add_option("-o,--output", derive_args.out, "law file to write (default: standard output)");

    CradleArgs cradle_args;
    auto* cradle_cmd = derive_cmd->add_subcommand("cradle", "the N-ball equal-mass elastic law (S = sort) with its symmetries declared; exit 0 law written, 2 bad input");
    cradle_cmd->add_option("--balls", cradle_args.balls, "number of balls N (2..12)")->required();
    cradle_cmd->add_option("--pieces", cradle_args.pieces, "representatives (one piece, the rest generated by the symmetries) or all (every ordering listed)")->capture_default_str();
    cradle_cmd->add_flag("--no-symmetries", cradle_args.no_symmetries, "declare no symmetries (needs --pieces all)");
    cradle_cmd->add_option("-o,--output", cradle_args.out, "law file to write (default: standard output)");

    auto* sweep_cmd = app.add_subcommand("sweep", "derive + verify over a grid of parameters named in --masses/--restitution; writes DIR/sweep.csv, sweep.json, sweep.html; exit 0 when it ran, 2 on bad input");
    sweep_cmd->add_option("--masses", sweep_args.masses, "ball masses, numbers or parameter names (1,m,1)")->required();
    sweep_cmd->add_option("--restitution", sweep_args.restitution, "E or E1,...,E(n-1), numbers or parameter names")->capture_default_str();
    sweep_cmd->add_option("--rule", sweep_args.rule, "most-negative, left-first or right-first")->capture_default_str();
    sweep_cmd->add_option("--max-impacts", sweep_args.max_impacts, "longest impact sequence allowed")->capture_default_str();
    sweep_cmd->add_option("--vary", sweep_args.vary, "NAME=LO..HI:COUNT[:log], once or twice")->required();
    sweep_cmd->add_option("--jobs", sweep_args.jobs, "worker processes (default: all cores)")->check(CLI::Range(1u, 256u));
    sweep_cmd->add_option("-o,--output", sweep_args.out, "directory to write sweep.csv, sweep.json and sweep.html into")->required();
    Limits limits;
    bool no_integer_kernels = false;
    unsigned verify_jobs = std::max(1u, std::thread::hardware_concurrency());
    for (auto* cmd : {verify_cmd, certify_cmd, report_cmd, sweep_cmd}) {
        cmd->add_option("--max-faces", limits.max_faces, "limit: simplex faces of one KKT enumeration (copositivity); beyond it an obligation is undecided")->capture_default_str();
        cmd->add_option("--max-chambers", limits.max_chambers, "limit: steps of the chamber enumeration that decides a fan not meeting face to face")->capture_default_str();
        cmd->add_option("--max-subsets", limits.max_subsets, "limit: constraint subsets for the extreme rays of cone intersections (P1, not face to face)")->capture_default_str();
        cmd->add_option("--max-pieces", limits.max_pieces, "limit: pieces of a law given by orbit representatives, listed and generated (input error beyond it)")->capture_default_str();
        cmd->add_flag("--no-integer-kernels", no_integer_kernels, "decide the pair forms over GMP alone (same verdicts; for comparison)");
    }
    for (auto* cmd : {verify_cmd, certify_cmd, report_cmd})
        cmd->add_option("--jobs", verify_jobs, "threads for the pairwise checks (default: all cores); the output does not depend on it")->check(CLI::Range(1u, 256u));

    auto* fuzz_cmd = app.add_subcommand("fuzz", "fuzz a float implementation against the exact law; exit 0 no violation, 1 violation, 2 bad input");
    fuzz_cmd->add_option_function<std::string>("--seed", [&](const std::string& text) {
        std::string why;
        const auto seed = fuzz::parse_seed(text, &why);
        if (!seed)
            throw CLI::ValidationError("--seed", text + ": " + why);
        fuzz_options.seed = *seed;
    }, "seed, a decimal integer in [0, 2^64 - 1] (a run is a pure function of seed and sample index)");
    fuzz_cmd->add_option("--samples", fuzz_options.samples, "number of samples")->check(CLI::PositiveNumber);
    fuzz_cmd->add_option("--seconds", fuzz_options.seconds, "stop after this many seconds")->check(CLI::NonNegativeNumber);
    fuzz_cmd->add_option("--jobs", fuzz_options.jobs, "threads")->check(CLI::Range(1u, 256u));
    fuzz_cmd->add_option("--law", fuzz_args.law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    fuzz_cmd->add_flag("--velocities", fuzz_args.velocities, "the implementation maps ball velocities u- to u+ (n doubles) instead of contact velocities");
    fuzz_cmd->add_option("--impl", fuzz_args.impl_spec, "LIB.so:SYMBOL, a C function void f(const double* in, double* out)");
    fuzz_cmd->add_option("--impl-cmd", fuzz_args.impl_cmd, "a command (any language) reading lines of hex doubles on stdin and writing one line of doubles per line");
    fuzz_cmd->add_option("--impl-timeout", fuzz_args.timeout, "seconds without an answer from --impl-cmd before a point counts as hung")->check(CLI::PositiveNumber)->capture_default_str();
    fuzz_cmd->add_option_function<std::string>("--max-ulps", [&](const std::string& text) {
        std::string why;
        const auto k = fuzz::parse_seed(text, &why); // the same grammar: a decimal integer in [0, 2^64 - 1]
        if (!k)
            throw CLI::ValidationError("--max-ulps", text + ": must be a decimal integer in [0, 2^64 - 1]");
        fuzz_args.max_ulps = *k;
    }, "allowed error per component in ulps of the correctly rounded value (default: 0, or the built-in float law's stated bound with --law)");
    fuzz_cmd->add_option("--max-rel-error", fuzz_args.max_rel_error, "allowed normwise error |y - S(x)| <= R |x| in the law's metric (H; M for --velocities)");
    fuzz_cmd->add_option("--keep", fuzz_options.keep, "violations kept as examples")->check(CLI::Range(std::size_t{0}, std::size_t{1000000}))->capture_default_str();
    fuzz_cmd->add_flag("--json", fuzz_args.json, "print the summary as impactcert-fuzz/1 JSON");
    fuzz_cmd->add_option("--junit", fuzz_args.junit, "also write a JUnit XML report to this file");

    try {
        app.parse(argc, argv);
    } catch (const CLI::Success& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        // One line, like every other error (app.exit would add a second line).
        std::string message = e.what();
        for (char& ch : message)
            if (ch == '\n' || ch == '\r')
                ch = ' ';
        while (!message.empty() && message.back() == ' ')
            message.pop_back();
        std::cerr << "impactcert: " << message << "\n";
        return kExitBadInput;
    }
    limits.integer_kernels = !no_integer_kernels;
    limits.jobs = verify_jobs;
    try {
        if (verify_cmd->parsed())
            return run_verify(law_path, json, junit_path, limits);
        if (certify_cmd->parsed())
            return run_certify(law_path, out_path, limits);
        if (report_cmd->parsed())
            return run_report(law_path, out_path, limits);
        if (smt_cmd->parsed())
            return run_smt(law_path, out_path);
        if (sequential_cmd->parsed())
            return run_derive_sequential(derive_args);
        if (cradle_cmd->parsed())
            return run_derive_cradle(cradle_args);
        if (sweep_cmd->parsed()) {
            limits.jobs = 1; // sweep's --jobs are worker processes: one thread each
            limits.evidence = false;
            return run_sweep_command(sweep_args, limits);
        }
        if (fuzz_cmd->parsed()) {
            fuzz_args.impl_given = fuzz_cmd->count("--impl") > 0;
            fuzz_args.impl_cmd_given = fuzz_cmd->count("--impl-cmd") > 0;
            return run_fuzz(fuzz_args);
        }
        eval_float_args.impl_given = eval_cmd->count("--impl") > 0;
        eval_float_args.impl_cmd_given = eval_cmd->count("--impl-cmd") > 0;
        return run_eval(law_path, velocities, eval_args, as_float, eval_float_args);
    } catch (const InputError& e) {
        std::cerr << "impactcert: " << e.what() << "\n";
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "impactcert: internal error (please report): " << e.what() << "\n";
        return kExitInternal;
    }
}
