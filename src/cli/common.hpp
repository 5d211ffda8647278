// SPDX-License-Identifier: GPL-3.0-or-later
// cli/common.hpp -- what every impactcert program shares: exit statuses, one-line messages,
// loading a law, progress on a terminal and checked writes (cli/options.hpp wires the options,
// cli/verify.cpp runs verify and certify; cli/tools.hpp declares the other commands).
//
// Contract: every error is an InputError (one line, exit 2) or a std::exception (exit 4, a bug).
// Output goes through write_file / write_stdout, which flush and check: a write that fails (a
// full disk, /dev/full, a closed pipe) is an error, never a silent exit 0.
#pragma once

#include "model/law.hpp"
#include "base/output_file.hpp"
#include "base/limits.hpp"
#include "prover/obligations.hpp"
#include "prover/shard.hpp"

#include <chrono>
#include <fstream>
#include <string>

namespace impactcert::cli {

constexpr int kExitProved = 0;
constexpr int kExitRefuted = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitUndecided = 3;
constexpr int kExitInternal = 4;

// Messages are printed through one_line_text (base/errors.hpp). (The checker escapes its messages
// with its own copy, one_line in src/checker/check.cpp: it shares no code.)

// The program's name at the start of its messages ("impactcert", "impactcert-verify"); set by
// run_program.
void set_program_name(const std::string& name);
const std::string& program_name();
// The start of a replay command that runs from any directory: `cd '<the working directory>' && `
// and the program as it was invoked (argv[0]; a bare name is looked up on PATH again). Relative
// paths of the run (law, system, library, --impl-cmd) stay valid after the cd.
void set_invocation(const char* argv0);
std::string replay_command(const std::string& subcommand);

// With `claims` (--claims): the law held to those obligations instead of its file's "claims".
Model load_model(const std::string& law_path, const Limits& limits);
Model load_model(const std::string& law_path, std::size_t max_pieces = Limits{}.max_pieces,
                 std::size_t max_memory_mb = Limits{}.max_memory_mb);

// Progress on a terminal for runs over a second: one line on stderr, rewritten in place.
class TerminalProgress {
  public:
    TerminalProgress();
    ~TerminalProgress();
    TerminalProgress(const TerminalProgress&) = delete;
    TerminalProgress& operator=(const TerminalProgress&) = delete;
    Progress callback();

  private:
    bool enabled_;
    bool shown_ = false;
    std::chrono::steady_clock::time_point start_, last_{};
};

// Output files, whole or absent: output_file.hpp.
using impactcert::OutputFile;
using impactcert::write_file;
void write_stdout(const std::string& text);                        // checked (fflush, ferror)

int run_verify_shard(const std::string& law_path, const Shard& shard, bool json, Limits limits); // cli/shard.cpp
int run_certify_shard(const std::string& law_path, const Shard& shard, const std::string& out_path, Limits limits);

} // namespace impactcert::cli
