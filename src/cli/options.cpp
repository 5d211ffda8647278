// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli/options.hpp"

#include "prover/stream.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <new>
#include <thread>

namespace impactcert::cli {

std::string positive_text(const std::string& text) {
    char* end = nullptr;
    const double d = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(d > 0) || !std::isfinite(d))
        return "must be a finite number > 0, got " + text;
    return {};
}

// --shard K/N given as an empty text (an unset $SHARD in a job script) is an error, not "no shard".
std::string shard_text(const std::string& text) {
    if (text.empty())
        return "expected K/N, got an empty text (an unset variable in a job script?)";
    return {};
}

std::string natural_text(const std::string& text) {
    if (text.empty() || text.size() > 19 || text.find_first_not_of("0123456789") != std::string::npos)
        return "must be a non-negative integer below 10^19, got " + text;
    return {};
}

Limits ProofOptions::resolved() const {
    Limits out = limits;
    out.integer_kernels = !no_integer_kernels;
    out.shard_block_pairs = shard_block;
    out.jobs = jobs;
    return out;
}

void add_limit_options(CLI::App* cmd, ProofOptions& proof) {
    Limits& limits = proof.limits;
    cmd->add_option("--max-faces", limits.max_faces, "limit: simplex faces of one KKT enumeration (copositivity); beyond it an obligation is undecided")->check(natural_text)->capture_default_str();
    cmd->add_option("--max-chambers", limits.max_chambers, "limit: steps of the chamber enumeration that decides a fan not meeting face to face")->check(natural_text)->capture_default_str();
    cmd->add_option("--max-subsets", limits.max_subsets, "limit: constraint subsets for the extreme rays of cone intersections (P1, not face to face)")->check(natural_text)->capture_default_str();
    cmd->add_option("--max-memory", limits.max_memory_mb, "limit: megabytes of the pieces a law's symmetries generate (counted by the size of their numbers; input error beyond it); sweep: also the regions and pieces each derivation holds (undecided beyond it)")->check(natural_text)->capture_default_str();
    cmd->add_option("--max-pieces", limits.max_pieces, "limit: pieces of a law given by orbit representatives, listed and generated (input error beyond it)")->check(natural_text)->capture_default_str();
    cmd->add_flag("--no-integer-kernels", proof.no_integer_kernels, "decide the pair forms over GMP alone (same verdicts; for comparison)");
}

void add_claims_option(CLI::App* cmd, ProofOptions& proof) {
    cmd->add_option_function<std::string>("--claims", [&proof](const std::string& text) {
        if (text.empty())
            throw CLI::ValidationError("--claims", "expected obligation ids separated by commas, or all; got an empty text");
        proof.limits.claims = text;
    }, "the obligations to hold the law to, replacing its file's \"claims\": ids separated by commas (fan,P1,kinematic,...), or all (every one that applies); the rest are still decided and reported (docs/laws.md, \"What a law claims\")");
}

void add_jobs_option(CLI::App* cmd, ProofOptions& proof) {
    proof.jobs = std::max(1u, std::thread::hardware_concurrency());
    cmd->add_option("--jobs", proof.jobs, "threads for the pairwise checks (and with --stream the symmetry expansion and the membership pass; default: all cores); the output does not depend on it")->check(natural_text)->check(CLI::Range(1u, 256u));
}

void add_shard_block_option(CLI::App* cmd, ProofOptions& proof) {
    cmd->add_option("--shard-block", proof.shard_block, "with --shard: pairs of nonexpansive per block (the merged result does not depend on it)")->check(natural_text)->check(CLI::Range(std::size_t{1}, std::size_t{1} << 40))->capture_default_str();
}

void add_verify_options(CLI::App* cmd, VerifyArgs& args, ProofOptions& proof) {
    cmd->add_option("--law", args.law_path, "law file (impactcert-law/1); default: the paper's 3-ball law");
    cmd->add_flag("--json", args.json, "print the impactcert-verdict/1 JSON instead of the table");
    cmd->add_option("--junit", args.junit_path, "also write a JUnit XML report to this file");
    cmd->add_flag("--stream", args.stream, "keep only the ids of each piece's rays and images (a law given by orbit representatives, "
                                           "larger than memory as matrices); same verdicts, streamed checks (proofs/README.md, \"Streamed laws\")");
    cmd->add_flag("--worst-case", args.worst_case, "also the law's exact worst case: sup T+/T- over its cones and, for a continuous law that "
                                                   "tiles the space, its Lipschitz constant in H (algebraic numbers with certified enclosures; "
                                                   "proofs/README.md, \"The exact worst case of a law\")");
    cmd->add_option("--shard", args.shard_text, "K/N: decide slice K of N only (obligation i when i mod N = K-1, and nonexpansive's pair blocks b mod N = K-1)")->check(shard_text);
    add_shard_block_option(cmd, proof);
    add_limit_options(cmd, proof);
    add_claims_option(cmd, proof);
    add_jobs_option(cmd, proof);
}

int run_program(CLI::App& app, int argc, char** argv, const std::function<int()>& run) {
    set_program_name(app.get_name());
    if (argc > 0)
        set_invocation(argv[0]);
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
        std::cerr << app.get_name() << ": " << one_line_text(message) << "\n";
        return kExitBadInput;
    }
    try {
        const int status = run();
        // Every command's standard output is flushed and checked before the exit status is
        // final: a lost write (a full disk, /dev/full, a closed pipe) is exit 2, never a silent
        // success.
        write_stdout("");
        return status;
    } catch (const InputError& e) {
        std::cerr << app.get_name() << ": " << one_line_text(e.what()) << "\n";
        return kExitBadInput;
    } catch (const Undecided& e) {
        std::cerr << app.get_name() << ": undecided: " << one_line_text(e.what()) << "\n";
        return kExitUndecided;
    } catch (const StreamRefused& e) {
        std::cerr << app.get_name() << ": undecided: --stream: " << one_line_text(e.what()) << "; verify without --stream\n";
        return kExitUndecided;
    } catch (const std::bad_alloc&) {
        std::cerr << app.get_name() << ": out of memory (raise the memory limit, or lower the limits that size the work)\n";
        return kExitUndecided;
    } catch (const std::exception& e) {
        std::cerr << app.get_name() << ": internal error (please report): " << e.what() << "\n";
        return kExitInternal;
    }
}

int verify_program(int argc, char** argv) {
    CLI::App app{"impactcert-verify: decide every proof obligation of a law (`impactcert verify` alone: the same options, "
                 "output and exit statuses); exit 0 when every claim is proved, 1 when one is refuted, 2 on bad input, "
                 "3 when a limit leaves a claim undecided",
                 "impactcert-verify"};
    app.set_version_flag("--version", std::string("impactcert-verify ") + IMPACTCERT_VERSION);
    VerifyArgs args;
    ProofOptions proof;
    add_verify_options(&app, args, proof);
    return run_program(app, argc, argv, [&] { return run_verify_command(args, proof.resolved()); });
}

} // namespace impactcert::cli
