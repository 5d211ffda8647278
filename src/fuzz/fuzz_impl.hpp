// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_impl.hpp -- the implementations the fuzzer can test.
//
// Contract:
//   - An Implementation maps points of in_dim doubles to points of out_dim doubles, in batches;
//     each point gets a status: ok, or (for a separate process) crashed, hung or malformed. A
//     failing point never stops the run: the process is restarted and the batch goes on.
//   - clone() gives an independent instance for another worker thread (its own process).
//   - Built-ins: the paper's float law (fp::S, or fp::sort_velocities on ball velocities) and
//     FloatLaw for any law (contact velocities; it also reports its stated error bound).
//   - `--impl LIB.so:SYMBOL`: a C function void f(const double* in, double* out) (dlopen).
//   - `--impl-cmd CMD`: `/bin/sh -c CMD`; one line of in_dim hex doubles (%a) per point on its
//     stdin, one line of out_dim doubles (hex or decimal, anything strtod reads) expected back per
//     line, in order. The fuzzer writes and reads at once (poll), so a batch never deadlocks on a
//     full pipe; a point with no answer within `timeout` seconds (plus 2 s for a process that
//     has not answered anything yet: its start-up) is `hung`; an early end of
//     output (or the process's end, seen by waitpid) is `crashed`; a line that is not out_dim
//     numbers, or longer than 64 KiB, is `malformed`; more lines than inputs make the whole batch
//     `malformed` (the answers can no longer be matched to inputs) and restart the process.
//     Progress is a complete line, so a trickle of bytes is a hang. The command runs in its own
//     process group (killed as one), with SIGPIPE at its default, and dies with the fuzzer. A command that
//     answers nothing at all (not found, not executable, exits at once) is bad input (InputError).
//   - replay_flags(): the command-line options that select this implementation again.
#pragma once

#include "model/law.hpp"

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace impactcert::fuzz {

// refused: a built-in declined the input; skipped: not evaluated (the run's time ran out).
// nondeterministic: the same input was answered differently (a process only: the batch's first
// input is sent again at its end; when the answers differ and a fresh process answers it twice
// differently too, or otherwise than the batch did, the map is not a function of its input). The
// point's `out` is its first answer; repeated_answer(point) the other.
enum class ImplStatus : std::uint8_t { ok, crashed, hung, malformed, refused, skipped, nondeterministic };

// What an implementation run as a process wrote on its standard error: collected in one file for
// all its processes (never echoed per sample) and summarised at the end of a run.
struct StderrSummary {
    std::uint64_t lines = 0, bytes = 0;
    std::vector<std::string> first; // up to three distinct lines, in order, each cut at 200 characters
};

class Implementation {
  public:
    virtual ~Implementation() = default;
    // bound: null, or out_dim per point: the implementation's own stated error bound.
    virtual void eval(const double* in, double* out, double* bound, std::size_t count, ImplStatus* status) = 0;
    virtual bool states_bound() const { return false; }
    // Samples per batch: small for in-process implementations (the batch stays in cache),
    // large for a separate process (fewer round trips through the pipes).
    virtual std::size_t batch_samples() const { return 64; }
    // A flag the run raises when --seconds runs out: a slow implementation may then leave the
    // rest of a batch `skipped` instead of finishing it.
    virtual void set_stop_flag(const std::atomic<bool>*) {}
    virtual std::unique_ptr<Implementation> clone() const = 0;
    virtual std::string describe() const = 0;
    virtual std::string replay_flags() const = 0;
    // After eval() marked point `point` (of that call) nondeterministic: the other answer it gave
    // to the same input.
    virtual std::vector<double> repeated_answer(std::size_t /*point*/) const { return {}; }
    // A process's standard error, collected (nothing for in-process implementations).
    virtual std::optional<StderrSummary> stderr_summary() const { return std::nullopt; }
};

// The paper's law in double (contact velocities g1, g2; or ball velocities, sorted).
std::unique_ptr<Implementation> builtin_paper(bool velocities);
// FloatLaw of any law (contact velocities), with its stated bound. Keeps a reference to model.
std::unique_ptr<Implementation> builtin_float_law(const Model& model);
// The same in ball velocities, for a law on dependent contact columns: u- -> W_B^T u- -> the
// float law -> u+ = u- + M^-1 W_B H_B (y+ - y), in doubles. No stated bound.
std::unique_ptr<Implementation> builtin_float_law_velocities(const Model& model);
// LIB.so:SYMBOL. Throws InputError (missing library or symbol).
std::unique_ptr<Implementation> load_symbol(const std::string& spec, std::size_t in_dim, std::size_t out_dim);
// CMD through /bin/sh. Throws InputError when the command does not answer a first probe.
std::unique_ptr<Implementation> command(const std::string& cmd, std::size_t in_dim, std::size_t out_dim,
                                        double timeout_seconds);

// Single-quotes `s` for a POSIX shell.
std::string shell_quote(const std::string& s);
// Two answers are the same when every component is equal as a number (0 and -0 alike) or both are
// NaN: what matters for one input is the value, not its last bits of text.
bool same_values(const double* a, const double* b, std::size_t n);

// The shortest decimal ("%.Ng", N = 1..17) that reads back as x: a tolerance, a mutant's
// parameter or a replay's option says exactly the run's double.
std::string shortest_decimal(double x);
// "%a"-style hex text of a double, fast (parseable by strtod and Python's float.fromhex).
std::string hex(double x);
char* hex_to(double x, char* out); // writes at out, returns the end (no terminator)

} // namespace impactcert::fuzz
