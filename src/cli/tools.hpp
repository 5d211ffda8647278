// SPDX-License-Identifier: GPL-3.0-or-later
// cli/tools.hpp -- the commands of the full `impactcert` program beyond verify and certify:
// derive (cli/derive.cpp), fuzz and eval (cli/fuzz.cpp, cli/consistency.cpp), and the number
// and system arguments they share (cli/arguments.cpp). impactcert-verify compiles none of them.
#pragma once

#include "cli/common.hpp"
#include "derive/derive.hpp"
#include "fuzz/fuzz.hpp"
#include "model/system.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace impactcert::cli {

std::vector<Rational> number_list(const std::string& option, const std::string& text);
std::vector<std::string> tokens_of(const std::string& text); // white space, commas; brackets ignored
std::string line_of(const Vector& v);
double parse_double(const std::string& text, const std::string& where);

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
    std::string restitution, rule = "most-negative", out, outcomes_from; // restitution "": the scene's, else 1
    std::string restitution_on = "all";
    std::string restitution_tangential; // friction: e_T of every tangent (empty: the system's, else 0)
    std::size_t max_modes = kMaxFrictionModes; // friction: contact modes enumerated at most
    std::size_t max_impacts = 100, max_bits = kDefaultMaxBits, max_words = kDefaultMaxWords;
    std::size_t max_memory_mb = kDefaultDeriveMemoryMb;
    bool json = false;
    bool stream = false; // sequential: --stream (derive_sequential_streamed)
};
int run_derive_sequential(const DeriveArgs& a);

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
    std::string restitution; // consistency: the restitution the implementation is meant to apply
    std::string reference;   // consistency: the exact law it is meant to compute (a file, or a name)
    std::string cone;        // consistency: --cone box|circular, the friction of a contact with two tangents
    std::string allow;       // law mode: classes of violations that do not fail the run ("extreme")
    std::string mutant;      // law mode: --mutant ID, a mutant of the law's plain double evaluation
    std::string efforts;     // consistency: --efforts E1,E2,...: the values of {iterations} in --impl-cmd
    std::optional<std::size_t> mutants; // --mutants N: the gate against N mutants
    std::optional<double> min_kill_rate; // with --mutants: exit 1 below this kill rate
    bool velocities = false, json = false, pair = false, pieces = false;
    bool impl_given = false, impl_cmd_given = false; // given, even as an empty string
    bool restitution_given = false, reference_given = false, mutant_given = false;
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
