// SPDX-License-Identifier: GPL-3.0-or-later
// The Checker's fan (proofs/README.md, "fan", and "What the checker establishes", 5): the
// evidence of each method re-decided independently (sectors for c = 2, the facet criterion, the
// walls, the gap beside a facet with one cone, the canonical chamber points counted by a second
// route), and whether S is a function,
// with the canonical domain witness.
#include "checker.hpp"

#include "tiling.hpp"

#include <algorithm>
#include <set>

namespace impactcert_check::detail {

namespace {

// The test direction of the sector from lo to hi: lo + hi when the sector spans less than
// pi, else the quarter turn of lo.
Vec sector_point(const Vec& lo, const Vec& hi, std::size_t m) {
    if (m > 1 && sign_det2(lo, hi) > 0)
        return Vec{lo[0] + hi[0], lo[1] + hi[1]};
    return Vec{-lo[1], lo[0]};
}

Json jvec(const Vec& v) {
    Json a = Json::array();
    for (const auto& x : v)
        a.push_back(x.get_str());
    return a;
}

} // namespace

// The distinct rays (c = 2) in angular order from the positive gamma1 axis, as the prover
// sorts them.
std::vector<Vec> Checker::rays_by_angle() const {
    std::vector<Vec> sorted = law_.distinct_rays;
    auto half = [](const Vec& v) { return (sgn(v[1]) > 0 || (sgn(v[1]) == 0 && sgn(v[0]) > 0)) ? 0 : 1; };
    std::sort(sorted.begin(), sorted.end(), [&](const Vec& a, const Vec& b) {
        return half(a) != half(b) ? half(a) < half(b) : sign_det2(a, b) > 0;
    });
    return sorted;
}

// For c = 2: how many open cones contain each open sector (sector k runs counter-clockwise
// from sorted[k] to sorted[k + 1]). A cone's rays are two of the sorted rays, so the cone
// contains exactly the sectors of the arc (less than pi) between them: one pass over the
// pieces with a circular difference array, instead of testing every piece at every sector
// point (P^2 work for P sectors).
std::vector<std::size_t> Checker::planar_cover(const std::vector<Vec>& sorted) const {
    const std::size_t m = sorted.size();
    std::map<Vec, std::size_t> position;
    for (std::size_t k = 0; k < m; ++k)
        position[sorted[k]] = k;
    std::vector<long> delta(m + 1, 0);
    for (std::size_t p = 0; p < P(); ++p) {
        const Vec &r0 = pc(p).rays[0], &r1 = pc(p).rays[1];
        // Counter-clockwise from `from` to `to` spans less than pi (the rays are independent).
        const bool ccw = sign_det2(r0, r1) > 0;
        const std::size_t from = position.at(ccw ? r0 : r1), to = position.at(ccw ? r1 : r0);
        ++delta[from];
        --delta[to];
        if (from > to) { // wraps past sorted[0]
            ++delta[0];
            --delta[m];
        }
    }
    std::vector<std::size_t> cover;
    long running = 0;
    for (std::size_t k = 0; k < m; ++k)
        cover.push_back(static_cast<std::size_t>(running += delta[k]));
    return cover;
}

bool Checker::fan_planar(const Json& data, const std::string& dp) {
    require(law_.c == 2, at(dp, "rays_by_angle"), "the angular method needs c = 2");
    std::vector<Vec> listed;
    const Json& rl = list(data, dp, "rays_by_angle");
    for (std::size_t k = 0; k < rl.size(); ++k)
        listed.push_back(vec(rl[k], at(at(dp, "rays_by_angle"), k)));
    const std::vector<Vec> sorted = rays_by_angle();
    std::vector<Vec> a = listed, b = sorted;
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    require(a == b, at(dp, "rays_by_angle"), "is not the set of distinct rays");
    require(listed == sorted, at(dp, "rays_by_angle"), "not in angular order from the positive gamma1 axis");
    const std::size_t m = sorted.size();
    const Json& points = list(data, dp, "sector_points");
    require(points.size() == m, at(dp, "sector_points"), "is not one point per sector");
    fan_points_.clear();
    for (std::size_t k = 0; k < points.size(); ++k) {
        const Vec d = vec(points[k], at(at(dp, "sector_points"), k));
        require(d.size() == 2, at(at(dp, "sector_points"), k), "wrong size");
        const Vec &lo = sorted[k], &hi = sorted[(k + 1) % m];
        require(d == sector_point(lo, hi, m), at(at(dp, "sector_points"), k), "is not the sector's test direction");
        const bool on_lo = sign_det2(lo, d) == 0 && sgn(dot(lo, d)) > 0;
        require(!on_lo && ccw_before(lo, d, hi), at(at(dp, "sector_points"), k), "not strictly inside its sector");
        fan_points_.push_back(d);
    }
    // Each point is strictly inside its sector, so the cones containing it are those
    // containing the sector.
    fan_cover_ = planar_cover(sorted);
    return std::all_of(fan_cover_.begin(), fan_cover_.end(), [](std::size_t n) { return n == 1; });
}

// Facets keyed by their ray ids (first appearance in the law), owners in piece order.
const std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, int>>>& Checker::all_facets() const {
    if (facets_)
        return *facets_; // computed once: the fan's evidence, its criterion and the generic point use it
    auto& facets = facets_.emplace();
    for (std::size_t p = 0; p < P(); ++p)
        for (std::size_t drop = 0; drop < law_.c; ++drop) {
            std::vector<std::size_t> ids;
            for (std::size_t k = 0; k < law_.c; ++k)
                if (k != drop)
                    ids.push_back(ray_id(pc(p).rays[k]));
            std::sort(ids.begin(), ids.end());
            std::vector<Vec> cols;
            for (auto id : ids)
                cols.push_back(law_.distinct_rays[id]);
            cols.push_back(pc(p).rays[drop]);
            facets[ids].push_back({p, sgn(det(from_cols(cols)))});
        }
    return facets;
}

std::vector<Vec> Checker::facet_rays(const std::vector<std::size_t>& ids) const {
    std::vector<Vec> out;
    for (auto id : ids)
        out.push_back(law_.distinct_rays[id]);
    return out;
}

std::vector<Vec> Checker::listed_rays(const Json& l, const std::string& path) const {
    std::vector<Vec> out;
    if (!l.is_array())
        malformed(path, "expected an array of rays");
    for (std::size_t r = 0; r < l.size(); ++r)
        out.push_back(vec(l[r], at(path, r)));
    return out;
}

std::vector<std::string> Checker::listed_names(const Json& l, const std::string& path) const {
    std::vector<std::string> out;
    if (!l.is_array())
        malformed(path, "expected an array of piece names");
    for (const auto& o : l)
        out.push_back(str(o, path));
    return out;
}

Vec Checker::generic_point() const {
    if (generic_point_)
        return *generic_point_;
    const auto& facets = all_facets();
    for (long t = 1;; ++t) {
        Vec p(law_.c);
        Q power = 1;
        for (std::size_t i = 0; i < law_.c; ++i, power *= t)
            p[i] = power;
        bool generic = true;
        for (const auto& entry : facets) {
            std::vector<Vec> cols = facet_rays(entry.first);
            cols.push_back(p);
            generic = generic && sgn(det(from_cols(cols))) != 0;
        }
        if (generic)
            return *(generic_point_ = p);
    }
}

bool Checker::fan_facets(const Json& data, const std::string& dp) {
    const auto& facets = all_facets();
    const Json& l = list(data, dp, "facets");
    require(l.size() == facets.size(), at(dp, "facets"), "does not list every facet");
    bool ok = true;
    std::size_t k = 0;
    for (const auto& [ids, owners] : facets) {
        const std::string ep = at(at(dp, "facets"), k);
        expect_keys(l[k], ep, {"rays", "pieces"});
        require(listed_rays(field(l[k], ep, "rays"), at(ep, "rays")) == facet_rays(ids), at(ep, "rays"),
                "is not the next facet");
        std::vector<std::string> names;
        for (const auto& [p, side] : owners)
            names.push_back(name(p));
        require(listed_names(field(l[k], ep, "pieces"), at(ep, "pieces")) == names, at(ep, "pieces"),
                "are not the cones having this facet");
        ok = ok && owners.size() == 2 && owners[0].second != owners[1].second;
        ++k;
    }
    if (!ok) {
        require(!data.contains("generic_point"), at(dp, "generic_point"), "listed although a facet is unmatched");
        return false;
    }
    const Vec p = vec(field(data, dp, "generic_point"), at(dp, "generic_point"));
    require(p == generic_point(), at(dp, "generic_point"), "is not the first generic point of the moment curve");
    fan_points_ = {p};
    fan_cover_ = {law_.interiors(p).size()};
    return fan_cover_[0] == 1;
}

// The prover's gap rule, with this checker's arithmetic: for the first 64 facets with one cone
// (in the order of their sorted ray ids), y = 2 (the sum of the facet's rays) - (the cone's other
// ray); the first y in no closed cone.
std::optional<Checker::GapPoint> Checker::gap_point() const {
    std::size_t tried = 0;
    for (const auto& [ids, owners] : all_facets()) {
        if (owners.size() != 1)
            continue;
        if (tried++ == 64)
            break;
        const std::size_t p = owners.front().first;
        Vec y(law_.c, Q(0));
        for (const auto& r : pc(p).rays) {
            const std::size_t id = ray_id(r);
            const int weight = std::binary_search(ids.begin(), ids.end(), id) ? 2 : -1;
            for (std::size_t i = 0; i < law_.c; ++i)
                y[i] += weight * law_.distinct_rays[id][i];
        }
        bool in_none = true;
        for (std::size_t q = 0; q < P() && in_none; ++q)
            in_none = !law_.in_cone(q, y);
        if (in_none)
            return GapPoint{ids, p, y};
    }
    return std::nullopt;
}

// The fast path: every facet shared by exactly two cones on opposite sides, and the first
// generic point of the moment curve covered once.
bool Checker::facet_criterion() const {
    for (const auto& [ids, owners] : all_facets())
        if (owners.size() != 2 || owners[0].second == owners[1].second)
            return false;
    return law_.interiors(generic_point()).size() == 1;
}

// The cones tile R^c, decided by walls (the checker's own recursion).
bool Checker::walls_tile() {
    if (!walls_tile_) {
        std::vector<WCone> family;
        for (std::size_t p = 0; p < P(); ++p)
            family.push_back({pc(p).rays, 1});
        walls_tile_ = walls_balance(family, law_.c, 1);
    }
    return *walls_tile_;
}

// The cones form a fan meeting face to face (then P1 is decided on shared rays).
bool Checker::face_to_face() {
    if (!face_to_face_) {
        if (law_.c == 2) {
            const auto cover = planar_cover(rays_by_angle());
            face_to_face_ = std::all_of(cover.begin(), cover.end(), [](std::size_t n) { return n == 1; });
        } else {
            face_to_face_ = facet_criterion();
        }
    }
    return *face_to_face_;
}

// The distinct facet hyperplanes, as sorted canonical normals.
std::vector<Vec> Checker::facet_hyperplanes() const {
    std::set<Vec> out;
    for (std::size_t p = 0; p < P(); ++p)
        for (std::size_t drop = 0; drop < law_.c; ++drop) {
            std::vector<Vec> rows;
            for (std::size_t k = 0; k < law_.c; ++k)
                if (k != drop)
                    rows.push_back(pc(p).rays[k]);
            out.insert(canonical_line(kernel(rows, law_.c).at(0)));
        }
    return {out.begin(), out.end()};
}

// Complete decision: the listed points lie on no facet hyperplane, in pairwise different
// chambers, as many as the arrangement has (counted by deletion and restriction).
bool Checker::fan_chambers(const Json& data, const std::string& dp) {
    const std::vector<Vec> planes = facet_hyperplanes();
    const Json& hl = list(data, dp, "hyperplanes");
    require(listed_rays(hl, at(dp, "hyperplanes")) == planes, at(dp, "hyperplanes"),
            "are not the facet hyperplanes (canonical normals, sorted)");
    const Json& pl = list(data, dp, "chamber_points");
    std::set<std::vector<int>> chambers;
    bool ok = true;
    fan_points_.clear();
    fan_cover_.clear();
    for (std::size_t k = 0; k < pl.size(); ++k) {
        const std::string ep = at(at(dp, "chamber_points"), k);
        const Vec x = vec(pl[k], ep);
        require(x.size() == law_.c, ep, "wrong size");
        std::vector<int> signs;
        for (const auto& n : planes) {
            signs.push_back(sgn(dot(n, x)));
            require(signs.back() != 0, ep, "lies on a facet hyperplane");
        }
        require(chambers.insert(signs).second, ep, "lies in the chamber of an earlier point");
        fan_cover_.push_back(law_.interiors(x).size());
        ok = ok && fan_cover_.back() == 1;
        fan_points_.push_back(x);
    }
    const std::size_t count = count_chambers(planes, law_.c, pl.size());
    require(count == pl.size(), at(dp, "chamber_points"),
            "misses a chamber: the arrangement has more chambers than points are listed");
    // Bounded by the listed points: each step of the enumeration emits at least one point;
    // and by the prover's --max-chambers, counted as the prover counts its steps.
    std::size_t budget = 4 * (pl.size() + 1) * (planes.size() + 1);
    ChamberSteps steps{0, limits_.max_chambers, at(dp, "chamber_points")};
    require(canonical_chamber_points(planes, law_.c, budget, steps) == fan_points_, at(dp, "chamber_points"),
            "are not the canonical chamber points (the prover's deletion and restriction)");
    return ok;
}

// Whether S is a function on R^c (no gap; overlapping interiors carry equal matrices), from
// the fan's validated test points; rejects when the fan is undecided.
bool Checker::s_is_a_function(const std::string& path) {
    const Truth fan = holds("fan");
    require(fan != Truth::undecided, path, "the fan is undecided: S is not known to be a function");
    return fan == Truth::proved || !domain_witness();
}

// The canonical witness that S is not a function (the prover's rule, proofs/README.md):
// the first test point in no cone, or the first covered by two cones with different
// matrices, moved off the kernel of their difference when needed.
std::optional<Json> Checker::domain_witness() {
    if (domain_)
        return *domain_;
    domain_ = std::optional<Json>();
    if (holds("fan") != Truth::refuted)
        return *domain_;
    const std::size_t c = law_.c;
    for (std::size_t k = 0; k < fan_points_.size(); ++k) {
        if (fan_cover_[k] == 1)
            continue;
        const Vec& x = fan_points_[k];
        const auto cov = law_.interiors(x);
        if (cov.empty()) {
            domain_ = Json{{"via", "fan"}, {"gamma", jvec(x)}, {"interior_of", Json::array()},
                           {"reason", "S is undefined at gamma: it lies in no cone"}};
            return *domain_;
        }
        for (std::size_t u = 0; u < cov.size(); ++u)
            for (std::size_t v = u + 1; v < cov.size(); ++v) {
                const std::size_t a = cov[u], b = cov[v];
                const Mat diff = sub(pc(a).Q_, pc(b).Q_);
                if (diff == zeros(c, c))
                    continue;
                auto vanishes = [&](const Vec& y) {
                    const Vec d = mul(diff, y);
                    return std::all_of(d.begin(), d.end(), [](const Q& q) { return sgn(q) == 0; });
                };
                Vec y = x;
                for (std::size_t e = 0; e < c && vanishes(y); ++e) {
                    Q delta = 1;
                    for (std::size_t p : {a, b}) {
                        const Vec sx = mul(pc(p).R_inv, x);
                        for (std::size_t i = 0; i < c; ++i)
                            if (sgn(pc(p).R_inv[i][e]) < 0)
                                delta = std::min(delta, Q(sx[i] / (2 * abs(pc(p).R_inv[i][e]))));
                    }
                    y = x;
                    y[e] += delta;
                    y = primitive(y);
                }
                require(!vanishes(y), "$.obligations[0].data", "two different matrices agree on a basis");
                Json names = Json::array();
                for (auto p : law_.interiors(y))
                    names.push_back(name(p));
                domain_ = Json{{"via", "fan"}, {"gamma", jvec(y)}, {"interior_of", names},
                               {"reason", "S is two-valued near gamma: it is interior to two cones whose matrices differ there"}};
                return *domain_;
            }
    }
    return *domain_;
}

} // namespace impactcert_check::detail
