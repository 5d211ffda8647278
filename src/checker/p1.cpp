// SPDX-License-Identifier: GPL-3.0-or-later
// The Checker's P1 (proofs/README.md, "P1 (continuity)"): the pairs to examine (across walls,
// or every pair with different matrices, walked without listing them), the extreme rays of
// their intersections, and the rays shared by two pieces, each in the prover's order.
#include "checker.hpp"

#include "tiling.hpp"

#include <algorithm>
#include <cstdint>
#include <set>

namespace impactcert_check::detail {

// Pairs i < j, Q_i != Q_j, with facets in one hyperplane on opposite sides.
std::vector<std::pair<std::size_t, std::size_t>> Checker::across_walls() const {
    std::map<Vec, std::pair<std::set<std::size_t>, std::set<std::size_t>>> sides;
    for (std::size_t p = 0; p < P(); ++p)
        for (std::size_t drop = 0; drop < law_.c; ++drop) {
            std::vector<Vec> facet;
            for (std::size_t k = 0; k < law_.c; ++k)
                if (k != drop)
                    facet.push_back(pc(p).rays[k]);
            const Vec n = canonical_line(kernel(facet, law_.c).at(0));
            (sgn(dot(n, pc(p).rays[drop])) > 0 ? sides[n].first : sides[n].second).insert(p);
        }
    std::set<std::pair<std::size_t, std::size_t>> out;
    for (const auto& [n, two] : sides)
        for (auto a : two.first)
            for (auto b : two.second)
                if (a != b && pc(a).Q_ != pc(b).Q_)
                    out.insert({std::min(a, b), std::max(a, b)});
    return {out.begin(), out.end()};
}

// The extreme rays of C_i ∩ C_j = {R_i s : s >= 0, R_j^-1 R_i s >= 0}: for every choice of
// c-1 of the 2c constraints whose solutions form a line, the directions on it that satisfy
// all constraints. Primitive, sorted.
std::vector<Vec> Checker::intersection_rays(std::size_t i, std::size_t j) const {
    const std::size_t c = law_.c;
    const Mat T = mul(pc(j).R_inv, pc(i).R);
    std::vector<Vec> cons;
    for (std::size_t k = 0; k < c; ++k) {
        Vec e(c, Q(0));
        e[k] = 1;
        cons.push_back(e);
    }
    for (const auto& row : T)
        cons.push_back(row);
    std::vector<Vec> out;
    std::vector<bool> chosen(cons.size(), false);
    std::fill(chosen.end() - static_cast<std::ptrdiff_t>(c - 1), chosen.end(), true);
    do {
        std::vector<Vec> rows;
        for (std::size_t k = 0; k < cons.size(); ++k)
            if (chosen[k])
                rows.push_back(cons[k]);
        const auto line = kernel(rows, c);
        if (line.size() != 1)
            continue;
        for (int sign : {1, -1}) {
            Vec s = line[0];
            for (auto& x : s)
                x *= sign;
            if (std::all_of(cons.begin(), cons.end(), [&](const Vec& g) { return sgn(dot(g, s)) >= 0; })) {
                const Vec ray = primitive(mul(pc(i).R, s));
                if (std::find(out.begin(), out.end(), ray) == out.end())
                    out.push_back(ray);
            }
        }
    } while (std::next_permutation(chosen.begin(), chosen.end()));
    std::sort(out.begin(), out.end());
    return out;
}

// C(2c, c-1): the constraint subsets intersection_rays tries for one pair, saturating at
// the largest size_t (the prover's intersection_subsets, src/prover/fan.cpp, without overflow).
std::size_t Checker::subsets_per_pair() const {
    const std::size_t n = 2 * law_.c, k = law_.c - 1;
    mpz_class out;
    mpz_bin_uiui(out.get_mpz_t(), n, k);
    return out.fits_ulong_p() ? static_cast<std::size_t>(out.get_ui()) : SIZE_MAX;
}

// Pieces numbered by their matrix (equal Q, equal class), and for each piece the next one
// after it in another class: enough to walk the pairs i < j with Q_i != Q_j in order
// without listing them all (P^2 / 2 of them) or comparing matrices pair by pair.
void Checker::number_matrices() {
    if (!q_class_.empty())
        return;
    std::map<Mat, std::size_t> classes;
    std::map<std::size_t, std::size_t> sizes;
    for (std::size_t p = 0; p < P(); ++p) {
        q_class_.push_back(classes.emplace(pc(p).Q_, classes.size()).first->second);
        ++sizes[q_class_.back()];
    }
    next_other_.assign(P(), P());
    for (std::size_t p = P() - 1; p-- > 0;)
        next_other_[p] = q_class_[p + 1] != q_class_[p] ? p + 1 : next_other_[p + 1];
    distinct_pairs_ = P() * (P() - 1) / 2;
    for (const auto& [cls, size] : sizes)
        distinct_pairs_ -= size * (size - 1) / 2;
}

// The pair after (i, j) (start with (0, 0)) among i < j with Q_i != Q_j; false at the end.
bool Checker::next_distinct_pair(std::size_t& i, std::size_t& j) const {
    for (++j;; j = i + 1) {
        if (j <= i)
            j = i + 1;
        while (j < P() && q_class_[j] == q_class_[i])
            j = next_other_[j]; // the next piece in another class than j's, which is i's
        if (j < P())
            return true;
        if (++i >= P())
            return false;
    }
}

// P1 when the cones do not meet face to face: every pair with different matrices, the
// extreme rays of the intersection of their cones, both matrices agreeing on each.
bool Checker::p1_intersections(const Json& data, const std::string& dp) {
    // With a tiling (walls) only pairs across a common facet hyperplane, else every pair.
    const bool walls = law_.c != 2 && walls_tile();
    std::vector<std::pair<std::size_t, std::size_t>> wall_pairs;
    std::size_t count = 0;
    if (walls) {
        wall_pairs = across_walls();
        count = wall_pairs.size();
    } else {
        number_matrices();
        count = distinct_pairs_;
    }
    // The prover's --max-subsets (src/prover/obligations/p1.cpp), before any intersection is computed.
    const std::size_t per_pair = subsets_per_pair();
    if (count > 0 && per_pair > limits_.max_subsets / count)
        undecided("--max-subsets", at(dp, "intersections"),
                  "the intersections of " + std::to_string(count) + " pairs of cones need " + std::to_string(per_pair) +
                      " constraint subsets each, more than " + std::to_string(limits_.max_subsets) + " in all");
    const Json& l = list(data, dp, "intersections");
    require(l.size() <= count, at(dp, "intersections"), "too many entries");
    bool ok = true;
    std::size_t i = 0, j = 0;
    for (std::size_t k = 0; k < l.size(); ++k) {
        if (walls)
            std::tie(i, j) = wall_pairs[k];
        else
            next_distinct_pair(i, j);
        const std::string ep = at(at(dp, "intersections"), k);
        expect_keys(l[k], ep, {"piece_a", "piece_b", "rays"});
        expect_piece(l[k], ep, "piece_a", i);
        expect_piece(l[k], ep, "piece_b", j);
        const std::vector<Vec> rays = intersection_rays(i, j);
        require(listed_rays(field(l[k], ep, "rays"), at(ep, "rays")) == rays, at(ep, "rays"),
                "are not the extreme rays of the intersection (primitive, sorted)");
        bool this_ok = true;
        for (const auto& r : rays)
            this_ok = this_ok && mul(pc(i).Q_, r) == mul(pc(j).Q_, r);
        ends_at_first_failure(this_ok, k, l.size(), at(dp, "intersections"));
        ok = ok && this_ok;
    }
    complete_unless_failed(!ok, l.size(), count, at(dp, "intersections"));
    return ok;
}

// The rays shared by two pieces, in the prover's order (pairs i < j, then the rays of i in
// order), at most `limit` of them: generated from the pieces through each ray, so that the
// work follows the evidence listed rather than the P^2 / 2 pairs.
// With the symmetries holding: the pairs (i, j), i one piece per orbit (firsts) and j != i any
// piece, in that order.
std::vector<std::tuple<std::size_t, std::size_t, Vec>> Checker::shared_rays(std::size_t limit) {
    std::vector<std::vector<std::size_t>> through(law_.distinct_rays.size()); // pieces in order
    for (std::size_t p = 0; p < P(); ++p)
        for (const auto& r : pc(p).rays)
            through[ray_id(r)].push_back(p);
    const bool reduced = symmetry_check().hold;
    const std::vector<std::size_t> first_pieces = firsts();
    std::vector<std::tuple<std::size_t, std::size_t, Vec>> out;
    for (std::size_t f = 0; f < first_pieces.size() && out.size() < limit; ++f) {
        const std::size_t i = first_pieces[f];
        std::vector<std::pair<std::size_t, std::size_t>> mine; // (j, index of the ray in i)
        for (std::size_t a = 0; a < law_.c; ++a) {
            // The first `limit` pieces after i (any piece but i, reduced) through this ray
            // (sorted) are all that can be among the first `limit` pairs of piece i.
            const auto& ps = through[ray_id(pc(i).rays[a])];
            auto it = reduced ? ps.begin() : std::upper_bound(ps.begin(), ps.end(), i);
            for (std::size_t taken = 0; it != ps.end() && taken < limit; ++it) {
                if (*it == i)
                    continue;
                mine.emplace_back(*it, a);
                ++taken;
            }
        }
        std::sort(mine.begin(), mine.end());
        for (const auto& [j, a] : mine)
            if (out.size() < limit)
                out.emplace_back(i, j, pc(i).rays[a]);
    }
    return out;
}

// Whether two pieces differ on a ray they share (in the order of shared_rays), walked without
// listing the pairs: the prover looks there first when the cones do not meet face to face.
bool Checker::first_differing_shared_ray() {
    std::vector<std::vector<std::size_t>> through(law_.distinct_rays.size());
    for (std::size_t p = 0; p < P(); ++p)
        for (const auto& r : pc(p).rays)
            through[ray_id(r)].push_back(p);
    const bool reduced = symmetry_check().hold;
    for (const std::size_t i : firsts())
        for (const auto& v : pc(i).rays) {
            const Vec qi = mul(pc(i).Q_, v);
            for (const std::size_t j : through[ray_id(v)])
                if (j != i && (reduced || j > i) && mul(pc(j).Q_, v) != qi)
                    return true;
        }
    return false;
}

} // namespace impactcert_check::detail
