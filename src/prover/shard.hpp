// SPDX-License-Identifier: GPL-3.0-or-later
// shard.hpp -- work split over processes and machines the way SAT proofs are split and checked
// (cube and conquer): `--shard K/N` makes a deterministic slice of a run, self-contained, and the
// slices are merged and checked for coverage (proofs/README.md, "Shards").
//
// Contract:
//   - parse_shard("K/N"): 1 <= K <= N <= 1,000,000; an InputError naming --shard otherwise.
//   - A verification (verify, certify) is sliced by obligation and by pair block: obligation i of
//     kObligationIds belongs to shard i mod N + 1 (owns_obligation); the pair forms of
//     `nonexpansive`, in the order of a single run, are cut into blocks of --shard-block pairs
//     (1,024 by default; the part records it), and
//     block b belongs to shard b mod N + 1. A shard decides its obligations, and the blocks of
//     nonexpansive that are its own, each with its counts and evidence, until one fails or stops
//     at a limit (a later block cannot come first in the merged order). When nonexpansive is
//     decided before any pair form (S not a function, P1's discontinuity), it belongs to its
//     owner like any other obligation.
//   - A sweep is sliced by grid point: point k (in the order of sweep.json) belongs to shard
//     k mod N + 1.
//   - A part names its shard, the whole run (the law and its hash; the sweep's parameters) and
//     its slice; merging requires parts of one run, every shard exactly once, every slice exactly
//     what its shard owns. certify's parts are merged and checked by impactcert-check
//     (impactcert-check PART...), the sweep's by `impactcert sweep --merge PART...`.
#pragma once

#include <cstddef>
#include <string>

namespace impactcert {

inline constexpr const char* kCertificatePartFormat = "impactcert-certificate-part/1";
inline constexpr const char* kSweepPartFormat = "impactcert-sweep-part/1";

struct Shard {
    std::size_t index = 0; // 0-based (K - 1)
    std::size_t count = 1; // N
};

Shard parse_shard(const std::string& text); // "K/N"
inline bool owns(const Shard& s, std::size_t item) { return item % s.count == s.index; }

} // namespace impactcert
