// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz.hpp -- differential testing of floating-point implementations of any law against the
// exact law.
//
// Contract:
//   - Samples are a pure function of (seed, index) (SplitMix64), so a run is reproducible from
//     --seed whatever --jobs is, and any sample can be replayed alone. The generators work for
//     any law, in contact or ball velocities: log-uniform magnitudes over the whole double range,
//     a common scale with spread components, points on rays and (exactly, for integer rays) on
//     facets, at distances from facets spread log-uniformly from an ulp to the point's scale,
//     signed zeros, subnormals, the overflow region, and close pairs straddling facets.
//   - The reference is LawReference (fuzz_reference.hpp): exact, correctly rounded, fast.
//   - Tolerances: --max-ulps K (componentwise, in ulps of the correctly rounded value),
//     --max-rel-error R (normwise in the law's metric: |y - S(x)| <= R |x|, H for contact
//     velocities, M for ball velocities), or an implementation's own stated bound (FloatLaw).
//     An output outside its tolerance is a violation; for such an output the fuzzer also reports
//     what it breaks among the law's properties that `verify` proved (Properties): a negative
//     contact velocity, an energy increase or a non-expansivity violation beyond the tolerance.
//     (An output inside the tolerance cannot break them: proofs/README.md, "Fuzzing any law".)
//   - reference_fast / reference_naive: the paper's law only, by TwoSum and by GMP; a second,
//     independent route the tests compare the general reference with.
//   - parse_seed: the --seed grammar, a decimal integer in [0, 2^64 - 1], nothing else.
#pragma once

#include "fuzz/fuzz_impl.hpp"
#include "fuzz/fuzz_reference.hpp"
#include "model/law.hpp"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace impactcert::fuzz {

// ---------------------------------------------------------------------------------------------
// Samples

struct Sample {
    double a[kMaxDim] = {};
    double b[kMaxDim] = {};
    bool pair = false;     // also check non-expansivity between a and b
    const char* kind = ""; // generator name
    long facet = -1;       // the facet (piece side) it was made on or near, for the coverage; -1: none
};

// The generator of a run. Indices below prefix_count() are the deterministic prefix, which every
// run covers first however short: the input at rest, ties, an interior point of every piece, both
// sides of every facet, every ray, each at the middle of the range and at its ends (the overflow
// and underflow limits without --range), and close pairs straddling facets at both ends. The
// others are random (kinds()), including points stratified over the pieces (positive
// combinations of a piece's rays, thin cones included) and near-ties. With a range (lo..hi,
// hi > 0) every random sample is then scaled by a power of two drawn uniformly among those that
// put its largest component in [lo, hi] (fit_range): log-uniform scales, exact ratios kept.
class Generator {
  public:
    explicit Generator(const LawReference& reference, double lo = 0, double hi = 0);
    std::size_t dim() const { return dim_; }
    void make(std::uint64_t seed, std::uint64_t index, Sample& s) const;
    std::uint64_t prefix_count() const { return prefix_.size(); }
    std::size_t facets() const { return g_.facet_rays.size(); }
    static const std::vector<std::string>& kinds();

  private:
    struct Probe {
        enum Kind : unsigned char { rest, tie, piece, ray, facet, facet_side, straddle } kind;
        unsigned char where; // 0 the bottom of the range, 1 its middle, 2 its top
        std::uint32_t id;    // piece, ray or facet
        signed char side;    // facet_side: +1 inward, -1 outward
    };
    LawReference::Geometry g_;
    std::size_t dim_;
    double lo_, hi_;
    std::vector<Probe> prefix_;
    void facet_point(std::uint64_t& st, std::size_t facet, double* p, int& scale) const;
    void make_probe(const Probe& probe, Sample& s) const;
};

// The paper's law's generator (contact velocities), for tests and benchmarks.
Sample make_paper_sample(std::uint64_t seed, std::uint64_t index);

// ---------------------------------------------------------------------------------------------
// The paper's law, second route

struct Reference {
    double value[2];    // correctly rounded exact S(g1, g2)
    double residual[2]; // exact S(g1, g2) = value + residual (TwoSum), componentwise
    int cone;           // 0..5: I, IIa, IIb, III, IVb, IVa
};

Reference reference_fast(double g1, double g2);
Reference reference_naive(const Model& paper, double g1, double g2);

// Distance in units in the last place between two doubles (+0 and -0 are equal; an infinity
// is one ulp beyond the largest double).
std::uint64_t ulp_distance(double a, double b);

// ---------------------------------------------------------------------------------------------
// The run

enum class Tolerance { ulps, relative, stated_bound };

struct Properties { // proved by `verify` for this law; checked only then
    bool nonnegative = false;  // kinematic: gamma+ >= 0
    bool energy = false;       // energetic: |S(x)| <= |x|
    bool nonexpansive = false; // |S(a) - S(b)| <= |a - b|
};

struct Options {
    std::uint64_t seed = 1;
    std::uint64_t samples = 1000000;
    double seconds = 0;        // > 0: stop after this long (whichever comes first)
    unsigned jobs = 1;
    Tolerance tolerance = Tolerance::ulps;
    std::uint64_t max_ulps = 0;
    double max_rel_error = 0;
    std::size_t keep = 10;     // violations kept as examples
    std::string replay_prefix = "impactcert eval --float"; // + law and space options
    // --range LO..HI (0 < LO <= HI; both 0: the whole double range): every sample, a pair's two
    // points alike, is scaled by a power of two drawn uniformly among those that put its largest
    // component in [LO, HI] (log-uniform scales), then components below LO become 0 (fit_range).
    double range_lo = 0, range_hi = 0;
    bool allow_extreme = false; // --allow extreme: violations at extreme inputs do not fail the run
    bool stop_on_failure = false; // end the run at the first chunk whose violations fail it (--mutants)
};

// The sample moved into the run's --range (Options::range_lo/hi), as described there. A scale by
// a power of two is exact, so points on facets stay on them (the law is positively homogeneous).
// `draw` picks the power of two uniformly among those that fit (0: the largest, as before).
void fit_range(Sample& s, std::size_t dim, double lo, double hi, std::uint64_t draw = 0);

// The magnitudes a plain implementation cannot be asked to handle: an input whose largest
// component is above 2^500 (about 3.3e150: squares and norms overflow) or, non-zero, below
// 2^-500 (their squares underflow). Violations there are counted as `extreme` as well, a class
// a gate may allow (--allow extreme) while every other input stays gated.
bool extreme_input(const double* x, std::size_t dim);

struct Violation {
    std::uint64_t index = 0;
    std::string what;
    std::string kind; // generator
    bool extreme = false; // at an extreme input (extreme_input)
    std::vector<double> input, input_b, output, expected;
    std::string replay; // a ready command that shows it again
};

struct Summary {
    std::uint64_t samples = 0, points = 0, pairs = 0;
    std::uint64_t slow = 0;    // reference decided through GMP
    std::uint64_t outside = 0; // points in no cone (a law that is not a tiling)
    double seconds = 0;
    std::vector<std::uint64_t> max_ulps; // per output component
    double max_rel_error = 0;            // normwise, over the outputs that were not exact
    // Violations:
    std::uint64_t inaccurate = 0;    // outside the tolerance (classification ones included)
    std::uint64_t misclassified = 0; // of those: the output is another piece's formula
    std::uint64_t negative = 0, energy = 0, nonexpansive = 0; // properties broken beyond tolerance
    std::uint64_t non_finite = 0;    // NaN or infinity where the correctly rounded value is finite
    std::uint64_t crashed = 0, hung = 0, malformed = 0, refused = 0; // implementation failures
    std::vector<Violation> examples;
    std::uint64_t violations() const {
        return inaccurate + negative + energy + nonexpansive + non_finite + crashed + hung + malformed + refused;
    }
    // Samples with a violation, at extreme inputs (extreme_input) and at the others.
    std::uint64_t extreme = 0, gated = 0;
    // Coverage: pieces whose cone held a checked input; facets (piece sides) a sample was made on
    // or near; the decades of the checked inputs' largest components.
    std::uint64_t pieces_hit = 0, pieces = 0, facets_probed = 0, facets = 0, prefix = 0;
    int decade_lo = 0, decade_hi = 0; // floor(log10) of the smallest and largest scale checked
    std::uint64_t decades = 0;        // distinct decades met
    bool fails(bool allow_extreme) const { return gated > 0 || (!allow_extreme && extreme > 0); }
};

// progress(done) is called from the coordinating thread about every 200 ms.
Summary run(const Options& options, const LawReference& reference, const Implementation& impl,
            const Properties& properties, const std::function<void(std::uint64_t)>& progress);

// One point explained (for `eval --float` replays): the implementation's output, the correctly
// rounded value(s), the piece(s) and the error in ulps, as lines of text.
// `worst_ulps`, when given, receives the implementation's error: the largest component distance
// in ulps to the nearest correctly rounded value (UINT64_MAX when it failed, answered a non-finite
// number, or the input lies in no cone).
// `answer`, when given, receives the implementation's output (empty when it failed).
std::string explain(const LawReference& reference, Implementation* impl, const double* x,
                    std::uint64_t* worst_ulps = nullptr, std::vector<double>* answer = nullptr);

// A seed as the command line gives it: decimal digits only, value in [0, 2^64 - 1]. No sign,
// exponent, hex or white space (they used to wrap or saturate silently); `why` gets the reason.
std::optional<std::uint64_t> parse_seed(std::string_view text, std::string* why = nullptr);

} // namespace impactcert::fuzz
