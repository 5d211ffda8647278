// SPDX-License-Identifier: GPL-3.0-or-later
// support.hpp -- shared helpers for the test suite.
//
// Contract:
//   - q("-7/12"), vec({...}): exact values from text, for hand-written fixtures.
//   - sorting_law(n): the equal-mass n-ball "sort the velocities" law, built from first
//     principles (one cone per ordering of the ball velocities), independent of the paper's table.
//   - revalidate(model, result): re-checks a refutation's counterexample from its JSON alone,
//     by recomputing S and the quantities it names; REQUIREs on failure.
//   - run_cli(args, stdin): runs the built `impactcert` binary, returns exit status and output.
#pragma once

#include "impactcert_check.hpp"
#include "base/json.hpp"
#include "model/law.hpp"
#include "prover/obligations.hpp"

#include <initializer_list>
#include <string>

namespace impactcert::test {

// Random samples per loop: the Release run takes n; the sanitizer run (ASan + UBSan, -O1, about
// ten times slower) repeats every case, every boundary point and every assertion on n / 4 random
// points (at least min(n, 250)), so that it stays a run of minutes.
#ifdef IMPACTCERT_SANITIZER_BUILD
inline constexpr std::size_t kSanitizerDivisor = 4;
#else
inline constexpr std::size_t kSanitizerDivisor = 1;
#endif
inline std::size_t samples(std::size_t n) {
    const std::size_t floor = n < 250 ? n : 250;
    return n / kSanitizerDivisor > floor ? n / kSanitizerDivisor : floor;
}

Rational q(const std::string& text);
Vector vec(std::initializer_list<const char*> xs);
Vector vec_of(const Json& j);

std::string source_path(const std::string& relative);
std::string read_file(const std::string& path);

// A fresh directory for one test (the system's temporary directory, impactcert-NAME-PID), removed
// when the test ends, passed or failed.
struct ScratchDir {
    std::string path;
    explicit ScratchDir(const std::string& name);
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir();
};

Law sorting_law(std::size_t n);

void revalidate(const Model& model, const ObligationResult& result);

// Every refuted obligation's witness re-validated, and the certificate of `report` verified by
// impactcert-check's library; REQUIREs on failure.
void require_sound(const Model& model, const VerifyReport& report);

// impactcert-check's library on a certificate held as JSON.
impactcert_check::Outcome check_certificate(const Json& cert);

struct CliRun {
    int status = -1;
    std::string out; // stdout
    std::string err; // stderr
};
CliRun run_cli(const std::string& args, const std::string& stdin_text = "");
// A replay command as the fuzzer prints it ("cd DIR && PROGRAM eval ..."), run by the shell from
// the root directory (a replay must run from any directory). Fails the test unless it has that
// shape and names the built impactcert.
CliRun run_replay(const std::string& replay);
// The same for another built program (IMPACTCERT_VERIFY_CLI, IMPACTCERT_CHECKER, ...).
CliRun run_program(const std::string& program, const std::string& args, const std::string& stdin_text = "");

} // namespace impactcert::test
