// SPDX-License-Identifier: GPL-3.0-or-later
// cli_main.cpp -- the `impactcert` command (SPEC section 6).
//
// Exit status: 0 success / every claim proved; 1 a claim refuted; 2 bad input or usage.
// Every error is one line on stderr: "impactcert: <place>: <reason>" (cli/options.cpp,
// run_program; impactcert-verify's lines start with its own name).
#include "cli/options.hpp"
#include "cli/tools.hpp"
#include "report/figure.hpp"
#include "report/report.hpp"
#include "prover/smt.hpp"
#include "sweep/sweep.hpp"
#include "model/law_json.hpp"
#include "model/scene.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

namespace impactcert {
namespace {

using namespace cli;

// A figure was written as SVG only: says once why there is no PDF.
void note_without_pdf(bool figures) {
    const std::string why = figures ? pdf_unavailable_reason() : "";
    if (!why.empty())
        std::cerr << "impactcert: note: " << why << "\n";
}

int run_report(const std::string& law_path, const std::string& dir, const Limits& limits, bool with_worst, bool bare) {
    const Model model = load_model(law_path, limits);
    const VerifyReport report = verify_with_progress(model, limits);
    std::optional<WorstCase> worst;
    if (with_worst)
        worst = worst_case_of(model, report, limits);
    const WorstCase* w = worst ? &*worst : nullptr;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
        throw InputError(dir + ": cannot create directory: " + ec.message());
    std::vector<std::string> written = {dir + "/report.md", dir + "/report.html", dir + "/law.tex", dir + "/verdicts.tex"};
    write_file(written[0], report_markdown(model, report, w));
    write_file(written[1], report_html(model, report, w));
    write_file(written[2], law_latex(model));
    write_file(written[3], verdicts_latex(model, report, w));
    for (const auto& path : write_report_figures(model, report, dir + "/figures", bare))
        written.push_back(path);
    for (const auto& path : written)
        std::cout << path << "\n";
    note_without_pdf(written.size() > 4);
    return kExitProved; // a report is written whatever the verdict
}

struct SweepArgs {
    std::string masses, restitution, rule = "most-negative", out, shard, system, scene, law = "sequential",
        restitution_on = "all";
    bool thresholds = false;
    std::size_t threshold_digits = 10;
    std::vector<std::string> vary, merge;
    std::size_t max_impacts = 100, max_points = 100000, max_words = 2000;
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

// One line per threshold of DIR/sweep.json: the column, the change, the enclosure, and for
// energetic the boundary's polynomial and its root.
void print_thresholds(const std::string& path) {
    const Json doc = Json::parse(read_file_text(path));
    if (!doc.contains("thresholds"))
        return;
    const std::string name = doc["parameters"][0]["name"].get<std::string>();
    for (const auto& t : doc["thresholds"]) {
        std::cout << t["column"].get<std::string>() << ": " << t["below"].get<std::string>() << " -> "
                  << t["above"].get<std::string>() << " at " << name << " in [" << t["in"][0].get<std::string>() << ", "
                  << t["in"][1].get<std::string>() << "] (" << t["approx"].get<std::string>() << ")";
        if (t.contains("stopped"))
            std::cout << "; stopped: " << t["stopped"].get<std::string>();
        if (t.contains("boundary")) {
            const Json& b = t["boundary"];
            if (b.contains("polynomial"))
                std::cout << "; boundary " << b["polynomial"].get<std::string>() << " = 0 at "
                          << (b.contains("root") ? b["root"].get<std::string>() : b["root_approx"].get<std::string>());
            else
                std::cout << "; no polynomial: " << b["why_not"].get<std::string>();
        }
        std::cout << "\n";
    }
}

int run_sweep_command(const SweepArgs& a, const Limits& limits) {
    if (!a.merge.empty()) {
        if (!a.masses.empty() || !a.system.empty() || !a.scene.empty() || !a.vary.empty() || !a.shard.empty() || a.thresholds)
            throw InputError("--merge: the run is described by its parts; give no --masses, --system, --scene, --vary, --thresholds or --shard");
        try {
            merge_sweep_parts(a.merge, a.out, a.max_points);
        } catch (const Json::exception& e) {
            throw InputError(std::string("--merge: a part is not an impactcert-sweep-part/1 document (") + e.what() + ")");
        }
        std::cout << a.out << "/sweep.csv\n" << a.out << "/sweep.json\n" << a.out << "/sweep.html\n" << a.out << "/figures/\n";
        print_thresholds(a.out + "/sweep.json");
        note_without_pdf(true);
        return kExitProved;
    }
    const int sources = !a.masses.empty() + !a.system.empty() + !a.scene.empty();
    if (sources != 1)
        throw InputError(sources == 0 ? "--masses, --system or --scene is required (or --merge PART...)"
                                      : "--masses, --system and --scene: give one");
    if (a.vary.empty())
        throw InputError("--vary is required (or --merge PART...)");
    SweepSpec spec;
    if (!a.shard.empty())
        spec.shard = parse_shard(a.shard);
    if (!a.masses.empty()) {
        spec.masses = items(a.masses);
        spec.restitution = items(a.restitution.empty() ? "1" : a.restitution);
    } else {
        const std::string& path = a.system.empty() ? a.scene : a.system;
        spec.system_text = read_file_text(path);
        spec.system_origin = path;
        spec.system = parse_system_text(spec.system_text, path);
        const bool scene = Json::parse(spec.system_text).value("format", "") == std::string(kSceneFormat);
        if (!a.scene.empty() && !scene)
            throw InputError("--scene " + path + ": not an impactcert-scene/1 file (use --system)");
        if (!a.system.empty() && scene)
            throw InputError("--system " + path + ": a scene (use --scene)");
        if (!a.restitution.empty())
            spec.restitution = items(a.restitution);
    }
    spec.law = parse_sweep_law(a.law);
    spec.on = parse_restitution_on(a.restitution_on);
    if (spec.law == SweepLaw::poisson && spec.on != RestitutionOn::all)
        throw InputError("--restitution-on: the Poisson-type law has no such choice");
    if (spec.law == SweepLaw::sequential && spec.on != RestitutionOn::all)
        throw InputError("--restitution-on: the sequential law applies restitution at each impact (newton only)");
    spec.thresholds = a.thresholds;
    spec.threshold_digits = a.threshold_digits;
    spec.rule = parse_rule(a.rule);
    spec.max_impacts = a.max_impacts;
    spec.max_words = a.max_words;
    spec.limits = limits;
    spec.jobs = a.jobs;
    spec.max_points = a.max_points;
    for (const auto& v : a.vary)
        spec.parameters.push_back(parse_vary(v));
    const bool tty = isatty(2) != 0;
    const auto start = std::chrono::steady_clock::now();
    if (tty)
        spec.threshold_progress = [](const std::string& what) {
            std::fprintf(stderr, "\r\033[Kimpactcert: sweep: narrowing the change of %s", what.c_str());
        };
    run_sweep(spec, a.out, [&](std::size_t done, std::size_t total) {
        if (tty && std::chrono::steady_clock::now() - start > std::chrono::seconds(1))
            std::fprintf(stderr, "\r\033[Kimpactcert: sweep %zu/%zu points", done, total);
    });
    if (tty)
        std::fprintf(stderr, "\r\033[K");
    if (spec.shard)
        std::cout << sweep_part_path(a.out, *spec.shard) << "\n";
    else
        std::cout << a.out << "/sweep.csv\n" << a.out << "/sweep.json\n" << a.out << "/sweep.html\n" << a.out << "/figures/\n";
    if (spec.thresholds && !spec.shard)
        print_thresholds(a.out + "/sweep.json");
    note_without_pdf(!spec.shard);
    return kExitProved; // the verdicts are data
}

int run_smt(const std::string& law_path, const std::string& dir) {
    const Model model = load_model(law_path);
    model.require_independent_columns("smt");
    if (model.has_friction())
        throw InputError("--law: smt does not take laws with friction yet (verify and impactcert-check decide them)");
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

} // namespace
} // namespace impactcert

int main(int argc, char** argv) {
    using namespace impactcert;
    CLI::App app{"impactcert: exact proofs for cone-wise linear impact laws", "impactcert"};
    app.set_version_flag("--version", std::string("impactcert ") + IMPACTCERT_VERSION);
    app.require_subcommand(1);

    std::string law_path, out_path;
    bool velocities = false, as_float = false;
    FuzzArgs fuzz_args, eval_float_args;
    fuzz::Options& fuzz_options = fuzz_args.options;
    fuzz_options.jobs = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::string> eval_args;
    DeriveArgs derive_args;
    SweepArgs sweep_args;
    sweep_args.jobs = std::max(1u, std::thread::hardware_concurrency());

    ProofOptions proof;
    VerifyArgs verify_args;
    auto* verify_cmd = app.add_subcommand("verify", "decide every proof obligation; exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input, 3 undecided (a limit, named)");
    add_verify_options(verify_cmd, verify_args, proof);

    auto* certify_cmd = app.add_subcommand("certify", "write the impactcert-certificate/1 JSON; exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input, 3 undecided (a limit, named); with --shard K/N: 0 when the part is written (the verdict is the merge's: impactcert-check PART...)");
    certify_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    certify_cmd->add_option("-o,--output", out_path, "certificate file to write")->required();
    std::string shard_text;
    certify_cmd->add_option("--shard", shard_text, "K/N: write the part of slice K of N (impactcert-certificate-part/1); impactcert-check PART... merges and checks the parts")->check(cli::shard_text);
    add_shard_block_option(certify_cmd, proof);
    bool certify_worst = false;
    certify_cmd->add_flag("--worst-case", certify_worst, "also certify the law's exact worst case (sup T+/T-, Lipschitz constant): impactcert-check checks it");

    auto* report_cmd = app.add_subcommand("report", "write report.md (CI job summary), a self-contained report.html with pictures of the law, LaTeX tables (law.tex, verdicts.tex) and standalone figures (figures/*.svg, and *.pdf with rsvg-convert)");
    report_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    report_cmd->add_option("-o,--output", out_path, "directory to write the report into (created)")->required();
    bool report_worst = false;
    bool report_bare = false;
    report_cmd->add_flag("--bare-figures", report_bare, "figures without their title and caption, for a paper that sets them in LaTeX (the legend stays; report.html has the captions)");
    report_cmd->add_flag("--worst-case", report_worst, "also the law's exact worst case (sup T+/T- and, for a continuous tiling, the Lipschitz constant in H) in report.md, report.html and verdicts.tex");

    auto* smt_cmd = app.add_subcommand("smt", "write one SMT-LIB2 file per universal claim (the claim negated: unsat = holds)");
    smt_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    smt_cmd->add_option("-o,--output", out_path, "directory to write the .smt2 files into")->required();

    auto* eval_cmd = app.add_subcommand("eval", "evaluate S exactly at points given as arguments or stdin lines; exit 0, 2 bad input; with --float and --impl/--impl-cmd (the fuzzer's replays): 1 when an answer is off (beyond --max-ulps, or inconsistent)");
    eval_cmd->add_option("--law", law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    eval_cmd->add_flag("--velocities", velocities, "points are ball velocities u- (print u+)");
    eval_cmd->add_flag("--float", as_float, "evaluate the float law in double (inputs read with strtod; output in hex, %a)");
    eval_cmd->add_option("--impl", eval_float_args.impl_spec, "with --float: run LIB.so:SYMBOL and show its output against the correctly rounded exact value");
    eval_cmd->add_option("--impl-cmd", eval_float_args.impl_cmd, "with --float: the same for a command (see fuzz --impl-cmd)");
    eval_cmd->add_option("--impl-timeout", eval_float_args.timeout, "seconds to wait for --impl-cmd's answer")->check(positive_text, "> 0");
    eval_cmd->add_flag("--pieces", eval_float_args.pieces, "also name the piece(s) each point lies in (for derived laws: the word)");
    eval_cmd->add_option("--masses", eval_float_args.system.masses, "with --float and --impl/--impl-cmd, no --law: check the output's consistency with this chain");
    eval_cmd->add_option("--walls", eval_float_args.system.walls, "with --masses: fixed walls")->capture_default_str();
    eval_cmd->add_option("--system", eval_float_args.system.system_path, "with --float and --impl/--impl-cmd: check consistency with this system");
    eval_cmd->add_option("--max-rel-error", eval_float_args.max_rel_error, "the relative tolerance the answers are judged by (as fuzz; law mode and consistency)");
    eval_cmd->add_option("--restitution", eval_float_args.restitution, "consistency: the restitution the implementation is meant to apply (as fuzz)");
    eval_cmd->add_option("--cone", eval_float_args.cone, "consistency: the friction cone the answer is judged by (as fuzz: box or circular)");
    eval_cmd->add_option("--reference", eval_float_args.reference, "consistency: the exact law the implementation means to compute (as fuzz): the answer is checked against it");
    eval_cmd->add_option_function<std::string>("--max-ulps", [&](const std::string& text) {
        std::string why;
        const auto k = fuzz::parse_seed(text, &why); // a decimal integer in [0, 2^64 - 1]
        if (!k)
            throw CLI::ValidationError("--max-ulps", text + ": must be a decimal integer in [0, 2^64 - 1]");
        eval_float_args.max_ulps = *k;
    }, "with --float and --impl/--impl-cmd against a law: the error allowed per component (default 0); exit 1 beyond it");
    eval_cmd->add_option("--mutant", eval_float_args.mutant, "with --float --law: the answer of this mutant of the law's plain double evaluation (fuzz --mutants), against the exact law");
    eval_cmd->add_option("--float-law", eval_float_args.float_law, "consistency: the implementation is impactcert's float law of this file");
    eval_cmd->add_flag("--pair", eval_float_args.pair, "consistency: the two points are a pair (non-expansivity, continuity)");
    eval_cmd->add_option("points", eval_args, "numbers: rationals (-3/4), decimals (0.1, 2.5e-3), hex floats (0x1.8p-3)");

    auto* derive_cmd = app.add_subcommand("derive", "derive an impact law from the mechanics (docs/derive.md)");
    derive_cmd->require_subcommand(1);
    DeriveArgs newton_args, poisson_args;
    auto* sequential_cmd = derive_cmd->add_subcommand("sequential", "the sequential impact law of a system (a chain by default); exit 0 law written, 1 with friction not a function or with --rule any the order matters (witness), 2 bad input, 3 a limit (--max-impacts: a sequence longer than the bound, with the point; --max-memory, --max-bits, --max-words)");
    auto* newton_cmd = derive_cmd->add_subcommand("newton", "the Newton-type simultaneous impact law (an LCP), exactly; exit 0 law written, 1 with friction: not a function (the witness), 2 bad input, 3 a limit (--max-bits, --max-memory, --max-modes)");
    auto* poisson_cmd = derive_cmd->add_subcommand("poisson", "the Poisson-type simultaneous impact law (compression and expansion LCPs), exactly; exit 0 law written, 2 bad input, 3 a limit (--max-bits, --max-memory)");
    for (auto [cmd, args] : {std::pair{sequential_cmd, &derive_args}, std::pair{newton_cmd, &newton_args}, std::pair{poisson_cmd, &poisson_args}}) {
        cmd->add_option("--masses", args->system.masses, "a chain: ball masses M1,M2,... (rationals, > 0)");
        cmd->add_option("--walls", args->system.walls, "with --masses: fixed walls, none, left or right (both would jam the chain: n + 1 contacts for n velocities)")->capture_default_str();
        cmd->add_option("--system", args->system.system_path, "a system file (impactcert-system/1, or a law file's head): M or masses, and W");
        cmd->add_option("--restitution", args->restitution, "E for every contact, or one per contact, each in [0, 1] (default: a scene's, else 1)");
        cmd->add_option("--outcomes-from", args->outcomes_from, "declare the outcomes of this law file (e.g. the observed ones of proofs/newton3/law.json) instead of the simulated ones");
        cmd->add_option("-o,--output", args->out, "law file to write (default, or -: standard output)");
    }
    for (auto [cmd, args] : {std::pair{sequential_cmd, &derive_args}, std::pair{newton_cmd, &newton_args}, std::pair{poisson_cmd, &poisson_args}})
    {
        cmd->add_option("--max-bits", args->max_bits, "limit: bits of one matrix entry (numerator and denominator) during the derivation; undecided (exit 3) beyond it")->check(natural_text)->capture_default_str();
        cmd->add_option("--max-memory", args->max_memory_mb, "limit: megabytes of the regions and pieces the derivation holds (counted as they grow); undecided (exit 3) beyond it")->check(natural_text)->capture_default_str();
    }
    sequential_cmd->add_flag("--json", derive_args.json, "with exit 1 (a witness) or exit 3 at --max-impacts (the point): the exact gamma- as JSON on standard output");
    sequential_cmd->add_option("--rule", derive_args.rule, "which approaching contact impacts first: most-negative, left-first or right-first; any: every admissible order (the law when the order never matters, else exit 1 with a witness)")->capture_default_str();
    sequential_cmd->add_option("--max-words", derive_args.max_words, "with --rule any: limit on the admissible words (cells) examined; undecided (exit 3) beyond it")->check(natural_text)->capture_default_str();
    sequential_cmd->add_option("--max-impacts", derive_args.max_impacts, "longest impact sequence allowed")->check(natural_text)->capture_default_str();
    sequential_cmd->add_flag("--stream", derive_args.stream, "write the pieces as they are found (needs -o FILE): memory grows with the exploration's frontier and the largest bucket of regions, not with the law; the same law, its pieces in another order; spill files beside FILE, removed at the end");
    newton_cmd->add_option("--restitution-tangential", newton_args.restitution_tangential, "with friction: e_T of every tangent, in [0, 1] (default: the system's, else 0)");
    newton_cmd->add_option("--max-modes", newton_args.max_modes, "with friction: limit on the contact modes enumerated (their pairs are compared); undecided (exit 3) beyond it")->check(natural_text)->capture_default_str();
    newton_cmd->add_flag("--json", newton_args.json, "with friction and exit 1 (not a function): the exact witness as JSON on standard output");
    newton_cmd->add_option("--restitution-on", newton_args.restitution_on, "all (the classical inequality law) or approaching (restitution only where gamma-_k < 0, as physics engines do)")->capture_default_str();

    CradleArgs cradle_args;
    auto* cradle_cmd = derive_cmd->add_subcommand("cradle", "the N-ball equal-mass elastic law (S = sort) with its symmetries declared; exit 0 law written, 2 bad input");
    cradle_cmd->add_option("--balls", cradle_args.balls, "number of balls N (2..12)")->check(natural_text)->required();
    cradle_cmd->add_option("--pieces", cradle_args.pieces, "representatives (one piece, the rest generated by the symmetries) or all (every ordering listed)")->capture_default_str();
    cradle_cmd->add_flag("--no-symmetries", cradle_args.no_symmetries, "declare no symmetries (needs --pieces all)");
    cradle_cmd->add_option("-o,--output", cradle_args.out, "law file to write (default: standard output)");

    auto* sweep_cmd = app.add_subcommand("sweep", "derive + verify over a grid of parameters named in --masses/--restitution; writes DIR/sweep.csv, sweep.json, sweep.html and figures/ (one SVG and PDF per map); exit 0 when it ran (verdicts per point in the files), 2 on bad input, 3 beyond --max-points");
    sweep_cmd->add_option("--masses", sweep_args.masses, "ball masses, numbers or parameter names (1,m,1)");
    sweep_cmd->add_option("--system", sweep_args.system, "an impactcert-system/1 file instead of a chain; parameters mu, muK (contact K's friction), e, eK (restitution)");
    sweep_cmd->add_option("--scene", sweep_args.scene, "an impactcert-scene/1 file instead of a chain (parameters as --system)");
    sweep_cmd->add_option("--law", sweep_args.law, "the law derived at each point: sequential, newton or poisson")->capture_default_str();
    sweep_cmd->add_option("--restitution-on", sweep_args.restitution_on, "newton: all or approaching")->capture_default_str();
    sweep_cmd->add_option("--restitution", sweep_args.restitution, "E or E1,...,E(n-1), numbers or parameter names (default: 1; a scene's own)");
    sweep_cmd->add_flag("--thresholds", sweep_args.thresholds, "one parameter: enclose each change of a verdict between grid points by exact bisection (energetic: with its polynomial), in sweep.json and sweep.html");
    sweep_cmd->add_option("--threshold-digits", sweep_args.threshold_digits, "--thresholds: enclosures at most 10^-D wide")->check(CLI::Range(1, 100))->capture_default_str();
    sweep_cmd->add_option("--rule", sweep_args.rule, "most-negative, left-first or right-first")->capture_default_str();
    sweep_cmd->add_option("--max-impacts", sweep_args.max_impacts, "longest impact sequence allowed")->check(natural_text)->capture_default_str();
    sweep_cmd->add_option("--max-words", sweep_args.max_words, "the order-independent column: cells walked per point (and 100 pairs per cell); undecided beyond")->check(natural_text)->capture_default_str();
    sweep_cmd->add_option("--vary", sweep_args.vary, "NAME=LO..HI:COUNT[:log], once or twice");
    sweep_cmd->add_option("--shard", sweep_args.shard, "K/N: only the grid points k with k mod N = K-1, written to DIR/sweep.part-K-of-N.json (merge with --merge)")->check(cli::shard_text);
    sweep_cmd->add_option("--merge", sweep_args.merge, "PART...: merge the part files of one sharded run (each shard once, every point covered) into DIR");
    sweep_cmd->add_option("--max-points", sweep_args.max_points, "limit: grid points in all (undecided, exit 3, beyond it)")->check(natural_text)->capture_default_str();
    sweep_cmd->add_option("--jobs", sweep_args.jobs, "worker processes (default: all cores)")->check(natural_text)->check(CLI::Range(1u, 256u));
    sweep_cmd->add_option("-o,--output", sweep_args.out, "directory to write sweep.csv, sweep.json, sweep.html and figures/ into")->required();
    for (auto* cmd : {certify_cmd, report_cmd, sweep_cmd})
        add_limit_options(cmd, proof);
    for (auto* cmd : {certify_cmd, report_cmd}) {
        add_claims_option(cmd, proof);
        add_jobs_option(cmd, proof);
    }

    auto* fuzz_cmd = app.add_subcommand("fuzz", "fuzz a float implementation against the exact law; exit 0 no violation, 1 violation, 2 bad input, 3 undecided (no sample checked before --seconds)");
    fuzz_cmd->add_option_function<std::string>("--seed", [&](const std::string& text) {
        std::string why;
        const auto seed = fuzz::parse_seed(text, &why);
        if (!seed)
            throw CLI::ValidationError("--seed", text + ": " + why);
        fuzz_options.seed = *seed;
    }, "seed, a decimal integer in [0, 2^64 - 1] (a run is a pure function of seed and sample index)");
    fuzz_cmd->add_option("--samples", fuzz_options.samples, "number of samples")->check(positive_text, "> 0");
    fuzz_cmd->add_option("--seconds", fuzz_options.seconds, "stop after this many seconds (> 0; without it, no time limit)")->check(positive_text, "> 0");
    fuzz_cmd->add_option("--jobs", fuzz_options.jobs, "threads")->check(natural_text)->check(CLI::Range(1u, 256u));
    fuzz_cmd->add_option("--law", fuzz_args.law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    fuzz_cmd->add_flag("--velocities", fuzz_args.velocities, "the implementation maps ball velocities u- to u+ (n doubles) instead of contact velocities");
    fuzz_cmd->add_option("--impl", fuzz_args.impl_spec, "LIB.so:SYMBOL, a C function void f(const double* in, double* out)");
    fuzz_cmd->add_option("--impl-cmd", fuzz_args.impl_cmd, "a command (any language) reading lines of hex doubles on stdin and writing one line of doubles per line");
    fuzz_cmd->add_option("--impl-timeout", fuzz_args.timeout, "seconds without an answer from --impl-cmd before a point counts as hung")->check(positive_text, "> 0")->capture_default_str();
    fuzz_cmd->add_option_function<std::string>("--max-ulps", [&](const std::string& text) {
        std::string why;
        const auto k = fuzz::parse_seed(text, &why); // the same grammar: a decimal integer in [0, 2^64 - 1]
        if (!k)
            throw CLI::ValidationError("--max-ulps", text + ": must be a decimal integer in [0, 2^64 - 1]");
        fuzz_args.max_ulps = *k;
    }, "allowed error per component in ulps of the correctly rounded value (default: 0, or the built-in float law's stated bound with --law)");
    fuzz_cmd->add_option("--max-rel-error", fuzz_args.max_rel_error, "allowed normwise error |y - S(x)| <= R |x| in the law's metric (H; M for --velocities)");
    fuzz_cmd->add_option("--keep", fuzz_options.keep, "violations kept as examples")->check(natural_text)->check(CLI::Range(std::size_t{0}, std::size_t{1000000}))->capture_default_str();
    fuzz_cmd->add_option("--masses", fuzz_args.system.masses, "without --law: check the implementation's consistency with this chain (ball masses)");
    fuzz_cmd->add_option("--walls", fuzz_args.system.walls, "with --masses: fixed walls, none, left or right (both would jam the chain: n + 1 contacts for n velocities)")->capture_default_str();
    fuzz_cmd->add_option("--system", fuzz_args.system.system_path, "without --law: check consistency with this system (impactcert-system/1 or a law file)");
    fuzz_cmd->add_option("--float-law", fuzz_args.float_law, "consistency: test impactcert's own float implementation of this law file (contact velocities)");
    fuzz_cmd->add_option("--require", fuzz_args.require, "consistency: also check nonexpansive and/or continuity on close pairs (comma-separated)");
    fuzz_cmd->add_option("--cone", fuzz_args.cone, "consistency, systems with friction: box (default: each tangent bounded by mu Lambda_N on its own, as impactcert's laws and ODE's dContactApprox1) or circular (|Lambda_T| <= mu Lambda_N over a contact's tangents and the friction opposite the slip, as Jolt, MuJoCo's elliptic cone and Siconos's fc3d; no --reference)");
    fuzz_cmd->add_option("--reference", fuzz_args.reference, "consistency: the exact law the implementation means to compute, a law file of the system or by name (approaching: the Newton law with restitution on approaching contacts, what sequential-impulse engines converge to; newton; poisson; with --restitution): each finding is then law-level or solver-level");
    fuzz_cmd->add_option("--restitution", fuzz_args.restitution, "consistency: the restitution the implementation is meant to apply (E, or one per contact); checks the restitution property (frictionless: where one contact alone approaches; with friction: Newton's, at every approaching contact that pushes) and gives the restitution of --reference approaching/newton");
    fuzz_cmd->add_option("--range", fuzz_args.range, "input components 0 or of magnitude in LO..HI (consistency: default 1e-3..1e3; law mode: default the whole double range, each sample scaled by a power of two drawn uniformly among those that put its largest component in the range)");
    fuzz_cmd->add_option("--allow", fuzz_args.allow, "law mode: extreme -- violations at inputs whose largest component is beyond 2^500 (about 3.3e150) or below 2^-500 are reported but do not fail the run (plain formulas overflow or underflow there)");
    fuzz_cmd->add_option("--efforts", fuzz_args.efforts, "consistency, with --reference and {iterations} in --impl-cmd: the efforts to run the command at (comma-separated integers, default 4,64); a distance to the reference that shrinks with effort is solver-level, one that does not is model-level (the engine computes another law)");
    fuzz_cmd->add_option("--mutants", fuzz_args.mutants, "law mode: run this gate (tolerance, --range, --samples/--seconds, --allow, --seed) against N mutants of the law's plain double evaluation (planted bugs: thresholds, cone tests, signs, formulas, float32, overflow) and print its kill rate; exit 1 when the control fails or the rate is below --min-kill-rate")->check(natural_text)->check(CLI::Range(std::size_t{1}, std::size_t{100000}));
    fuzz_cmd->add_option("--min-kill-rate", fuzz_args.min_kill_rate, "with --mutants: exit 1 when the kill rate is below this fraction (0..1)");
    fuzz_cmd->add_option("--mutant", fuzz_args.mutant, "law mode: fuzz one mutant of the law's plain double evaluation (an ID that --mutants prints; none: the plain evaluation itself)");
    fuzz_cmd->add_flag("--json", fuzz_args.json, "print the summary as impactcert-fuzz/1 JSON");
    fuzz_cmd->add_option("--junit", fuzz_args.junit, "also write a JUnit XML report to this file");

    // Examples and the exit statuses at the end of every --help (docs/exit-status.md has the table).
    app.footer("Exit statuses: 0 done (proved, written, no violation), 1 shown false with a witness, 2 bad input,\n"
               "3 undecided at a limit (the option is named). Table: docs/exit-status.md. Formats: docs/formats.md.\n"
               "Run `impactcert COMMAND --help` for a command's options and examples.");
    const std::pair<CLI::App*, const char*> examples[] = {
        {verify_cmd, "Examples:\n  impactcert verify                                 # the paper's 3-ball law\n"
                     "  impactcert verify --law proofs/newton4/law.json --json\n"
                     "  impactcert verify --law proofs/cradle4/law.json --shard 2/8 --json  # slice 2 of 8\n"
                     "  impactcert verify --law proofs/classical3/newton-approaching/law.json --worst-case  # sup T+/T- = 4/3"},
        {certify_cmd, "Examples:\n  impactcert certify -o cert.json && impactcert-check cert.json\n"
                      "  for k in 1 2 3; do impactcert certify --law proofs/cradle4/law.json --shard $k/3 -o part$k.json; done\n"
                      "  impactcert-check --merged cert.json part1.json part2.json part3.json\n"
                      "  impactcert certify --worst-case -o cert.json && impactcert-check cert.json  # with the exact worst case"},
        {report_cmd, "Examples:\n  impactcert report --law proofs/newton4/law.json -o report/"},
        {smt_cmd, "Examples:\n  impactcert smt -o smt/ && z3 smt/nonexpansive.smt2   # unsat: the claim holds"},
        {eval_cmd, "Examples:\n  impactcert eval -- -1 0                  # gamma+ of the paper's law at gamma- = (-1, 0)\n"
                   "  impactcert eval --velocities --pieces 1 0 0\n"
                   "  impactcert eval --float --law proofs/newton4/law.json -- 0x1p-3 -1 0"},
        {sequential_cmd, "Examples:\n  impactcert derive sequential --masses 1,1,1 -o newton3.json\n"
                         "  impactcert derive sequential --masses 1,2,1 --rule any --json\n"
                         "  impactcert derive sequential --system examples/scenes/two-disks.json --restitution 1/2"},
        {newton_cmd, "Examples:\n  impactcert derive newton --masses 1,1,1 --restitution-on approaching\n"
                     "  impactcert derive newton --system proofs/kane/gains/system.json --restitution 1/2"},
        {poisson_cmd, "Examples:\n  impactcert derive poisson --masses 1,2,1 --walls left --restitution 1/2"},
        {cradle_cmd, "Examples:\n  impactcert derive cradle --balls 6 -o cradle6.json"},
        {sweep_cmd, "Examples:\n  impactcert sweep --masses 1,m,1 --restitution e --vary m=1/4..4:8:log --vary e=0..1:5 -o sweep/"},
        {fuzz_cmd, "Examples:\n  impactcert fuzz --samples 100000                  # the built-in float law of the paper\n"
                   "  impactcert fuzz --law proofs/newton4/law.json --impl build/tests/libimpactcert_example_newton4.so:newton4_two_sweeps --samples 100000\n"
                   "  impactcert fuzz --masses 1,1,1 --velocities --impl-cmd 'python3 examples/engines/newton_cradle.py --restitution 1' --samples 2000"},
    };
    for (const auto& [cmd, text] : examples)
        cmd->footer(std::string(text) + "\nExit statuses: docs/exit-status.md.");

    return run_program(app, argc, argv, [&]() -> int {
        const Limits limits = proof.resolved();
        try {
            if (verify_cmd->parsed())
                return run_verify_command(verify_args, limits);
            if (certify_cmd->parsed()) {
                if (certify_worst && !shard_text.empty())
                    throw InputError("--worst-case: not with --shard (the worst case is certified over every piece in one process)");
                return shard_text.empty() ? run_certify(law_path, out_path, certify_worst, limits)
                                          : run_certify_shard(law_path, parse_shard(shard_text), out_path, limits);
            }
            if (report_cmd->parsed())
                return run_report(law_path, out_path, limits, report_worst, report_bare);
            if (smt_cmd->parsed())
                return run_smt(law_path, out_path);
            if (sequential_cmd->parsed())
                return run_derive_sequential(derive_args);
            if (newton_cmd->parsed())
                return run_derive_classical(newton_args, false);
            if (poisson_cmd->parsed())
                return run_derive_classical(poisson_args, true);
            if (cradle_cmd->parsed())
                return run_derive_cradle(cradle_args);
            if (sweep_cmd->parsed()) {
                Limits one_thread = limits;
                one_thread.jobs = 1; // sweep's --jobs are worker processes: one thread each
                one_thread.evidence = false;
                return run_sweep_command(sweep_args, one_thread);
            }
            if (fuzz_cmd->parsed()) {
                fuzz_args.impl_given = fuzz_cmd->count("--impl") > 0;
                fuzz_args.impl_cmd_given = fuzz_cmd->count("--impl-cmd") > 0;
                fuzz_args.restitution_given = fuzz_cmd->count("--restitution") > 0;
                fuzz_args.reference_given = fuzz_cmd->count("--reference") > 0;
                fuzz_args.mutant_given = fuzz_cmd->count("--mutant") > 0;
                return run_fuzz(fuzz_args);
            }
            eval_float_args.impl_given = eval_cmd->count("--impl") > 0;
            eval_float_args.impl_cmd_given = eval_cmd->count("--impl-cmd") > 0;
            eval_float_args.restitution_given = eval_cmd->count("--restitution") > 0;
            eval_float_args.reference_given = eval_cmd->count("--reference") > 0;
            eval_float_args.mutant_given = eval_cmd->count("--mutant") > 0;
            return run_eval(law_path, velocities, eval_args, as_float, eval_float_args);
        } catch (const DeriveLimit& e) {
            throw Undecided(std::string("derive: ") + e.what());
        } catch (const SweepLimit& e) {
            throw Undecided(e.what());
        }
    });
}
