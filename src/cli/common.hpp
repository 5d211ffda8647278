// cli/common.hpp -- what the commands of the `impactcert` program share (cli_main.cpp wires the
// options; cli/derive.cpp, cli/fuzz.cpp run the commands).
//
// Contract: every error is an InputError (one line, exit 2) or a std::exception (exit 4, a bug).
// Output goes through write_file / write_stdout, which flush and check: a write that fails (a
// full disk, /dev/full, a closed pipe) is an error, never a silent exit 0.
#pragma once

#include "derive.hpp"
#include "fuzz.hpp"
#include "law.hpp"
#include "limits.hpp"
#include "obligations.hpp"
#include "shard.hpp"
#include "system.hpp"

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::cli {

constexpr int kExitProved = 0;
constexpr int kExitRefuted = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitUndecided = 3;
constexpr int kExitInternal = 4;

// A message as one line of plain text: the backslash doubled, and control characters (C0, DEL,
// C1, U+2028 and U+2029) written as \n, \r, \t or \uXXXX, so that a name or key taken from the
// input can neither break an error line nor send escape sequences to a terminal. (The checker
// escapes its messages with its own copy, one_line in src/checker/check.cpp: it shares no code.)
std::string one_line_text(const std::string& text);

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

void write_file(const std::string& path, const std::string& text); // checked
void write_stdout(const std::string& text);                        // checked (fflush, ferror)

std::vector<Rational> number_list(const std::string& option, const std::string& text);
std::vector<std::string> tokens_of(const std::string& text); // white space, commas; brackets ignored
std::string line_of(const Vector& v);
double parse_double(const std::string& text, const std::string& where);
// An exact value for a one-line message: itself when short, else "~1.23457e+1000 (3011 digits)".
std::string short_text(const Rational& x);
std::string short_text(const Vector& v);

// The system options shared by derive, sweep and fuzz: --masses (a chain) with --walls, or
// --system FILE (impactcert-system/1 or a law file).
struct SystemArgs {
    std::string masses, walls = "none", system_path;
    bool given() const { return !masses.empty() || !system_path.empty(); }
};
System system_from(const SystemArgs& a); // InputError when both or neither are given
// The same options as command-line text (for replays).
std::string system_flags(const SystemArgs& a);
// One restitution value for every contact, or one per contact.
std::vector<Rational> restitution_list(const std::string& text, std::size_t contacts);

// ---- derive (cli/derive.cpp)
struct DeriveArgs {
    SystemArgs system;
    std::string restitution = "1", rule = "most-negative", out, outcomes_from;
    std::string restitution_on = "all";
    std::size_t max_impacts = 100, max_bits = kDefaultMaxBits, max_words = kDefaultMaxWords;
    bool json = false;
};
int run_derive_sequential(const DeriveArgs& a);

int run_verify_shard(const std::string& law_path, const Shard& shard, bool json, Limits limits); // cli/shard.cpp
int run_certify_shard(const std::string& law_path, const Shard& shard, const std::string& out_path, Limits limits);
int run_derive_classical(const DeriveArgs& a, bool poisson);

struct CradleArgs {
    std::size_t balls = 0;
    std::string pieces = "representatives", out;
    bool no_symmetries = false;
};
int run_derive_cradle(const CradleArgs& a);

// ---- fuzz and eval (cli/fuzz.cpp)
struct FuzzArgs {
    std::string law_path, impl_spec, impl_cmd, junit, range, float_law;
    SystemArgs system;
    std::string require;
    bool velocities = false, json = false, pair = false, pieces = false;
    bool impl_given = false, impl_cmd_given = false; // given, even as an empty string
    std::optional<std::uint64_t> max_ulps;
    std::optional<double> max_rel_error;
    double timeout = 10;
    fuzz::Options options;
};
int run_fuzz(FuzzArgs a);
// cli/consistency.cpp
int run_consistency_fuzz(const FuzzArgs& a);
int run_consistency_eval(const FuzzArgs& a, const std::vector<std::vector<std::string>>& points);
int run_eval(const std::string& law_path, bool velocities, const std::vector<std::string>& args, bool as_float,
             FuzzArgs float_args);

} // namespace impactcert::cli
