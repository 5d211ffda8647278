#include "fan.hpp"

#include <algorithm>
#include <map>
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

void fail_at_point(FanResult& r, const Vector& x, std::vector<std::size_t> covering) {
    r.proved = false;
    r.point = x;
    r.reason = covering.empty() ? "a direction lies in no cone (the cones do not cover R^c)"
                                : "a direction lies in the interior of " +
                                      std::to_string(covering.size()) + " cones (they overlap)";
    r.covering = std::move(covering);
}

} // namespace

FanResult check_fan_planar(const Model& model) {
    if (model.contacts() != 2)
        throw std::logic_error("check_fan_planar needs c = 2");
    FanResult r;
    r.method = "angular-sectors";
    std::vector<Vector> rays = model.rays();
    std::sort(rays.begin(), rays.end(), angle_less);
    r.rays_by_angle = rays;
    const std::size_t m = rays.size();
    for (std::size_t k = 0; k < m; ++k) {
        const Vector& a = rays[k];
        const Vector& b = rays[(k + 1) % m];
        // A direction strictly inside the open sector from a to b (counter-clockwise).
        Vector inside = (m > 1 && orientation(a, b) == Sign::positive) ? a + b
                                                                        : Vector{-a[1], a[0]};
        r.sector_points.push_back(inside);
        auto covering = interiors_containing(model, inside);
        r.checks += model.pieces().size();
        if (covering.size() != 1) {
            fail_at_point(r, inside, std::move(covering));
            return r;
        }
    }
    r.proved = true;
    return r;
}

FanResult check_fan_facets(const Model& model) {
    FanResult r;
    r.method = "facet-matching";
    const std::size_t c = model.contacts();
    const auto& pieces = model.pieces();
    struct Side {
        std::size_t piece;
        Sign side;
    };
    // Facet (sorted ray ids) -> the pieces having it, with the side of their remaining ray.
    std::map<std::vector<std::size_t>, std::vector<Side>> facets;
    auto facet_matrix = [&](const std::vector<std::size_t>& ids, const Vector& last) {
        std::vector<Vector> cols;
        for (auto id : ids)
            cols.push_back(model.rays()[id]);
        cols.push_back(last);
        return Matrix::from_columns(cols);
    };
    for (std::size_t p = 0; p < pieces.size(); ++p) {
        for (std::size_t drop = 0; drop < c; ++drop) {
            std::vector<std::size_t> ids;
            for (std::size_t k = 0; k < c; ++k)
                if (k != drop)
                    ids.push_back(pieces[p].ray_ids[k]);
            std::sort(ids.begin(), ids.end());
            const Sign side = sign_of(determinant(facet_matrix(ids, pieces[p].R.column(drop))));
            facets[ids].push_back({p, side});
            ++r.checks;
        }
    }
    for (const auto& [ids, sides] : facets) {
        FanResult::Facet record;
        for (auto id : ids)
            record.rays.push_back(model.rays()[id]);
        for (const auto& sd : sides)
            record.pieces.push_back(sd.piece);
        r.facets.push_back(std::move(record));
    }
    for (const auto& [ids, sides] : facets) {
        const bool ok = sides.size() == 2 && sides[0].side != sides[1].side;
        if (ok)
            continue;
        r.proved = false;
        r.piece = sides.front().piece;
        for (auto id : ids)
            r.facet.push_back(model.rays()[id]);
        for (std::size_t k = 1; k < sides.size(); ++k)
            r.neighbours.push_back(sides[k].piece);
        r.reason = sides.size() == 1 ? "a facet belongs to no other cone (the cones leave a gap)"
                   : sides.size() > 2 ? "a facet belongs to more than two cones (they overlap)"
                                      : "two cones sharing a facet lie on the same side of it "
                                        "(they overlap)";
        return r;
    }
    // One generic point: on the moment curve (1, t, t^2, ...), off every facet hyperplane. Each
    // hyperplane meets the curve in at most c-1 values of t, so the search terminates.
    Vector point(c);
    for (long t = 1;; ++t) {
        Rational power = 1;
        for (std::size_t i = 0; i < c; ++i, power *= Rational(t))
            point[i] = power;
        bool generic = true;
        for (const auto& entry : facets) {
            ++r.checks;
            if (sign_of(determinant(facet_matrix(entry.first, point))) == Sign::zero) {
                generic = false;
                break;
            }
        }
        if (generic)
            break;
    }
    r.generic_point = point;
    auto covering = interiors_containing(model, point);
    r.checks += pieces.size();
    if (covering.size() != 1) {
        fail_at_point(r, point, std::move(covering));
        return r;
    }
    r.proved = true;
    return r;
}

FanResult check_fan(const Model& model) {
    return model.contacts() == 2 ? check_fan_planar(model) : check_fan_facets(model);
}

} // namespace impactcert
