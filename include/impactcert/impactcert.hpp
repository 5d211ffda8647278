// SPDX-License-Identifier: GPL-3.0-or-later
// impactcert/impactcert.hpp -- the C++ library: systems and laws, derivation, the proof
// obligations with their exact witnesses, certificates and their independent check, exact
// evaluation, and fuzzing of an implementation given as a C++ callable, in-process.
// (docs/library.md; find_package(impactcert) -> impactcert::impactcert, libimpactcert.so.)
//
// Conventions:
//   - Exact numbers are GMP rationals (mpq_class) at this boundary; nothing on the exact path
//     is a double. Witnesses and reports are also given as the JSON text the command line
//     prints with --json (exact values as strings "p/q"), byte for byte the same.
//   - Errors are exceptions derived from impactcert::api::Error, carrying the command line's
//     exit status and one-line message: InputError (2, bad input, the message names the place),
//     LimitError (3, a limit was reached, the message names the option that raises it).
//     A refuted claim is not an error: it is a verdict in the report.
//   - Objects are immutable values, cheap to copy (shared), and safe to use from several threads
//     at once; every call is synchronous and holds no global lock.
//   - Only the names of this header are the API; the library's other symbols are hidden.
#pragma once

#include <gmpxx.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

// The library's exported names (it is built with every other symbol hidden).
#if defined(__GNUC__)
#define IMPACTCERT_API __attribute__((visibility("default")))
#else
#define IMPACTCERT_API
#endif

namespace impactcert::api {

using Rational = mpq_class;
using Vector = std::vector<mpq_class>;

// The library's version (the project's: "0.1.0").
IMPACTCERT_API std::string version();

class IMPACTCERT_API Error : public std::runtime_error {
  public:
    Error(int exit_status, const std::string& message);
    int exit_status() const noexcept { return exit_status_; }

  private:
    int exit_status_;
};
class IMPACTCERT_API InputError : public Error {
  public:
    explicit InputError(const std::string& message) : Error(2, message) {}
};
class IMPACTCERT_API LimitError : public Error {
  public:
    explicit LimitError(const std::string& message) : Error(3, message) {}
};

// An exact number written as the command line takes it: an integer, p/q, a decimal ("0.9" is
// 9/10), a decimal exponent ("1e-300" is 10^-300) or a hex float (a dyadic rational). InputError
// naming `where` otherwise.
IMPACTCERT_API Rational parse_exact(const std::string& text, const std::string& where = "number");

// ---------------------------------------------------------------------------------------------
// Systems: the mechanics a law is derived from (masses M, contact directions W, friction).

class IMPACTCERT_API System {
  public:
    // A chain of balls by their masses, with walls "none", "left", "right" or "both".
    static System chain(const Vector& masses, const std::string& walls = "none");
    // An impactcert-system/1 or impactcert-scene/1 file (told apart by its "format").
    static System read(const std::string& path);
    static System parse(const std::string& json_text, const std::string& origin = "system");

    std::size_t velocities() const; // n, the body velocity coordinates
    std::size_t contacts() const;   // normal contacts
    bool friction() const;
    std::string describe() const;   // "3 balls, 2 contacts (chain)"

    struct Impl;
    explicit System(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    const Impl& impl() const { return *impl_; }

  private:
    std::shared_ptr<const Impl> impl_;
};

// ---------------------------------------------------------------------------------------------
// Laws: cone-wise linear impact laws (impactcert-law/1).

struct LawLimits {
    std::size_t max_pieces = 500000;   // --max-pieces
    std::size_t max_memory_mb = 640;   // --max-memory: the pieces a symmetry expansion makes
};

class IMPACTCERT_API Law {
  public:
    static Law read(const std::string& path, const LawLimits& limits = {});
    static Law parse(const std::string& json_text, const std::string& origin = "law", const LawLimits& limits = {});
    // The embedded default: the 3-ball Newton's cradle law of Leine & Winandy.
    static Law paper();

    std::string name() const;
    std::size_t contacts() const;   // c (with friction: normals and tangents)
    std::size_t velocities() const; // n
    std::size_t pieces() const;     // after the declared symmetries are expanded
    std::vector<std::string> piece_names() const;
    // The law file, as `impactcert derive ... -o` writes it (2-space JSON, ending in a newline).
    std::string to_json() const;
    // Writes the law file: the file is whole or absent (written beside, then renamed).
    void write(const std::string& path) const;

    // S(gamma-): the value of every piece whose closed cone contains gamma- (one off the
    // boundaries, or for a continuous law), in contact velocities. InputError in a gap of the
    // cones or for a vector of the wrong length.
    std::vector<Vector> evaluate(const Vector& gamma_minus) const;
    // The names of the pieces whose closed cones contain gamma-.
    std::vector<std::string> pieces_at(const Vector& gamma_minus) const;
    // |gamma|_H^2 = gamma^T H gamma, twice the kinetic energy of the velocity that gamma stands
    // for (H = G^-1 in contact velocities, the metric of the energetic obligation), exactly.
    Rational energy(const Vector& gamma) const;
    // The law's picture, as `impactcert report` draws it (SVG text): two contacts, the cones and
    // their images in the metric H; three, the cones on the unit sphere; up to ten, S on each
    // plane of two contacts; "" beyond (or where that figure would be too large to draw).
    std::string figure_svg() const;

    struct Impl;
    explicit Law(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
    const Impl& impl() const { return *impl_; }

  private:
    std::shared_ptr<const Impl> impl_;
};

// ---------------------------------------------------------------------------------------------
// Derivation (`impactcert derive sequential | newton | poisson`).

enum class LawKind { sequential, newton, poisson };

struct DeriveOptions {
    LawKind kind = LawKind::sequential;
    // One value for every contact, or one per contact; empty: the system's own, else 1.
    Vector restitution;
    std::string rule = "most-negative"; // sequential: most-negative, left-first, right-first
    std::size_t max_impacts = 100;      // --max-impacts
    std::size_t max_bits = 65536;       // --max-bits
    std::size_t max_memory_mb = 2048;   // --max-memory
};

struct Derivation {
    std::optional<Law> law; // the law, claims set as derive sets them; or, with friction:
    std::string refutation; // why there is no law (not a function: two answers, or none)
    std::string witness;    // the exact gamma- that shows it, as JSON
};

// LimitError when a limit is reached (--max-impacts with the point in the message,
// --max-memory, --max-bits, --max-modes).
IMPACTCERT_API Derivation derive(const System& system, const DeriveOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Proof obligations (`impactcert verify`), certificates (`certify`) and their check.

struct VerifyOptions {
    std::size_t max_pieces = 500000;   // --max-pieces
    std::size_t max_memory_mb = 640;   // --max-memory
    unsigned jobs = 1;                 // --jobs
};

struct Obligation {
    std::string id;             // "fan", "P1", ..., "energetic", ...
    bool claimed = false;
    std::string verdict;        // proved, refuted, skipped, undecided
    std::uint64_t checks = 0;   // exact checks done
    std::string method;
    std::string limit;          // undecided: the limit and its option
    std::string counterexample; // refuted: the exact witness, as JSON ("" otherwise)
};

struct IMPACTCERT_API Report {
    std::string law;
    std::string verdict; // proved (every claim proved), refuted, undecided
    int exit_status = 0; // 0, 1, 3: as `impactcert verify`
    std::vector<Obligation> obligations;
    std::string json;    // impactcert-verdict/1, as `impactcert verify --json` prints it
    const Obligation& at(const std::string& id) const; // std::out_of_range for an unknown id
};

IMPACTCERT_API Report verify(const Law& law, const VerifyOptions& options = {});
// The certificate text (impactcert-certificate/1), as `impactcert certify -o` writes it; the
// report of the same run beside it.
IMPACTCERT_API std::string certify(const Law& law, const VerifyOptions& options = {}, Report* report = nullptr);

struct CheckResult {
    int exit_status = 0; // 0 verified, 1 rejected, 2 malformed, 3 undecided: as impactcert-check
    std::string message; // one line
};
// The independent checker (impactcert-check): its own code and arithmetic, none of the prover's.
IMPACTCERT_API CheckResult check_certificate(const std::string& certificate_text);

// ---------------------------------------------------------------------------------------------
// Fuzzing an implementation in-process (`impactcert fuzz --law`): the same samples, reference,
// properties, tolerances and report as the command line with --impl.

// Fills out[i * out_dim ...] for the `count` points in[i * in_dim ...] (in_dim = out_dim = the
// law's contacts, or its velocities with FuzzOptions::velocities). With jobs > 1 it is called
// from several threads at once.
using BatchFunction = std::function<void(const double* in, double* out, std::size_t count)>;

struct FuzzOptions {
    std::uint64_t seed = 1;
    std::uint64_t samples = 1000000;
    double seconds = 0;                      // > 0: stop after this long
    unsigned jobs = 1;
    std::optional<std::uint64_t> max_ulps;   // componentwise tolerance (default: 0 ulps)
    std::optional<double> max_rel_error;     // or normwise, in the law's metric
    bool velocities = false;                 // ball velocities instead of contact velocities
    std::string range;                       // "LO..HI", "" for the whole double range
    bool allow_extreme = false;              // --allow extreme
    std::string name = "in-process callable"; // how the report names the implementation
    std::size_t batch = 64;                  // points per call
};

struct FuzzResult {
    std::string verdict;        // "violations", "no violation", "undecided" (nothing checked)
    int exit_status = 0;        // 1, 0, 3: as `impactcert fuzz`
    std::uint64_t samples = 0;  // checked
    // Law mode: the samples with a violation that fails the run; consistency mode: the findings
    // (one per property broken at a sample) and the implementation's failures.
    std::uint64_t violating = 0;
    std::string json;           // impactcert-fuzz/1, as `impactcert fuzz --json` prints it
};

IMPACTCERT_API FuzzResult fuzz(const Law& law, const BatchFunction& implementation, const FuzzOptions& options = {});

// Consistency mode (`impactcert fuzz --masses|--system` without --law): a black-box impact map of
// a System checked against the laws of mechanics alone -- no penetration, pushing impulses,
// momentum (ball velocities), no energy gain, at rest stays at rest, and with friction the cone
// and Coulomb's law -- each finding recomputed exactly at the implementation's doubles; with a
// reference law each finding is law-level or solver-level. The same report as the command line.
struct ConsistencyOptions {
    std::uint64_t seed = 1;
    std::uint64_t samples = 1000000;
    double seconds = 0;
    unsigned jobs = 1;
    double max_rel_error = 1e-9;          // --max-rel-error
    bool velocities = false;              // ball velocities (momentum checked) instead of contact ones
    std::optional<Vector> restitution;    // --restitution: the restitution property (one value, or one per contact)
    std::string reference;                // --reference: approaching, newton, poisson, or a law file
    std::vector<std::string> require;     // --require: nonexpansive, continuity
    std::string range;                    // --range LO..HI ("": 1e-3..1e3)
    std::string name = "in-process callable";
    // Points per call: as many as the fuzzer sends a process (each block of samples also has a
    // fixed cost of its own: exact examples and replays; 64 points per call ran at 2/3 the rate).
    std::size_t batch = 2048;
};

IMPACTCERT_API FuzzResult fuzz_consistency(const System& system, const BatchFunction& implementation,
                                           const ConsistencyOptions& options = {});

} // namespace impactcert::api
