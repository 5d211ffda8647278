// SPDX-License-Identifier: GPL-3.0-or-later
// cli/consistency.cpp -- `impactcert fuzz --masses ... | --system F` with no --law: the consistency
// of a black-box impact map (consistency.hpp), and `eval --float` replays of its findings.
#include "cli/tools.hpp"

#include "fuzz/consistency.hpp"
#include "fuzz/consistency_report.hpp"
#include "derive/derive.hpp"
#include "prover/worst_case.hpp"
#include "base/json.hpp"
#include "base/junit.hpp"
#include "prover/verdict_output.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <sstream>
#include <cstdlib>
#include <memory>

namespace impactcert::cli {

namespace {

struct Setup {
    fuzz::ConsistencyPlan plan;
    std::unique_ptr<Model> law; // --float-law: the law whose float implementation is tested
    std::unique_ptr<fuzz::Implementation> impl;
};

// The options as the library's request (fuzz/consistency_report.hpp: checks, messages, the
// reference law), then the implementation, which only the command line makes.
Setup setup(const FuzzArgs& a) {
    fuzz::ConsistencyRequest q;
    q.system_source = [&a] { return system_from(a.system); };
    q.velocities = a.velocities;
    q.max_ulps_given = a.max_ulps.has_value();
    q.max_rel_error = a.max_rel_error;
    if (a.restitution_given)
        q.restitution_text = a.restitution;
    q.reference = a.reference;
    q.reference_given = a.reference_given;
    q.cone = a.cone;
    q.require = tokens_of(a.require);
    q.range = a.range;
    q.seed = a.options.seed;
    q.samples = a.options.samples;
    q.seconds = a.options.seconds;
    q.jobs = a.options.jobs;
    q.keep = a.options.keep;
    // The command line's own checks, where they always came: --junit writable before the run
    // (after --require and --range), one implementation and its timeout after the tolerance.
    auto between = [&](fuzz::PlanStage stage) {
        if (stage == fuzz::PlanStage::options) {
            if (!a.junit.empty())
                write_file(a.junit, ""); // writable before the run, not after it
            return;
        }
        if (a.impl_given && a.impl_cmd_given)
            throw InputError("--impl and --impl-cmd: give one implementation");
        if (!(a.timeout > 0 && std::isfinite(a.timeout)))
            throw InputError("--impl-timeout: must be a finite number of seconds > 0");
    };
    Setup s{fuzz::plan_consistency(q, between), nullptr, nullptr};
    const std::size_t dim = a.velocities ? s.plan.mech.balls() : s.plan.mech.contacts();
    if (!a.float_law.empty()) {
        if (a.impl_given || a.impl_cmd_given)
            throw InputError("--float-law and --impl/--impl-cmd: give one implementation");
        s.law = std::make_unique<Model>(load_model(a.float_law));
        if (a.velocities && !s.law->redundant())
            throw InputError("--float-law: impactcert's float law takes contact velocities (drop --velocities)");
        if (s.law->M() != s.plan.mech.M || s.law->full_W() != s.plan.mech.W)
            throw InputError("--float-law " + a.float_law + ": the law's system (M, W) is not the one given");
        // On dependent columns the system asks for --velocities (plan_consistency), and the float
        // law is wrapped into ball velocities.
        s.impl = s.law->redundant() ? fuzz::builtin_float_law_velocities(*s.law) : fuzz::builtin_float_law(*s.law);
    } else if (a.impl_given && !a.impl_spec.empty())
        s.impl = fuzz::load_symbol(a.impl_spec, dim, dim);
    else if (a.impl_cmd_given && !a.impl_cmd.empty())
        s.impl = fuzz::command(a.impl_cmd, dim, dim, a.timeout);
    else
        throw InputError("--impl, --impl-cmd or --float-law: consistency fuzzing needs an implementation (there is no built-in one "
                         "for a system without a law)");
    return s;
}

// One line for what the implementation wrote on its standard error (collected, not echoed).
std::string stderr_line(const fuzz::StderrSummary& e) {
    std::string s = "  its stderr:    " + std::to_string(e.lines) + " line" + (e.lines == 1 ? "" : "s") +
                    " (collected, not shown per sample)";
    for (std::size_t i = 0; i < e.first.size(); ++i)
        s += (i ? "; " : ", first: \"") + std::string(i ? "\"" : "") + e.first[i] + "\"";
    return s;
}

std::string num(double x) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return buf;
}

std::string decimals(const std::vector<double>& v) {
    std::string s;
    for (double x : v)
        s += (s.empty() ? "" : " ") + num(x);
    return s;
}

std::string finding_text(const fuzz::Finding& f) {
    std::string s = "      input  " + decimals(f.input);
    if (!f.input_b.empty())
        s += "  |  " + decimals(f.input_b);
    s += "\n      output " + decimals(f.output);
    if (!f.output_b.empty())
        s += "  |  " + decimals(f.output_b);
    return s + "\n";
}

std::string junit(const fuzz::ConsistencySummary& sum, const std::string& target, const bool* checked) {
    JunitSuite suite{"impactcert fuzz (consistency): " + target, {}};
    auto add = [&](const std::string& name, std::uint64_t count, const std::string& message) {
        JunitCase t;
        t.classname = "impactcert.consistency";
        t.name = name;
        if (suite.cases.empty()) // the run's time (every property is checked on the same samples)
            t.time = std::chrono::nanoseconds(static_cast<long long>(sum.seconds * 1e9));
        if (count) {
            t.kind = JunitCase::Kind::failed;
            t.type = "violations";
            t.message = std::to_string(count) + " violation(s) in " + std::to_string(sum.samples) + " samples";
            t.text = message;
        }
        suite.cases.push_back(std::move(t));
    };
    for (std::size_t p = 0; p < fuzz::kProperties; ++p) {
        if (!checked[p])
            continue;
        const auto& slot = sum.properties[p];
        add(fuzz::property_title(static_cast<fuzz::Property>(p)), slot.count,
            slot.worst ? slot.worst->detail + "; replay: " + slot.worst->replay : "");
    }
    add("implementation failures", sum.crashed + sum.hung + sum.malformed + sum.refused, "");
    JunitCase cov;
    cov.classname = "impactcert.consistency";
    cov.name = "coverage";
    cov.system_out = fuzz::coverage_text(sum);
    for (const auto& gap : fuzz::coverage_gaps(sum))
        cov.system_out += "\nnot tested: " + gap;
    suite.cases.push_back(std::move(cov));
    return junit_xml(suite);
}

} // namespace

// {iterations} in --impl-cmd: the command at one effort.
constexpr const char* kEffortPlaceholder = "{iterations}";

std::string at_effort(std::string cmd, std::uint64_t effort) {
    const std::string p = kEffortPlaceholder;
    for (std::size_t at = cmd.find(p); at != std::string::npos; at = cmd.find(p, at))
        cmd.replace(at, p.size(), std::to_string(effort));
    return cmd;
}

// --efforts: positive integers, ascending, at least two, at most eight.
std::vector<std::uint64_t> parse_efforts(const std::string& text) {
    std::vector<std::uint64_t> out;
    std::string item;
    std::stringstream in(text.empty() ? "4,64" : text);
    while (std::getline(in, item, ',')) {
        std::string why;
        const auto v = fuzz::parse_seed(item, &why);
        if (!v || *v == 0 || *v > 1000000000)
            throw InputError("--efforts: \"" + item + "\" is not an integer in 1..10^9");
        if (!out.empty() && *v <= out.back())
            throw InputError("--efforts: expected ascending efforts, got " + text);
        out.push_back(*v);
    }
    if (out.size() < 2 || out.size() > 8)
        throw InputError("--efforts: expected 2 to 8 efforts, got \"" + text + "\"");
    return out;
}

struct EffortRow {
    std::uint64_t effort = 0, findings = 0, samples = 0;
    double distance = 0; // the worst reference finding's |y - y*| / |x| (0: none)
};

// The diagnosis of a sweep over efforts (proofs/README.md, "Solver-level or model-level"):
// converged when the largest effort has no reference finding; solver-level when the worst
// distance at the largest effort is at most half of that at the smallest; model-level otherwise.
std::string effort_diagnosis(const std::vector<EffortRow>& rows) {
    if (rows.back().findings == 0)
        return "converged";
    return rows.back().distance <= rows.front().distance / 2 ? "solver-level" : "model-level";
}

int run_consistency_fuzz_at(const FuzzArgs& a, const FuzzArgs& given, const std::vector<std::uint64_t>& efforts);

int run_consistency_fuzz(const FuzzArgs& a) {
    if (!(a.options.seconds >= 0 && std::isfinite(a.options.seconds)))
        throw InputError("--seconds: must be a finite number >= 0");
    const bool effort_sweep = a.impl_cmd.find(kEffortPlaceholder) != std::string::npos;
    if (!a.efforts.empty() && !effort_sweep)
        throw InputError("--efforts: put {iterations} in --impl-cmd where the command takes its effort");
    if (effort_sweep && !a.reference_given)
        throw InputError("--impl-cmd {iterations}: give --reference (the distance to it is measured per effort)");
    const std::vector<std::uint64_t> efforts = effort_sweep ? parse_efforts(a.efforts) : std::vector<std::uint64_t>{};
    if (effort_sweep) {
        // The main run is the largest effort; the others are measured first.
        FuzzArgs main = a;
        main.impl_cmd = at_effort(a.impl_cmd, efforts.back());
        main.efforts.clear();
        return run_consistency_fuzz_at(main, a, efforts);
    }
    return run_consistency_fuzz_at(a, a, efforts);
}

int run_consistency_fuzz_at(const FuzzArgs& a, const FuzzArgs& given, const std::vector<std::uint64_t>& efforts) {
    Setup s = setup(a);
    fuzz::ConsistencyOptions& o = s.plan.options;
    const std::string& rbuf = s.plan.R_text;
    o.replay_prefix = replay_command("eval --float ") + system_flags(a.system) + (a.velocities ? " --velocities " : " ") +
                      (s.law ? "--float-law " + fuzz::shell_quote(a.float_law) : s.impl->replay_flags()) +
                      " --max-rel-error " + rbuf +
                      (a.restitution.empty() ? "" : " --restitution " + fuzz::shell_quote(a.restitution)) +
                      (o.cone == fuzz::Cone::circular ? " --cone circular" : "") +
                      (a.reference.empty() ? "" : " --reference " + fuzz::shell_quote(a.reference)) + " --";
    const bool tty = !a.json && isatty(STDERR_FILENO);
    const auto start = std::chrono::steady_clock::now();
    auto progress = [&](std::uint64_t done) {
        if (!tty)
            return;
        const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::fprintf(stderr, "\r\033[Kimpactcert: fuzz %llu/%llu samples, %.0f/s", static_cast<unsigned long long>(done),
                     static_cast<unsigned long long>(o.samples), secs > 0 ? static_cast<double>(done) / secs : 0.0);
    };
    // Every effort but the largest, with the same samples (the command at that effort, quietly).
    std::vector<EffortRow> effort_rows;
    const std::size_t ref_slot = static_cast<std::size_t>(fuzz::Property::reference);
    for (std::size_t k = 0; k + 1 < efforts.size(); ++k) {
        if (tty)
            std::fprintf(stderr, "\r\033[Kimpactcert: fuzz at {iterations} = %llu", static_cast<unsigned long long>(efforts[k]));
        const std::size_t dim = a.velocities ? s.plan.mech.balls() : s.plan.mech.contacts();
        const auto impl = fuzz::command(at_effort(given.impl_cmd, efforts[k]), dim, dim, a.timeout);
        fuzz::ConsistencyOptions oe = o;
        oe.keep = 0;
        const auto se = fuzz::run_consistency(s.plan.mech, oe, *impl, nullptr);
        const auto& slot = se.properties[ref_slot];
        effort_rows.push_back({efforts[k], slot.count, se.samples, slot.worst ? slot.worst->score : 0.0});
    }
    const fuzz::ConsistencySummary sum = fuzz::run_consistency(s.plan.mech, o, *s.impl, progress);
    if (tty)
        std::fprintf(stderr, "\r\033[K");
    std::string diagnosis;
    if (!efforts.empty()) {
        const auto& slot = sum.properties[ref_slot];
        effort_rows.push_back({efforts.back(), slot.count, sum.samples, slot.worst ? slot.worst->score : 0.0});
        diagnosis = effort_diagnosis(effort_rows);
    }
    // Findings the exact law does not make: solver-level, unless the effort sweep shows that more
    // effort does not bring the answers closer to the law (model-level).
    const std::string solver_word = diagnosis == "model-level" ? "model-level" : "solver-level";
    // Nothing checked is not a pass: a gate must not go green on an empty run.
    const bool nothing = sum.samples == 0;
    const auto checked = fuzz::checked_properties(s.plan, a.impl_cmd_given && !a.impl_cmd.empty());
    const std::string target = s.impl->describe();
    const std::string space = a.velocities ? "ball velocities" : "contact velocities";
    const double rate = sum.seconds > 0 ? static_cast<double>(sum.samples) / sum.seconds : 0;
    char range[96];
    std::snprintf(range, sizeof range, "%.6g..%.6g", o.range_lo, o.range_hi);
    if (!a.junit.empty())
        write_file(a.junit, junit(sum, target, checked.data()));
    const std::optional<LawBound> reference_sup = fuzz::reference_supremum(sum, s.plan);
    if (a.json) {
        Json effort;
        if (!effort_rows.empty()) {
            Json rows = Json::array();
            for (const auto& r : effort_rows)
                rows.push_back(Json{{"effort", r.effort}, {"samples", r.samples}, {"reference_findings", r.findings},
                                    {"worst_distance", r.distance}});
            effort = Json{{"command", given.impl_cmd}, {"runs", rows}, {"diagnosis", diagnosis}};
        }
        write_stdout(fuzz::consistency_report_json(sum, s.plan, target, checked, reference_sup, effort,
                                                   s.impl->stderr_summary())
                         .dump(2) +
                     "\n");
        return sum.violations() ? kExitRefuted : nothing ? kExitUndecided : kExitProved;
    }
    std::string out;
    auto line = [&](const std::string& text) { out += text + "\n"; };
    line("impactcert fuzz: " + target + ": consistency with " + s.plan.system.name + " (" + describe_system(s.plan.system) +
         "), in " + space + " (seed " + std::to_string(o.seed) + ", " + std::to_string(o.jobs) + " job" +
         (o.jobs == 1 ? "" : "s") + ")");
    line(std::string("  tolerance      --max-rel-error ") + rbuf + " (proofs/README.md, \"Consistency of black-box impact maps\")");
    if (s.plan.reference)
        line("  reference      " + s.plan.reference_name + " (--reference: each finding law-level or " + solver_word + ")");
    if (!effort_rows.empty()) {
        std::string runs;
        for (const auto& r : effort_rows) {
            char cell[96];
            if (r.findings)
                std::snprintf(cell, sizeof cell, "%llu: %llu off, worst %.3g", static_cast<unsigned long long>(r.effort),
                              static_cast<unsigned long long>(r.findings), r.distance);
            else
                std::snprintf(cell, sizeof cell, "%llu: none off", static_cast<unsigned long long>(r.effort));
            runs += (runs.empty() ? "" : "; ") + std::string(cell);
        }
        line("  effort         {iterations} = " + runs + " (answers farther from the reference than the tolerance)");
        line("  diagnosis      " + diagnosis +
             (diagnosis == "converged" ? ": at the largest effort every answer is within the tolerance of the reference"
              : diagnosis == "solver-level" ? ": the distance to the reference shrinks with effort (more iterations help)"
                                            : ": the distance to the reference does not shrink with effort (the engine computes another law; "
                                              "no iteration count will fix it)"));
    }
    line(std::string("  inputs         components 0 or of magnitude in ") + range + " (--range), some contact approaching");
    char buf[160];
    std::snprintf(buf, sizeof buf, "  samples        %llu (%llu pairs) in %.2f s, %.0f samples/s",
                  static_cast<unsigned long long>(sum.samples), static_cast<unsigned long long>(sum.pairs), sum.seconds, rate);
    line(buf);
    line("  coverage       " + fuzz::coverage_text(sum));
    for (const auto& gap : fuzz::coverage_gaps(sum))
        line("  not tested     " + gap);
    std::vector<std::string> found;
    for (std::size_t p = 0; p < fuzz::kProperties; ++p) {
        const auto prop = static_cast<fuzz::Property>(p);
        const auto& slot = sum.properties[p];
        std::string head = "  " + std::string(fuzz::property_title(prop)) + ": ";
        if (!checked[p]) {
            if (prop == fuzz::Property::momentum)
                line(head + "not checked (contact velocities carry no momentum; use --velocities)");
            else if (prop == fuzz::Property::nonexpansive || prop == fuzz::Property::continuity)
                line(head + "not requested (--require " + fuzz::property_id(prop) + ")");
            else if (prop == fuzz::Property::reference)
                line(head + "not checked (give --reference)");
            else if (prop == fuzz::Property::restitution)
                line(head + (s.plan.mech.redundant() && s.plan.mech.has_friction()
                                 ? "not checked (dependent contact columns with friction: which contacts push is not decided)"
                             : s.plan.mech.has_friction() ? "not checked (give --restitution E: Newton's, with friction)"
                                                          : "not checked (give --restitution E)"));
            continue;
        }
        if (!slot.count) {
            line(head + "none");
            continue;
        }
        found.push_back(std::string(fuzz::property_id(prop)) + " " + std::to_string(slot.count));
        line(head + std::to_string(slot.count) + " sample" + (slot.count == 1 ? "" : "s") + ", worst (sample " +
             std::to_string(slot.worst->index) + "): " + slot.worst->detail);
        out += finding_text(*slot.worst);
        line("      replay: " + slot.worst->replay);
        if (slot.projections)
            line("      " + std::to_string(slot.projections) + " of them where momentum fails: Lambda there is a projection of a "
                 "velocity change not made of contact impulses (look at momentum first)");
        if (s.plan.reference && prop != fuzz::Property::reference) {
            const std::uint64_t other = slot.count - slot.law - slot.solver;
            line("      against the reference law: " + std::to_string(slot.law) +
                 " law-level (the exact law breaks it there too: more iterations will not help), " +
                 std::to_string(slot.solver) + " " + solver_word + " (the exact law does not)" +
                 (other ? ", " + std::to_string(other) + " not classified" : std::string()));
            if (prop == fuzz::Property::energy && reference_sup && reference_sup->decided) {
                const AlgebraicValue& v = reference_sup->value;
                const std::string sup = v.exact ? to_string(*v.exact) : value_decimal(v);
                const Rational gain = Rational(100) * ((v.exact ? *v.exact : v.lo) - Rational(1));
                std::string pct = readable_text(gain, 3);
                if (pct[0] == '~')
                    pct.erase(0, 1);
                line("      the reference law's exact sup T+/T- (contact part) is " + sup + " (" +
                     (sign_of(gain) == Sign::negative ? "" : "+") + pct + "%)" +
                     (v.exact ? "" : ", a root of its polynomial (--json)") + ": no input gains more under the law");
            }
            if (slot.worst_solver) {
                char off[48];
                std::snprintf(off, sizeof off, "%.3g", slot.worst_solver->off);
                line("      " + solver_word + " worst (sample " + std::to_string(slot.worst_solver->index) + "): " + off +
                     " off the exact law (relative); " + slot.worst_solver->detail);
                line("      replay: " + slot.worst_solver->replay);
            }
        }
    }
    std::snprintf(buf, sizeof buf, "  implementation failures: %llu crashed, %llu hung, %llu malformed, %llu refused",
                  static_cast<unsigned long long>(sum.crashed), static_cast<unsigned long long>(sum.hung),
                  static_cast<unsigned long long>(sum.malformed), static_cast<unsigned long long>(sum.refused));
    line(buf);
    if (const auto e = s.impl->stderr_summary(); e && e->lines)
        line(stderr_line(*e));
    std::string verdict = sum.violations() ? "violations found"
                          : nothing ? "undecided: no sample was checked (--seconds ran out first; raise --seconds)"
                                    : "no violation";
    if (!found.empty()) {
        verdict += " (";
        for (std::size_t i = 0; i < found.size(); ++i)
            verdict += (i ? ", " : "") + found[i];
        verdict += ")";
    }
    line("verdict: " + verdict);
    write_stdout(out);
    return sum.violations() ? kExitRefuted : nothing ? kExitUndecided : kExitProved;
}

int run_consistency_eval(const FuzzArgs& a, const std::vector<std::vector<std::string>>& points) {
    Setup s = setup(a);
    const fuzz::ConsistencyChecker checker(s.plan.mech, a.velocities, s.plan.R, s.plan.options.restitution,
                                           s.plan.options.cone);
    const std::size_t d = checker.dim();
    std::vector<std::vector<double>> xs;
    for (const auto& toks : points) {
        std::vector<double> x;
        for (const auto& t : toks)
            x.push_back(parse_double(t, "input"));
        xs.push_back(x);
    }
    if (a.pair && xs.size() != 2)
        throw InputError("--pair: expected two points, got " + std::to_string(xs.size()));
    std::vector<double> in, out;
    for (const auto& x : xs)
        in.insert(in.end(), x.begin(), x.end());
    out.assign(in.size(), 0.0);
    std::vector<fuzz::ImplStatus> status(xs.size(), fuzz::ImplStatus::ok);
    s.impl->eval(in.data(), out.data(), nullptr, xs.size(), status.data());
    std::string text;
    bool violated = false;
    for (std::size_t i = 0; i < xs.size(); ++i) {
        if (status[i] == fuzz::ImplStatus::skipped)
            continue; // the rest of a nondeterministic batch
        text += "input  " + decimals(xs[i]) + "\n";
        if (status[i] == fuzz::ImplStatus::nondeterministic) {
            const auto f = checker.nondeterministic(&in[i * d], &out[i * d], s.impl->repeated_answer(i));
            text += "  " + std::string(fuzz::property_title(f.property)) + ": " + f.detail + "\n";
            violated = true;
            continue;
        }
        if (status[i] != fuzz::ImplStatus::ok) {
            text += "  the implementation failed on this input\n";
            violated = true;
            continue;
        }
        // The same input given again, answered otherwise (the replay of a nondeterministic finding).
        // (Inputs compared bit for bit, so that 0 and -0 are two inputs; answers as numbers.)
        if (i > 0 && std::memcmp(xs[i].data(), xs[i - 1].data(), d * sizeof(double)) == 0 &&
            status[i - 1] == fuzz::ImplStatus::ok && !fuzz::same_values(&out[(i - 1) * d], &out[i * d], d)) {
            const std::vector<double> again(out.begin() + static_cast<std::ptrdiff_t>(i * d),
                                            out.begin() + static_cast<std::ptrdiff_t>((i + 1) * d));
            const auto f = checker.nondeterministic(&in[(i - 1) * d], &out[(i - 1) * d], again);
            text += "  " + std::string(fuzz::property_title(f.property)) + ": " + f.detail + "\n";
            violated = true;
            continue;
        }
        text += "output " + decimals(std::vector<double>(out.begin() + static_cast<std::ptrdiff_t>(i * d),
                                                         out.begin() + static_cast<std::ptrdiff_t>((i + 1) * d))) + "\n";
        if (!checker.approaching(&in[i * d]))
            text += "  (no contact approaches at this input)\n";
        auto findings = checker.check(&in[i * d], &out[i * d]);
        bool at_rest = true;
        for (std::size_t k = 0; k < d; ++k)
            at_rest = at_rest && in[i * d + k] == 0;
        if (at_rest)
            if (auto f = checker.at_rest(&out[i * d])) // the probe's own finding, by its name
                findings.insert(findings.begin(), std::move(*f));
        if (s.plan.reference)
            if (auto f = checker.reference(&in[i * d], &out[i * d], *s.plan.reference))
                findings.push_back(std::move(*f));
        for (const auto& f : findings)
            text += "  " + std::string(fuzz::property_title(f.property)) + ": " + f.detail + "\n";
        if (findings.empty())
            text += "  consistent within the tolerance (kinematic, kinetic" + std::string(a.velocities ? ", momentum" : "") +
                    ", energy" + (s.plan.reference ? ", reference" : "") + ")\n";
        violated = violated || !findings.empty();
    }
    if (a.pair && status[0] == fuzz::ImplStatus::ok && status[1] == fuzz::ImplStatus::ok) {
        const auto findings = checker.check_pair(&in[0], &out[0], &in[d], &out[d], true, true);
        for (const auto& f : findings)
            text += "pair: " + std::string(fuzz::property_title(f.property)) + ": " + f.detail + "\n";
        if (findings.empty())
            text += "pair: non-expansive and continuous within the tolerance\n";
        violated = violated || !findings.empty();
    }
    write_stdout(text);
    return violated ? kExitRefuted : kExitProved;
}

} // namespace impactcert::cli
