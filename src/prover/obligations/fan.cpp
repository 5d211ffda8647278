// SPDX-License-Identifier: GPL-3.0-or-later
// fan -- proofs/README.md, "fan": Lemma T (tiling = N ≡ 1 off the hyperplanes), "Check, c = 2",
// "Check, any c", "Check, walls", "Check, complete", and "S as a function".
// Claim: the cones tile R^c (union R^c, interiors pairwise disjoint); they need not meet face
// to face. By Lemma T they tile iff N(x) = #{i : x in int C_i} = 1 at every generic x.
// Check (check_fan, src/prover/fan.cpp): N = 1 at one direction per angular sector (c = 2); else every
// facet matched by one cone on its other side and N = 1 at one generic point; else the walls
// balance; else a point outside a facet that no other cone has lies in no cone (a gap); else
// N = 1 at one point of every chamber of the facet arrangement. The first test
// point covered k != 1 times is the witness. S is a function (check_domain) iff at every test
// point of a complete method N >= 1 and the cones containing it have equal matrices.
#include "prover/obligations/prover.hpp"

#include <string>
#include <vector>

namespace impactcert::detail {

const FanResult& Prover::fan_result() {
    if (fan_limit_)
        throw *fan_limit_;
    if (!fan_) {
        try {
            fan_ = check_fan(m_, limits_);
        } catch (const LimitExceeded& e) {
            fan_limit_ = e;
            throw;
        }
    }
    return *fan_;
}

const DomainResult& Prover::domain() {
    if (!domain_)
        domain_ = check_domain(m_, fan_result());
    return *domain_;
}

Outcome Prover::fan() {
    const FanResult& f = fan_result();
    Outcome o;
    o.checks = f.checks;
    o.method = f.method;
    if (limits_.evidence) {
        Json points = Json::array();
        for (const auto& p : f.test_points)
            points.push_back(to_json(p));
        if (f.method == "angular-sectors") {
            Json rays = Json::array();
            for (const auto& r : f.rays_by_angle)
                rays.push_back(to_json(r));
            o.data["rays_by_angle"] = rays;
            o.data["sector_points"] = points;
        } else if (f.method == "facet-matching") {
            Json facets = Json::array();
            for (const auto& fc : f.facets) {
                Json rays = Json::array();
                for (const auto& r : fc.rays)
                    rays.push_back(to_json(r));
                facets.push_back(Json{{"rays", rays}, {"pieces", names_of(fc.pieces)}});
            }
            o.data["facets"] = facets;
            o.data["generic_point"] = points.at(0);
        } else if (f.method == "unmatched-facet") {
            Json rays = Json::array();
            for (const auto& r : f.facets.at(0).rays)
                rays.push_back(to_json(r));
            o.data["facet"] = Json{{"rays", rays}, {"pieces", names_of(f.facets.at(0).pieces)}};
            o.data["gap_point"] = points.at(0);
        } else {
            Json planes = Json::array();
            for (const auto& n : f.hyperplanes)
                planes.push_back(to_json(n));
            o.data["hyperplanes"] = planes;
            if (f.method == "walls")
                o.data["generic_point"] = points.at(0);
            else
                o.data["chamber_points"] = points;
        }
    }
    if (!f.proved) {
        const std::size_t k = *f.failing;
        const Vector& x = f.test_points[k];
        const auto& cov = f.covering[k];
        // Re-validate: a point in no closed cone, or in two interiors.
        ensure(cov.size() >= 2 || m_.pieces_containing(x).empty(), "fan point");
        return refute(o, Json{{"gamma", to_json(x)}, {"interior_of", names_of(cov)},
                              {"reason", cov.empty() ? "gamma lies in no cone (the cones leave a gap)"
                                                     : "gamma lies in the interiors of " +
                                                           std::to_string(cov.size()) +
                                                           " cones (they overlap)"}});
    }
    return o;
}

// Obligations that need S to be a function on R^c: refuted by a point where S is undefined
// or two-valued on an open set (SPEC section 3, witness rules); nothing when S is one.
std::optional<Json> Prover::domain_witness() {
    const DomainResult& d = domain();
    if (d.function)
        return std::nullopt;
    const Vector& x = *d.point;
    if (d.interior_of.empty()) {
        ensure(m_.pieces_containing(x).empty(), "domain gap");
    } else {
        bool differ = false;
        for (auto a : d.interior_of)
            for (auto b : d.interior_of)
                differ = differ || pieces_[a].Q * x != pieces_[b].Q * x;
        ensure(differ, "domain two-valued");
    }
    return Json{{"via", "fan"}, {"gamma", to_json(x)}, {"interior_of", names_of(d.interior_of)},
                {"reason", d.reason}};
}

} // namespace impactcert::detail
