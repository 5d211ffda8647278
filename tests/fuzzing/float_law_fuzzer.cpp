// float_law_fuzzer.cpp -- libFuzzer target: the float law against the exact law, coverage-guided.
//
// Input: 16 bytes, read as two doubles (gamma1-, gamma2-); non-finite inputs are outside the
// domain and skipped. Checks, aborting on failure (libFuzzer then saves the input):
//   - fp::S is correctly rounded: 0 ulp from the naive GMP reference (exact rationals);
//   - the fast TwoSum reference of `impactcert fuzz` agrees with the GMP one;
//   - gamma+ >= 0, and the batch form equals the scalar form.
// Built only with -DIMPACTCERT_LIBFUZZER=ON and clang; see README.md beside this file.
#include "fuzz.hpp"
#include "paper_law.hpp"

#include <impactcert/float_law.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace impactcert;
    if (size < 2 * sizeof(double))
        return 0;
    double g[2];
    std::memcpy(g, data, sizeof g);
    if (!std::isfinite(g[0]) || !std::isfinite(g[1]))
        return 0;
    static const Model paper(paper_law());
    double out[2], b1, b2;
    fp::S(g[0], g[1], out);
    fp::S_batch(&g[0], &g[1], &b1, &b2, 1);
    const auto naive = fuzz::reference_naive(paper, g[0], g[1]);
    const auto fast = fuzz::reference_fast(g[0], g[1]);
    const bool ok = fuzz::ulp_distance(out[0], naive.value[0]) == 0 && fuzz::ulp_distance(out[1], naive.value[1]) == 0 &&
                    fuzz::ulp_distance(fast.value[0], naive.value[0]) == 0 &&
                    fuzz::ulp_distance(fast.value[1], naive.value[1]) == 0 && out[0] >= 0 && out[1] >= 0 &&
                    fuzz::ulp_distance(b1, out[0]) == 0 && fuzz::ulp_distance(b2, out[1]) == 0;
    if (!ok) {
        std::fprintf(stderr, "mismatch at %a %a: law %a %a, batch %a %a, exact %a %a\n", g[0], g[1], out[0], out[1], b1,
                     b2, naive.value[0], naive.value[1]);
        std::abort();
    }
    return 0;
}
