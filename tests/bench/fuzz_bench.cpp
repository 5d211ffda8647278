// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_bench.cpp -- fuzzing throughput against its honest naive baseline, measured in one run
// (printed by scripts/bench):
//   - for the paper's law and for proofs/newton4/law.json: samples per second per core of the
//     fuzzer (generators, implementation, exact reference, checks: fuzz::run with one job) and
//     of a naive cross-check of the same samples and implementation (every point converted to
//     GMP rationals, classified and evaluated exactly, rounded to nearest, compared in ulps);
//   - the --impl-cmd protocol with the cheapest program (tests/impls/echo_impl.cpp), all cores;
//   - consistency fuzzing (no law, 3 balls in ball velocities) through the same program;
//   - consistency fuzzing of 4 balls: the protocol alone, an in-process C ABI implementation,
//     and the same with the exact reference law (--reference).
// Usage: impactcert_fuzz_bench SOURCE_DIR NEWTON4_IMPLS.so ECHO_PROGRAM
#include "fuzz/consistency.hpp"
#include "fuzz/fuzz.hpp"
#include "fuzz/fuzz_mutants.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"

#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

using namespace impactcert;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The naive cross-check: same samples, same implementation, GMP for every point.
double naive_rate(const fuzz::LawReference& ref, fuzz::Implementation& impl, std::uint64_t samples) {
    const fuzz::Generator gen(ref);
    const std::size_t m = ref.in_dim();
    std::uint64_t bad = 0;
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t i = 0; i < samples; ++i) {
        fuzz::Sample s;
        gen.make(7, i, s);
        for (const double* x : {s.a, s.b}) {
            if (x == s.b && !s.pair)
                break;
            double y[fuzz::kMaxDim];
            fuzz::ImplStatus st;
            impl.eval(x, y, nullptr, 1, &st);
            fuzz::RefPoint r;
            ref.eval_exact(x, r);
            for (std::size_t j = 0; j < m && r.values; ++j)
                bad += fuzz::ulp_distance(y[j], r.value[0][j]) > 0;
        }
    }
    const double t = seconds_since(start);
    std::fprintf(stderr, "%s", bad == 12345 ? " " : "");
    return static_cast<double>(samples) / t;
}

double fuzz_rate(const fuzz::LawReference& ref, const fuzz::Implementation& impl, std::uint64_t samples,
                 unsigned jobs, const fuzz::Properties& props) {
    fuzz::Options o;
    o.seed = 7;
    o.samples = samples;
    o.jobs = jobs;
    o.tolerance = fuzz::Tolerance::relative;
    o.max_rel_error = 1e-12;
    const auto sum = fuzz::run(o, ref, impl, props, nullptr);
    return static_cast<double>(sum.samples) / sum.seconds;
}

void compare(const char* name, const Model& model, const fuzz::Implementation& impl, std::uint64_t naive_samples) {
    const fuzz::LawReference ref(model, false, true);
    const fuzz::Properties props{true, true, true};
    auto naive_impl = impl.clone();
    const double naive = naive_rate(ref, *naive_impl, naive_samples);
    const double fast = fuzz_rate(ref, impl, 20 * naive_samples, 1, props);
    std::printf("%-28s fuzzer %8.3f M samples/s/core   naive GMP cross-check %7.3f M/s   ratio %6.1fx (target >= 30x)\n",
                name, fast / 1e6, naive / 1e6, fast / naive);
}

} // namespace

int main(int argc, char** argv) {
    if (argc != 4) {
        std::fprintf(stderr, "usage: impactcert_fuzz_bench SOURCE_DIR NEWTON4_IMPLS.so ECHO_PROGRAM\n");
        return 2;
    }
    const std::string source = argv[1];
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    std::printf("fuzz throughput (%u cores on this machine; per-core figures use one job)\n", cores);
    const Model paper(paper_law());
    compare("paper's law (built-in)", paper, *fuzz::builtin_paper(false), 200000);
    const Model newton4(load_law_file(source + "/proofs/newton4/law.json"));
    compare("newton4 (newton4_sorted)", newton4, *fuzz::load_symbol(std::string(argv[2]) + ":newton4_sorted", 3, 3), 20000);
    // The law-mode sampler: the gate of docs/fuzzing.md on the law's plain evaluation, with a
    // --range (log-uniform scales drawn per sample) against the whole double range (baseline, this
    // run); then the time to the first kill of three mutants, with the gate stopping at its first
    // failing chunk as `fuzz --mutants` does.
    {
        const fuzz::LawReference r4(newton4, false, true);
        const fuzz::Properties p4{true, true, true};
        const auto control = fuzz::plain_law(newton4, fuzz::Mutation{});
        fuzz::Options g;
        g.seed = 7;
        g.samples = 400000;
        g.tolerance = fuzz::Tolerance::relative;
        g.max_rel_error = 1e-12;
        g.allow_extreme = true;
        const auto whole = fuzz::run(g, r4, *control, p4, nullptr);
        g.range_lo = 1e-150;
        g.range_hi = 1e150;
        const auto ranged = fuzz::run(g, r4, *control, p4, nullptr);
        const double rw = static_cast<double>(whole.samples) / whole.seconds, rr = static_cast<double>(ranged.samples) / ranged.seconds;
        std::printf("%-28s %8.3f M samples/s/core, --range 1e-150..1e150 %8.3f M/s: %.2fx the whole-range baseline (target >= 0.9x)\n",
                    "newton4 gate, plain control", rw / 1e6, rr / 1e6, rr / rw);
        for (const char* id : {"dead-zone:1e-06", "slow-contact:1e-09", "float32"}) {
            const auto mutant = fuzz::plain_law(newton4, fuzz::parse_mutation(id, newton4));
            fuzz::Options k = g;
            k.range_lo = k.range_hi = 0;
            k.samples = 10000000;
            k.stop_on_failure = true;
            const auto sum = fuzz::run(k, r4, *mutant, p4, nullptr);
            std::printf("%-28s first kill after %llu samples, %.4f s (%s)\n", (std::string("mutant ") + id).c_str(),
                        static_cast<unsigned long long>(sum.samples), sum.seconds,
                        sum.fails(true) ? "killed" : "NOT killed");
        }
    }
    // --impl-cmd with the echo program: protocol overhead only (every answer is "wrong").
    const fuzz::LawReference ref(newton4, false, true);
    const auto echo = fuzz::command(argv[3], 3, 3, 10);
    fuzz::Options o;
    o.seed = 7;
    o.samples = 2000000;
    o.jobs = cores;
    o.keep = 1;
    o.tolerance = fuzz::Tolerance::relative;
    o.max_rel_error = 1e300; // nothing to report: measure the protocol, not the diagnostics
    const auto start = std::chrono::steady_clock::now();
    const auto sum = fuzz::run(o, ref, *echo, fuzz::Properties{}, nullptr);
    const double t = seconds_since(start);
    std::printf("%-28s %8.3f M samples/s with %u jobs (%llu samples in %.2f s; goal >= 1 M/s)\n",
                "--impl-cmd echo (newton4)", static_cast<double>(sum.samples) / t / 1e6, cores,
                static_cast<unsigned long long>(sum.samples), t);
    // Consistency fuzzing (no law) through the same program: sampling, the protocol and the exact
    // checks of every answer (the echo answer u+ = u- breaks kinematic on every sample, so the
    // report path is exercised too). Baseline: the line above, the protocol alone.
    const Mechanics three = make_mechanics(chain_system({Rational(1), Rational(1), Rational(1)}, Walls::none));
    fuzz::ConsistencyOptions c;
    c.seed = 7;
    c.samples = 200000;
    c.jobs = cores;
    c.keep = 1;
    c.velocities = true;
    const auto cstart = std::chrono::steady_clock::now();
    const auto csum = fuzz::run_consistency(three, c, *echo, nullptr);
    const double ct = seconds_since(cstart);
    std::printf("%-28s %8.3f M samples/s with %u jobs (%llu samples in %.2f s, %llu kinematic findings; baseline: the line above)\n",
                "consistency --impl-cmd echo", static_cast<double>(csum.samples) / ct / 1e6, cores,
                static_cast<unsigned long long>(csum.samples), ct,
                static_cast<unsigned long long>(csum.properties[static_cast<std::size_t>(fuzz::Property::kinematic)].count));
    // Consistency fuzzing of a 4-ball chain in contact velocities (proofs/newton4: the elastic law,
    // S = sort): the protocol alone (the echo program through --impl-cmd, the baseline of this
    // run), a trivial in-process implementation through the C ABI (newton4_sorted, consistent:
    // every sample checked, nothing found), and the same with the exact reference law
    // (--reference proofs/newton4/law.json: each sample also evaluated exactly by the law).
    {
        const Mechanics four = make_mechanics(newton4.system());
        fuzz::ConsistencyOptions f;
        f.seed = 7;
        f.samples = 200000;
        f.jobs = cores;
        f.keep = 1;
        f.max_rel_error = 1e-9; // the CLI's default tolerance
        f.velocities = false;   // contact velocities: the law's and the symbol's space
        const auto sorted = fuzz::load_symbol(std::string(argv[2]) + ":newton4_sorted", 3, 3);
        struct Row {
            const char* name;
            const fuzz::Implementation* impl;
            const Model* reference;
        };
        double baseline = 0;
        for (const Row& row : {Row{"consistency 4 balls: echo", echo.get(), nullptr},
                               Row{"  in-process C ABI (sorted)", sorted.get(), nullptr},
                               Row{"  + exact reference law", sorted.get(), &newton4}}) {
            f.reference = row.reference;
            const auto t0 = std::chrono::steady_clock::now();
            const auto r = fuzz::run_consistency(four, f, *row.impl, nullptr);
            const double rate = static_cast<double>(r.samples) / seconds_since(t0);
            if (baseline == 0)
                baseline = rate;
            std::printf("%-28s %8.3f M samples/s with %u jobs (%llu samples, %llu findings)%s%.2fx the protocol-only baseline\n",
                        row.name, rate / 1e6, cores, static_cast<unsigned long long>(r.samples),
                        static_cast<unsigned long long>(r.violations()), "; ", rate / baseline);
        }
    }
    // With friction (SPEC section 9): a spinning disk on rough ground (x, y, theta; one rough
    // contact), the same echo program, against the same disk without friction (baseline, this run).
    auto disk = [](bool rough) {
        System s;
        s.name = rough ? "rough-disk" : "smooth-disk";
        s.masses = {Rational(1), Rational(1), Rational(1, 2)};
        Matrix W(3, 1);
        W(1, 0) = 1;
        s.W = W;
        if (rough)
            s.friction.push_back(FrictionDecl{0, Rational(1, 2), {Vector{Rational(1), Rational(0), Rational(1)}}, Rational(0)});
        return make_mechanics(s);
    };
    for (const bool rough : {false, true}) {
        const Mechanics m = disk(rough);
        const auto rough_start = std::chrono::steady_clock::now();
        const auto dsum = fuzz::run_consistency(m, c, *echo, nullptr);
        const double dt = seconds_since(rough_start);
        std::printf("%-28s %8.3f M samples/s with %u jobs (%llu samples in %.2f s)%s\n",
                    rough ? "consistency, rough disk" : "consistency, smooth disk", static_cast<double>(dsum.samples) / dt / 1e6,
                    cores, static_cast<unsigned long long>(dsum.samples), dt,
                    rough ? "; baseline: the smooth disk above (friction cone and Coulomb's law added)" : "");
    }
    return 0;
}
