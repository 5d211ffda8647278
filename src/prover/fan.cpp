// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/fan.hpp"

#include "exact/int_kernel.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <stdexcept>

namespace impactcert {

namespace {

Sign orientation(const Vector& a, const Vector& b) { return sign_of(a[0] * b[1] - a[1] * b[0]); }

// 0 for directions in [0, pi), 1 for [pi, 2 pi).
int half_plane(const Vector& v) {
    const Sign y = sign_of(v[1]);
    return (y == Sign::positive || (y == Sign::zero && sign_of(v[0]) == Sign::positive)) ? 0 : 1;
}

bool angle_less(const Vector& a, const Vector& b) {
    const int ha = half_plane(a), hb = half_plane(b);
    if (ha != hb)
        return ha < hb;
    return orientation(a, b) == Sign::positive;
}

std::vector<std::size_t> interiors_containing(const Model& model, const Vector& x) {
    std::vector<std::size_t> out;
    for (std::size_t p = 0; p < model.pieces().size(); ++p)
        if (model.in_interior(p, x))
            out.push_back(p);
    return out;
}

// Records the covering of every test point and the first one covered k != 1 times.
void cover(const Model& model, FanResult& r) {
    r.covering.clear();
    r.failing.reset();
    for (std::size_t k = 0; k < r.test_points.size(); ++k) {
        r.covering.push_back(interiors_containing(model, r.test_points[k]));
        r.checks += model.pieces().size();
        if (r.covering.back().size() != 1 && !r.failing)
            r.failing = k;
    }
    r.proved = !r.failing;
}

void check_planar(const Model& model, FanResult& r) {
    r.method = "angular-sectors";
    std::vector<Vector> rays = model.rays();
    std::sort(rays.begin(), rays.end(), angle_less);
    r.rays_by_angle = rays;
    const std::size_t m = rays.size();
    for (std::size_t k = 0; k < m; ++k) {
        const Vector& a = rays[k];
        const Vector& b = rays[(k + 1) % m];
        // A direction strictly inside the open sector from a to b (counter-clockwise).
        r.test_points.push_back((m > 1 && orientation(a, b) == Sign::positive) ? a + b
                                                                                : Vector{-a[1], a[0]});
    }
    cover(model, r);
    r.fast_path = r.proved;
}

// Every facet of every cone, by its sorted ray ids: the cones having it, each with the index of
// the ray it leaves out, in piece order. Built once, for the facet criterion and the gap check.
using FacetOwners = std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, std::size_t>>>;
FacetOwners facet_owners(const Model& model) {
    const std::size_t c = model.contacts();
    FacetOwners owners;
    for (std::size_t p = 0; p < model.pieces().size(); ++p)
        for (std::size_t drop = 0; drop < c; ++drop) {
            std::vector<std::size_t> ids;
            for (std::size_t k = 0; k < c; ++k)
                if (k != drop)
                    ids.push_back(model.pieces()[p].ray_ids[k]);
            std::sort(ids.begin(), ids.end());
            owners[ids].push_back({p, drop});
        }
    return owners;
}

// The facet criterion: true when every facet is shared by exactly two cones on opposite sides
// and the first generic point of the moment curve is covered once.
bool check_facets(const Model& model, const FacetOwners& owners, FanResult& r) {
    const std::size_t c = model.contacts();
    const auto& pieces = model.pieces();
    struct Side {
        std::size_t piece;
        Sign side;
    };
    std::map<std::vector<std::size_t>, std::vector<Side>> facets;
    // The rays in int64 where they fit: the sign of a determinant by fraction-free
    // elimination (int_kernel.hpp), over GMP when an entry or an intermediate does not fit.
    std::vector<std::optional<std::vector<intk::i64>>> int_rays;
    for (const auto& ray : model.rays())
        int_rays.push_back(intk::to_int_vector(ray));
    std::vector<intk::i64> scratch(c * c);
    auto facet_sign = [&](const std::vector<std::size_t>& ids, const Vector& last) {
        const auto last_int = intk::to_int_vector(last);
        bool fits = last_int.has_value();
        for (std::size_t k = 0; k < ids.size() && fits; ++k)
            fits = int_rays[ids[k]].has_value();
        if (fits) {
            for (std::size_t row = 0; row < c; ++row) {
                for (std::size_t k = 0; k < ids.size(); ++k)
                    scratch[row * c + k] = (*int_rays[ids[k]])[row];
                scratch[row * c + c - 1] = (*last_int)[row];
            }
            if (const auto sign = intk::det_sign(scratch, c))
                return static_cast<Sign>(*sign);
        }
        std::vector<Vector> cols;
        for (auto id : ids)
            cols.push_back(model.rays()[id]);
        cols.push_back(last);
        return sign_of(determinant(Matrix::from_columns(cols)));
    };
    for (const auto& [ids, own] : owners)
        for (const auto& [p, drop] : own) {
            facets[ids].push_back({p, facet_sign(ids, pieces[p].R.column(drop))});
            ++r.checks;
        }
    for (const auto& [ids, sides] : facets) {
        FanResult::Facet record;
        for (auto id : ids)
            record.rays.push_back(model.rays()[id]);
        for (const auto& sd : sides)
            record.pieces.push_back(sd.piece);
        r.facets.push_back(std::move(record));
        if (sides.size() != 2 || sides[0].side == sides[1].side)
            return false;
    }
    // One generic point on the moment curve (1, t, t^2, ...): each facet hyperplane meets the
    // curve in at most c-1 values of t, so the search ends.
    Vector point(c);
    for (long t = 1;; ++t) {
        Rational power = 1;
        for (std::size_t i = 0; i < c; ++i, power *= Rational(t))
            point[i] = power;
        bool generic = true;
        for (const auto& entry : facets) {
            ++r.checks;
            if (facet_sign(entry.first, point) == Sign::zero) {
                generic = false;
                break;
            }
        }
        if (generic)
            break;
    }
    r.test_points = {point};
    cover(model, r);
    return r.proved;
}

std::vector<int> sign_vector(const std::vector<Vector>& normals, const Vector& x) {
    std::vector<int> s;
    s.reserve(normals.size());
    for (const auto& n : normals)
        s.push_back(static_cast<int>(sign_of(dot(n, x))));
    return s;
}

void charge(std::size_t& steps, std::size_t max_steps) {
    if (++steps > max_steps)
        throw LimitExceeded("the facet arrangement needs more than " + std::to_string(max_steps) +
                                " chamber-enumeration steps",
                            "--max-chambers");
}

// ---- walls: the signed count of cones is constant across every facet hyperplane

struct SignedCone {
    std::vector<Vector> rays; // d primitive rays in R^d, sorted
    long weight = 0;
};

Vector facet_normal(const std::vector<Vector>& rays, std::size_t d) {
    return canonical_line(null_space(rays, d).at(0));
}

bool in_open_cone(const std::vector<Vector>& rays, const Vector& x) {
    const auto s = solve(Matrix::from_columns(rays), x);
    return s && std::all_of(s->begin(), s->end(), [](const Rational& v) { return sign_of(v) == Sign::positive; });
}

// The first point (1, t, t^2, ...) of the moment curve off every hyperplane.
Vector moment_point(const std::vector<Vector>& normals, std::size_t d, std::size_t& checks) {
    for (long t = 1;; ++t) {
        Vector x(d);
        Rational power = 1;
        for (std::size_t i = 0; i < d; ++i, power *= Rational(t))
            x[i] = power;
        bool generic = true;
        for (const auto& n : normals) {
            ++checks;
            if (sign_of(dot(n, x)) == Sign::zero) {
                generic = false;
                break;
            }
        }
        if (generic)
            return x;
    }
}

// Whether sum_i w_i [x in int C_i] equals `target` at every generic x (proofs/README.md,
// "Check, walls"): identical cones cancel; one generic point has the target; and across every
// facet hyperplane h the facets lying in h, weighted by the side of their cone, cancel as a
// family of cones of h (recursively, with target 0).
bool balanced(std::vector<SignedCone> family, std::size_t d, long target, std::size_t& checks,
              std::vector<Vector>* top_normals, Vector* top_point) {
    std::map<std::vector<Vector>, long> net;
    for (auto& cone : family) {
        std::sort(cone.rays.begin(), cone.rays.end());
        net[cone.rays] += cone.weight;
    }
    family.clear();
    for (auto& [rays, w] : net)
        if (w != 0)
            family.push_back({rays, w});
    if (family.empty())
        return target == 0;
    if (d == 1) {
        long plus = 0, minus = 0;
        for (const auto& cone : family)
            (sign_of(cone.rays[0][0]) == Sign::positive ? plus : minus) += cone.weight;
        return plus == target && minus == target;
    }
    // Facets by hyperplane: normal -> (facet rays -> signed weight).
    std::map<Vector, std::map<std::vector<Vector>, long>> walls;
    for (const auto& cone : family)
        for (std::size_t drop = 0; drop < d; ++drop) {
            std::vector<Vector> facet;
            for (std::size_t k = 0; k < d; ++k)
                if (k != drop)
                    facet.push_back(cone.rays[k]);
            const Vector n = facet_normal(facet, d);
            const long side = sign_of(dot(n, cone.rays[drop])) == Sign::positive ? 1 : -1;
            walls[n][facet] += side * cone.weight;
            ++checks;
        }
    std::vector<Vector> normals;
    for (const auto& entry : walls)
        normals.push_back(entry.first);
    const Vector x0 = moment_point(normals, d, checks);
    if (top_normals)
        *top_normals = normals;
    if (top_point)
        *top_point = x0;
    long count = 0;
    for (const auto& cone : family) {
        ++checks;
        if (in_open_cone(cone.rays, x0))
            count += cone.weight;
    }
    if (count != target)
        return false;
    for (const auto& [n, facets] : walls) {
        std::vector<std::pair<const std::vector<Vector>*, long>> open;
        for (const auto& [facet, w] : facets)
            if (w != 0)
                open.push_back({&facet, w});
        if (open.empty())
            continue; // every facet in h is matched by one on the other side
        // The facets in h as cones of h, in the coordinates of a basis of h.
        const std::vector<Vector> basis = null_space({n}, d);
        const Matrix B = Matrix::from_columns(basis);
        const Matrix gram = transpose(B) * B;
        std::vector<SignedCone> induced;
        for (const auto& [facet, w] : open) {
            SignedCone sc;
            sc.weight = w;
            for (const auto& r : *facet)
                sc.rays.push_back(primitive_ray(*solve(gram, transpose(B) * r)));
            induced.push_back(std::move(sc));
        }
        if (!balanced(std::move(induced), d - 1, 0, checks, nullptr, nullptr))
            return false;
    }
    return true;
}

} // namespace

std::vector<Vector> chamber_points(const std::vector<Vector>& normals, std::size_t d,
                                   std::size_t max_steps, std::size_t& steps) {
    // Deletion and restriction (proofs/README.md, "Check, complete"), unrolled over the
    // hyperplanes so that the recursion is only on the dimension (depth <= d): after step k the
    // points are one per chamber of the first k+1 hyperplanes.
    charge(steps, max_steps);
    if (d == 1)
        return normals.empty() ? std::vector<Vector>{Vector{1}} : std::vector<Vector>{Vector{1}, Vector{-1}};
    std::vector<Vector> points = {unit_vector(d, 0)};
    for (std::size_t k = 0; k < normals.size(); ++k) {
        const Vector& n = normals[k];
        const std::vector<Vector> before(normals.begin(), normals.begin() + static_cast<std::ptrdiff_t>(k));
        std::vector<Vector> next;
        for (auto& p : points)
            if (sign_of(dot(n, p)) != Sign::zero)
                next.push_back(std::move(p));
        const std::vector<Vector> basis = null_space({n}, d); // d-1 vectors spanning h
        std::vector<Vector> restricted;
        for (const auto& m : before) {
            Vector local(d - 1);
            for (std::size_t i = 0; i + 1 < d; ++i)
                local[i] = dot(basis[i], m);
            Vector line = canonical_line(local); // non-zero: m is not a multiple of n
            if (std::find(restricted.begin(), restricted.end(), line) == restricted.end())
                restricted.push_back(std::move(line));
        }
        for (const auto& local : chamber_points(restricted, d - 1, max_steps, steps)) {
            Vector y(d);
            for (std::size_t i = 0; i + 1 < d; ++i)
                y = y + local[i] * basis[i];
            // Step off h by less than any other hyperplane allows: the two points lie in the two
            // chambers on either side of the chamber of h that contains y.
            Rational eps = 1;
            for (const auto& m : before) {
                const Rational mn = dot(m, n);
                if (sign_of(mn) != Sign::zero)
                    eps = std::min(eps, abs_of(dot(m, y)) / (2 * abs_of(mn)));
            }
            next.push_back(primitive_ray(y + eps * n));
            next.push_back(primitive_ray(y - eps * n));
            charge(steps, max_steps);
        }
        const std::vector<Vector> upto(normals.begin(), normals.begin() + static_cast<std::ptrdiff_t>(k + 1));
        std::set<std::vector<int>> seen;
        points.clear();
        for (auto& p : next)
            if (seen.insert(sign_vector(upto, p)).second)
                points.push_back(std::move(p));
    }
    return points;
}

std::vector<Vector> facet_hyperplanes(const Model& model) {
    const std::size_t c = model.contacts();
    std::set<Vector> lines;
    for (const auto& piece : model.pieces())
        for (std::size_t drop = 0; drop < c; ++drop) {
            std::vector<Vector> rows;
            for (std::size_t k = 0; k < c; ++k)
                if (k != drop)
                    rows.push_back(piece.R.column(k));
            const auto normal = null_space(rows, c); // one vector: the rays are independent
            lines.insert(canonical_line(normal.at(0)));
        }
    return {lines.begin(), lines.end()};
}

// ---- unmatched facets: a point just outside a facet that no other cone has, in no closed cone
// (proofs/README.md, "Check, gaps"). For the first kMaxGapCandidates facets with one cone (in
// the order of their sorted ray ids), with f the sum of the facet's rays and d the cone's other
// ray: y = 2 f - d has coordinate -1 on d in that cone, so it is not in it; if no closed cone
// contains y, the cones leave a gap there.
namespace {

std::optional<FanResult> unmatched_facet_gap(const Model& model, const FacetOwners& owners) {
    const auto& pieces = model.pieces();
    FanResult r;
    r.method = "unmatched-facet";
    std::size_t tried = 0;
    for (const auto& [ids, own] : owners) {
        if (own.size() != 1)
            continue;
        if (tried++ == kMaxGapCandidates)
            break;
        const auto [p, drop] = own.front();
        Vector y = Rational(-1) * model.rays()[pieces[p].ray_ids[drop]];
        for (auto id : ids)
            y = y + Rational(2) * model.rays()[id];
        r.checks += pieces.size();
        if (!model.pieces_containing(y).empty())
            continue;
        FanResult::Facet facet;
        for (auto id : ids)
            facet.rays.push_back(model.rays()[id]);
        facet.pieces = {p};
        r.facets = {std::move(facet)};
        r.test_points = {y};
        r.covering = {{}};
        r.failing = 0;
        r.proved = false;
        return r;
    }
    return std::nullopt;
}

} // namespace

FanResult check_fan(const Model& model, const Limits& limits) {
    FanResult r;
    if (model.contacts() == 2) {
        check_planar(model, r);
        return r;
    }
    r.method = "facet-matching";
    const FacetOwners owners = facet_owners(model);
    if (check_facets(model, owners, r)) {
        r.fast_path = true;
        return r;
    }
    // Walls: a tiling that need not be face to face, decided without enumerating chambers.
    std::size_t checks = r.checks;
    {
        FanResult walls;
        walls.method = "walls";
        walls.checks = r.checks;
        std::vector<SignedCone> family;
        for (const auto& piece : model.pieces())
            family.push_back({[&] {
                                  std::vector<Vector> rays;
                                  for (std::size_t k = 0; k < model.contacts(); ++k)
                                      rays.push_back(piece.R.column(k));
                                  return rays;
                              }(),
                              1});
        Vector point;
        if (balanced(family, model.contacts(), 1, walls.checks, &walls.hyperplanes, &point)) {
            walls.test_points = {point};
            cover(model, walls);
            if (!walls.proved)
                throw std::logic_error("check_fan: the walls balance but the generic point is not covered once");
            return walls;
        }
        checks = walls.checks;
    }
    // A gap next to a facet that no other cone has: decided without enumerating chambers.
    if (auto gap = unmatched_facet_gap(model, owners)) {
        gap->checks += checks;
        return *gap;
    }
    // Complete decision: one point in every chamber of the facet arrangement.
    FanResult full;
    full.method = "chambers";
    full.checks = checks;
    full.hyperplanes = facet_hyperplanes(model);
    std::size_t steps = 0;
    full.test_points = chamber_points(full.hyperplanes, model.contacts(), limits.max_chambers, steps);
    full.checks += steps;
    cover(model, full);
    return full;
}

DomainResult check_domain(const Model& model, const FanResult& fan) {
    DomainResult d;
    if (fan.proved)
        return d;
    const auto& pieces = model.pieces();
    const std::size_t c = model.contacts();
    for (std::size_t k = 0; k < fan.test_points.size(); ++k) {
        const Vector& x = fan.test_points[k];
        const auto& cov = fan.covering[k];
        if (cov.empty()) {
            d.function = false;
            d.point = x;
            d.reason = "S is undefined at gamma: it lies in no cone";
            return d;
        }
        for (std::size_t u = 0; u < cov.size(); ++u)
            for (std::size_t v = u + 1; v < cov.size(); ++v) {
                const std::size_t a = cov[u], b = cov[v];
                if (pieces[a].Q == pieces[b].Q)
                    continue;
                // A point of int C_a ∩ int C_b where the matrices differ: x itself, or x moved
                // along a unit vector by less than the cone coordinates allow.
                const Matrix diff = pieces[a].Q - pieces[b].Q;
                Vector y = x;
                for (std::size_t e = 0; e < c && is_zero(diff * y); ++e) {
                    Rational delta = 1;
                    for (std::size_t p : {a, b}) {
                        const Vector s = pieces[p].R_inv * x, dir = pieces[p].R_inv.column(e);
                        for (std::size_t i = 0; i < c; ++i)
                            if (sign_of(dir[i]) == Sign::negative)
                                delta = std::min(delta, s[i] / (2 * abs_of(dir[i])));
                    }
                    y = primitive_ray(x + delta * unit_vector(c, e));
                }
                if (is_zero(diff * y))
                    throw std::logic_error("check_domain: the matrices differ but agree on a basis");
                d.function = false;
                d.point = y;
                d.interior_of = interiors_containing(model, y);
                d.reason = "S is two-valued near gamma: it is interior to two cones whose matrices differ there";
                return d;
            }
    }
    return d;
}

std::vector<std::pair<std::size_t, std::size_t>> wall_pairs(const Model& model) {
    const std::size_t c = model.contacts();
    const auto& pieces = model.pieces();
    // Facet hyperplane -> the cones having a facet in it, by side.
    std::map<Vector, std::pair<std::vector<std::size_t>, std::vector<std::size_t>>> sides;
    for (std::size_t p = 0; p < pieces.size(); ++p)
        for (std::size_t drop = 0; drop < c; ++drop) {
            std::vector<Vector> facet;
            for (std::size_t k = 0; k < c; ++k)
                if (k != drop)
                    facet.push_back(pieces[p].R.column(k));
            const Vector n = canonical_line(null_space(facet, c).at(0));
            auto& entry = sides[n];
            (sign_of(dot(n, pieces[p].R.column(drop))) == Sign::positive ? entry.first : entry.second).push_back(p);
        }
    std::set<std::pair<std::size_t, std::size_t>> pairs;
    for (const auto& [n, entry] : sides)
        for (auto a : entry.first)
            for (auto b : entry.second)
                if (a != b && pieces[a].Q != pieces[b].Q)
                    pairs.insert({std::min(a, b), std::max(a, b)});
    return {pairs.begin(), pairs.end()};
}

std::size_t intersection_subsets(std::size_t c) {
    // C(2c, c-1), exactly (the running product of binomials stays integral).
    std::size_t n = 2 * c, k = c - 1, out = 1;
    for (std::size_t i = 1; i <= k; ++i)
        out = out * (n - k + i) / i;
    return out;
}

namespace {

// det of the n x n integer matrix a (n <= 5; destroyed) by Bareiss's fraction-free elimination:
// exact in int128 while products of two minors of a fit (intersection_rays's entry bounds B).
intk::i128 bareiss_det(intk::i128 (&a)[5][5], std::size_t n) {
    if (n == 0)
        return 1; // the empty determinant
    intk::i128 prev = 1;
    int sign = 1;
    for (std::size_t k = 0; k < n; ++k) {
        std::size_t p = k;
        while (p < n && a[p][k] == 0)
            ++p;
        if (p == n)
            return 0;
        if (p != k) {
            for (std::size_t q = 0; q < n; ++q)
                std::swap(a[p][q], a[k][q]);
            sign = -sign;
        }
        for (std::size_t r = k + 1; r < n; ++r) {
            for (std::size_t q = k + 1; q < n; ++q)
                a[r][q] = (a[r][q] * a[k][k] - a[r][k] * a[k][q]) / prev;
            a[r][k] = 0;
        }
        prev = a[k][k];
    }
    return sign * a[n - 1][n - 1];
}

// An int128 as a Rational, exactly (its magnitude in two 62-bit halves).
Rational rational_of(intk::i128 x) {
    const bool negative = x < 0;
    const intk::i128 m = negative ? -x : x; // |x| < 2^125 (the callers' bound: minors below 2^70)
    const intk::i128 low_mask = (static_cast<intk::i128>(1) << 62) - 1;
    Rational r = Rational(static_cast<long>(m >> 62)) * Rational(static_cast<long>(1LL << 62)) +
                 Rational(static_cast<long>(m & low_mask));
    return negative ? -r : r;
}

} // namespace

std::vector<Vector> intersection_rays(const Model& model, std::size_t i, std::size_t j,
                                      std::size_t& subsets) {
    const std::size_t c = model.contacts();
    const Piece& a = model.pieces()[i];
    const Piece& b = model.pieces()[j];
    // x = G s, s >= 0, with G = R_a (all of C_a); or, when a facet hyperplane n_k . x = 0 of C_a
    // (n_k row k of R_a^-1) leaves C_b on its other side (n_k . r <= 0 for every ray r of C_b),
    // C_a ∩ C_b = F ∩ C_b with F = C_a ∩ {n_k . x = 0} the facet spanned by the other c - 1 rays
    // of C_a: G = R_a without column k, one dimension less (proofs/README.md, "P1": the same
    // cone, so the same extreme rays, from C(2c-1, c-2) subsets instead of C(2c, c-1)).
    Matrix G = a.R;
    for (std::size_t k = 0; k < c && G.cols() == c; ++k) {
        const Vector n = a.R_inv.row(k);
        bool other_side = true;
        for (std::size_t r = 0; r < c && other_side; ++r)
            other_side = sign_of(dot(n, b.R.column(r))) != Sign::positive;
        if (other_side) {
            Matrix F(c, c - 1);
            for (std::size_t row = 0; row < c; ++row)
                for (std::size_t col = 0, out = 0; col < c; ++col)
                    if (col != k)
                        F(row, out++) = a.R(row, col);
            G = F;
        }
    }
    const std::size_t d = G.cols();
    if (d == 0) // one contact: the facet is the origin, C_a ∩ C_b = {0}, no ray
        return {};
    // s >= 0 and t = R_b^-1 G s >= 0: d + c constraints on s.
    const Matrix T = b.R_inv * G;
    std::vector<Vector> constraints;
    for (std::size_t k = 0; k < d; ++k)
        constraints.push_back(unit_vector(d, k));
    for (std::size_t k = 0; k < c; ++k)
        constraints.push_back(T.row(k));
    auto feasible = [&](const Vector& sv) {
        return std::all_of(constraints.begin(), constraints.end(),
                           [&](const Vector& g) { return sign_of(dot(g, sv)) != Sign::negative; });
    };
    // The integer path (proofs/README.md, "Integer kernels"): each constraint scaled by a positive
    // integer (the same half-space), entries bounded (below), d <= 6. The null space of d-1 rows
    // of rank d-1 is spanned by their signed maximal minors m (Cramer), computed by fraction-free
    // elimination in int128, and the sign tests g . (+-m) are exact in int128. The same subsets and the same candidate directions
    // +-m (a positive multiple of the GMP path's), so the same primitive rays and the same count.
    // Entries at most B: every minor of order d-1 is at most (d-1)! B^(d-1), Bareiss multiplies
    // two of them, and a sign test sums d products of an entry and a minor, all below 2^126 with
    // B = 2^20 for d <= 4, 2^14 for d = 5 and 2^11 for d = 6.
    const intk::i64 B = d <= 4 ? (1 << 20) : d == 5 ? (1 << 14) : (1 << 11);
    std::vector<std::vector<intk::i64>> ints;
    bool integer = d <= 6;
    for (std::size_t k = 0; k < constraints.size() && integer; ++k) {
        auto v = intk::to_int_scaled(constraints[k]);
        integer = v.has_value();
        if (integer && std::any_of(v->begin(), v->end(), [](intk::i64 x) { return x != 0; }))
            intk::make_primitive(*v); // divided by a positive gcd: the same half-space
        if (integer)
            for (auto x : *v)
                integer = integer && x <= B && x >= -B;
        if (integer)
            ints.push_back(std::move(*v));
    }
    // Every extreme ray of the pointed cone {s : constraints >= 0} is the one-dimensional
    // solution set of d-1 independent tight constraints: try every such subset.
    std::set<Vector> rays;
    std::set<std::array<intk::i128, 6>> directions; // the integer path's, mapped to rays at the end
    std::vector<std::size_t> pick(d - 1);
    for (std::size_t k = 0; k + 1 < d; ++k)
        pick[k] = k;
    const std::size_t total = constraints.size();
    while (true) {
        ++subsets;
        if (integer) {
            // m_k = (-1)^k det(rows without column k).
            intk::i128 m[6] = {};
            bool zero = true;
            for (std::size_t col = 0; col < d; ++col) {
                intk::i128 sub[5][5];
                for (std::size_t r = 0; r + 1 < d; ++r)
                    for (std::size_t q = 0, out = 0; q < d; ++q)
                        if (q != col)
                            sub[r][out++] = ints[pick[r]][q];
                m[col] = ((col % 2) ? -1 : 1) * bareiss_det(sub, d - 1);
                zero = zero && m[col] == 0;
            }
            if (!zero)
                for (int sign : {1, -1}) {
                    bool ok = true;
                    for (std::size_t g = 0; g < ints.size() && ok; ++g) {
                        intk::i128 dt = 0;
                        for (std::size_t q = 0; q < d; ++q)
                            dt += static_cast<intk::i128>(ints[g][q]) * m[q];
                        ok = sign * dt >= 0;
                    }
                    if (ok) {
                        intk::i128 gcd = 0;
                        for (std::size_t q = 0; q < d; ++q) {
                            intk::i128 y = m[q] < 0 ? -m[q] : m[q];
                            while (y) {
                                const intk::i128 t = gcd % y;
                                gcd = y;
                                y = t;
                            }
                        }
                        // Reduced and signed: one entry per direction (subsets repeat them).
                        std::array<intk::i128, 6> key{};
                        for (std::size_t q = 0; q < d; ++q)
                            key[q] = sign * (m[q] / gcd);
                        directions.insert(key);
                    }
                }
        } else {
            std::vector<Vector> rows;
            for (auto k : pick)
                rows.push_back(constraints[k]);
            const auto ns = null_space(rows, d);
            if (ns.size() == 1)
                for (const Vector& sv : {ns[0], Rational(-1) * ns[0]})
                    if (feasible(sv))
                        rays.insert(primitive_ray(G * sv));
        }
        // Next (d-1)-subset of {0..total-1} in lexicographic order.
        std::size_t k = d - 1;
        while (k > 0 && pick[k - 1] == total - (d - 1) + (k - 1))
            --k;
        if (k == 0)
            break;
        ++pick[k - 1];
        for (std::size_t l = k; l < d - 1; ++l)
            pick[l] = pick[l - 1] + 1;
    }
    for (const auto& key : directions) {
        Vector sv;
        for (std::size_t q = 0; q < d; ++q)
            sv.push_back(rational_of(key[q]));
        rays.insert(primitive_ray(G * sv));
    }
    return {rays.begin(), rays.end()};
}

} // namespace impactcert
