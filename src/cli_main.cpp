// cli_main.cpp -- the `impactcert` command (SPEC section 6).
//
// Exit status: 0 success / every claim proved; 1 a claim refuted; 2 bad input or usage.
// Every error is one line on stderr: "impactcert: <place>: <reason>".
#include "certificate.hpp"
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
#include <sstream>
#include <thread>

namespace impactcert {
namespace {

constexpr int kExitProved = 0;
constexpr int kExitRefuted = 1;
constexpr int kExitBadInput = 2;

Model load_model(const std::string& law_path) {
    return Model(law_path.empty() ? paper_law() : load_law_file(law_path));
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
    const Model model = load_model(law_path);
    const VerifyReport report = verify_with_progress(model, limits);
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
    const Model model = load_model(law_path);
    const VerifyReport report = verify_with_progress(model, limits);
    const std::string text = certificate_text(make_certificate(model, report));
    std::ofstream out(out_path, std::ios::binary);
    out << text;
    out.close();
    if (!out)
        throw InputError(out_path + ": cannot write the certificate");
    std::cerr << "impactcert: wrote " << out_path << " (" << report.law << ": "
              << report.verdict() << ")\n";
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
    const Model model = load_model(law_path);
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

// "LIB.so:SYMBOL" -> a C-ABI `void f(const double* gamma_minus, double* gamma_plus)`.
fuzz::Impl load_impl(const std::string& spec) {
    const auto colon = spec.rfind(':');
    if (colon == std::string::npos || colon == 0 || colon + 1 == spec.size())
        throw InputError("--impl " + spec + ": expected LIB.so:SYMBOL");
    const std::string lib = spec.substr(0, colon), symbol = spec.substr(colon + 1);
    void* handle = dlopen(lib.find('/') == std::string::npos ? ("./" + lib).c_str() : lib.c_str(), RTLD_NOW);
    if (!handle)
        throw InputError("--impl " + spec + ": cannot load: " + dlerror());
    void* f = dlsym(handle, symbol.c_str());
    if (!f)
        throw InputError("--impl " + spec + ": no symbol " + symbol);
    fuzz::Impl impl;
    static_assert(sizeof impl == sizeof f);
    std::memcpy(&impl, &f, sizeof f);
    return impl;
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

int run_eval_float(const std::string& law_path, bool velocities, const std::string& impl_spec,
                   const std::vector<std::vector<std::string>>& points) {
    if (!law_path.empty()) {
        // Any law file: the general float evaluator, with its error bound.
        if (velocities || !impl_spec.empty())
            throw InputError("--float --law: --velocities and --impl apply to the built-in float law only");
        const Model model = load_model(law_path);
        const FloatLaw law(model);
        for (const auto& toks : points) {
            std::vector<double> x;
            for (const auto& t : toks)
                x.push_back(parse_double(t, "input"));
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
    const fuzz::Impl impl = impl_spec.empty() ? nullptr : load_impl(impl_spec);
    for (const auto& toks : points) {
        std::vector<double> x;
        for (const auto& t : toks)
            x.push_back(parse_double(t, "input"));
        if (velocities) {
            fp::sort_velocities(x.data());
            std::printf("%a %a %a\n", x[0], x[1], x[2]);
            continue;
        }
        double law[2];
        fp::S(x[0], x[1], law);
        if (!impl) {
            std::printf("%a %a\n", law[0], law[1]);
            continue;
        }
        double out[2];
        impl(x.data(), out);
        const auto ref = fuzz::reference_fast(x[0], x[1]);
        std::printf("impl %a %a\nlaw  %a %a  (error %llu, %llu ulp)\n", out[0], out[1], ref.value[0], ref.value[1],
                    static_cast<unsigned long long>(fuzz::ulp_distance(out[0], ref.value[0])),
                    static_cast<unsigned long long>(fuzz::ulp_distance(out[1], ref.value[1])));
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

int run_fuzz(const fuzz::Options& options, bool json) {
    const fuzz::Impl impl = options.impl_spec.empty() ? nullptr : load_impl(options.impl_spec);
    const bool tty = !json && isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    auto progress = [&](std::uint64_t done) {
        if (!tty)
            return;
        const double frac = options.samples ? std::min(1.0, static_cast<double>(done) / static_cast<double>(options.samples)) : 1.0;
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const int width = 30, filled = static_cast<int>(frac * width);
        std::fprintf(stderr, "\r[%s%s] %3.0f%% %s/%s samples, %.1f M/s ", std::string(static_cast<std::size_t>(filled), '#').c_str(),
                     std::string(static_cast<std::size_t>(width - filled), '.').c_str(), frac * 100, count_text(done).c_str(),
                     count_text(options.samples).c_str(), secs > 0 ? static_cast<double>(done) / secs / 1e6 : 0.0);
    };
    const fuzz::Summary sum = fuzz::run(options, impl, progress);
    if (tty)
        std::fprintf(stderr, "\r%80s\r", "");
    const double rate = sum.seconds > 0 ? static_cast<double>(sum.samples) / sum.seconds : 0;
    const std::string target = options.impl_spec.empty() ? "built-in float law" : options.impl_spec;
    if (json) {
        Json j;
        j["format"] = "impactcert-fuzz/1";
        j["implementation"] = target;
        j["seed"] = options.seed;
        j["jobs"] = options.jobs;
        j["samples"] = sum.samples;
        j["pairs"] = sum.pairs;
        j["seconds"] = sum.seconds;
        j["samples_per_second"] = rate;
        j["max_error_ulps"] = {sum.max_ulps[0], sum.max_ulps[1]};
        j["violations"] = {{"classification", sum.misclassified}, {"error_above_max_ulps", sum.not_rounded},
                           {"negative_output", sum.negative}, {"energy", sum.energy},
                           {"nonexpansive", sum.nonexpansive}, {"non_finite", sum.non_finite}};
        Json examples = Json::array();
        for (const auto& v : sum.examples) {
            Json input = {fuzz::hex(v.sample.a.g[0]), fuzz::hex(v.sample.a.g[1])};
            examples.push_back({{"index", v.index}, {"what", v.what}, {"generator", v.sample.kind}, {"input", input},
                                {"output", {fuzz::hex(v.output[0]), fuzz::hex(v.output[1])}},
                                {"expected", {fuzz::hex(v.expected[0]), fuzz::hex(v.expected[1])}},
                                {"replay", v.replay}});
        }
        j["examples"] = examples;
        j["verdict"] = sum.violations() ? "violations" : "no violation";
        std::cout << j.dump(2) << "\n";
    } else {
        std::printf("impactcert fuzz: %s vs the exact law (seed %llu, %u job%s)\n", target.c_str(),
                    static_cast<unsigned long long>(options.seed), options.jobs, options.jobs == 1 ? "" : "s");
        std::printf("  samples                        %llu (%llu close pairs)\n",
                    static_cast<unsigned long long>(sum.samples), static_cast<unsigned long long>(sum.pairs));
        std::printf("  time                           %.2f s (%.1f M samples/s, %.1f M/s per job)\n", sum.seconds,
                    rate / 1e6, rate / 1e6 / std::max(1u, options.jobs));
        std::printf("  max error                      %llu ulp (gamma1+), %llu ulp (gamma2+)\n",
                    static_cast<unsigned long long>(sum.max_ulps[0]), static_cast<unsigned long long>(sum.max_ulps[1]));
        std::printf("  classification disagreements   %llu\n", static_cast<unsigned long long>(sum.misclassified));
        std::printf("  errors above %llu ulp             %llu\n", static_cast<unsigned long long>(options.max_ulps),
                    static_cast<unsigned long long>(sum.not_rounded));
        std::printf("  negative outputs (gamma+ < 0)  %llu\n", static_cast<unsigned long long>(sum.negative));
        std::printf("  energy increases               %llu\n", static_cast<unsigned long long>(sum.energy));
        std::printf("  non-expansivity violations     %llu\n", static_cast<unsigned long long>(sum.nonexpansive));
        std::printf("  non-finite outputs             %llu\n", static_cast<unsigned long long>(sum.non_finite));
        for (const auto& v : sum.examples)
            std::printf("  violation at sample %llu (%s): %s\n    input %a %a -> output %a %a, exact %a %a\n    replay: %s\n",
                        static_cast<unsigned long long>(v.index), v.sample.kind, v.what.c_str(), v.sample.a.g[0],
                        v.sample.a.g[1], v.output[0], v.output[1], v.expected[0], v.expected[1], v.replay.c_str());
        std::printf("verdict: %s\n", sum.violations() ? "violations found" : "no violation");
    }
    return sum.violations() ? kExitRefuted : kExitProved;
}

int run_eval(const std::string& law_path, bool velocities, const std::vector<std::string>& args, bool as_float,
             const std::string& impl_spec) {
    if (!impl_spec.empty() && !as_float)
        throw InputError("--impl needs --float");
    if (as_float) {
        const std::size_t dim = !law_path.empty() ? load_model(law_path).contacts() : velocities ? 3 : 2;
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
        return run_eval_float(law_path, velocities, impl_spec, points);
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
    std::string impl_spec;
    fuzz::Options fuzz_options;
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
    eval_cmd->add_option("--impl", impl_spec, "with --float: also run LIB.so:SYMBOL and show its error in ulps");
    eval_cmd->add_option("points", eval_args, "numbers: rationals (-3/4), decimals (0.1, 2.5e-3), hex floats (0x1.8p-3)");

    auto* derive_cmd = app.add_subcommand("derive", "derive an impact law from the mechanics (SPEC section 7)");
    derive_cmd->require_subcommand(1);
    auto* sequential_cmd = derive_cmd->add_subcommand("sequential", "the sequential impact law of a chain; exit 0 law written, 1 no finite law (with a witness), 2 bad input");
    sequential_cmd->add_option("--masses", derive_args.masses, "ball masses M1,M2,... (rationals, > 0)")->required();
    sequential_cmd->add_option("--restitution", derive_args.restitution, "E for every contact, or E1,...,E(n-1), each in [0, 1]")->capture_default_str();
    sequential_cmd->add_option("--rule", derive_args.rule, "which approaching contact impacts first: most-negative, left-first or right-first")->capture_default_str();
    sequential_cmd->add_option("--max-impacts", derive_args.max_impacts, "longest impact sequence allowed")->capture_default_str();
    sequential_cmd->add_option("-o,--output", derive_args.out, "law file to write (default: standard output)");

    auto* sweep_cmd = app.add_subcommand("sweep", "derive + verify over a grid of parameters named in --masses/--restitution; writes DIR/sweep.csv, sweep.json, sweep.html; exit 0 when it ran, 2 on bad input");
    sweep_cmd->add_option("--masses", sweep_args.masses, "ball masses, numbers or parameter names (1,m,1)")->required();
    sweep_cmd->add_option("--restitution", sweep_args.restitution, "E or E1,...,E(n-1), numbers or parameter names")->capture_default_str();
    sweep_cmd->add_option("--rule", sweep_args.rule, "most-negative, left-first or right-first")->capture_default_str();
    sweep_cmd->add_option("--max-impacts", sweep_args.max_impacts, "longest impact sequence allowed")->capture_default_str();
    sweep_cmd->add_option("--vary", sweep_args.vary, "NAME=LO..HI:COUNT[:log], once or twice")->required();
    sweep_cmd->add_option("--jobs", sweep_args.jobs, "worker processes (default: all cores)")->check(CLI::Range(1u, 256u));
    sweep_cmd->add_option("-o,--output", sweep_args.out, "directory to write sweep.csv, sweep.json and sweep.html into")->required();
    Limits limits;
    for (auto* cmd : {verify_cmd, certify_cmd, report_cmd, sweep_cmd}) {
        cmd->add_option("--max-faces", limits.max_faces, "limit: simplex faces of one KKT enumeration (copositivity); beyond it an obligation is undecided")->capture_default_str();
        cmd->add_option("--max-chambers", limits.max_chambers, "limit: steps of the chamber enumeration that decides a fan not meeting face to face")->capture_default_str();
        cmd->add_option("--max-subsets", limits.max_subsets, "limit: constraint subsets for the extreme rays of cone intersections (P1, not face to face)")->capture_default_str();
    }

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
    fuzz_cmd->add_option("--max-ulps", fuzz_options.max_ulps, "allowed error per component (default 0: correctly rounded)");
    fuzz_cmd->add_option("--impl", fuzz_options.impl_spec, "LIB.so:SYMBOL, a C function void f(const double* in, double* out)");
    fuzz_cmd->add_flag("--json", json, "print the summary as impactcert-fuzz/1 JSON");

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
        if (sweep_cmd->parsed())
            return run_sweep_command(sweep_args, limits);
        if (fuzz_cmd->parsed())
            return run_fuzz(fuzz_options, json);
        return run_eval(law_path, velocities, eval_args, as_float, impl_spec);
    } catch (const InputError& e) {
        std::cerr << "impactcert: " << e.what() << "\n";
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "impactcert: internal error (please report): " << e.what() << "\n";
        return kExitInternal;
    }
}
