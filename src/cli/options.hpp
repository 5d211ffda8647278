// SPDX-License-Identifier: GPL-3.0-or-later
// cli/options.hpp -- the command line both programs share: the options of verify (and of the
// commands that decide obligations: certify, report, sweep), and the exit-status contract of
// every run (run_program). cli_main.cpp builds `impactcert` from them, verify_main.cpp the
// program `impactcert-verify`, which is `impactcert verify` alone: the same options, output and
// exit statuses, without derive, sweep, fuzz or report (half the code to compile).
#pragma once

#include "prover/worst_case.hpp"

#include "cli/common.hpp"

#include <CLI/CLI.hpp>

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>

namespace impactcert::cli {

// Validators with one-line messages: a positive finite number; digits only (so that -1 is
// refused as -1, not read as 2^64 - 1).
std::string positive_text(const std::string& text);
std::string natural_text(const std::string& text);
std::string shard_text(const std::string& text); // --shard: not empty

// The options of the commands that decide obligations (verify, certify, report, sweep): the
// limits, the integer kernels, and (not sweep's) the threads.
struct ProofOptions {
    Limits limits;
    bool no_integer_kernels = false;
    unsigned jobs = 1; // set to the core count by add_proof_options
    std::size_t shard_block = 1024;

    Limits resolved() const; // limits with the kernels, the threads and the shard block applied
};
void add_limit_options(CLI::App* cmd, ProofOptions& proof);
void add_claims_option(CLI::App* cmd, ProofOptions& proof); // --claims (verify, certify, report)
void add_jobs_option(CLI::App* cmd, ProofOptions& proof);
void add_shard_block_option(CLI::App* cmd, ProofOptions& proof);

// verify's own options (added to a subcommand of impactcert, or to impactcert-verify itself).
struct VerifyArgs {
    std::string law_path, junit_path, shard_text;
    bool json = false, stream = false;
    bool worst_case = false; // --worst-case: the law's exact sup T+/T- (and Lipschitz constant)
};
void add_verify_options(CLI::App* cmd, VerifyArgs& args, ProofOptions& proof);
VerifyReport verify_with_progress(const Model& model, const Limits& limits); // with TerminalProgress
// --worst-case (cli/verify.cpp): the exact worst case of the law; the Lipschitz constant when the
// report proves fan and P1 (a continuous tiling).
WorstCase worst_case_of(const Model& model, const VerifyReport& report, const Limits& limits);
std::string worst_case_lines(const WorstCase& w, const Model& model);
int run_verify_command(const VerifyArgs& args, const Limits& limits); // cli/verify.cpp
int run_certify(const std::string& law_path, const std::string& out_path, bool worst_case, const Limits& limits);

// A command's own "undecided" (a limit of derive or sweep): run_program prints
// "<program>: undecided: <what>" and exits 3, like every other limit.
struct Undecided : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Parses the command line (an error: one line, exit 2), runs `run`, checks that standard output
// was written (a lost write: exit 2), and maps every exception to its exit status and one line.
int run_program(CLI::App& app, int argc, char** argv, const std::function<int()>& run);

// The whole of impactcert-verify (verify_main.cpp calls it; CLI11 stays in this file's unit).
int verify_program(int argc, char** argv);

} // namespace impactcert::cli
