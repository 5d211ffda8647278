// SPDX-License-Identifier: GPL-3.0-or-later
// Chambers, walls and planar orientation (tiling.hpp).
#include "tiling.hpp"

#include <algorithm>
#include <map>
#include <set>

namespace impactcert_check::detail {

// The number of chambers of the central arrangement {x : n . x = 0} (n in `normals`, distinct
// lines) in R^d, by deletion and restriction of the first hyperplane, unrolled:
// r(A) = 1 + sum_k r(A_{>k} restricted to h_k), A_{>k} the hyperplanes after h_k (so the
// recursion is on the dimension only). Gives up (returns more than `cap`) once over `cap`.
std::size_t count_chambers(const std::vector<Vec>& normals, std::size_t d, std::size_t cap) {
    if (normals.empty())
        return 1;
    if (d == 1)
        return 2;
    std::size_t total = 1;
    for (std::size_t k = 0; k < normals.size() && total <= cap; ++k) {
        const std::vector<Vec> basis = kernel({normals[k]}, d);
        std::vector<Vec> restricted;
        std::set<Vec> seen;
        for (std::size_t l = k + 1; l < normals.size(); ++l) {
            Vec local;
            for (const auto& b : basis)
                local.push_back(dot(b, normals[l]));
            const Vec line = canonical_line(local);
            if (seen.insert(line).second)
                restricted.push_back(line);
        }
        total += count_chambers(restricted, d - 1, cap - total);
    }
    return total;
}

// One point per chamber, by the prover's rule (proofs/README.md, "Check, complete"): the
// hyperplanes added in order; after adding h (normal n) the earlier points off h are kept, and
// every point y of the earlier hyperplanes restricted to h (in the primitive kernel basis of n)
// gives y +- eps n, eps = min(1, |m.y| / (2 |m.n|) over earlier m with m.n != 0), primitive;
// then the first point of every sign vector is kept. The checker regenerates the list to demand
// the canonical one (so no point can be changed unnoticed) and counts the chambers by a second
// route (count_chambers) to know that the list is complete.
std::vector<Vec> canonical_chamber_points(const std::vector<Vec>& normals, std::size_t d, std::size_t& budget,
                                          ChamberSteps& steps) {
    if (budget == 0)
        reject("$.obligations[0].data.chamber_points", "more chamber-enumeration work than the certificate lists points");
    --budget;
    steps.charge();
    if (d == 1)
        return normals.empty() ? std::vector<Vec>{Vec{Q(1)}} : std::vector<Vec>{Vec{Q(1)}, Vec{Q(-1)}};
    Vec first(d, Q(0));
    first[0] = 1;
    std::vector<Vec> points = {first};
    for (std::size_t k = 0; k < normals.size(); ++k) {
        const Vec& n = normals[k];
        std::vector<Vec> next;
        for (const auto& p : points)
            if (sgn(dot(n, p)) != 0)
                next.push_back(p);
        std::vector<Vec> basis = kernel({n}, d);
        for (auto& b : basis)
            b = primitive(b);
        std::vector<Vec> restricted;
        for (std::size_t l = 0; l < k; ++l) {
            Vec local;
            for (const auto& b : basis)
                local.push_back(dot(b, normals[l]));
            const Vec line = canonical_line(local);
            if (std::find(restricted.begin(), restricted.end(), line) == restricted.end())
                restricted.push_back(line);
        }
        for (const auto& local : canonical_chamber_points(restricted, d - 1, budget, steps)) {
            Vec y(d, Q(0));
            for (std::size_t i = 0; i + 1 < d; ++i)
                for (std::size_t j = 0; j < d; ++j)
                    y[j] += local[i] * basis[i][j];
            Q eps = 1;
            for (std::size_t l = 0; l < k; ++l) {
                const Q mn = dot(normals[l], n);
                if (sgn(mn) != 0)
                    eps = std::min(eps, Q(abs(dot(normals[l], y)) / (2 * abs(mn))));
            }
            for (int side : {1, -1}) {
                Vec z = y;
                for (std::size_t j = 0; j < d; ++j)
                    z[j] += side * eps * n[j];
                next.push_back(primitive(z));
            }
            steps.charge();
        }
        std::set<std::vector<int>> seen;
        points.clear();
        for (const auto& p : next) {
            std::vector<int> signs;
            for (std::size_t l = 0; l <= k; ++l)
                signs.push_back(sgn(dot(normals[l], p)));
            if (seen.insert(signs).second)
                points.push_back(p);
        }
    }
    return points;
}

// ---- Tilings by walls (proofs/README.md, "Check, walls"): sum w_i [x in int C_i] equals the
// target at every generic x iff identical cones cancel to the target's count at one generic
// point and, across every facet hyperplane, the facets in it (weighted by the side of their
// cone) cancel as cones of the hyperplane, recursively.

namespace {

bool inside_open(const std::vector<Vec>& rays, const Vec& x) {
    Vec s;
    return solve(from_cols(rays), x, s) && positive(s);
}

} // namespace

Vec first_generic(const std::vector<Vec>& normals, std::size_t d) {
    for (long t = 1;; ++t) {
        Vec x;
        Q power = 1;
        for (std::size_t i = 0; i < d; ++i, power *= t)
            x.push_back(power);
        if (std::all_of(normals.begin(), normals.end(), [&](const Vec& n) { return sgn(dot(n, x)) != 0; }))
            return x;
    }
}

bool walls_balance(const std::vector<WCone>& in, std::size_t d, long target) {
    std::map<std::vector<Vec>, long> net;
    for (auto cone : in) {
        std::sort(cone.rays.begin(), cone.rays.end());
        net[cone.rays] += cone.w;
    }
    std::vector<WCone> family;
    for (const auto& [rays, w] : net)
        if (w != 0)
            family.push_back({rays, w});
    if (family.empty())
        return target == 0;
    if (d == 1) {
        long pos = 0, neg = 0;
        for (const auto& cone : family)
            (sgn(cone.rays[0][0]) > 0 ? pos : neg) += cone.w;
        return pos == target && neg == target;
    }
    std::map<Vec, std::map<std::vector<Vec>, long>> walls;
    for (const auto& cone : family)
        for (std::size_t drop = 0; drop < d; ++drop) {
            std::vector<Vec> facet;
            for (std::size_t k = 0; k < d; ++k)
                if (k != drop)
                    facet.push_back(cone.rays[k]);
            const Vec n = canonical_line(kernel(facet, d).at(0));
            walls[n][facet] += (sgn(dot(n, cone.rays[drop])) > 0 ? 1 : -1) * cone.w;
        }
    std::vector<Vec> normals;
    for (const auto& entry : walls)
        normals.push_back(entry.first);
    const Vec x0 = first_generic(normals, d);
    long count = 0;
    for (const auto& cone : family)
        if (inside_open(cone.rays, x0))
            count += cone.w;
    if (count != target)
        return false;
    for (const auto& [n, facets] : walls) {
        std::vector<Vec> basis = kernel({n}, d);
        for (auto& b : basis)
            b = primitive(b);
        // Coordinates in h: the basis has full column rank; solve the normal equations.
        Mat gram(basis.size(), Vec(basis.size()));
        for (std::size_t i = 0; i < basis.size(); ++i)
            for (std::size_t j = 0; j < basis.size(); ++j)
                gram[i][j] = dot(basis[i], basis[j]);
        std::vector<WCone> induced;
        for (const auto& [facet, w] : facets) {
            if (w == 0)
                continue;
            WCone wc;
            wc.w = w;
            for (const auto& r : facet) {
                Vec rhs, y;
                for (const auto& b : basis)
                    rhs.push_back(dot(b, r));
                if (!solve(gram, rhs, y))
                    reject("$.law.pieces", "a facet basis is singular");
                wc.rays.push_back(primitive(y));
            }
            induced.push_back(wc);
        }
        if (!induced.empty() && !walls_balance(induced, d - 1, 0))
            return false;
    }
    return true;
}

int sign_det2(const Vec& a, const Vec& b) { return sgn(a[0] * b[1] - a[1] * b[0]); }

// Angle of v measured counter-clockwise from a, as (half, v): comparable with ccw_less.
bool ccw_before(const Vec& a, const Vec& x, const Vec& y) {
    auto half = [&](const Vec& v) { return (sign_det2(a, v) > 0 || (sign_det2(a, v) == 0 && sgn(dot(a, v)) > 0)) ? 0 : 1; };
    if (half(x) != half(y))
        return half(x) < half(y);
    return sign_det2(x, y) > 0;
}

} // namespace impactcert_check::detail
