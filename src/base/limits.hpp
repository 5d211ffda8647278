// SPDX-License-Identifier: GPL-3.0-or-later
// limits.hpp -- resource limits of the exact decisions.
//
// Contract: every exact decision whose cost can grow exponentially with the input (KKT
// enumeration, the chambers of a hyperplane arrangement, extreme rays of cone intersections)
// takes its limit from here and throws LimitExceeded before exceeding it. The obligation that
// needed the decision is then `undecided` (SPEC section 3), naming the limit and the option that
// raises it; exit status 3 when such an obligation is claimed and none is refuted.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace impactcert {

struct Limits {
    std::size_t max_faces = 16384;      // --max-faces: simplex faces of one KKT enumeration
    std::size_t max_chambers = 200000;  // --max-chambers: chambers of the facet arrangement
    std::size_t max_subsets = 5000000;  // --max-subsets: constraint subsets for cone intersections
    std::size_t max_pieces = 500000;    // --max-pieces: pieces of a law with symmetries, listed and generated
    std::size_t max_memory_mb = 640;    // --max-memory: megabytes of generated pieces (counted by the size of their numbers)

    // How the work is done; no effect on any verdict, method, count or witness.
    bool evidence = true;          // build each obligation's evidence (certify); verify needs none
    bool integer_kernels = true;   // --no-integer-kernels: decide the pair forms over GMP alone
    unsigned jobs = 1;             // --jobs: threads for the pairwise checks (--stream: the expansion too)
    // --shard K/N (shard.hpp): this process decides slice K of N (0-based here) of the work.
    std::size_t shard_index = 0, shard_count = 1;
    std::size_t shard_block_pairs = 1024; // --shard-block: pairs of nonexpansive per block
    // --claims: the obligations the run holds the law to, replacing the law file's "claims"
    // (comma-separated ids, or "all": every one that applies); empty: the law's own.
    std::string claims;
};

struct LimitExceeded : std::runtime_error {
    LimitExceeded(const std::string& what, std::string option_)
        : std::runtime_error(what), option(std::move(option_)) {}
    std::string option; // the command-line option that raises the limit
};

} // namespace impactcert
