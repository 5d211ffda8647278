// SPDX-License-Identifier: GPL-3.0-or-later
// float_law_fuzzer.cpp -- libFuzzer target: float implementations against the exact law,
// coverage-guided.
//
// Without IMPACTCERT_FUZZ_LAW: the paper's law. Input: 16 bytes, read as two doubles (gamma1-,
// gamma2-); non-finite inputs are outside the domain and skipped. Checks, aborting on failure
// (libFuzzer then saves the input):
//   - fp::S is correctly rounded: 0 ulp from the naive GMP reference (exact rationals);
//   - the fast TwoSum reference of `impactcert fuzz` agrees with the GMP one;
//   - gamma+ >= 0, and the batch form equals the scalar form.
// With IMPACTCERT_FUZZ_LAW=path/to/law.json: that law (c contacts). Input: 8c bytes, c doubles.
// Checks: the fuzzer's fast exact reference equals its GMP path (values and exactness), and
// FloatLaw's output lies within its stated bound of the exact value (exact comparison).
// Built only with -DIMPACTCERT_LIBFUZZER=ON and clang; see README.md beside this file.
#include "fuzz/float_eval.hpp"
#include "fuzz/fuzz.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"

#include <impactcert/float_law.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace {

// The law named by IMPACTCERT_FUZZ_LAW, or null.
struct LawTarget {
    impactcert::Model model;
    impactcert::fuzz::LawReference reference;
    impactcert::FloatLaw float_law;
    explicit LawTarget(const char* path)
        : model(impactcert::load_law_file(path)), reference(model, false, false), float_law(model) {}
};

const LawTarget* law_target() {
    static const LawTarget* target = [] {
        const char* path = std::getenv("IMPACTCERT_FUZZ_LAW");
        return path && *path ? new LawTarget(path) : nullptr;
    }();
    return target;
}

int check_law(const LawTarget& t, const std::uint8_t* data, std::size_t size) {
    using namespace impactcert;
    const std::size_t c = t.model.contacts();
    if (size < c * sizeof(double))
        return 0;
    std::vector<double> x(c);
    std::memcpy(x.data(), data, c * sizeof(double));
    for (double v : x)
        if (!std::isfinite(v))
            return 0;
    fuzz::RefPoint fast, exact;
    t.reference.eval(x.data(), fast);
    t.reference.eval_exact(x.data(), exact);
    bool ok = fast.in_domain == exact.in_domain && fast.values == exact.values;
    for (std::size_t v = 0; ok && v < fast.values; ++v)
        for (std::size_t i = 0; i < c; ++i)
            ok = ok && fuzz::ulp_distance(fast.value[v][i], exact.value[v][i]) == 0 &&
                 fast.exact[v][i] == exact.exact[v][i];
    const auto r = t.float_law.eval(x);
    if (ok && r.ok) {
        const Vector value = t.reference.exact_value(x.data(), r.piece);
        for (std::size_t i = 0; i < c && ok; ++i) {
            Rational err = Rational(r.value[i]) - value[i];
            if (sign_of(err) == Sign::negative)
                err = -err;
            ok = std::isinf(r.bound[i]) || err <= Rational(r.bound[i]);
        }
        ok = ok && t.reference.contains(r.piece, x.data());
    }
    if (!ok) {
        std::fprintf(stderr, "mismatch at");
        for (double v : x)
            std::fprintf(stderr, " %a", v);
        std::fprintf(stderr, "\n");
        std::abort();
    }
    return 0;
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace impactcert;
    if (const LawTarget* t = law_target())
        return check_law(*t, data, size);
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
