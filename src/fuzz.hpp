// fuzz.hpp -- differential testing of a floating-point impact law against the exact one.
//
// Contract:
//   - Samples are a pure function of (seed, index) (SplitMix64), so a run is reproducible from
//     --seed whatever --jobs is, and any sample can be replayed alone.
//   - reference_fast(g1, g2): the correctly rounded exact value of the paper's law without GMP.
//     It is derived independently of the float law: the cone is the exact ordering of the ball
//     velocities (0, g1, g1+g2), every output is a difference of two of them (+-g1, +-g2 or
//     +-(g1+g2)), and g1+g2 is formed by TwoSum, whose rounded part is the correctly rounded sum.
//   - reference_naive(model, g1, g2): the same through GMP rationals and the exact law of a
//     Model, rounded to nearest-even by exact comparison. The slow path the tests and the
//     benchmark compare against.
//   - run(options, impl): fuzzes `impl` (the built-in float law when null) and summarises.
//   - parse_seed: the --seed grammar, a decimal integer in [0, 2^64 - 1], nothing else.
#pragma once

#include "law.hpp"

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace impactcert::fuzz {

using Impl = void (*)(const double* gamma_minus, double* gamma_plus);

struct Point {
    double g[2];
};

struct Sample {
    Point a;           // the input
    bool pair = false; // also check non-expansivity against b
    Point b;
    const char* kind = ""; // generator name
};

Sample make_sample(std::uint64_t seed, std::uint64_t index);

struct Reference {
    double value[2];    // correctly rounded exact S(g1, g2)
    double residual[2]; // exact S(g1, g2) = value + residual (TwoSum), componentwise
    int cone;           // 0..5: I, IIa, IIb, III, IVb, IVa
};

Reference reference_fast(double g1, double g2);
Reference reference_naive(const Model& paper, double g1, double g2);

// Distance in units in the last place between two finite doubles (+0 and -0 are equal).
std::uint64_t ulp_distance(double a, double b);

struct Violation {
    std::uint64_t index = 0;
    std::string what;     // "not correctly rounded", "negative output", ...
    Sample sample;
    double output[2] = {0, 0};
    double expected[2] = {0, 0};
    std::string replay;   // a ready impactcert eval command
};

struct Options {
    std::uint64_t seed = 1;
    std::uint64_t samples = 1000000;
    double seconds = 0;        // > 0: stop after this long (whichever comes first)
    unsigned jobs = 1;
    std::uint64_t max_ulps = 0; // allowed error per component
    std::string impl_spec;      // for replay commands
    std::size_t keep = 10;      // violations kept as examples
};

struct Summary {
    std::uint64_t samples = 0, pairs = 0;
    double seconds = 0;
    std::uint64_t max_ulps[2] = {0, 0};
    std::uint64_t misclassified = 0;    // output is another cone's formula
    std::uint64_t not_rounded = 0;      // error above max_ulps
    std::uint64_t negative = 0;         // gamma+ < 0
    std::uint64_t energy = 0;           // |gamma+|_H > |gamma-|_H beyond rounding
    std::uint64_t nonexpansive = 0;     // |S(a)-S(b)|_H > |a-b|_H beyond rounding
    std::uint64_t non_finite = 0;       // NaN or infinite output for finite input
    std::vector<Violation> examples;
    std::uint64_t violations() const {
        return misclassified + not_rounded + negative + energy + nonexpansive + non_finite;
    }
};

// progress(done) is called from the coordinating thread about every 200 ms.
Summary run(const Options& options, Impl impl, const std::function<void(std::uint64_t)>& progress);

std::string hex(double x); // "%a"

// A seed as the command line gives it: decimal digits only, value in [0, 2^64 - 1]. No sign,
// exponent, hex or white space (they used to wrap or saturate silently); `why` gets the reason.
std::optional<std::uint64_t> parse_seed(std::string_view text, std::string* why = nullptr);

} // namespace impactcert::fuzz
