#include "fuzz.hpp"

#include "float_eval.hpp"
#include "paper_law.hpp"

#include <impactcert/float_law.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <thread>

namespace impactcert::fuzz {

// ---------------------------------------------------------------------------------------------
// Samples

namespace {

std::uint64_t splitmix(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

double from_bits(std::uint64_t bits) {
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

// A finite double with a uniformly random binary exponent over the whole range (subnormals
// included) and a random sign: log-uniform magnitudes.
double log_uniform(std::uint64_t& st) {
    const std::uint64_t r = splitmix(st);
    const std::uint64_t exponent = r % 2047; // 0 (subnormal/zero) .. 2046
    const std::uint64_t mantissa = splitmix(st) & ((1ULL << 52) - 1);
    return from_bits((r >> 63) << 63 | exponent << 52 | mantissa);
}

double nudge(double x, int ulps) {
    const double toward = ulps > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
    for (int k = 0; k < std::abs(ulps); ++k)
        x = std::nextafter(x, toward);
    return x;
}

Point boundary_point(std::uint64_t& st) {
    // A point on or within a few ulps of one of the six boundary rays.
    static const int rays[6][2] = {{1, 0}, {0, 1}, {-1, 1}, {-1, 0}, {0, -1}, {1, -1}};
    const auto& r = rays[splitmix(st) % 6];
    const double t = std::fabs(log_uniform(st));
    Point p{{r[0] * t, r[1] * t}};
    for (double& g : p.g) {
        const int k = static_cast<int>(splitmix(st) % 9) - 4;
        if (g == 0.0) {
            const std::uint64_t pick = splitmix(st) % 4;
            g = pick == 0 ? 0.0 : pick == 1 ? -0.0 : k * std::numeric_limits<double>::denorm_min();
        } else {
            g = nudge(g, k);
        }
    }
    return p;
}

} // namespace

Sample make_sample(std::uint64_t seed, std::uint64_t index) {
    std::uint64_t st = seed * 0xD1B54A32D192ED03ULL ^ (index + 1) * 0x9E3779B97F4A7C15ULL;
    Sample s;
    const std::uint64_t kind = splitmix(st) % 16;
    if (kind < 6) {
        s.kind = "log-uniform";
        s.a = {{log_uniform(st), log_uniform(st)}};
    } else if (kind < 10) {
        s.kind = "boundary-ray";
        s.a = boundary_point(st);
    } else if (kind == 10) {
        s.kind = "signed-zero";
        const double zero = (splitmix(st) & 1) ? 0.0 : -0.0;
        const double other = (splitmix(st) & 1) ? ((splitmix(st) & 1) ? 0.0 : -0.0) : log_uniform(st);
        s.a = (splitmix(st) & 1) ? Point{{zero, other}} : Point{{other, zero}};
    } else if (kind == 11) {
        s.kind = "subnormal";
        auto sub = [&] {
            const double d = from_bits(splitmix(st) & ((1ULL << 52) - 1));
            return (splitmix(st) & 1) ? -d : d;
        };
        s.a = {{sub(), sub()}};
    } else if (kind == 12) {
        s.kind = "overflow-region";
        auto big = [&] {
            const double d = from_bits((2042ULL + splitmix(st) % 5) << 52 | (splitmix(st) & ((1ULL << 52) - 1)));
            return (splitmix(st) & 1) ? -d : d;
        };
        s.a = {{big(), big()}};
    } else {
        s.kind = "close-pair";
        s.a = (splitmix(st) & 1) ? boundary_point(st) : Point{{log_uniform(st), log_uniform(st)}};
        s.pair = true;
        s.b = s.a;
        const int shift = 1 + static_cast<int>(splitmix(st) % 52);
        for (double& g : s.b.g) {
            const double scale = std::max(std::fabs(g), std::fabs(s.a.g[0] + s.a.g[1]));
            const double step = std::ldexp(scale, -shift) * ((splitmix(st) & 1) ? 1 : -1);
            g = std::isfinite(g + step) ? g + step : g;
        }
    }
    return s;
}

// ---------------------------------------------------------------------------------------------
// References

Reference reference_fast(double g1, double g2) {
    // TwoSum: s + e == g1 + g2 exactly, with s = RN(g1 + g2) the correctly rounded sum.
    const double s = g1 + g2;
    const double bv = s - g1;
    const double e = (g1 - (s - bv)) + (g2 - bv);
    // Ball velocities (0, g1, g1 + g2), ordered exactly: sign(g1) orders 0 and g1, sign(s) orders
    // 0 and g1 + g2 (s has the sign of the exact sum), sign(g2) orders g1 and g1 + g2.
    const bool u1_ge_u0 = g1 >= 0, u2_ge_u0 = s >= 0, u2_ge_u1 = g2 >= 0;
    // Sorted u+ = (lo, mid, hi); gamma+ = (mid - lo, hi - mid), each the difference of two of
    // {0, g1, g1 + g2}: +-g1, +-g2 (exact) or +-(g1 + g2) = +-(s + e).
    if (u1_ge_u0 && u2_ge_u1) // 0 <= g1 <= g1+g2
        return {{g1, g2}, {0, 0}, 0};
    if (!u1_ge_u0 && u2_ge_u0) // g1 < 0 <= g1+g2: (g1, 0, g1+g2)
        return {{-g1, s}, {0, e}, 1};
    if (!u1_ge_u0 && u2_ge_u1) // g1 <= g1+g2 < 0: (g1, g1+g2, 0)
        return {{g2, -s}, {0, -e}, 2};
    if (!u1_ge_u0) // g1+g2 < g1 < 0: (g1+g2, g1, 0)
        return {{-g2, -g1}, {0, 0}, 3};
    if (!u2_ge_u0) // g1+g2 < 0 <= g1: (g1+g2, 0, g1)
        return {{-s, g1}, {-e, 0}, 4};
    return {{s, -g2}, {e, 0}, 5}; // 0 <= g1+g2 < g1: (0, g1+g2, g1)
}

Reference reference_naive(const Model& paper, double g1, double g2) {
    const Vector gamma = {Rational(g1), Rational(g2)};
    const auto pieces = paper.pieces_containing(gamma);
    Reference r{};
    r.residual[0] = r.residual[1] = 0;
    r.cone = static_cast<int>(pieces.front());
    const Vector exact = paper.pieces()[pieces.front()].Q * gamma;
    r.value[0] = nearest_double(exact[0]);
    r.value[1] = nearest_double(exact[1]);
    return r;
}

std::uint64_t ulp_distance(double a, double b) {
    auto ordered = [](double x) {
        std::int64_t i;
        std::memcpy(&i, &x, 8);
        return i >= 0 ? i : -(i & 0x7fffffffffffffffLL);
    };
    const std::int64_t x = ordered(a), y = ordered(b);
    return x > y ? static_cast<std::uint64_t>(x) - static_cast<std::uint64_t>(y)
                 : static_cast<std::uint64_t>(y) - static_cast<std::uint64_t>(x);
}

std::string hex(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", x);
    return buf;
}

std::optional<std::uint64_t> parse_seed(std::string_view text, std::string* why) {
    auto fail = [&](const char* reason) -> std::optional<std::uint64_t> {
        if (why)
            *why = reason;
        return std::nullopt;
    };
    if (text.empty() || !std::all_of(text.begin(), text.end(), [](char ch) { return ch >= '0' && ch <= '9'; }))
        return fail("a seed must be a decimal integer in [0, 2^64 - 1] (digits only)");
    std::uint64_t value = 0;
    for (char ch : text) {
        const auto digit = static_cast<std::uint64_t>(ch - '0');
        if (value > (std::numeric_limits<std::uint64_t>::max() - digit) / 10)
            return fail("a seed must be at most 2^64 - 1 = 18446744073709551615");
        value = value * 10 + digit;
    }
    return value;
}

// ---------------------------------------------------------------------------------------------
// The run

namespace {

// |x|_H^2 for the paper's law (H = (1/3) [[2,1],[1,2]]), exactly.
Rational energy(const Rational& x1, const Rational& x2) {
    return (Rational(2) * x1 * x1 + Rational(2) * x1 * x2 + Rational(2) * x2 * x2) / 3;
}

const Rational& growth() { // (1 + 2^-53)^2: the rounding allowance of a correctly rounded result
    static const Rational g = [] {
        Rational u = 1;
        for (int k = 0; k < 53; ++k)
            u /= 2;
        return (1 + u) * (1 + u);
    }();
    return g;
}

long double energy_ld(long double x1, long double x2) { return (2 * x1 * x1 + 2 * x1 * x2 + 2 * x2 * x2) / 3; }

struct Worker {
    const Options& opt;
    Impl impl;
    Summary sum;

    void eval(const Point& p, double* out) const {
        if (impl)
            impl(p.g, out);
        else
            fp::S(p.g[0], p.g[1], out);
    }

    std::string replay(const Sample& s) const {
        std::string cmd = "impactcert eval --float";
        if (!opt.impl_spec.empty())
            cmd += " --impl " + opt.impl_spec;
        cmd += " -- " + hex(s.a.g[0]) + " " + hex(s.a.g[1]);
        if (s.pair)
            cmd += " " + hex(s.b.g[0]) + " " + hex(s.b.g[1]);
        return cmd;
    }

    void record(std::uint64_t index, const char* what, const Sample& s, const double* out, const double* expected) {
        if (sum.examples.size() >= opt.keep)
            return;
        Violation v;
        v.index = index;
        v.what = what;
        v.sample = s;
        v.output[0] = out[0];
        v.output[1] = out[1];
        v.expected[0] = expected[0];
        v.expected[1] = expected[1];
        v.replay = replay(s);
        sum.examples.push_back(std::move(v));
    }

    // Checks one point; returns whether the output was correctly rounded. Fills out.
    bool check_point(std::uint64_t index, const Sample& s, const Point& p, double* out, bool spot) {
        eval(p, out);
        const Reference ref = reference_fast(p.g[0], p.g[1]);
        if (!std::isfinite(out[0]) || !std::isfinite(out[1])) {
            ++sum.non_finite;
            record(index, "non-finite output", s, out, ref.value);
            return false;
        }
        const std::uint64_t e0 = ulp_distance(out[0], ref.value[0]), e1 = ulp_distance(out[1], ref.value[1]);
        sum.max_ulps[0] = std::max(sum.max_ulps[0], e0);
        sum.max_ulps[1] = std::max(sum.max_ulps[1], e1);
        if (out[0] < 0 || out[1] < 0) {
            ++sum.negative;
            record(index, "negative output (gamma+ >= 0 violated)", s, out, ref.value);
        }
        const bool exact = e0 == 0 && e1 == 0;
        if (!exact) {
            // Another cone's formula? Then the implementation chose the wrong cone.
            bool other = false;
            const double g1 = p.g[0], g2 = p.g[1], sm = g1 + g2;
            const double formulas[6][2] = {{g1, g2}, {-g1, sm}, {g2, -sm}, {-g2, -g1}, {-sm, g1}, {sm, -g2}};
            for (int c = 0; c < 6; ++c)
                other = other || (c != ref.cone && ulp_distance(out[0], formulas[c][0]) == 0 &&
                                  ulp_distance(out[1], formulas[c][1]) == 0);
            if (other) {
                ++sum.misclassified;
                record(index, "classification disagreement (another cone's formula)", s, out, ref.value);
            } else if (e0 > opt.max_ulps || e1 > opt.max_ulps) {
                ++sum.not_rounded;
                record(index, "error above the allowed ulps", s, out, ref.value);
            }
        }
        if (!exact || spot) {
            // Exact energy check (GMP): |y|_H^2 <= (1 + 2^-53)^2 |gamma-|_H^2.
            const Rational ey = energy(Rational(out[0]), Rational(out[1]));
            if (ey > growth() * energy(Rational(p.g[0]), Rational(p.g[1]))) {
                ++sum.energy;
                record(index, "energy increase beyond rounding", s, out, ref.value);
            }
        }
        return exact;
    }

    void run_range(std::uint64_t begin, std::uint64_t end, std::atomic<std::uint64_t>& done,
                   const std::atomic<bool>& stop) {
        for (std::uint64_t i = begin; i < end; ++i) {
            if ((i & 4095) == 0) {
                if (stop.load(std::memory_order_relaxed))
                    return;
            }
            const Sample s = make_sample(opt.seed, i);
            double ya[2], yb[2];
            const bool spot = (i & 1023) == 0;
            const bool exact_a = check_point(i, s, s.a, ya, spot);
            ++sum.samples;
            if (s.pair) {
                ++sum.pairs;
                const bool exact_b = check_point(i, s, s.b, yb, spot);
                // Correctly rounded outputs cannot violate the bound (proofs/README.md, fuzzing);
                // otherwise, and on spot checks, measure it.
                if (!(exact_a && exact_b) || spot) {
                    const long double da1 = s.a.g[0] - static_cast<long double>(s.b.g[0]);
                    const long double da2 = s.a.g[1] - static_cast<long double>(s.b.g[1]);
                    const long double lhs = std::sqrt(energy_ld(static_cast<long double>(ya[0]) - yb[0],
                                                                static_cast<long double>(ya[1]) - yb[1]));
                    const long double rhs = std::sqrt(energy_ld(da1, da2));
                    const long double u = std::ldexp(1.0L, -53);
                    const long double slack = u * (std::sqrt(energy_ld(s.a.g[0], s.a.g[1])) +
                                                   std::sqrt(energy_ld(s.b.g[0], s.b.g[1])));
                    if (lhs > (rhs + slack) * (1 + 1e-15L)) {
                        ++sum.nonexpansive;
                        record(i, "non-expansivity violated beyond rounding", s, ya, yb);
                    }
                }
            }
            if ((i & 1023) == 1023)
                done.fetch_add(1024, std::memory_order_relaxed);
        }
    }
};

} // namespace

Summary run(const Options& options, Impl impl, const std::function<void(std::uint64_t)>& progress) {
    const unsigned jobs = std::max(1u, options.jobs);
    std::vector<Worker> workers;
    for (unsigned j = 0; j < jobs; ++j)
        workers.push_back(Worker{options, impl, {}});
    std::atomic<std::uint64_t> done{0};
    std::atomic<bool> stop{false};
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::thread> threads;
    const std::uint64_t n = options.samples;
    for (unsigned j = 0; j < jobs; ++j) {
        const std::uint64_t begin = n * j / jobs, end = n * (j + 1) / jobs;
        threads.emplace_back([&, j, begin, end] { workers[j].run_range(begin, end, done, stop); });
    }
    // Coordinate: progress and the time limit.
    std::atomic<unsigned> finished{0};
    std::thread watcher([&] {
        for (;;) {
            std::this_thread::sleep_for(std::chrono::milliseconds(200));
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (options.seconds > 0 && elapsed >= options.seconds)
                stop = true;
            if (finished.load() == jobs)
                return;
            if (progress)
                progress(done.load());
        }
    });
    for (auto& t : threads)
        t.join();
    finished = jobs;
    watcher.join();
    Summary total;
    total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (auto& w : workers) {
        const Summary& s = w.sum;
        total.samples += s.samples;
        total.pairs += s.pairs;
        for (int k = 0; k < 2; ++k)
            total.max_ulps[k] = std::max(total.max_ulps[k], s.max_ulps[k]);
        total.misclassified += s.misclassified;
        total.not_rounded += s.not_rounded;
        total.negative += s.negative;
        total.energy += s.energy;
        total.nonexpansive += s.nonexpansive;
        total.non_finite += s.non_finite;
        for (const auto& v : s.examples)
            if (total.examples.size() < options.keep)
                total.examples.push_back(v);
    }
    std::sort(total.examples.begin(), total.examples.end(),
              [](const Violation& a, const Violation& b) { return a.index < b.index; });
    return total;
}

} // namespace impactcert::fuzz
