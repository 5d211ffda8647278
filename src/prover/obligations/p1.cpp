// SPDX-License-Identifier: GPL-3.0-or-later
// P1 -- proofs/README.md, "P1 (continuity)", with Lemma R (rays suffice for linear statements).
// Claim: Q_i x = Q_j x for every x in C_i ∩ C_j (with S a function: S is continuous).
// Check, face to face (the fan's fast path): Q_i v = Q_j v on every ray v shared by two pieces,
// since then C_i ∩ C_j = cone(shared rays). Not face to face, the shared rays first too: a
// shared ray where two pieces differ is a point of both cones, a witness. Check, any cones: for every pair with Q_i != Q_j,
// the extreme rays of C_i ∩ C_j (every c-1 of its 2c constraints whose solutions form a line),
// Q_i r = Q_j r on each (Minkowski-Weyl and Lemma R); with the fan proved by walls, only the
// pairs across a common facet hyperplane. A ray where they differ is the witness.
#include "prover/obligations/prover.hpp"

#include <algorithm>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace impactcert::detail {

Json Prover::p1_witness(std::size_t i, std::size_t j, const Vector& x) {
    const Vector qi = pieces_[i].Q * x, qj = pieces_[j].Q * x;
    ensure(qi != qj, "P1 values differ");
    const auto in = m_.pieces_containing(x);
    ensure(std::find(in.begin(), in.end(), i) != in.end() && std::find(in.begin(), in.end(), j) != in.end(),
           "P1 point in both cones");
    p1_discontinuity_ = Discontinuity{i, j, x};
    return Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"gamma", to_json(x)},
                {"image_a", to_json(qi)}, {"image_b", to_json(qj)}};
}

Outcome Prover::p1() {
    if (p1_limit_)
        throw *p1_limit_;
    if (p1_)
        return *p1_;
    // The fast path of the fan is decided before its chamber enumeration, so a fan beyond
    // its limit means the cones do not meet face to face: P1 then needs intersections.
    bool face_to_face = false, walls = false;
    try {
        face_to_face = fan_result().fast_path;
        walls = fan_result().method == "walls";
    } catch (const LimitExceeded&) {
    }
    try {
        if (face_to_face) {
            p1_ = p1_shared_rays();
        } else {
            // Not face to face: the rays two pieces share come first (cheap, through the ray
            // index); one where they differ lies in both cones and refutes P1 at once. Only
            // when they all agree are the intersections enumerated.
            Outcome shared = p1_shared_rays();
            if (!shared.proved) {
                shared.method = "a shared ray where two pieces differ, before the intersections";
                p1_ = std::move(shared);
            } else {
                p1_ = p1_intersections(walls);
            }
        }
    } catch (const LimitExceeded& e) {
        p1_limit_ = e;
        throw;
    }
    return *p1_;
}

// The cones form a fan meeting face to face: agreement on shared rays, for the pairs i < j;
// with verified symmetries, for the pairs (i, j), j != i, with i an orbit representative
// ("Symmetries": (sigma i, sigma j) agrees on P (C_i ∩ C_j) when (i, j) agrees on C_i ∩ C_j).
Outcome Prover::p1_shared_rays() {
    Outcome o;
    o.method = "products on shared rays";
    const bool reduced = symmetry() != nullptr;
    const std::vector<std::size_t> firsts = orbit_representatives();
    o.method += by_symmetries();
    // The pieces through each ray of a first piece (ascending), found by the ray ids of the
    // Model (primitive rays, hashed once when the law is read): the work follows the shared
    // rays, not the P^2 / 2 pairs. Q_p v is computed once per (piece, ray).
    std::vector<char> wanted(m_.rays().size(), 0);
    for (const std::size_t i : firsts)
        for (const auto id : pieces_[i].ray_ids)
            wanted[id] = 1;
    std::unordered_map<std::size_t, std::vector<std::size_t>> through;
    for (std::size_t p = 0; p < pieces_.size(); ++p)
        for (const auto id : pieces_[p].ray_ids)
            if (wanted[id])
                through[id].push_back(p);
    std::unordered_map<std::size_t, Vector> images; // key p * c + slot
    auto image = [&](std::size_t p, std::size_t id) -> const Vector& {
        const auto& ids = pieces_[p].ray_ids;
        const std::size_t slot = static_cast<std::size_t>(std::find(ids.begin(), ids.end(), id) - ids.begin());
        auto [it, fresh] = images.try_emplace(p * c_ + slot);
        if (fresh)
            it->second = pieces_[p].Q * m_.rays()[id];
        return it->second;
    };
    for (std::size_t f = 0; f < firsts.size() && o.proved; ++f) {
        const std::size_t i = firsts[f];
        if (i % 64 == 0)
            report_progress("P1", f, firsts.size());
        std::vector<std::pair<std::size_t, std::size_t>> mine; // (j, slot of the ray in i), in order
        for (std::size_t a = 0; a < c_; ++a)
            for (const std::size_t j : through[pieces_[i].ray_ids[a]])
                if (j != i && (reduced || j > i))
                    mine.emplace_back(j, a);
        std::sort(mine.begin(), mine.end());
        for (const auto& [j, a] : mine) {
            const auto id = pieces_[i].ray_ids[a];
            const Vector& v = m_.rays()[id];
            const Vector& qi = image(i, id);
            const Vector& qj = image(j, id);
            ++o.checks;
            if (limits_.evidence)
                o.data["shared"].push_back(Json{{"piece_a", name(i)}, {"piece_b", name(j)},
                                                {"ray", to_json(v)}, {"image_a", to_json(qi)},
                                                {"image_b", to_json(qj)}});
            if (qi != qj) {
                o = refute(o, p1_witness(i, j, v));
                break;
            }
        }
    }
    return o;
}

// Any cones: for every pair with different matrices, the extreme rays of C_i ∩ C_j.
// With a tiling proved by walls, only pairs across a common facet hyperplane.
Outcome Prover::p1_intersections(bool across_walls) {
    Outcome o;
    o.method = across_walls ? "extreme rays of intersections across walls" : "extreme rays of pairwise intersections";
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    if (across_walls)
        pairs = wall_pairs(m_);
    else
        for (std::size_t i = 0; i < pieces_.size(); ++i)
            for (std::size_t j = i + 1; j < pieces_.size(); ++j)
                if (pieces_[i].Q != pieces_[j].Q)
                    pairs.emplace_back(i, j);
    const std::size_t per_pair = intersection_subsets(c_);
    if (!pairs.empty() && per_pair > limits_.max_subsets / pairs.size())
        throw LimitExceeded("the intersections of " + std::to_string(pairs.size()) +
                                " pairs of cones need " + std::to_string(per_pair) +
                                " constraint subsets each, more than " +
                                std::to_string(limits_.max_subsets) + " in all",
                            "--max-subsets");
    o.data["intersections"] = Json::array();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto [i, j] = pairs[k];
        const auto rays = intersection_rays(m_, i, j, o.checks);
        if (k % 256 == 0)
            report_progress("P1", k, pairs.size());
        Json listed = Json::array();
        for (const auto& r : rays)
            listed.push_back(to_json(r));
        o.data["intersections"].push_back(Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"rays", listed}});
        for (const auto& r : rays)
            if (pieces_[i].Q * r != pieces_[j].Q * r)
                return refute(o, p1_witness(i, j, r));
    }
    return o;
}

} // namespace impactcert::detail
