// SPDX-License-Identifier: GPL-3.0-or-later
// splitmix.hpp -- the samplers' generator: SplitMix64 (Steele, Lea and Flood), one 64-bit state,
// so that a sample is a pure function of (seed, index). Shared by the law fuzzer and the
// consistency fuzzer.
#pragma once

#include <cstdint>

namespace impactcert::fuzz {

inline std::uint64_t splitmix(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

// Uniform in [0, n) for n < 2^32 by a multiply-shift (no division; bias below n 2^-32).
inline std::uint64_t below(std::uint64_t& st, std::uint64_t n) { return ((splitmix(st) >> 32) * n) >> 32; }

} // namespace impactcert::fuzz
