// SPDX-License-Identifier: GPL-3.0-or-later
// cli/verify.cpp -- verify (whole, streamed or one shard) and certify: the commands that
// decide a law's obligations, shared by impactcert and impactcert-verify (cli/options.hpp).
#include "cli/options.hpp"

#include "prover/certificate.hpp"
#include "model/law_json.hpp"
#include "prover/stream.hpp"
#include "prover/verdict_output.hpp"

#include <fstream>
#include <iostream>

namespace impactcert::cli {

VerifyReport verify_with_progress(const Model& model, const Limits& limits) {
    TerminalProgress progress;
    return verify(model, limits, progress.callback());
}

WorstCase worst_case_of(const Model& model, const VerifyReport& report, const Limits& limits) {
    auto proved = [&](const char* id) {
        for (const auto& o : report.obligations)
            if (o.id == id)
                return o.verdict == Verdict::proved;
        return false;
    };
    return worst_case(model, proved("fan") && proved("P1"), WorstCaseOptions{limits.max_faces, limits.integer_kernels});
}

std::string worst_case_lines(const WorstCase& w, const Model& model) {
    std::string out;
    auto line = [&](const char* what, const LawBound& b, const char* where) {
        out += std::string("  ") + what;
        if (!b.decided) {
            out += "undecided (" + b.limit + ")\n";
            return;
        }
        // The point as decimals (largest entry +-1); the exact one is in --json and the certificate.
        const Vector& x = b.pieces[b.top].point;
        Rational big(0);
        for (const auto& e : x)
            big = std::max(big, abs_of(e));
        std::string point;
        for (const auto& e : x)
            point += (point.empty() ? "" : ", ") + readable_text(e / big, 6);
        out += value_text(b.value) + (b.value.exact ? ", attained" : ", approached") + " in piece " +
               model.pieces()[b.pieces[b.top].piece].name + " at " + where + " (" + point + ")\n";
    };
    out += "worst case (exact):\n";
    line("sup T+/T-        ", w.energy, "gamma- =");
    if (w.lipschitz)
        line("Lipschitz^2 in H ", *w.lipschitz, "direction");
    else
        out += "  Lipschitz^2 in H not computed: fan and P1 are not both proved (no continuous tiling)\n";
    return out;
}

namespace {

// A worst case stopped by a limit is undecided: exit 3 (unless a claim is refuted), one line on
// stderr naming the limit.
int worst_case_status(int status, const WorstCase& w) {
    const LawBound* stopped = !w.energy.decided ? &w.energy : w.lipschitz && !w.lipschitz->decided ? &*w.lipschitz : nullptr;
    if (!stopped)
        return status;
    std::cerr << program_name() << ": worst case undecided: " << stopped->limit << "\n";
    return status == 0 ? kExitUndecided : status;
}

int run_verify(const std::string& law_path, bool json, const std::string& junit_path, bool worst, const Limits& limits) {
    const Model model = load_model(law_path, limits);
    Limits no_evidence = limits;
    no_evidence.evidence = false; // a verdict needs no certificate
    const VerifyReport report = verify_with_progress(model, no_evidence);
    std::optional<WorstCase> w;
    if (worst)
        w = worst_case_of(model, report, limits);
    if (json) {
        Json j = verdict_json(report);
        if (w)
            j["worst_case"] = to_json(*w, model);
        std::cout << j.dump(2) << "\n";
    } else {
        std::cout << verdict_table(report, model);
        if (w)
            std::cout << worst_case_lines(*w, model);
    }
    if (!junit_path.empty())
        write_file(junit_path, verdict_junit(report)); // flushed, closed and checked
    return w ? worst_case_status(report.exit_status(), *w) : report.exit_status();
}

int run_verify_stream(const std::string& law_path, bool json, const std::string& junit_path, const Limits& limits) {
    if (law_path.empty())
        throw StreamRefused("the paper's law lists every piece");
    const Law law = load_law_declaration(law_path);
    TerminalProgress progress;
    Limits no_evidence = limits;
    no_evidence.evidence = false;
    StreamResult result;
    try {
        result = verify_stream(law, no_evidence, progress.callback());
    } catch (const InputError& e) {
        throw InputError(law_path + ": " + e.what());
    }
    if (json)
        std::cout << verdict_json(result.report).dump(2) << "\n";
    else
        std::cout << verdict_table(result.report, result.balls, result.contacts, result.pieces)
                  << "  streamed: " << result.pieces << " pieces as ids of " << result.rays << " rays and " << result.images
                  << " images, " << (result.bytes >> 20) << " MB counted against --max-memory\n";
    if (!junit_path.empty())
        write_file(junit_path, verdict_junit(result.report));
    return result.report.exit_status();
}

} // namespace

int run_verify_command(const VerifyArgs& args, const Limits& limits) {
    if (!args.shard_text.empty() && !args.junit_path.empty())
        throw InputError("--junit: not with --shard (a slice is not a verdict: merge certify's parts with impactcert-check)");
    if (args.stream && !args.shard_text.empty())
        throw InputError("--stream: not with --shard (a streamed law is decided in one process)");
    if (args.worst_case && (args.stream || !args.shard_text.empty()))
        throw InputError(std::string("--worst-case: not with ") + (args.stream ? "--stream" : "--shard") +
                         " (the worst case is computed over every piece in one process)");
    if (args.stream)
        return run_verify_stream(args.law_path, args.json, args.junit_path, limits);
    if (!args.shard_text.empty())
        return run_verify_shard(args.law_path, parse_shard(args.shard_text), args.json, limits);
    return run_verify(args.law_path, args.json, args.junit_path, args.worst_case, limits);
}

int run_certify(const std::string& law_path, const std::string& out_path, bool worst, const Limits& limits) {
    const Model model = load_model(law_path, limits);
    // The header names the top verdict: a first pass without evidence gives it; the second
    // writes each obligation as it is decided (one obligation's evidence in memory at a time).
    Limits quick = limits;
    quick.evidence = false;
    const VerifyReport first = verify_with_progress(model, quick);
    OutputFile out(out_path); // the whole certificate or none (common.hpp)
    CertificateWriter writer(out.stream(), model, first.verdict());
    TerminalProgress progress;
    const VerifyReport report =
        verify_streaming(model, limits, progress.callback(), [&](ObligationResult& r) { writer.add(r); });
    std::optional<WorstCase> w;
    if (worst) {
        w = worst_case_of(model, report, limits);
        writer.add_worst_case(to_json(*w, model));
    }
    writer.finish();
    for (std::size_t k = 0; k < report.obligations.size(); ++k) {
        const auto &a = first.obligations.at(k), &b = report.obligations[k];
        if (a.verdict != b.verdict || a.checks != b.checks || a.method != b.method || a.counterexample != b.counterexample)
            throw std::logic_error("certify: the two passes disagree on " + a.id);
    }
    out.commit();
    std::cerr << "impactcert: wrote " << out_path << " (" << report.law << ": " << report.verdict() << ")\n";
    return w ? worst_case_status(report.exit_status(), *w) : report.exit_status();
}

} // namespace impactcert::cli
