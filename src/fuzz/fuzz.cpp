// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/fuzz.hpp"

#include "exact/exact_double.hpp"
#include "base/splitmix.hpp"

#include "exact/eft.hpp"
#include "fuzz/float_eval.hpp"
#include "model/paper_law.hpp"
#include "base/parallel.hpp"

#include <algorithm>
#include <cfenv>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace impactcert::fuzz {

// ---------------------------------------------------------------------------------------------
// Samples

namespace {


double from_bits(std::uint64_t bits) {
    double d;
    std::memcpy(&d, &bits, sizeof d);
    return d;
}

bool coin(std::uint64_t& st) { return splitmix(st) & 1; }

// A finite double with a uniformly random binary exponent over the whole range (subnormals
// included) and a random sign: log-uniform magnitudes.
double log_uniform(std::uint64_t& st) {
    const std::uint64_t r = splitmix(st);
    const std::uint64_t exponent = r % 2047; // 0 (subnormal/zero) .. 2046
    const std::uint64_t mantissa = splitmix(st) & ((1ULL << 52) - 1);
    return from_bits((r >> 63) << 63 | exponent << 52 | mantissa);
}

double nudge(double x, int ulps) {
    const double toward = ulps > 0 ? INFINITY : -INFINITY;
    for (int k = 0; k < std::abs(ulps); ++k)
        x = std::nextafter(x, toward);
    return x;
}

double max_abs(const double* p, std::size_t m) {
    double big = 0;
    for (std::size_t j = 0; j < m; ++j)
        big = std::fmax(big, std::fabs(p[j]));
    return big;
}

// Scales p by a power of two so that its largest component has binary exponent `e`.
void rescale(double* p, std::size_t m, int e) {
    const double big = max_abs(p, m);
    if (big == 0 || !std::isfinite(big))
        return;
    const int shift = e - std::ilogb(big);
    for (std::size_t j = 0; j < m; ++j)
        p[j] = eft::ldexp_fast(p[j], shift);
}

} // namespace

Generator::Generator(const LawReference& reference, double lo, double hi)
    : g_(reference.geometry()), dim_(reference.in_dim()), lo_(lo), hi_(hi) {
    // The deterministic prefix, most telling first, at most kMaxPrefix probes (a law of many
    // pieces gets the rest of its pieces from the stratified random kind "piece").
    constexpr std::size_t kMaxPrefix = 1 << 14;
    const std::size_t pieces = g_.piece_rays.size(), rays = g_.rays.size(), facets = g_.facet_rays.size();
    auto add = [&](Probe::Kind kind, unsigned where, std::size_t id, int side = 0) {
        if (prefix_.size() < kMaxPrefix)
            prefix_.push_back({kind, static_cast<unsigned char>(where), static_cast<std::uint32_t>(id),
                               static_cast<signed char>(side)});
    };
    add(Probe::rest, 1, 0);
    for (std::size_t t = 0; t < 2; ++t)
        add(Probe::tie, 1, t);
    for (std::size_t p = 0; p < pieces; ++p)
        add(Probe::piece, 1, p);
    for (std::size_t f = 0; f < facets; ++f) {
        add(Probe::facet_side, 1, f, 1);
        add(Probe::facet_side, 1, f, -1);
    }
    for (std::size_t r = 0; r < rays; ++r)
        add(Probe::ray, 1, r);
    for (unsigned where : {2u, 0u}) {
        for (std::size_t p = 0; p < pieces; ++p)
            add(Probe::piece, where, p);
        for (std::size_t f = 0; f < facets; ++f)
            add(Probe::straddle, where, f);
        for (std::size_t r = 0; r < rays; ++r)
            add(Probe::ray, where, r);
    }
    for (std::size_t f = 0; f < facets; ++f)
        add(Probe::facet, 1, f);
}

const std::vector<std::string>& Generator::kinds() {
    static const std::vector<std::string> k = {"log-uniform", "common-scale", "ray",       "facet",
                                               "near-facet",  "piece",        "near-tie",  "signed-zero",
                                               "subnormal",   "overflow-region", "close-pair", "prefix"};
    return k;
}

namespace {

// The power of two 2^k for a point whose largest component is `top` (> 0, finite): the feasible k
// put top 2^k in [lo, hi]; `where` 0 takes the smallest, 2 the largest, 1 the middle one, and 3 one
// drawn uniformly by `draw`. Without a feasible k (hi < 2 lo): nothing.
std::optional<int> range_power(double top, double lo, double hi, int where, std::uint64_t draw) {
    int e_top = 0, e_hi = 0, e_lo = 0;
    std::frexp(top, &e_top); // top in [2^(e_top-1), 2^e_top)
    std::frexp(hi, &e_hi);
    std::frexp(lo, &e_lo);
    int k_max = e_hi - e_top;
    while (eft::ldexp_fast(top, k_max) > hi)
        --k_max;
    while (eft::ldexp_fast(top, k_max + 1) <= hi)
        ++k_max;
    int k_min = e_lo - e_top;
    while (eft::ldexp_fast(top, k_min) < lo)
        ++k_min;
    while (k_min > -2200 && eft::ldexp_fast(top, k_min - 1) >= lo)
        --k_min;
    if (k_min > k_max)
        return std::nullopt;
    switch (where) {
    case 0: return k_min;
    case 1: return k_min + (k_max - k_min) / 2;
    case 2: return k_max;
    default: return k_min + static_cast<int>((draw >> 1) % static_cast<std::uint64_t>(k_max - k_min + 1)); // bit 0 is the caller's flag
    }
}

// Multiplies by 2^k in two steps (no overflow on the way; the final value may round if it is
// subnormal).
double times_power(double x, int k) { return eft::ldexp_fast(eft::ldexp_fast(x, k / 2), k - k / 2); }

} // namespace

// A probe of the prefix, near unit scale, then placed at the bottom, middle or top of the range
// (without a range: of the doubles, down to the subnormals and up to the overflow limit).
void Generator::make_probe(const Probe& probe, Sample& s) const {
    const std::size_t m = dim_;
    for (std::size_t j = 0; j < m; ++j)
        s.a[j] = s.b[j] = 0;
    s.kind = "prefix";
    s.pair = false;
    s.facet = -1;
    // A positive combination of rays, each first brought to unit scale (rays near the double
    // range's ends would overflow in the sum).
    auto combine = [&](const std::vector<std::size_t>& ids, double* p) {
        for (std::size_t r : ids) {
            double ray[kMaxDim];
            for (std::size_t j = 0; j < m; ++j)
                ray[j] = g_.rays[r][j];
            rescale(ray, m, 0);
            for (std::size_t j = 0; j < m; ++j)
                p[j] += ray[j];
        }
    };
    auto unit = [&](double* p) { rescale(p, m, 0); };
    switch (probe.kind) {
    case Probe::rest:
        return;
    case Probe::tie: // every component -1; or alternating -1, +1
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = probe.id == 0 || j % 2 == 0 ? -1.0 : 1.0;
        break;
    case Probe::piece:
        combine(g_.piece_rays[probe.id], s.a);
        unit(s.a);
        break;
    case Probe::ray:
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = g_.rays[probe.id][j];
        unit(s.a);
        break;
    case Probe::facet:
    case Probe::facet_side:
    case Probe::straddle: {
        s.facet = static_cast<long>(probe.id);
        combine(g_.facet_rays[probe.id], s.a);
        unit(s.a);
        if (probe.kind == Probe::facet)
            break;
        const double delta = 0x1p-20 * max_abs(s.a, m);
        const auto& normal = g_.facet_normals[probe.id];
        if (probe.kind == Probe::facet_side) {
            for (std::size_t j = 0; j < m; ++j)
                s.a[j] += probe.side * delta * normal[j];
        } else {
            s.pair = true;
            for (std::size_t j = 0; j < m; ++j) {
                s.b[j] = s.a[j] - delta * normal[j];
                s.a[j] += delta * normal[j];
            }
        }
        break;
    }
    }
    for (std::size_t j = 0; j < m; ++j) { // finite, as every sample (no non-finite input reaches the reference)
        if (!std::isfinite(s.a[j]))
            s.a[j] = 0;
        if (!std::isfinite(s.b[j]))
            s.b[j] = s.a[j];
    }
    double top = max_abs(s.a, m);
    if (s.pair)
        top = std::fmax(top, max_abs(s.b, m));
    if (!(top > 0) || !std::isfinite(top))
        return;
    const double lo = hi_ > 0 ? lo_ : 0x1p-1040, hi = hi_ > 0 ? hi_ : std::numeric_limits<double>::max();
    // Without a range the middle is the unit scale itself (the probe as made, |largest| in [1, 2)).
    const auto k = hi_ > 0 || probe.where != 1 ? range_power(top, lo, hi, probe.where, 0) : std::optional<int>(0);
    if (!k)
        return fit_range(s, m, lo_, hi_, 0);
    for (std::size_t j = 0; j < m; ++j) {
        s.a[j] = times_power(s.a[j], *k);
        s.b[j] = times_power(s.b[j], *k);
        if (hi_ > 0 && std::fabs(s.a[j]) < lo_)
            s.a[j] = 0.0;
        if (hi_ > 0 && std::fabs(s.b[j]) < lo_)
            s.b[j] = 0.0;
    }
}

// A point of the facet (a non-negative combination of its rays; in ball velocities plus a
// multiple of the directions every cone contains), near unit scale. With integer rays the
// coefficients are small integers and the point lies exactly on the facet; `scale` receives a
// random binary exponent for the caller to apply (exact for such points away from the
// subnormal range).
void Generator::facet_point(std::uint64_t& st, std::size_t facet, double* p, int& scale) const {
    for (std::size_t j = 0; j < dim_; ++j)
        p[j] = 0;
    const auto& rays = g_.facet_rays[facet];
    for (std::size_t r : rays) {
        double coef;
        if (g_.integer_rays) {
            coef = static_cast<double>(below(st, 4) == 0 ? 0 : below(st, 64));
        } else {
            coef = below(st, 4) == 0 ? 0 : eft::ldexp_fast(1.0 + static_cast<double>(below(st, 1u << 20)) / (1u << 20),
                                                       -static_cast<int>(below(st, 40)));
        }
        for (std::size_t j = 0; j < dim_; ++j)
            p[j] += coef * g_.rays[r][j];
    }
    for (const auto& k : g_.kernel) {
        const double t = static_cast<double>(static_cast<std::int64_t>(below(st, 129)) - 64);
        for (std::size_t j = 0; j < dim_; ++j)
            p[j] += t * k[j];
    }
    scale = static_cast<int>(below(st, 1900)) - 950;
}

void Generator::make(std::uint64_t seed, std::uint64_t index, Sample& s) const {
    if (index < prefix_.size())
        return make_probe(prefix_[index], s);
    std::uint64_t st = seed * 0xD1B54A32D192ED03ULL ^ (index + 1) * 0x9E3779B97F4A7C15ULL;
    const std::size_t m = dim_;
    s.pair = false;
    s.facet = -1;
    // The generator kind is drawn per block of 16 consecutive indices (still a pure function of
    // seed and index): runs of one kind keep the branches of the generator, the implementation
    // and the reference predictable, which makes the whole loop much faster.
    std::uint64_t block = seed * 0x9E3779B97F4A7C15ULL ^ ((index >> 4) + 1) * 0xD1B54A32D192ED03ULL;
    const std::uint64_t pick = below(block, 32);
    const std::size_t facets = g_.facet_rays.size();
    auto near_facet = [&](double* p, std::size_t& facet, double& delta) {
        facet = below(st, facets);
        s.facet = static_cast<long>(facet);
        int scale;
        facet_point(st, facet, p, scale);
        for (std::size_t j = 0; j < m; ++j)
            p[j] = eft::ldexp_fast(p[j], scale);
        const double size = max_abs(p, m);
        // A distance from one ulp of the point's scale up to the scale itself, log-uniformly.
        delta = eft::ldexp_fast(size > 0 ? size : eft::ldexp_fast(1.0, scale), -static_cast<int>(below(st, 54))) *
                (coin(st) ? 1 : -1);
        for (std::size_t j = 0; j < m; ++j)
            p[j] += delta * g_.facet_normals[facet][j];
    };
    if (pick < 5) {
        s.kind = "log-uniform";
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = below(st, 8) == 0 ? (coin(st) ? 0.0 : -0.0) : log_uniform(st);
    } else if (pick < 8) {
        s.kind = "common-scale";
        const int e = static_cast<int>(below(st, 2000)) - 1000;
        for (std::size_t j = 0; j < m; ++j) {
            const double mant = 1.0 + static_cast<double>(splitmix(st) >> 12) * 0x1p-52;
            s.a[j] = below(st, 6) == 0 ? 0.0 : eft::ldexp_fast(mant, e - static_cast<int>(below(st, 64))) * (coin(st) ? 1 : -1);
        }
    } else if (pick < 10) {
        s.kind = "ray";
        const auto& r = g_.rays[below(st, g_.rays.size())];
        const double t = eft::ldexp_fast(1.0 + static_cast<double>(splitmix(st) >> 12) * 0x1p-52,
                                    static_cast<int>(below(st, 2000)) - 1040);
        for (std::size_t j = 0; j < m; ++j) {
            s.a[j] = r[j] * t;
            if (!std::isfinite(s.a[j]))
                s.a[j] = std::copysign(std::numeric_limits<double>::max(), r[j]);
            const int k = coin(st) ? 0 : static_cast<int>(below(st, 9)) - 4;
            if (s.a[j] != 0)
                s.a[j] = nudge(s.a[j], k);
            else if (k != 0) // off the ray by a few ulps of the point's scale (rarely: of the subnormals)
                s.a[j] = below(st, 16) == 0 ? k * std::numeric_limits<double>::denorm_min()
                                             : k * eft::ldexp_fast(std::fabs(t), -52 - static_cast<int>(below(st, 8)));
            if (!std::isfinite(s.a[j]))
                s.a[j] = 0;
        }
    } else if (pick < 12) {
        s.kind = "facet";
        int scale;
        s.facet = static_cast<long>(below(st, facets));
        facet_point(st, static_cast<std::size_t>(s.facet), s.a, scale);
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = eft::ldexp_fast(s.a[j], scale);
    } else if (pick < 16) {
        s.kind = "near-facet";
        std::size_t f;
        double delta;
        near_facet(s.a, f, delta);
    } else if (pick < 20) {
        // Stratified over the pieces: a positive combination of one piece's rays, with weights
        // spread over 2^0..2^-60 so that thin cones and the corners of wide ones are reached.
        s.kind = "piece";
        const auto& ids = g_.piece_rays[below(st, g_.piece_rays.size())];
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = 0;
        for (std::size_t r : ids) {
            const double w = eft::ldexp_fast(1.0 + static_cast<double>(splitmix(st) >> 12) * 0x1p-52,
                                             -static_cast<int>(below(st, 4) == 0 ? below(st, 61) : below(st, 4)));
            for (std::size_t j = 0; j < m; ++j)
                s.a[j] += w * g_.rays[r][j];
        }
        for (const auto& k : g_.kernel) {
            const double t = static_cast<double>(static_cast<std::int64_t>(below(st, 129)) - 64);
            for (std::size_t j = 0; j < m; ++j)
                s.a[j] += t * k[j];
        }
        rescale(s.a, m, static_cast<int>(below(st, 1900)) - 950);
    } else if (pick < 22) {
        // Near-ties: one component equal to another (or its negative) up to a relative difference
        // of 2^-1 .. 2^-53 (an ulp): slow relative motion beside fast motion.
        s.kind = "near-tie";
        const int e = static_cast<int>(below(st, 1900)) - 950;
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = eft::ldexp_fast(1.0 + static_cast<double>(splitmix(st) >> 12) * 0x1p-52,
                                     e - static_cast<int>(below(st, 4))) * (coin(st) ? 1 : -1);
        if (m >= 2) {
            const std::size_t i = below(st, m), j = (i + 1 + below(st, m - 1)) % m;
            s.a[j] = s.a[i] * (coin(st) ? 1 : -1);
            s.a[j] = nudge(s.a[j], coin(st) ? 1 : -1) ;
            if (coin(st))
                s.a[j] = s.a[i] * (coin(st) ? 1 : -1) * (1 + eft::ldexp_fast(coin(st) ? 1.0 : -1.0, -1 - static_cast<int>(below(st, 53))));
        }
    } else if (pick < 24) {
        s.kind = "signed-zero";
        int scale;
        facet_point(st, below(st, facets), s.a, scale);
        for (std::size_t j = 0; j < m; ++j)
            s.a[j] = coin(st) ? (coin(st) ? 0.0 : -0.0) : eft::ldexp_fast(s.a[j], scale);
    } else if (pick < 25) {
        s.kind = "subnormal";
        if (coin(st)) {
            for (std::size_t j = 0; j < m; ++j)
                s.a[j] = from_bits(splitmix(st) & ((1ULL << 52) - 1)) * (coin(st) ? 1 : -1);
        } else {
            int scale;
            facet_point(st, below(st, facets), s.a, scale);
            rescale(s.a, m, -1023 - static_cast<int>(below(st, 40)));
        }
    } else if (pick < 27) {
        s.kind = "overflow-region";
        if (coin(st)) {
            for (std::size_t j = 0; j < m; ++j)
                s.a[j] = log_uniform(st);
        } else {
            int scale;
            facet_point(st, below(st, facets), s.a, scale);
        }
        rescale(s.a, m, 1015 + static_cast<int>(below(st, 9)));
    } else {
        s.kind = "close-pair";
        s.pair = true;
        std::size_t f;
        double delta;
        near_facet(s.a, f, delta);
        if (coin(st)) { // the mirror image across the facet: the pair straddles it
            for (std::size_t j = 0; j < m; ++j)
                s.b[j] = s.a[j] - 2 * delta * g_.facet_normals[f][j];
        } else { // a small step in a random direction
            const double size = std::fmax(max_abs(s.a, m), std::numeric_limits<double>::denorm_min());
            const int shift = 1 + static_cast<int>(below(st, 52));
            for (std::size_t j = 0; j < m; ++j) {
                const double step = eft::ldexp_fast(size, -shift) * (static_cast<double>(below(st, 2001)) - 1000) / 1000;
                s.b[j] = s.a[j] + step;
            }
        }
    }
    // Every input is finite, whatever the geometry (rays scaled by up to 2^950 overflow, and
    // inf - inf is NaN): an overflowed component is clamped to the largest double, a NaN is 0,
    // and the partner of a pair falls back on the (now finite) point. No non-finite double may
    // reach the exact reference (exact_double.hpp).
    for (std::size_t j = 0; j < m; ++j)
        if (std::isnan(s.a[j]))
            s.a[j] = 0;
        else if (std::isinf(s.a[j]))
            s.a[j] = std::copysign(std::numeric_limits<double>::max(), s.a[j]);
    if (s.pair)
        for (std::size_t j = 0; j < m; ++j)
            if (!std::isfinite(s.b[j]))
                s.b[j] = s.a[j];
    fit_range(s, m, lo_, hi_, splitmix(st) | 1);
}

void fit_range(Sample& s, std::size_t dim, double lo, double hi, std::uint64_t draw) {
    if (!(hi > 0))
        return;
    double top = 0;
    for (std::size_t j = 0; j < dim; ++j) {
        top = std::max(top, std::fabs(s.a[j]));
        if (s.pair)
            top = std::max(top, std::fabs(s.b[j]));
    }
    if (!(top > 0) || !std::isfinite(top))
        return; // at rest (or not finite: the generators never make such a sample)
    // A power of two 2^k with top 2^k in [lo, hi]: drawn uniformly among those that fit (draw != 0),
    // or the largest (draw == 0).
    const auto k = range_power(top, lo, hi, draw ? 3 : 2, draw);
    // No power of two fits (hi < 2 lo): a rounded scale into the middle of the range instead,
    // the largest component kept at least lo (the sample is then not an exact multiple).
    const bool power = k.has_value();
    const double mid = lo / 2 + hi / 2;
    auto fit = [&](double* v) {
        for (std::size_t j = 0; j < dim; ++j) {
            double x = power ? times_power(v[j], *k) // two steps: no overflow on the way
                             : v[j] / top * mid;    // |v[j] / top| <= 1: no overflow
            if (!power && std::fabs(v[j]) == top)
                x = std::copysign(std::clamp(std::fabs(x), lo, hi), x);
            if (std::fabs(x) < lo)
                x = 0.0;
            else if (std::fabs(x) > hi)
                x = std::copysign(hi, x);
            v[j] = x;
        }
    };
    fit(s.a);
    if (s.pair)
        fit(s.b);
}

bool extreme_input(const double* x, std::size_t dim) {
    const double big = max_abs(x, dim);
    return big > 0x1p500 || (big > 0 && big < 0x1p-500) || !(big == big);
}

Sample make_paper_sample(std::uint64_t seed, std::uint64_t index) {
    static const Model paper(paper_law());
    static const LawReference reference(paper, false, true);
    static const Generator generator(reference);
    Sample s;
    generator.make(seed, index, s);
    return s;
}

// ---------------------------------------------------------------------------------------------
// The paper's law, second route

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

// ---------------------------------------------------------------------------------------------
// The run

namespace {

// The law's metric in double (H for contact velocities, M for ball velocities): diagnostics with
// a relative margin, never a proof (every exact question goes through the reference).
struct Metric {
    std::size_t m = 0;
    std::vector<double> h, habs; // row-major
    Matrix exact;                // the metric itself (H, or M in ball velocities)

    explicit Metric(const LawReference& ref) : m(ref.in_dim()), exact(ref.in_dim(), ref.in_dim()) {
        const Model& model = ref.model();
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < m; ++j) {
                const Rational q = ref.velocities() ? model.M()(i, j) : model.H()(i, j);
                exact(i, j) = q;
                h.push_back(nearest_double(q));
                habs.push_back(std::fabs(h.back()));
            }
        double total = 0;
        for (double a : habs)
            total += a;
        allowance_unit = static_cast<double>(m) * std::sqrt(total) * (1 + 0x1p-40);
    }
    double norm(const double* v) const {
        double s = 0;
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < m; ++j)
                s += h[i * m + j] * v[i] * v[j];
        return std::sqrt(std::fmax(s, 0.0));
    }
    // An enclosure of |v|_H for the exact H and v given exactly up to a relative error of
    // 2^-50 per component: v^T H v computed in double is within
    // (m^2 + 8) 2^-52 sum |h_ij v_i v_j| of the exact value (m^2 roundings of the sum, the
    // products, the entries of H rounded to double, and the perturbation of v), with room.
    // Ill-conditioned metrics make the enclosure wide; the callers then decide exactly.
    void enclose(const double* v, double& lo, double& hi) const {
        double s = 0, a = 0;
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < m; ++j) {
                const double t = h[i * m + j] * v[i] * v[j];
                s += t;
                a += std::fabs(t);
            }
        const double delta = static_cast<double>(m * m + 8) * 0x1p-52 * a;
        lo = std::sqrt(std::fmax(s - delta, 0.0)) * (1 - 0x1p-50);
        hi = std::sqrt(s + delta) * (1 + 0x1p-50);
    }
    double allowance_unit = 0; // m sqrt(sum_ij |h_ij|) (1 + 2^-40): see Worker::underflow_allowance
    double norm_abs(const double* d) const { // >= the norm of any vector with |v_i| <= d_i
        double s = 0;
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < m; ++j)
                s += habs[i * m + j] * d[i] * d[j];
        return std::sqrt(s);
    }
};

// The gap from |v| up to the next double (2^1024 - DBL_MAX = 2^971 above the largest; infinite
// for an infinite v), by its exponent bits.
double ulp_of(double v) {
    std::uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    const int e = static_cast<int>((b >> 52) & 0x7ff);
    if (e == 0x7ff)
        return INFINITY;
    return e == 0 ? 0x1p-1074 : eft::ldexp_fast(1.0, e - 1075); // exact: a power of two, >= 2^-1074
}

constexpr double kMargin = 1e-9; // relative margin of the floating-point property checks

struct Worker {
    Worker(const Options& o, const LawReference& r, const Properties& p, const Metric& mt, const Generator& g,
           std::unique_ptr<Implementation> i)
        : opt(o), ref(r), props(p), metric(mt), gen(g), impl(std::move(i)), m(r.in_dim()), mo(r.out_dim()) {
        sum.max_ulps.assign(mo, 0);
        piece_hit.assign(r.model().pieces().size(), 0);
        facet_probed.assign(g.facets(), 0);
        decade_seen.assign(kDecades, 0);
    }
    // Coverage (Summary): decades of the largest component, from 10^-324 (index 0) to 10^308.
    static constexpr int kDecadeMin = -324, kDecades = 633;
    std::vector<char> piece_hit, facet_probed, decade_seen;
    static int decade_of(double big) { return static_cast<int>(std::floor(std::log10(big))); }
    const Options& opt;
    const LawReference& ref;
    const Properties& props;
    const Metric& metric;
    const Generator& gen;
    std::unique_ptr<Implementation> impl;
    Summary sum;
    std::size_t m = 0, mo = 0;
    std::vector<Sample> samples;
    std::vector<double> in, out, bound;
    std::vector<ImplStatus> status;
    RefPoint ra, rb;

    std::string name(std::size_t p) const { return ref.model().pieces()[p].name; }

    std::string replay(const double* x, const double* xb) const {
        std::string cmd = opt.replay_prefix;
        const std::string flags = impl->replay_flags();
        if (!flags.empty())
            cmd += " " + flags;
        cmd += " --";
        for (std::size_t j = 0; j < m; ++j)
            cmd += " " + hex(x[j]);
        if (xb)
            for (std::size_t j = 0; j < m; ++j)
                cmd += " " + hex(xb[j]);
        return cmd;
    }

    void record(std::uint64_t index, const std::string& what, const Sample& s, const double* x, const double* xb,
                const double* y, const double* expected) {
        // Extreme only when every point of the sample is (a violation at a point within the range
        // is never allowed because its pair partner lies beyond it).
        const bool extreme = extreme_input(s.a, m) && (!s.pair || extreme_input(s.b, m));
        std::size_t slot = sum.examples.size();
        if (slot >= opt.keep) { // full: a violation within the range replaces the latest extreme one
            if (extreme)
                return;
            for (slot = sum.examples.size(); slot > 0 && !sum.examples[slot - 1].extreme; --slot) {
            }
            if (slot == 0)
                return;
            --slot;
        }
        Violation v;
        v.index = index;
        v.what = what;
        v.kind = s.kind;
        v.extreme = extreme;
        v.input.assign(x, x + m);
        if (xb)
            v.input_b.assign(xb, xb + m);
        if (y)
            v.output.assign(y, y + mo);
        if (expected)
            v.expected.assign(expected, expected + mo);
        v.replay = replay(x, xb);
        if (slot < sum.examples.size())
            sum.examples[slot] = std::move(v);
        else
            sum.examples.push_back(std::move(v));
    }

    // Common power-of-two scale for vectors that enter a quadratic form (no overflow).
    static int scale_of(std::initializer_list<std::pair<const double*, std::size_t>> vs) {
        double big = 0;
        for (const auto& [p, n] : vs)
            for (std::size_t j = 0; j < n; ++j)
                if (std::isfinite(p[j]))
                    big = std::fmax(big, std::fabs(p[j]));
        return big > 0 ? -std::ilogb(big) : 0;
    }

    // The tolerance around the value v at x in the metric, in units of 2^-k.
    // An upper bound of the tolerance around the value v at x in the metric, in units of 2^-k:
    // K ulps away from v is at most (2K + 1) upward gaps of v away from the exact value (gaps
    // at most double within K steps); a stated bound b plus the rounding of v; or, relative,
    // sqrt(R^2 |x|^2 + A^2) with the underflow allowance A (see accurate()).
    double tolerance(const double* x, const double* v, const double* b, int k) const {
        double d[kMaxDim];
        if (opt.tolerance == Tolerance::relative) {
            for (std::size_t j = 0; j < m; ++j)
                d[j] = eft::ldexp_fast(x[j], k);
            double lo, hi;
            metric.enclose(d, lo, hi);
            return std::hypot(opt.max_rel_error * hi, underflow_allowance(k)) * (1 + kMargin);
        }
        for (std::size_t i = 0; i < mo; ++i) {
            const double allowed = opt.tolerance == Tolerance::ulps
                                       ? (2 * static_cast<double>(opt.max_ulps) + 1) * ulp_of(v[i])
                                       : (b ? b[i] : 0) + ulp_of(v[i]);
            d[i] = eft::ldexp_fast(allowed, k);
        }
        return metric.norm_abs(d) * (1 + kMargin);
    }

    // A = |a|_{|H|} with a_i = m 2^-1074: what a dot product of m terms may lose to underflow in
    // each component (no double arithmetic does better below the normal range), in units of 2^-k:
    // m sqrt(sum |h_ij|) 2^(k-1074), rounded up generously.
    double underflow_allowance(int k) const {
        return k - 1074 >= -1022 ? eft::ldexp_fast(metric.allowance_unit, k - 1074)
                                 : std::ldexp(metric.allowance_unit, k - 1074);
    }

    // --max-rel-error R: |y - S(x)|_H^2 <= R^2 |x|_H^2 + A^2, decided by an enclosure in double
    // and, where that cannot tell, exactly (rationals).
    bool accurate_relative(const double* x, const double* y, const double* v, std::size_t piece, double& rel) const {
        bool finite = true;
        for (std::size_t i = 0; i < mo; ++i)
            finite = finite && std::isfinite(v[i]) && std::isfinite(y[i]);
        rel = 0;
        if (finite) {
            const int k = scale_of({{x, m}, {y, mo}, {v, mo}});
            double e[kMaxDim], h[kMaxDim], xs[kMaxDim];
            for (std::size_t i = 0; i < mo; ++i) {
                e[i] = eft::ldexp_fast(y[i], k) - eft::ldexp_fast(v[i], k); // relative error <= 2^-53
                h[i] = eft::ldexp_fast(ulp_of(v[i]), k - 1);                  // |v - S(x)| <= h (a power of two)
            }
            for (std::size_t j = 0; j < m; ++j)
                xs[j] = eft::ldexp_fast(x[j], k);
            double elo, ehi, xlo, xhi;
            metric.enclose(e, elo, ehi);
            metric.enclose(xs, xlo, xhi);
            const double hn = metric.norm_abs(h) * (1 + 0x1p-50), allowance = underflow_allowance(k);
            const double err_lo = std::fmax(elo - hn, 0.0), err_hi = ehi + hn;
            const double R = opt.max_rel_error;
            // hypot: no overflow in the squares (R may be huge); an infinite bound accepts.
            const double rhs_lo = std::hypot(R * xlo, allowance) * (1 - 0x1p-48);
            const double rhs_hi = std::hypot(R * xhi, allowance) * (1 + 0x1p-48);
            rel = xlo > 0 ? (elo + ehi) / (xlo + xhi) : 0;
            if (std::isfinite(err_hi) && err_hi <= rhs_lo)
                return true;
            if (std::isfinite(err_lo) && std::isfinite(rhs_hi) && err_lo > rhs_hi)
                return false;
        }
        // Exactly: e = y - S(x) (a non-finite y is never within a finite tolerance).
        for (std::size_t i = 0; i < mo; ++i)
            if (!std::isfinite(y[i]))
                return false;
        const Vector value = ref.exact_value(x, piece);
        Vector e, xr, a;
        for (std::size_t i = 0; i < mo; ++i) {
            e.push_back(exact_double(y[i], "fuzz") - value[i]);
            a.push_back(exact_double(static_cast<double>(m) * 0x1p-1074, "fuzz"));
        }
        for (std::size_t j = 0; j < m; ++j)
            xr.push_back(exact_double(x[j], "fuzz"));
        Matrix habs_exact = metric.exact;
        for (std::size_t i = 0; i < mo; ++i)
            for (std::size_t j = 0; j < mo; ++j)
                if (sign_of(habs_exact(i, j)) == Sign::negative)
                    habs_exact(i, j) = -habs_exact(i, j);
        const Rational R(opt.max_rel_error);
        return bilinear(e, metric.exact, e) <= R * R * bilinear(xr, metric.exact, xr) + bilinear(a, habs_exact, a);
    }

    // The index of the value nearest y (several only where a law is several-valued).
    std::size_t nearest_value(const RefPoint& r, const double* y, std::uint64_t& worst) const {
        std::size_t best = 0;
        worst = std::numeric_limits<std::uint64_t>::max();
        for (std::size_t v = 0; v < r.values; ++v) {
            std::uint64_t w = 0;
            for (std::size_t i = 0; i < mo; ++i)
                w = std::max(w, ulp_distance(y[i], r.value[v][i]));
            if (w < worst) {
                worst = w;
                best = v;
            }
        }
        return best;
    }

    // Within the stated bound b_i, exactly where the floating-point screen cannot tell.
    bool within_bound(const double* x, const double* y, const double* b, std::size_t piece, const double* v,
                      const bool* exact) const {
        bool ok = true;
        for (std::size_t i = 0; i < mo && ok; ++i) {
            // |y - X| <= |y - v| + |v - X|, and |v - X| is 0 or at most half the larger gap at v.
            const double diff = std::fabs(y[i] - v[i]);
            if (std::isfinite(diff) && diff * (1 + 0x1p-50) + (exact[i] ? 0 : ulp_of(v[i])) <= b[i])
                continue;
            if (!std::isfinite(y[i]) || !std::isfinite(b[i])) {
                ok = !std::isfinite(b[i]) || y[i] == v[i];
                continue;
            }
            const Vector value = ref.exact_value(x, piece);
            Rational err = exact_double(y[i], "fuzz") - value[i];
            if (sign_of(err) == Sign::negative)
                err = -err;
            ok = err <= exact_double(b[i], "fuzz");
        }
        return ok;
    }

    // Checks one output. Returns whether it is within the tolerance (failures of the
    // implementation and points outside every cone count as within: nothing to compare).
    bool check_point(std::uint64_t index, const Sample& s, const double* x, const double* y, const double* b,
                     ImplStatus st, RefPoint& r) {
        ++sum.points;
        ref.eval(x, r, opt.tolerance == Tolerance::stated_bound);
        sum.slow += r.slow ? 1 : 0;
        if (st == ImplStatus::crashed || st == ImplStatus::hung || st == ImplStatus::malformed ||
            st == ImplStatus::nondeterministic) {
            ++(st == ImplStatus::crashed ? sum.crashed : st == ImplStatus::hung ? sum.hung : sum.malformed);
            record(index,
                   st == ImplStatus::crashed ? "the implementation crashed (its process ended) on this input"
                   : st == ImplStatus::hung  ? "the implementation did not answer within the timeout"
                   : st == ImplStatus::nondeterministic ? "nondeterministic: the implementation answered this input differently when it came again"
                                             : "the implementation's answer is not the expected number of values",
                   s, x, nullptr, nullptr, r.in_domain ? r.value[0] : nullptr);
            return true;
        }
        if (!r.in_domain) {
            ++sum.outside;
            return true;
        }
        for (std::size_t v = 0; v < r.values; ++v)
            piece_hit[r.piece[v]] = 1;
        std::uint64_t worst = 0;
        const std::size_t vi = nearest_value(r, y, worst);
        const double* v = r.value[vi];
        if (st == ImplStatus::refused) { // legitimate where some value lies beyond the double range
            bool finite = true;
            for (std::size_t w = 0; w < r.values; ++w)
                for (std::size_t i = 0; i < mo; ++i)
                    finite = finite && std::isfinite(r.value[w][i]);
            if (finite) {
                ++sum.refused;
                record(index, "the built-in implementation refused an input whose exact output is finite", s, x,
                       nullptr, nullptr, v);
            }
            return true;
        }
        for (std::size_t i = 0; i < mo; ++i) {
            // Infinity is one ulp beyond the largest double: within --max-ulps K >= 1 of it.
            const bool allowed_inf = std::isinf(y[i]) && opt.tolerance == Tolerance::ulps &&
                                     ulp_distance(y[i], v[i]) <= opt.max_ulps;
            if (std::isfinite(v[i]) && !std::isfinite(y[i]) && !allowed_inf) {
                ++sum.non_finite;
                ++sum.inaccurate;
                record(index, "non-finite output where the correctly rounded value is finite", s, x, nullptr, y, v);
                return false;
            }
            sum.max_ulps[i] = std::max(sum.max_ulps[i], ulp_distance(y[i], v[i]));
        }
        if (worst == 0 && opt.tolerance != Tolerance::stated_bound)
            return true;
        // Not correctly rounded: measure the normwise error and apply the tolerance.
        const int k = scale_of({{x, m}, {y, mo}, {v, mo}});
        double xs[kMaxDim];
        for (std::size_t j = 0; j < m; ++j)
            xs[j] = eft::ldexp_fast(x[j], k);
        bool ok = true;
        double rel = 0;
        switch (opt.tolerance) {
        case Tolerance::ulps:
            ok = worst <= opt.max_ulps;
            {
                double e[kMaxDim];
                for (std::size_t i = 0; i < mo; ++i)
                    e[i] = eft::ldexp_fast(y[i], k) - eft::ldexp_fast(v[i], k);
                const double xnorm = metric.norm(xs);
                rel = xnorm > 0 ? metric.norm(e) / xnorm : 0;
            }
            break;
        case Tolerance::relative:
            ok = accurate_relative(x, y, v, r.piece[vi], rel);
            break;
        case Tolerance::stated_bound:
            ok = b && within_bound(x, y, b, r.piece[vi], v, r.exact[vi]);
            break;
        }
        if (std::isfinite(rel))
            sum.max_rel_error = std::max(sum.max_rel_error, rel);
        if (ok)
            return true;
        ++sum.inaccurate;
        // Another piece's formula?
        std::string what;
        const std::size_t pieces = ref.model().pieces().size();
        for (std::size_t p = 0; p < pieces && p < 512 && what.empty(); ++p) {
            if (p == r.piece[vi])
                continue;
            double z[kMaxDim];
            ref.formula(p, x, z);
            std::uint64_t w = 0;
            for (std::size_t i = 0; i < mo; ++i)
                w = std::max(w, ulp_distance(y[i], z[i]));
            if (w <= (opt.tolerance == Tolerance::ulps ? opt.max_ulps : 0) && !ref.contains(p, x))
                what = "classification: the output is piece " + name(p) + "'s formula, the input lies in piece " +
                       name(r.piece[vi]);
        }
        if (!what.empty())
            ++sum.misclassified;
        else
            what = opt.tolerance == Tolerance::ulps        ? "error of " + std::to_string(worst) + " ulp, above --max-ulps " + std::to_string(opt.max_ulps)
                   : opt.tolerance == Tolerance::relative ? "normwise error above --max-rel-error"
                                                          : "error above the implementation's stated bound";
        record(index, what, s, x, nullptr, y, v);
        // Properties the output breaks (beyond the tolerance, for the metric ones).
        bool finite_output = true;
        for (std::size_t i = 0; i < mo; ++i)
            finite_output = finite_output && std::isfinite(y[i]);
        if (props.nonnegative && finite_output) {
            bool negative = false;
            if (ref.velocities()) {
                const Matrix& W = ref.model().W(); // gamma+ = W^T y, exactly
                // with friction only the normals have a sign (SPEC section 9)
                for (std::size_t c = 0; c < ref.model().normals() && !negative; ++c) {
                    Rational g = 0;
                    for (std::size_t i = 0; i < mo; ++i)
                        g += W(i, c) * exact_double(y[i], "fuzz");
                    negative = sign_of(g) == Sign::negative;
                }
            } else {
                for (std::size_t i = 0; i < mo && i < ref.model().normals(); ++i)
                    negative = negative || y[i] < 0;
            }
            if (negative) {
                ++sum.negative;
                record(index, "negative contact velocity after impact (gamma+ >= 0 broken)", s, x, nullptr, y, v);
            }
        }
        if (props.energy && finite_output) {
            double ys[kMaxDim], ylo, yhi, xlo, xhi;
            for (std::size_t i = 0; i < mo; ++i)
                ys[i] = eft::ldexp_fast(y[i], k);
            metric.enclose(ys, ylo, yhi);
            metric.enclose(xs, xlo, xhi);
            if (ylo * (1 - kMargin) > xhi * (1 + kMargin) + tolerance(x, v, b, k)) {
                ++sum.energy;
                record(index, "energy increase beyond the tolerance", s, x, nullptr, y, v);
            }
        }
        return false;
    }

    void check_pair(std::uint64_t index, const Sample& s, const double* ya, const double* yb, const double* ba,
                    const double* bb) {
        if (!ra.in_domain || !rb.in_domain)
            return;
        std::uint64_t w;
        const double* va = ra.value[nearest_value(ra, ya, w)];
        const double* vb = rb.value[nearest_value(rb, yb, w)];
        for (std::size_t i = 0; i < mo; ++i)
            if (!std::isfinite(ya[i]) || !std::isfinite(yb[i]))
                return;
        const int k = scale_of({{s.a, m}, {s.b, m}, {ya, mo}, {yb, mo}});
        double dy[kMaxDim], dx[kMaxDim];
        for (std::size_t i = 0; i < mo; ++i)
            dy[i] = eft::ldexp_fast(ya[i], k) - eft::ldexp_fast(yb[i], k);
        for (std::size_t j = 0; j < m; ++j)
            dx[j] = eft::ldexp_fast(s.a[j], k) - eft::ldexp_fast(s.b[j], k);
        double ylo, yhi, xlo, xhi;
        metric.enclose(dy, ylo, yhi);
        metric.enclose(dx, xlo, xhi);
        const double lhs = ylo * (1 - kMargin);
        const double rhs = xhi * (1 + kMargin) + tolerance(s.a, va, ba, k) + tolerance(s.b, vb, bb, k);
        if (lhs > rhs) {
            ++sum.nonexpansive;
            record(index, "non-expansivity broken beyond the tolerance: |S(a) - S(b)| > |a - b|", s, s.a, s.b, ya, yb);
        }
    }

    // Copies a few doubles: a plain loop, which GCC would otherwise turn into a call to memmove
    // (several times slower for 2 to 4 doubles; it showed as 6% of a fuzz run).
    static void copy_small(const double* from, double* to, std::size_t n) {
        for (std::size_t j = 0; j < n; ++j) {
            to[j] = from[j];
            asm volatile("" ::: "memory"); // not a memmove pattern
        }
    }

    void run_chunk(std::uint64_t begin, std::uint64_t end) {
        const std::size_t count = static_cast<std::size_t>(end - begin);
        samples.resize(count);
        in.resize(2 * count * m);
        std::size_t points = 0;
        for (std::size_t i = 0; i < count; ++i) {
            gen.make(opt.seed, begin + i, samples[i]);
            copy_small(samples[i].a, &in[points * m], m);
            ++points;
            if (samples[i].pair) {
                copy_small(samples[i].b, &in[points * m], m);
                ++points;
            }
        }
        out.resize(points * mo);
        const bool bounded = impl->states_bound();
        bound.resize(bounded ? points * mo : 0);
        status.resize(points);
        impl->eval(in.data(), out.data(), bounded ? bound.data() : nullptr, points, status.data());
        // The reference needs round-to-nearest; an implementation may have changed the mode.
        if (std::fegetround() != FE_TONEAREST)
            std::fesetround(FE_TONEAREST);
        std::size_t q = 0;
        for (std::size_t i = 0; i < count; ++i) {
            const Sample& s = samples[i];
            const std::uint64_t index = begin + i;
            if (status[q] == ImplStatus::skipped || (s.pair && status[q + 1] == ImplStatus::skipped))
                break; // the run's time ran out inside this batch
            ++sum.samples;
            const std::uint64_t before = sum.violations();
            struct Tally { // counts the sample's violations, extreme or gated, however it ends
                Worker& w;
                const Sample& s;
                std::uint64_t before;
                ~Tally() {
                    if (w.sum.violations() == before)
                        return;
                    const bool extreme = extreme_input(s.a, w.m) && (!s.pair || extreme_input(s.b, w.m));
                    ++(extreme ? w.sum.extreme : w.sum.gated);
                }
            } tally{*this, s, before};
            if (s.facet >= 0)
                facet_probed[static_cast<std::size_t>(s.facet)] = 1;
            {
                double big = 0;
                for (std::size_t j = 0; j < m; ++j)
                    big = std::fmax(big, std::fabs(s.a[j]));
                if (big > 0 && std::isfinite(big))
                    decade_seen[static_cast<std::size_t>(std::clamp(decade_of(big) - kDecadeMin, 0, kDecades - 1))] = 1;
            }
            const double* ya = &out[q * mo];
            const double* ba = bounded ? &bound[q * mo] : nullptr;
            const ImplStatus sa = status[q++];
            const bool ok_a = check_point(index, s, s.a, ya, ba, sa, ra);
            if (!s.pair)
                continue;
            ++sum.pairs;
            const double* yb = &out[q * mo];
            const double* bb = bounded ? &bound[q * mo] : nullptr;
            const ImplStatus sb = status[q++];
            const bool ok_b = check_point(index, s, s.b, yb, bb, sb, rb);
            // Outputs within the tolerance cannot break non-expansivity beyond it.
            if (props.nonexpansive && !(ok_a && ok_b) && sa == ImplStatus::ok && sb == ImplStatus::ok)
                check_pair(index, s, ya, yb, ba, bb);
        }
    }
};

} // namespace

Summary run(const Options& options, const LawReference& reference, const Implementation& impl,
            const Properties& properties, const std::function<void(std::uint64_t)>& progress) {
    const unsigned jobs = std::max(1u, options.jobs);
    const Metric metric(reference);
    const Generator gen(reference, options.range_lo, options.range_hi);
    std::atomic<bool> stop{false};
    std::vector<std::unique_ptr<Worker>> workers;
    for (unsigned j = 0; j < jobs; ++j) {
        workers.push_back(std::make_unique<Worker>(options, reference, properties, metric, gen, impl.clone()));
        workers.back()->impl->set_stop_flag(&stop);
    }
    const std::uint64_t kChunk = impl.batch_samples();
    std::atomic<std::uint64_t> next{0}, done{0};
    const auto start = std::chrono::steady_clock::now();
    const std::uint64_t n = options.samples;
    // A worker's exception stops the others and is rethrown after the joins.
    std::vector<std::exception_ptr> errors(jobs);
    auto work = [&](unsigned j) {
        try {
            // The reference's error-free transformations need IEEE round-to-nearest.
            std::fesetround(FE_TONEAREST);
            for (;;) {
                if (stop.load(std::memory_order_relaxed))
                    return;
                const std::uint64_t begin = next.fetch_add(kChunk);
                if (begin >= n)
                    return;
                const std::uint64_t end = std::min(n, begin + kChunk);
                workers[j]->run_chunk(begin, end);
                done.fetch_add(end - begin, std::memory_order_relaxed);
                if (options.stop_on_failure && workers[j]->sum.fails(options.allow_extreme))
                    stop = true;
            }
        } catch (...) {
            errors[j] = std::current_exception();
            stop = true;
        }
    };
    // Progress and the time limit, from a watcher that wakes every 200 ms or when the work ends;
    // it starts first (the time limit needs it). Workers that cannot start leave their chunks to
    // the others (parallel.hpp); worker 0 runs on this thread.
    std::mutex mutex;
    std::condition_variable wake;
    bool finished = false;
    std::vector<std::thread> threads;
    threads.reserve(jobs); // before the watcher starts: a failure here leaves no thread to join
    std::thread watcher = start_required_thread([&] {
        std::unique_lock<std::mutex> lock(mutex);
        while (!wake.wait_for(lock, std::chrono::milliseconds(200), [&] { return finished; })) {
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (options.seconds > 0 && elapsed >= options.seconds)
                stop = true;
            if (progress)
                progress(done.load());
        }
    });
    for (unsigned j = 1; j < jobs; ++j)
        start_thread(threads, [&work, j] { work(j); });
    {
        // Worker 0 runs here: the floating-point environment an in-process implementation may
        // change (traps, flush-to-zero) is this thread's again afterwards.
        std::fenv_t env;
        std::fegetenv(&env);
        work(0);
        std::fesetenv(&env);
    }
    for (auto& t : threads)
        t.join();
    const auto end = std::chrono::steady_clock::now();
    {
        std::lock_guard<std::mutex> lock(mutex);
        finished = true;
    }
    wake.notify_all();
    watcher.join();
    for (const auto& e : errors)
        if (e)
            std::rethrow_exception(e);
    Summary total;
    total.seconds = std::chrono::duration<double>(end - start).count();
    total.max_ulps.assign(reference.out_dim(), 0);
    for (auto& w : workers) {
        const Summary& s = w->sum;
        total.samples += s.samples;
        total.points += s.points;
        total.pairs += s.pairs;
        total.slow += s.slow;
        total.outside += s.outside;
        for (std::size_t k = 0; k < total.max_ulps.size(); ++k)
            total.max_ulps[k] = std::max(total.max_ulps[k], s.max_ulps[k]);
        total.max_rel_error = std::max(total.max_rel_error, s.max_rel_error);
        total.inaccurate += s.inaccurate;
        total.misclassified += s.misclassified;
        total.negative += s.negative;
        total.energy += s.energy;
        total.nonexpansive += s.nonexpansive;
        total.non_finite += s.non_finite;
        total.crashed += s.crashed;
        total.hung += s.hung;
        total.malformed += s.malformed;
        total.refused += s.refused;
        total.extreme += s.extreme;
        total.gated += s.gated;
        for (const auto& v : s.examples)
            total.examples.push_back(v);
    }
    // Coverage, merged over the workers.
    total.pieces = reference.model().pieces().size();
    total.facets = gen.facets();
    total.prefix = std::min<std::uint64_t>(gen.prefix_count(), total.samples);
    for (std::size_t p = 0; p < total.pieces; ++p) {
        bool hit = false;
        for (auto& w : workers)
            hit = hit || w->piece_hit[p];
        total.pieces_hit += hit ? 1 : 0;
    }
    for (std::size_t f = 0; f < total.facets; ++f) {
        bool hit = false;
        for (auto& w : workers)
            hit = hit || w->facet_probed[f];
        total.facets_probed += hit ? 1 : 0;
    }
    bool any = false;
    for (int d = 0; d < Worker::kDecades; ++d) {
        bool hit = false;
        for (auto& w : workers)
            hit = hit || w->decade_seen[static_cast<std::size_t>(d)];
        if (!hit)
            continue;
        ++total.decades;
        total.decade_hi = d + Worker::kDecadeMin;
        if (!any)
            total.decade_lo = d + Worker::kDecadeMin;
        any = true;
    }
    // Violations at inputs within the range first: with --allow extreme they are what fails.
    std::stable_sort(total.examples.begin(), total.examples.end(), [](const Violation& a, const Violation& b) {
        return a.extreme != b.extreme ? !a.extreme : a.index < b.index;
    });
    if (total.examples.size() > options.keep)
        total.examples.resize(options.keep);
    return total;
}

std::string explain(const LawReference& reference, Implementation* impl, const double* x, std::uint64_t* worst_ulps,
                    std::vector<double>* answer) {
    const std::size_t mo = reference.out_dim();
    if (worst_ulps)
        *worst_ulps = UINT64_MAX;
    if (answer)
        answer->clear();
    std::fesetround(FE_TONEAREST);
    RefPoint r;
    reference.eval(x, r);
    std::string text;
    auto line = [&](const char* label, const double* v) {
        text += label;
        for (std::size_t i = 0; i < mo; ++i)
            text += " " + hex(v[i]);
    };
    double y[kMaxDim];
    if (impl) {
        ImplStatus st = ImplStatus::ok;
        impl->eval(x, y, nullptr, 1, &st);
        if (st != ImplStatus::ok)
            text += std::string("impl  (") +
                    (st == ImplStatus::crashed ? "crashed" : st == ImplStatus::hung ? "no answer" : st == ImplStatus::refused ? "refused" : "malformed answer") +
                    ")\n";
        else {
            line("impl ", y);
            text += "\n";
            if (answer)
                answer->assign(y, y + mo);
        }
        if (st != ImplStatus::ok)
            impl = nullptr;
    }
    if (!r.in_domain) {
        text += "exact (the input lies in no cone of the law: nothing to compare)\n";
        if (worst_ulps)
            *worst_ulps = 0; // as the fuzzer, which skips such points
        return text;
    }
    for (std::size_t v = 0; v < r.values; ++v) {
        line("exact", r.value[v]);
        text += "  # correctly rounded, piece " + reference.model().pieces()[r.piece[v]].name;
        if (impl) {
            text += ", error";
            std::uint64_t worst = 0;
            for (std::size_t i = 0; i < mo; ++i) {
                const std::uint64_t d = ulp_distance(y[i], r.value[v][i]);
                text += (i ? ", " : " ") + std::to_string(d);
                const bool bad = std::isnan(y[i]) && !std::isnan(r.value[v][i]);
                worst = std::max(worst, bad ? UINT64_MAX : d);
            }
            text += " ulp";
            if (worst_ulps)
                *worst_ulps = std::min(*worst_ulps, worst);
        }
        text += "\n";
    }
    return text;
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

} // namespace impactcert::fuzz
