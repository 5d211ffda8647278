// SPDX-License-Identifier: GPL-3.0-or-later
// cli/verify.cpp -- verify (whole, streamed or one shard) and certify: the commands that
// decide a law's obligations, shared by impactcert and impactcert-verify (cli/options.hpp).
#include "cli/options.hpp"

#include "certificate.hpp"
#include "law_json.hpp"
#include "stream.hpp"
#include "verdict_output.hpp"

#include <fstream>
#include <iostream>

namespace impactcert::cli {

VerifyReport verify_with_progress(const Model& model, const Limits& limits) {
    TerminalProgress progress;
    return verify(model, limits, progress.callback());
}

namespace {

int run_verify(const std::string& law_path, bool json, const std::string& junit_path, const Limits& limits) {
    const Model model = load_model(law_path, limits.max_pieces, limits.max_memory_mb);
    Limits no_evidence = limits;
    no_evidence.evidence = false; // a verdict needs no certificate
    const VerifyReport report = verify_with_progress(model, no_evidence);
    if (json)
        std::cout << verdict_json(report).dump(2) << "\n";
    else
        std::cout << verdict_table(report, model);
    if (!junit_path.empty())
        write_file(junit_path, verdict_junit(report)); // flushed, closed and checked
    return report.exit_status();
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
    if (args.stream)
        return run_verify_stream(args.law_path, args.json, args.junit_path, limits);
    if (!args.shard_text.empty())
        return run_verify_shard(args.law_path, parse_shard(args.shard_text), args.json, limits);
    return run_verify(args.law_path, args.json, args.junit_path, limits);
}

int run_certify(const std::string& law_path, const std::string& out_path, const Limits& limits) {
    const Model model = load_model(law_path, limits.max_pieces, limits.max_memory_mb);
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
    writer.finish();
    for (std::size_t k = 0; k < report.obligations.size(); ++k) {
        const auto &a = first.obligations.at(k), &b = report.obligations[k];
        if (a.verdict != b.verdict || a.checks != b.checks || a.method != b.method || a.counterexample != b.counterexample)
            throw std::logic_error("certify: the two passes disagree on " + a.id);
    }
    out.commit();
    std::cerr << "impactcert: wrote " << out_path << " (" << report.law << ": " << report.verdict() << ")\n";
    return report.exit_status();
}

} // namespace impactcert::cli
