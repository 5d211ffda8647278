// SPDX-License-Identifier: GPL-3.0-or-later
// cli/fuzz.cpp -- `impactcert fuzz` and `impactcert eval` against a law (cli/consistency.cpp: the
// consistency of a black-box map against a system alone).
#include "cli/tools.hpp"

#include "fuzz/consistency.hpp"
#include "fuzz/float_eval.hpp"
#include "fuzz/fuzz_mutants.hpp"
#include "fuzz/fuzz_report.hpp"
#include "base/json.hpp"
#include "base/junit.hpp"
#include "prover/verdict_output.hpp"

#include <impactcert/float_law.hpp>

#include <unistd.h>

#include <array>
#include <chrono>
#include <map>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>

namespace impactcert::cli {

namespace {

// One point: c contact velocities, or n ball velocities with --velocities.
std::string evaluate_point(const Model& model, const Vector& x, bool velocities, const std::string& where,
                           bool show_pieces = false) {
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
    if (show_pieces) {
        // Which piece (for a derived law: which word) the point lies in; several on a boundary.
        std::string names;
        for (auto p : model.pieces_containing(gamma))
            names += (names.empty() ? "" : ", ") + model.pieces()[p].name;
        out += "  # " + std::string(model.pieces_containing(gamma).size() > 1 ? "pieces " : "piece ") + names;
    }
    return out;
}

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
    if (!a.mutant.empty()) {
        if (a.impl_given || a.impl_cmd_given)
            throw InputError("--mutant and --impl/--impl-cmd: a mutant is of the law's own plain evaluation; give one");
        if (a.velocities)
            throw InputError("--mutant: the law's plain evaluation takes contact velocities (no --velocities)");
        return fuzz::plain_law(model, fuzz::parse_mutation(a.mutant, model));
    }
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
std::vector<double> parse_doubles(const std::vector<std::string>& toks) {
    std::vector<double> x;
    for (const auto& t : toks)
        x.push_back(parse_double(t, "input"));
    return x;
}

int run_eval_float(const FuzzArgs& a, const std::vector<std::vector<std::string>>& points) {
    if (a.impl_given || a.impl_cmd_given || !a.mutant.empty()) {
        // An implementation against the exact law, point by point (the fuzzer's replays).
        const Model model = load_model(a.law_path);
        model.require_independent_columns("fuzz --law");
        const fuzz::LawFacts facts = fuzz::law_facts(model, a.velocities);
        const fuzz::LawReference reference(model, a.velocities, facts.continuous_tiling);
        auto impl = make_impl(a, model, reference.in_dim());
        if (a.max_ulps && a.max_rel_error)
            throw InputError("--max-ulps and --max-rel-error: give one tolerance");
        if (a.max_rel_error && !(*a.max_rel_error >= 0 && std::isfinite(*a.max_rel_error)))
            throw InputError("--max-rel-error: must be a finite number >= 0");
        // Exit 1 when an answer is not within the tolerance the fuzzer used: --max-ulps (default
        // 0) of a correctly rounded value, or --max-rel-error in the law's metric, decided exactly
        // (issue 32: a replay showing a 10^18-ulp error exited 0; a replay that dropped
        // --max-rel-error judged at 0 ulp).
        const std::uint64_t allowed = a.max_ulps.value_or(0);
        fuzz::Options tol;
        if (a.max_rel_error) {
            tol.tolerance = fuzz::Tolerance::relative;
            tol.max_rel_error = *a.max_rel_error;
        }
        bool off = false;
        for (const auto& toks : points) {
            const auto x = parse_doubles(toks);
            std::uint64_t worst = 0;
            std::vector<double> y;
            std::printf("%s", fuzz::explain(reference, impl.get(), x.data(), &worst, &y).c_str());
            if (!a.max_rel_error)
                off = off || worst > allowed;
            else
                off = off || (y.empty() ? worst > 0 : fuzz::exact_violation(model, tol, x.data(), y.data(), nullptr, a.velocities));
        }
        if (off && a.max_rel_error)
            std::printf("not within --max-rel-error %s of the exact value in the law's metric\n",
                        fuzz::shortest_decimal(*a.max_rel_error).c_str());
        else if (off)
            std::printf("not within %llu ulp of the correctly rounded value (--max-ulps)\n",
                        static_cast<unsigned long long>(allowed));
        return off ? kExitRefuted : kExitProved;
    }
    if (!a.law_path.empty()) {
        // Any law file: the general float evaluator, with its error bound.
        if (a.velocities)
            throw InputError("--float --law --velocities: the built-in float law takes contact velocities");
        const Model model = load_model(a.law_path);
        model.require_independent_columns("fuzz --law");
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

std::string fuzz_junit(const fuzz::Summary& sum, const std::string& target, const fuzz::Options& o) {
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
                          {"implementation failures", sum.crashed + sum.hung + sum.malformed + sum.refused},
                          {"extreme magnitudes", sum.extreme}};
    // Each failing case quotes an example of its own class (the examples' `what` says which).
    auto starts = [](const std::string& s, const char* p) { return s.rfind(p, 0) == 0; };
    auto class_of = [&](const fuzz::Violation& v) -> std::string {
        if (starts(v.what, "classification:"))
            return "classification";
        if (starts(v.what, "non-finite"))
            return "non-finite outputs";
        if (starts(v.what, "negative contact velocity"))
            return "negative contact velocities";
        if (starts(v.what, "energy increase"))
            return "energy";
        if (starts(v.what, "non-expansivity"))
            return "non-expansivity";
        if (starts(v.what, "the implementation") || starts(v.what, "nondeterministic") || starts(v.what, "the built-in"))
            return "implementation failures";
        return "accuracy";
    };
    auto example_of = [&](const std::string& name) {
        for (const auto& v : sum.examples)
            if (name == "extreme magnitudes" ? v.extreme : (class_of(v) == name && (!v.extreme || !o.allow_extreme)))
                return v.what + "; replay: " + v.replay;
        // A classification error is an accuracy violation too: its example stands for both.
        if (name == "accuracy")
            for (const auto& v : sum.examples)
                if (class_of(v) == "classification" && (!v.extreme || !o.allow_extreme))
                    return v.what + "; replay: " + v.replay;
        return std::string("no example of this class among the ") + std::to_string(sum.examples.size()) +
               " kept (raise --keep)";
    };
    JunitSuite suite{"impactcert fuzz: " + target, {}};
    for (const auto& c : cases) {
        JunitCase t;
        t.classname = "impactcert.fuzz";
        t.name = c.name;
        if (suite.cases.empty()) // the run's time (every class is checked on the same samples)
            t.time = std::chrono::nanoseconds(static_cast<long long>(sum.seconds * 1e9));
        const bool allowed_class = o.allow_extreme && std::string(c.name) == "extreme magnitudes";
        if (c.count && sum.fails(o.allow_extreme) && !allowed_class) {
            t.kind = JunitCase::Kind::failed;
            t.type = "violations";
            t.message = std::to_string(c.count) + " violation(s) in " + std::to_string(sum.samples) + " samples";
            t.text = example_of(c.name);
        } else if (c.count) { // violations at extreme inputs, allowed
            t.system_out = std::to_string(c.count) + (allowed_class ? " sample(s) with violations at extreme magnitudes (allowed: --allow extreme)"
                                                                    : " violation(s), all at extreme magnitudes (allowed: --allow extreme)");
        }
        suite.cases.push_back(std::move(t));
    }
    JunitCase cov;
    cov.classname = "impactcert.fuzz";
    cov.name = "coverage";
    cov.system_out = fuzz::coverage_text(sum);
    for (const auto& line : fuzz::untested(sum, o))
        cov.system_out += "\nnot tested: " + line;
    suite.cases.push_back(std::move(cov));
    return junit_xml(suite);
}

// fuzz --mutants N: the configured gate against mutants of the law's plain double evaluation.
int run_mutants_gate(const FuzzArgs& a, const Model& model, const fuzz::LawReference& reference,
                     const fuzz::Properties& properties, const std::string& tolerance) {
    const fuzz::Options& o = a.options;
    const bool tty = !a.json && isatty(STDERR_FILENO);
    auto progress = [&](std::size_t done, std::size_t total) {
        if (tty)
            std::fprintf(stderr, "\r  mutants: %zu/%zu ", done, total);
    };
    const fuzz::MutantsReport rep = fuzz::run_mutants(o, reference, properties, *a.mutants, progress);
    if (tty)
        std::fprintf(stderr, "\r\033[K");
    using Status = fuzz::MutantResult::Status;
    auto status_name = [&](const fuzz::MutantResult& r) -> std::string {
        switch (r.status) {
        case Status::killed:
            return "killed";
        case Status::equivalent:
            return "equivalent";
        case Status::unconfirmed:
            return "unconfirmed";
        case Status::survived:
            break;
        }
        if (r.witness.empty())
            return "survived-no-witness";
        return r.witness_extreme && o.allow_extreme ? "survived-extreme-only" : "survived";
    };
    auto point = [](const std::vector<double>& v) {
        std::string t;
        for (double x : v)
            t += (t.empty() ? "" : " ") + fuzz::hex(x);
        return t;
    };
    auto replay = [&](const fuzz::MutantResult& r) {
        return o.replay_prefix + " --mutant " + r.site.mutation.id() + " -- " + point(r.witness);
    };
    const bool control_fails = rep.control.fails(o.allow_extreme);
    const bool below = a.min_kill_rate && rep.measured() && rep.kill_rate() < *a.min_kill_rate;
    const int code = control_fails || rep.unconfirmed || below        ? kExitRefuted
                     : rep.control.samples == 0 || !rep.measured() ? kExitUndecided
                                                                    : kExitProved;
    char rate[64];
    std::snprintf(rate, sizeof rate, "%.1f%%", 100 * rep.kill_rate());
    std::string budget = o.seconds > 0 ? "at most " + fuzz::shortest_decimal(o.seconds) + " s or " : "";
    budget += std::to_string(o.samples) + " samples";
    std::string range = "the whole double range";
    if (o.range_hi > 0)
        range = fuzz::shortest_decimal(o.range_lo) + ".." + fuzz::shortest_decimal(o.range_hi);
    if (a.json) {
        Json j;
        j["format"] = "impactcert-mutants/1";
        j["law"] = model.law().name;
        j["gate"] = {{"tolerance", tolerance}, {"range", range}, {"budget", budget}, {"seed", o.seed},
                     {"allow_extreme", o.allow_extreme}};
        j["control"] = {{"samples", rep.control.samples}, {"violations", rep.control.fails(o.allow_extreme)}};
        j["mutations_of_the_law"] = rep.enumerated;
        Json list = Json::array();
        for (const auto& r : rep.mutants) {
            Json e = {{"id", r.site.mutation.id()}, {"what", r.site.mutation.what(model)}, {"result", status_name(r)}};
            if (r.status == Status::equivalent)
                e["why"] = r.site.equivalent;
            else {
                e["samples"] = r.samples;
                e["seconds"] = r.seconds;
            }
            if (r.status == Status::killed) {
                e["sample"] = r.kill_index;
                e["generator"] = r.kill_kind;
            }
            if (!r.witness.empty()) {
                Json w = Json::array(), y = Json::array();
                for (double x : r.witness)
                    w.push_back(fuzz::hex(x));
                for (double x : r.output)
                    y.push_back(fuzz::hex(x));
                e["witness"] = {{"input", w}, {"output", y}, {"extreme", r.witness_extreme}, {"why", r.witness_what},
                                {"replay", replay(r)}};
            }
            list.push_back(e);
        }
        j["mutants"] = list;
        j["counts"] = {{"killed", rep.killed}, {"survived_with_witness", rep.survived_witness},
                       {"survived_without_witness", rep.survived_unknown}, {"survived_extreme_only", rep.extreme_only},
                       {"equivalent", rep.equivalent}, {"unconfirmed", rep.unconfirmed}};
        j["kill_rate"] = rep.measured() ? Json(rep.kill_rate()) : Json(nullptr);
        j["verdict"] = code == kExitProved ? "measured" : code == kExitUndecided ? "undecided" : "failed";
        std::cout << j.dump(2) << "\n";
        write_stdout("");
        return code;
    }
    std::printf("impactcert fuzz --mutants: the gate against mutants of law %s's plain double evaluation\n",
                model.law().name.c_str());
    std::printf("  gate           %s, inputs %s, %s per mutant, seed %llu%s\n", tolerance.c_str(), range.c_str(),
                budget.c_str(), static_cast<unsigned long long>(o.seed), o.allow_extreme ? ", --allow extreme" : "");
    std::printf("  control        the plain evaluation: %s (%llu samples)\n",
                control_fails ? "VIOLATIONS: the gate rejects the plain evaluation itself (a tolerance too tight for it, as "
                                "--max-ulps usually is, or an ill-conditioned law); no mutant was run"
                              : "passes",
                static_cast<unsigned long long>(rep.control.samples));
    if (control_fails || rep.control.samples == 0)
        std::printf("  mutants        none run (the law has %zu mutations)\n", rep.enumerated);
    else
        std::printf("  mutants        %zu of the law's %zu mutations, one operator after another\n", rep.mutants.size(),
                    rep.enumerated);
    // Per operator, in the order they were taken; then every survivor with its witness, and the
    // mutants no witness was found for (the JSON lists every mutant).
    std::vector<std::string> ops;
    std::map<std::string, std::array<std::size_t, 6>> per; // killed, survived, no witness, extreme only, equivalent, unconfirmed
    for (const auto& r : rep.mutants) {
        const std::string id = r.site.mutation.id(), op = id.substr(0, id.find(':'));
        if (!per.count(op))
            ops.push_back(op);
        auto& row = per[op];
        const std::string st = status_name(r);
        ++row[st == "killed" ? 0 : st == "survived" ? 1 : st == "survived-no-witness" ? 2
              : st == "survived-extreme-only" ? 3 : st == "equivalent" ? 4 : 5];
    }
    if (!ops.empty())
        std::printf("    %-18s %7s %9s %11s %13s %11s%s\n", "operator", "killed", "survived", "no witness", "extreme only",
                    "equivalent", rep.unconfirmed ? "  unconfirmed" : "");
    for (const auto& op : ops) {
        const auto& row = per[op];
        std::printf("    %-18s %7zu %9zu %11zu %13zu %11zu", op.c_str(), row[0], row[1], row[2], row[3], row[4]);
        if (rep.unconfirmed)
            std::printf(" %12zu", row[5]);
        std::printf("\n");
    }
    std::string unknown;
    std::size_t unknown_shown = 0;
    for (const auto& r : rep.mutants) {
        if (r.status == Status::unconfirmed)
            std::printf("  unconfirmed    %s (%s): the gate's example was not confirmed by the exact second route; please report this\n",
                        r.site.mutation.id().c_str(), r.site.mutation.what(model).c_str());
        if (r.status != Status::survived)
            continue;
        if (r.witness.empty()) {
            if (unknown_shown++ < 12)
                unknown += (unknown.empty() ? "" : ", ") + r.site.mutation.id();
            continue;
        }
        const bool allowed = r.witness_extreme && o.allow_extreme;
        std::printf("  %-14s %s: %s%s\n", allowed ? "extreme only" : "survivor", r.site.mutation.id().c_str(),
                    r.site.mutation.what(model).c_str(), allowed ? " (not counted: --allow extreme)" : "");
        std::printf("    differs at%s %s -> %s\n    replay: %s\n", r.witness_extreme ? " the extreme input" : "",
                    point(r.witness).c_str(), point(r.output).c_str(), replay(r).c_str());
    }
    if (!unknown.empty())
        std::printf("  no witness     %s%s (no input found where they differ: they may be equivalent)\n", unknown.c_str(),
                    unknown_shown > 12 ? (", and " + std::to_string(unknown_shown - 12) + " more").c_str() : "");
    if (rep.measured())
        std::printf("  kill rate      %zu of %zu mutants shown different by an exact witness (%s)\n", rep.killed,
                    rep.killed + rep.survived_witness, rate);
    else
        std::printf("  kill rate      not measured: no mutant was shown different by an exact witness\n");
    std::printf("  not counted    %zu equivalent, %zu with no witness found, %zu differing only at extreme magnitudes (--allow extreme)\n",
                rep.equivalent, rep.survived_unknown, rep.extreme_only);
    std::printf("verdict: %s\n", control_fails ? "the gate fails the control"
                                  : code == kExitUndecided && rep.control.samples == 0
                                      ? "undecided: the control checked no sample (raise --seconds)"
                                  : code == kExitUndecided ? "undecided: no mutant was shown different"
                                  : rep.unconfirmed     ? "a kill was not confirmed exactly"
                                  : below               ? "kill rate below --min-kill-rate"
                                                        : "measured");
    write_stdout("");
    return code;
}

} // namespace

int run_fuzz(FuzzArgs a) {
    if (a.mutant_given && a.mutant.empty())
        throw InputError("--mutant: empty (expected an ID that --mutants prints, or none)");
    if (!(a.options.seconds >= 0 && std::isfinite(a.options.seconds)))
        throw InputError("--seconds: must be a finite number >= 0");
    if (!a.allow.empty() && a.allow != "extreme")
        throw InputError("--allow: expected extreme, got \"" + a.allow + "\"");
    if (a.law_path.empty() && a.system.given()) {
        if (!a.allow.empty())
            throw InputError("--allow extreme: law mode only (consistency inputs lie within --range, at most 1e150)");
        if (a.mutants || !a.mutant.empty() || a.min_kill_rate)
            throw InputError(std::string(a.mutants ? "--mutants" : !a.mutant.empty() ? "--mutant" : "--min-kill-rate") +
                             ": law mode only (mutants of a law's plain evaluation; give --law)");
        return run_consistency_fuzz(a);
    }
    a.options.allow_extreme = !a.allow.empty();
    if (a.system.given())
        throw InputError("--law and --masses/--system: a law names its own system (without --law the implementation "
                         "is checked for consistency with the system alone)");
    if (a.min_kill_rate && !a.mutants)
        throw InputError("--min-kill-rate: with --mutants only");
    if (a.min_kill_rate && !(*a.min_kill_rate >= 0 && *a.min_kill_rate <= 1))
        throw InputError("--min-kill-rate: a fraction in 0..1");
    if (a.mutants) {
        if (a.impl_given || a.impl_cmd_given || !a.mutant.empty())
            throw InputError("--mutants: mutants of the law's own plain evaluation; no --impl, --impl-cmd or --mutant");
        if (a.velocities)
            throw InputError("--mutants: the law's plain evaluation takes contact velocities (no --velocities)");
        if (!a.max_ulps && !a.max_rel_error)
            throw InputError("--mutants: give the gate's tolerance (--max-rel-error R or --max-ulps K)");
        if (!a.junit.empty())
            throw InputError("--mutants and --junit: the JUnit report is of one run (use --json)");
    }
    if (!a.require.empty() || a.restitution_given || a.reference_given || !a.cone.empty())
        throw InputError(std::string(!a.require.empty() ? "--require" : a.restitution_given ? "--restitution"
                                     : a.reference_given                                 ? "--reference"
                                                                                         : "--cone") +
                         ": consistency fuzzing only (give --masses or --system, no --law)");
    if (!a.junit.empty() && !std::ofstream(a.junit)) // before the run, not after it
        throw InputError("--junit " + a.junit + ": cannot write");
    const Model model = load_model(a.law_path);
    model.require_independent_columns("fuzz --law");
    if (a.max_ulps && a.max_rel_error)
        throw InputError("--max-ulps and --max-rel-error: give one tolerance");
    if (a.max_rel_error && !(*a.max_rel_error >= 0 && std::isfinite(*a.max_rel_error)))
        throw InputError("--max-rel-error: must be a finite number >= 0");
    const fuzz::LawFacts facts = fuzz::law_facts(model, a.velocities);
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
    if (!a.range.empty())
        std::tie(options.range_lo, options.range_hi) = fuzz::parse_range(a.range);
    options.replay_prefix = replay_command("eval --float");
    if (options.tolerance == fuzz::Tolerance::ulps && options.max_ulps > 0)
        options.replay_prefix += " --max-ulps " + std::to_string(options.max_ulps);
    if (options.tolerance == fuzz::Tolerance::relative)
        options.replay_prefix += " --max-rel-error " + fuzz::shortest_decimal(options.max_rel_error);
    if (!a.law_path.empty())
        options.replay_prefix += " --law " + fuzz::shell_quote(a.law_path);
    if (a.velocities)
        options.replay_prefix += " --velocities";
    if (a.mutants)
        return run_mutants_gate(a, model, reference, facts.properties, fuzz::tolerance_text(options));
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
                     std::string(static_cast<std::size_t>(width - filled), '.').c_str(), frac * 100, fuzz::count_text(done).c_str(),
                     secs > 0 ? static_cast<double>(done) / secs / 1e6 : 0.0);
    };
    const fuzz::Summary sum = fuzz::run(options, reference, *impl, facts.properties, progress);
    if (tty)
        std::fprintf(stderr, "\r\033[K");
    const double rate = sum.seconds > 0 ? static_cast<double>(sum.samples) / sum.seconds : 0;
    const std::string target = impl->describe();
    const std::string space = a.velocities ? "ball velocities" : "contact velocities";
    const std::string tolerance = fuzz::tolerance_text(options);
    if (!a.junit.empty()) {
        write_file(a.junit, fuzz_junit(sum, target, options));
    }
    if (a.json) {
        std::cout << fuzz::report_json(sum, options, facts.properties, model.law().name, target, a.velocities,
                                       impl->stderr_summary()).dump(2)
                  << "\n";
    } else {
        auto u = [](std::uint64_t x) { return static_cast<unsigned long long>(x); };
        std::string ulps;
        for (auto e : sum.max_ulps)
            ulps += (ulps.empty() ? "" : ", ") + std::to_string(e);
        std::printf("impactcert fuzz: %s vs the exact law %s, in %s (seed %llu, %u job%s)\n", target.c_str(),
                    model.law().name.c_str(), space.c_str(), u(options.seed), options.jobs, options.jobs == 1 ? "" : "s");
        std::printf("  tolerance                      %s\n", tolerance.c_str());
        if (options.range_hi > 0)
            std::printf("  inputs                         components 0 or of magnitude in %.6g..%.6g (--range), scales log-uniform\n",
                        options.range_lo, options.range_hi);
        else
            std::printf("  inputs                         the whole double range; extreme: largest component beyond 2^500 or below 2^-500\n");
        std::printf("  coverage                       %s\n", fuzz::coverage_text(sum).c_str());
        for (const auto& line : fuzz::untested(sum, options))
            std::printf("  not tested                     %s\n", line.c_str());
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
        std::printf("  samples with violations        %llu within 2^-500..2^500, %llu at extreme magnitudes%s\n", u(sum.gated),
                    u(sum.extreme), sum.extreme == 0 ? "" : options.allow_extreme ? " (allowed: --allow extreme)" : " (fail the run; --allow extreme accepts them)");
        if (const auto e = impl->stderr_summary(); e && e->lines) {
            std::string first;
            for (std::size_t i = 0; i < e->first.size(); ++i)
                first += (i ? "; \"" : ", first: \"") + e->first[i] + "\"";
            std::printf("  its stderr                     %llu line%s (collected, not shown per sample)%s\n", u(e->lines),
                        e->lines == 1 ? "" : "s", first.c_str());
        }
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
            std::printf("  violation at sample %llu (%s%s): %s\n    input%s -> output%s, exact%s\n    replay: %s\n",
                        u(v.index), v.kind.c_str(), v.extreme ? ", extreme" : "", v.what.c_str(), in.c_str(), out.empty() ? " (none)" : out.c_str(),
                        ex.empty() ? " (none)" : ex.c_str(), v.replay.c_str());
        }
        std::printf("verdict: %s\n", sum.fails(options.allow_extreme) ? "violations found"
                                      : sum.violations() && sum.samples ? "no violation within 2^-500..2^500 (those at extreme magnitudes allowed)"
                                      : sum.samples == 0 ? "undecided: no sample was checked (--seconds ran out first; raise --seconds)"
                                                         : "no violation");
    }
    write_stdout("");
    // Nothing checked is not a pass: a gate must not go green on an empty run.
    return sum.fails(options.allow_extreme) ? kExitRefuted : sum.samples == 0 ? kExitUndecided : kExitProved;
}

int run_eval(const std::string& law_path, bool velocities, const std::vector<std::string>& args, bool as_float,
             FuzzArgs float_args) {
    if (float_args.mutant_given && float_args.mutant.empty())
        throw InputError("--mutant: empty (expected an ID that fuzz --mutants prints, or none)");
    if ((float_args.impl_given || float_args.impl_cmd_given || !float_args.mutant.empty()) && !as_float)
        throw InputError("--impl, --impl-cmd and --mutant need --float");
    if (!float_args.mutant.empty() && float_args.system.given())
        throw InputError("--mutant: a mutant of a law's plain evaluation; give --law, not --masses/--system");
    if (float_args.pieces && as_float)
        throw InputError("--pieces: exact evaluation only (--float already names the piece with --law)");
    if (!float_args.cone.empty() && !float_args.system.given())
        throw InputError("--cone: consistency replays only (give --masses or --system)");
    if ((float_args.system.given() || float_args.pair || !float_args.float_law.empty()) && !as_float)
        throw InputError("--masses, --system, --pair and --float-law: consistency replays need --float");
    if (as_float) {
        float_args.law_path = law_path;
        float_args.velocities = velocities;
        std::size_t dim = 0;
        if (float_args.system.given()) {
            if (!law_path.empty())
                throw InputError("--law and --masses/--system: give one");
            const Mechanics m = make_mechanics(system_from(float_args.system), Dependent::allow); // the replay plans as fuzz did
            dim = velocities ? m.balls() : m.contacts();
        } else {
            const Model dims = load_model(law_path);
            dims.require_independent_columns("fuzz --law");
            dim = velocities ? dims.balls() : dims.contacts();
        }
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
        if (float_args.system.given())
            return run_consistency_eval(float_args, points);
        return run_eval_float(float_args, points);
    }
    const Model model = load_model(law_path);
    model.require_independent_columns("fuzz --law");
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
                                        "arguments", float_args.pieces)
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
        std::cout << evaluate_point(model, read_point(toks, 0, where), velocities, where, float_args.pieces) << "\n";
    }
    return kExitProved;
}


} // namespace impactcert::cli
