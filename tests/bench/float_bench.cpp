// SPDX-License-Identifier: GPL-3.0-or-later
// float_bench.cpp -- Google Benchmark figures for the float law and the fuzzer, each printed
// with the baseline it is compared to, measured in the same run:
//   1. float law throughput, batch (branch-free, vectorisable) vs a plain branchy scalar loop;
//   2. exact-checked fuzz samples per second per core, fast (TwoSum, no GMP) vs naive (every
//      sample through GMP rationals and the exact law).
#include "fuzz/fuzz.hpp"
#include "model/paper_law.hpp"

#include <benchmark/benchmark.h>
#include <impactcert/float_law.hpp>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace {

using namespace impactcert;

struct Inputs {
    std::vector<double> g1, g2;
    explicit Inputs(std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) {
            const auto s = fuzz::make_paper_sample(99, i);
            g1.push_back(s.a[0]);
            g2.push_back(s.a[1]);
        }
    }
};

const Inputs& inputs() {
    static const Inputs in(1 << 14);
    return in;
}

// The plain branchy scalar version: one call per sample to the scalar law, whose switch on the
// cone is a data-dependent branch (random inputs: mispredicted about half the time).
__attribute__((noinline)) void scalar_one(double g1, double g2, double* out) { fp::S(g1, g2, out); }

__attribute__((noinline)) void branchy(const double* g1, const double* g2, double* o1, double* o2, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
        double out[2];
        scalar_one(g1[i], g2[i], out);
        o1[i] = out[0];
        o2[i] = out[1];
    }
}

__attribute__((noinline)) void batch(const double* g1, const double* g2, double* o1, double* o2, std::size_t n) {
    fp::S_batch(g1, g2, o1, o2, n);
}

void BM_law_branchy_scalar(benchmark::State& state) {
    const auto& in = inputs();
    std::vector<double> o1(in.g1.size()), o2(in.g1.size());
    for (auto _ : state) {
        branchy(in.g1.data(), in.g2.data(), o1.data(), o2.data(), in.g1.size());
        benchmark::DoNotOptimize(o1.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * in.g1.size()));
}

void BM_law_batch_branchfree(benchmark::State& state) {
    const auto& in = inputs();
    std::vector<double> o1(in.g1.size()), o2(in.g1.size());
    for (auto _ : state) {
        batch(in.g1.data(), in.g2.data(), o1.data(), o2.data(), in.g1.size());
        benchmark::DoNotOptimize(o1.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * in.g1.size()));
}

// One exact-checked fuzz sample: evaluate the float law, compute the exact reference, compare.
void BM_fuzz_check_fast(benchmark::State& state) {
    const auto& in = inputs();
    std::size_t i = 0, bad = 0;
    for (auto _ : state) {
        double out[2];
        fp::S(in.g1[i], in.g2[i], out);
        const auto ref = fuzz::reference_fast(in.g1[i], in.g2[i]);
        bad += fuzz::ulp_distance(out[0], ref.value[0]) + fuzz::ulp_distance(out[1], ref.value[1]);
        i = (i + 1) & (in.g1.size() - 1);
    }
    benchmark::DoNotOptimize(bad);
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

void BM_fuzz_check_naive_gmp(benchmark::State& state) {
    const auto& in = inputs();
    const Model paper(paper_law());
    std::size_t i = 0, bad = 0;
    for (auto _ : state) {
        double out[2];
        fp::S(in.g1[i], in.g2[i], out);
        const auto ref = fuzz::reference_naive(paper, in.g1[i], in.g2[i]);
        bad += fuzz::ulp_distance(out[0], ref.value[0]) + fuzz::ulp_distance(out[1], ref.value[1]);
        i = (i + 1) & (in.g1.size() - 1);
    }
    benchmark::DoNotOptimize(bad);
    state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}

BENCHMARK(BM_law_branchy_scalar);
BENCHMARK(BM_law_batch_branchfree);
BENCHMARK(BM_fuzz_check_fast);
BENCHMARK(BM_fuzz_check_naive_gmp);

// Records items/s of every run, then prints the ratios.
class RatioReporter : public benchmark::ConsoleReporter {
  public:
    std::map<std::string, double> rate;
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const auto& r : runs) {
            auto it = r.counters.find("items_per_second");
            if (it != r.counters.end())
                rate[r.benchmark_name()] = it->second;
        }
        ConsoleReporter::ReportRuns(runs);
    }
};

} // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    RatioReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    auto ratio = [&](const char* fast, const char* base, double target, const char* what) {
        if (!reporter.rate.count(fast) || !reporter.rate.count(base))
            return;
        const double f = reporter.rate[fast], b = reporter.rate[base];
        std::printf("%s: %.1f M/s vs baseline %.1f M/s = %.1fx (target >= %.0fx: %s)\n", what, f / 1e6, b / 1e6, f / b,
                    target, f / b >= target ? "met" : "MISSED");
    };
    std::printf("\n");
    ratio("BM_law_batch_branchfree", "BM_law_branchy_scalar", 5, "float law, batch vs branchy scalar");
    ratio("BM_fuzz_check_fast", "BM_fuzz_check_naive_gmp", 30, "fuzz exact checks per core, TwoSum vs GMP");
    benchmark::Shutdown();
    return 0;
}
