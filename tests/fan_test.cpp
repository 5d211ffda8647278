// SPDX-License-Identifier: GPL-3.0-or-later
#include "prover/fan.hpp"
#include "model/law_json.hpp"
#include "model/paper_law.hpp"
#include "support.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <optional>
#include <random>
#include <set>

using namespace impactcert;
using impactcert::test::source_path;
using impactcert::test::vec;

namespace {

Law two_d_law(std::vector<std::pair<const char*, std::vector<Vector>>> cones) {
    Law law;
    law.name = "fan-fixture";
    law.masses = vec({"1", "1", "1"});
    for (auto& [name, rays] : cones)
        law.pieces.push_back(PieceDecl{name, Matrix::identity(2), rays});
    return law;
}

// Every point off every hyperplane, one per chamber (sign vectors pairwise different).
void require_one_point_per_chamber(const std::vector<Vector>& normals, const std::vector<Vector>& points) {
    std::set<std::vector<int>> seen;
    for (const auto& x : points) {
        std::vector<int> signs;
        for (const auto& n : normals) {
            signs.push_back(static_cast<int>(sign_of(dot(n, x))));
            REQUIRE(signs.back() != 0);
        }
        REQUIRE(seen.insert(signs).second);
    }
}

std::vector<Vector> chambers(const std::vector<Vector>& normals, std::size_t d) {
    std::size_t steps = 0;
    std::vector<Vector> lines;
    for (const auto& n : normals)
        lines.push_back(canonical_line(n));
    const auto points = chamber_points(lines, d, 10000000, steps);
    require_one_point_per_chamber(lines, points);
    return points;
}

// Splits piece p of `law` through a point strictly inside the edge between its rays a and b.
void split_edge(Law& law, std::size_t p, std::size_t a, std::size_t b, const Rational& t) {
    PieceDecl piece = law.pieces[p];
    const auto rays = piece.rays.value();
    const Vector mid = t * rays[a] + (Rational(1) - t) * rays[b];
    PieceDecl first = piece, second = piece;
    first.name += ".1";
    second.name += ".2";
    auto r1 = rays, r2 = rays;
    r1[a] = mid;
    r2[b] = mid;
    first.rays = r1;
    second.rays = r2;
    law.pieces[p] = first;
    law.pieces.insert(law.pieces.begin() + static_cast<std::ptrdiff_t>(p) + 1, second);
}

} // namespace

TEST_CASE("fan: the paper's six cones cover the plane exactly once", "[fan]") {
    const Model m(paper_law());
    const auto r = check_fan(m, Limits{});
    CHECK(r.proved);
    CHECK(r.fast_path);
    CHECK(r.method == "angular-sectors");
    CHECK(r.checks == 36); // six sectors, six cones each
}

TEST_CASE("fan: chambers of known arrangements are counted exactly", "[fan][chambers]") {
    // Coordinate hyperplanes of R^d: 2^d orthants.
    for (std::size_t d = 1; d <= 6; ++d) {
        std::vector<Vector> normals;
        for (std::size_t k = 0; k < d; ++k)
            normals.push_back(unit_vector(d, k));
        CHECK(chambers(normals, d).size() == (std::size_t{1} << d));
    }
    // The braid arrangement of 4 velocities in contact coordinates (u_i = u_j, c = 3): 4! = 24.
    std::vector<Vector> braid;
    for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = i; j < 3; ++j) {
            Vector n(3);
            for (std::size_t k = i; k <= j; ++k)
                n[k] = 1;
            braid.push_back(n);
        }
    CHECK(chambers(braid, 3).size() == 24);
    // k lines through 0 in the plane: 2k sectors; k generic planes in R^3: k^2 - k + 2.
    CHECK(chambers({vec({"1", "0"}), vec({"0", "1"}), vec({"1", "1"}), vec({"1", "-2"})}, 2).size() == 8);
    CHECK(chambers({vec({"1", "0", "0"}), vec({"0", "1", "0"}), vec({"0", "0", "1"}), vec({"1", "1", "1"}),
                    vec({"1", "2", "-3"})},
                   3)
              .size() == 22);
}

TEST_CASE("fan: the chamber decision agrees with the angular sectors on every 2-contact law we ship", "[fan][chambers]") {
    for (const char* name : {"newton3/law", "controls/perturbed-entry", "controls/swapped-pieces",
                             "controls/missing-cone", "controls/newton-simultaneous",
                             "controls/discontinuous-isometric", "controls/expansive-scaled"}) {
        INFO(name);
        const Model m(load_law_file(source_path(std::string("proofs/") + name + ".json")));
        const auto normals = facet_hyperplanes(m);
        bool once = true;
        for (const auto& x : chambers(normals, 2)) {
            std::size_t k = 0;
            for (std::size_t p = 0; p < m.pieces().size(); ++p)
                k += m.in_interior(p, x) ? 1 : 0;
            once = once && k == 1;
        }
        CHECK(check_fan(m, Limits{}).proved == once);
    }
}

TEST_CASE("fan: a gap is found with a direction in no cone", "[fan]") {
    const Model m(two_d_law({{"Q1", {vec({"1", "0"}), vec({"0", "1"})}},
                             {"Q2", {vec({"0", "1"}), vec({"-1", "0"})}},
                             {"Q3", {vec({"-1", "0"}), vec({"0", "-1"})}}}));
    const auto r = check_fan(m, Limits{});
    REQUIRE_FALSE(r.proved);
    REQUIRE(r.failing);
    CHECK(m.pieces_containing(r.test_points[*r.failing]).empty());
    const auto d = check_domain(m, r);
    CHECK_FALSE(d.function);
    CHECK(m.pieces_containing(*d.point).empty());
}

TEST_CASE("fan: a cone counted twice around the origin is a double cover, not a fan", "[fan]") {
    // Six cones winding twice around the origin; every facet matches, only the count catches it.
    const Model m(two_d_law({{"a", {vec({"1", "0"}), vec({"-1", "1"})}},
                             {"b", {vec({"-1", "1"}), vec({"0", "-1"})}},
                             {"c", {vec({"0", "-1"}), vec({"1", "1"})}},
                             {"d", {vec({"1", "1"}), vec({"-1", "0"})}},
                             {"e", {vec({"-1", "0"}), vec({"1", "-1"})}},
                             {"f", {vec({"1", "-1"}), vec({"1", "0"})}}}));
    const auto r = check_fan(m, Limits{});
    REQUIRE_FALSE(r.proved);
    CHECK(r.covering[*r.failing].size() == 2);
    // All matrices are equal: S is still a function.
    CHECK(check_domain(m, r).function);
}

TEST_CASE("fan: the 4-ball sorting law's 24 cones take the face-to-face fast path", "[fan]") {
    const Model m(test::sorting_law(4));
    const auto r = check_fan(m, Limits{});
    CHECK(r.proved);
    CHECK(r.fast_path);
    CHECK(r.method == "facet-matching");
}

namespace {

// The unmatched-facet point, by a second route: y = 2 (sum of the facet's rays) - d, with d the
// ray of the facet's one cone off the facet, is outside that cone and in no closed cone.
void require_gap_beside_its_facet(const Model& m, const FanResult& r) {
    REQUIRE(r.method == "unmatched-facet");
    REQUIRE(r.facets.size() == 1);
    REQUIRE(r.facets[0].pieces.size() == 1);
    const auto& piece = m.pieces()[r.facets[0].pieces[0]];
    Vector y(m.contacts());
    std::size_t on_facet = 0;
    for (std::size_t k = 0; k < m.contacts(); ++k) {
        const Vector ray = primitive_ray(piece.R.column(k));
        const bool in = std::find(r.facets[0].rays.begin(), r.facets[0].rays.end(), ray) != r.facets[0].rays.end();
        on_facet += in ? 1 : 0;
        y = y + Rational(in ? 2 : -1) * ray;
    }
    CHECK(on_facet + 1 == m.contacts());
    CHECK(r.test_points.at(0) == y);
    CHECK(r.covering.at(0).empty());
    CHECK(m.pieces_containing(y).empty());
    for (const auto& other : m.pieces()) { // and by the cone coordinates R^-1 y: one is negative
        const Vector coordinates = other.R_inv * y;
        CHECK(std::any_of(coordinates.begin(), coordinates.end(), [](const Rational& x) { return x < 0; }));
    }
    // No other cone has the facet.
    std::size_t owners = 0;
    for (const auto& other : m.pieces()) {
        std::size_t shared = 0;
        for (std::size_t k = 0; k < m.contacts(); ++k)
            shared += std::find(r.facets[0].rays.begin(), r.facets[0].rays.end(), primitive_ray(other.R.column(k))) !=
                              r.facets[0].rays.end()
                          ? 1
                          : 0;
        owners += shared + 1 == m.contacts() ? 1 : 0;
    }
    CHECK(owners == 1);
    // And it is the first that works of the (first 64) facets with one cone, in the order of
    // their sorted ray ids (ids: positions in m.rays()).
    auto id_of = [&](const Vector& ray) {
        return static_cast<std::size_t>(std::find(m.rays().begin(), m.rays().end(), ray) - m.rays().begin());
    };
    std::map<std::vector<std::size_t>, std::vector<std::pair<std::size_t, std::size_t>>> facets;
    for (std::size_t p = 0; p < m.pieces().size(); ++p)
        for (std::size_t drop = 0; drop < m.contacts(); ++drop) {
            std::vector<std::size_t> ids;
            for (std::size_t k = 0; k < m.contacts(); ++k)
                if (k != drop)
                    ids.push_back(id_of(primitive_ray(m.pieces()[p].R.column(k))));
            std::sort(ids.begin(), ids.end());
            facets[ids].push_back({p, drop});
        }
    std::optional<Vector> first;
    std::size_t candidates = 0;
    for (const auto& [ids, own] : facets) {
        if (own.size() != 1 || first || candidates++ == 64)
            continue;
        Vector z = Rational(-1) * primitive_ray(m.pieces()[own[0].first].R.column(own[0].second));
        for (auto id : ids)
            z = z + Rational(2) * m.rays()[id];
        if (m.pieces_containing(z).empty())
            first = z;
    }
    REQUIRE(first);
    CHECK(*first == y);
}

} // namespace

TEST_CASE("fan: dropping one of the 24 cones in R^3 leaves a gap, found as a point", "[fan]") {
    Law law = test::sorting_law(4);
    law.pieces.erase(law.pieces.begin() + 7);
    const Model m(law);
    const auto r = check_fan(m, Limits{});
    REQUIRE_FALSE(r.proved);
    // The walls do not balance; a point beside a facet the dropped cone shared is in no cone.
    CHECK(r.method == "unmatched-facet");
    REQUIRE(r.test_points.size() == 1);
    CHECK(m.pieces_containing(r.test_points[*r.failing]).empty());
    require_gap_beside_its_facet(m, r);
    // A second route: the chambers of the facet arrangement leave one uncovered.
    std::size_t steps = 0, uncovered = 0;
    for (const auto& x : chamber_points(facet_hyperplanes(m), m.contacts(), 10000000, steps))
        uncovered += m.pieces_containing(x).empty() ? 1 : 0;
    CHECK(uncovered >= 1);
}

TEST_CASE("fan: tilings that are not face to face are proved by walls, and the chambers agree", "[fan][walls]") {
    for (const char* name : {"tjunction-newton4-split", "tjunction-orthants-zero"}) {
        INFO(name);
        const Model m(load_law_file(source_path(std::string("tests/laws/") + name + ".json")));
        const auto r = check_fan(m, Limits{});
        CHECK(r.proved);
        CHECK_FALSE(r.fast_path);
        CHECK(r.method == "walls");
        // The chamber enumeration, run by hand, finds every chamber covered exactly once.
        std::size_t steps = 0;
        const auto normals = facet_hyperplanes(m);
        const auto chambers = chamber_points(normals, m.contacts(), 10000000, steps);
        REQUIRE(chambers.size() >= m.pieces().size()); // every cone holds a chamber: the loop is not empty
        for (const auto& x : chambers) {
            std::size_t k = 0;
            for (std::size_t p = 0; p < m.pieces().size(); ++p)
                k += m.in_interior(p, x) ? 1 : 0;
            REQUIRE(k == 1);
        }
    }
    const Model gap(load_law_file(source_path("tests/laws/gap-newton4-missing-cone.json")));
    const auto r = check_fan(gap, Limits{});
    CHECK_FALSE(r.proved);
    CHECK(r.method == "unmatched-facet");
    require_gap_beside_its_facet(gap, r);
}

TEST_CASE("fan: random edge splits of the 4-ball fan still tile - moving one ray never does", "[fan][chambers]") {
    std::mt19937_64 rng(7);
    std::size_t gaps = 0, chambers = 0;
    for (int round = 0; round < 12; ++round) {
        Law law = test::sorting_law(4);
        const int splits = 1 + round % 3;
        for (int s = 0; s < splits; ++s) {
            const std::size_t p = rng() % law.pieces.size();
            const std::size_t a = rng() % 3, b = (a + 1 + rng() % 2) % 3;
            split_edge(law, p, a, b, Rational(static_cast<int>(1 + rng() % 7), 8));
        }
        INFO("round " << round);
        const Model m(law);
        const auto r = check_fan(m, Limits{});
        CHECK(r.proved);
        // Move one ray of one cone slightly: its neighbours now overlap it or leave a gap.
        Law moved = law;
        auto& rays = *moved.pieces[0].rays;
        rays[0] = rays[0] + Rational(1, 16) * rays[1] + Rational(1, 32) * rays[2];
        const Model mm(moved);
        const auto rm = check_fan(mm, Limits{});
        REQUIRE_FALSE(rm.proved);
        const Vector& x = rm.test_points[*rm.failing];
        const auto& cov = rm.covering[*rm.failing];
        CHECK((cov.size() >= 2 || mm.pieces_containing(x).empty()));
        if (rm.method == "unmatched-facet") {
            require_gap_beside_its_facet(mm, rm);
            ++gaps;
        } else {
            CHECK(rm.method == "chambers");
            ++chambers;
        }
        // A cone listed twice: no facet has one cone, so no gap point; the chambers find the overlap.
        Law doubled = law;
        doubled.pieces.push_back(law.pieces[static_cast<std::size_t>(round) % law.pieces.size()]);
        doubled.pieces.back().name += "-again";
        const Model md(doubled);
        const auto rd = check_fan(md, Limits{});
        REQUIRE_FALSE(rd.proved);
        CHECK(rd.method == "chambers");
        CHECK(rd.covering[*rd.failing].size() == 2);
        ++chambers;
    }
    // Both ways occur: a moved ray leaves a gap beside an unmatched facet; a doubled cone only
    // overlaps.
    CHECK(gaps > 0);
    CHECK(chambers > 0);
}

TEST_CASE("fan: the chamber enumeration stops at its limit", "[fan][chambers]") {
    // A gap beside a facet of one cone is found without chambers, whatever the limit.
    const Model one(load_law_file(source_path("tests/laws/one-piece-c12.json")));
    Limits tight;
    tight.max_chambers = 100;
    const auto gap = check_fan(one, tight);
    CHECK(gap.method == "unmatched-facet");
    require_gap_beside_its_facet(one, gap);
    // A cone listed twice (in R^4): every facet has three cones or two, none has one, and the
    // walls do not balance: only the chambers decide it, and they stop at the limit.
    Law law = test::sorting_law(5);
    law.pieces.push_back(law.pieces[17]);
    law.pieces.back().name += "-again";
    const Model twice(law);
    CHECK_THROWS_AS(check_fan(twice, tight), LimitExceeded);
    const auto r = check_fan(twice, Limits{});
    CHECK(r.method == "chambers");
    REQUIRE_FALSE(r.proved);
    CHECK(r.covering[*r.failing].size() == 2); // the overlap
}

TEST_CASE("fan: overlapping cones with different matrices give a two-valued witness", "[fan]") {
    Law law = two_d_law({{"Q1", {vec({"1", "0"}), vec({"0", "1"})}},
                         {"Q2", {vec({"0", "1"}), vec({"-1", "0"})}},
                         {"Q3", {vec({"-1", "0"}), vec({"0", "-1"})}},
                         {"Q4", {vec({"0", "-1"}), vec({"1", "0"})}},
                         {"top", {vec({"1", "1"}), vec({"-1", "1"})}}});
    // Equal matrices on the overlap: a function. A matrix that agrees with Q1 on (1,1) only,
    // so that the sector point (1,1)+... must be moved off the kernel of the difference.
    const Model same(law);
    CHECK(check_domain(same, check_fan(same, Limits{})).function);
    law.pieces[4].Q = Matrix::from_rows({vec({"0", "1"}), vec({"1", "0"})});
    const Model m(law);
    const auto d = check_domain(m, check_fan(m, Limits{}));
    REQUIRE_FALSE(d.function);
    REQUIRE(d.interior_of.size() == 2);
    const auto a = d.interior_of[0], b = d.interior_of[1];
    CHECK(m.in_interior(a, *d.point));
    CHECK(m.in_interior(b, *d.point));
    CHECK(m.pieces()[a].Q * *d.point != m.pieces()[b].Q * *d.point);
}

TEST_CASE("fan: extreme rays of cone intersections", "[fan][intersections]") {
    const Model m(test::sorting_law(4));
    // Face to face: the intersection of two cones is spanned by their shared rays.
    std::size_t subsets = 0;
    for (std::size_t i = 0; i < m.pieces().size(); ++i)
        for (std::size_t j = i + 1; j < m.pieces().size(); ++j) {
            std::set<Vector> shared;
            for (auto id : m.pieces()[i].ray_ids) {
                const auto& rj = m.pieces()[j].ray_ids;
                if (std::find(rj.begin(), rj.end(), id) != rj.end())
                    shared.insert(m.rays()[id]);
            }
            const auto rays = intersection_rays(m, i, j, subsets);
            CHECK(std::set<Vector>(rays.begin(), rays.end()) == shared);
        }
    // Pairs on two sides of a facet hyperplane of the first cone are enumerated within that
    // facet: C(2c-1, c-2) = 5 sets instead of C(2c, c-1) = 15 (proofs/README.md, "P1"); the rays
    // above are the same either way.
    std::size_t separated = 0;
    for (std::size_t i = 0; i < m.pieces().size(); ++i)
        for (std::size_t j = i + 1; j < m.pieces().size(); ++j) {
            bool found = false;
            for (std::size_t k = 0; k < 3 && !found; ++k) {
                bool other_side = true;
                for (std::size_t r = 0; r < 3; ++r)
                    other_side = other_side && sign_of(dot(m.pieces()[i].R_inv.row(k), m.pieces()[j].R.column(r))) != Sign::positive;
                found = other_side;
            }
            separated += found;
        }
    CHECK(separated > 0);
    CHECK(subsets == separated * 5 + (276 - separated) * intersection_subsets(3));
    CHECK(intersection_subsets(3) == 15);
    CHECK(intersection_subsets(1) == 1);
    // A T-junction: the two halves of a split cone meet the neighbour across its facet in parts.
    const Model t(load_law_file(source_path("tests/laws/tjunction-newton4-split.json")));
    const auto rays = intersection_rays(t, 0, 1, subsets); // the two halves share a facet
    CHECK(rays.size() == 2);
    for (const auto& r : rays) {
        CHECK(t.pieces_containing(r).size() >= 2);
    }
}

TEST_CASE("cone membership: the int64 rows decide as R^-1 gamma over GMP, at the boundaries and at every scale", "[fan]") {
    // pieces_containing and in_interior test R^-1 gamma row by row, in int64 where R^-1 and
    // gamma fit (over common denominators) and over GMP otherwise. Reference: the full product.
    auto reference = [](const Model& m, std::size_t p, const Vector& g, bool interior) {
        for (const auto& s : m.pieces()[p].R_inv * g)
            if (sign_of(s) == Sign::negative || (interior && sign_of(s) == Sign::zero))
                return false;
        return true;
    };
    const Rational big = Rational(std::int64_t{1} << 62) - 1; // fits int64; its products need 128 bits
    Law wide;
    wide.name = "wide";
    wide.masses = vec({"1", "1", "1"});
    wide.pieces.push_back(PieceDecl{"a", Matrix::identity(2), std::vector<Vector>{vec({"1", "0"}), Vector{big, Rational(1)}}});
    wide.pieces.push_back(PieceDecl{"b", Matrix::identity(2), std::vector<Vector>{Vector{big, Rational(1)}, Vector{-big, Rational(-1, 3)}}});
    wide.pieces.push_back(PieceDecl{"c", Matrix::identity(2), std::vector<Vector>{vec({"0", "1"}), Vector{big * big, Rational(-1)}}});
    // R^-1 with a row of 63-bit entries (R unimodular): at points with entries near 2^63 the
    // row's 128-bit sum overflows and the row is summed over GMP.
    const Rational top = Rational(INT64_MAX);
    Law edge;
    edge.name = "edge";
    edge.masses = vec({"1", "1", "1", "1"});
    edge.pieces.push_back(PieceDecl{"a", Matrix::identity(3),
                                    std::vector<Vector>{vec({"-1", "1", "0"}), Vector{1 - top, top - 2, Rational(0)},
                                                        Vector{top - 6, 6 - top, Rational(1)}}});
    std::mt19937 rng(11251);
    std::uniform_int_distribution<int> small(-3, 3);
    std::size_t boundary = 0, inside = 0, wide_sums = 0;
    for (const Law& law : {test::sorting_law(4), paper_law(), wide, edge}) {
        const Model m(law);
        const std::size_t c = m.contacts();
        std::vector<Vector> points;
        for (const auto& piece : m.pieces())
            for (std::size_t k = 0; k < c; ++k) {
                points.push_back(piece.R.column(k));                                   // a ray
                points.push_back(piece.R.column(k) + piece.R.column((k + 1) % c));    // a face
                points.push_back(piece.R * Vector(c, Rational(1)));                   // the centre
            }
        for (int t = 0; t < 300; ++t) {
            Vector g(c);
            for (auto& x : g)
                x = Rational(small(rng)) / Rational(1 + std::abs(small(rng)));
            points.push_back(g);
        }
        const std::size_t listed = points.size();
        for (std::size_t i = 0; i < listed; ++i) {
            points.push_back((big * big) * points[i]); // beyond int64: the GMP rows
            points.push_back(big * points[i]);         // int64 rows whose products need 128 bits
        }
        if (law.name == "edge") // entries of +-(2^63 - 1) (less a little) and small ones
            for (int t = 0; t < 200; ++t) {
                Vector g(c);
                for (auto& x : g) {
                    const int k = small(rng);
                    x = k == 0 ? Rational(small(rng)) : k > 0 ? top - Rational(k - 1) : -top + Rational(-k - 1);
                }
                points.push_back(g);
            }
        for (const auto& g : points) {
            std::vector<std::size_t> expected;
            for (std::size_t p = 0; p < m.pieces().size(); ++p) {
                if (reference(m, p, g, false))
                    expected.push_back(p);
                CHECK(m.in_interior(p, g) == reference(m, p, g, true));
                inside += reference(m, p, g, true) ? 1 : 0;
            }
            boundary += expected.size() >= 2 ? 1 : 0;
            CHECK(m.pieces_containing(g) == expected);
            if (law.name == "edge") { // does in_cone meet a row whose 128-bit sum overflows?
                // As Model::in_cone does it: both in int64 over common denominators, the rows in
                // order, each summed in order, stopping at the first row that is negative.
                const auto gi = intk::to_int(Matrix::from_columns({g}));
                const auto ai = intk::to_int(m.pieces()[0].R_inv);
                for (std::size_t r = 0; gi && ai && r < c; ++r) {
                    intk::i128 sum = 0;
                    bool over = false;
                    for (std::size_t j = 0; j < c && !over; ++j)
                        over = __builtin_add_overflow(sum, static_cast<intk::i128>((*ai)(r, j)) * gi->a[j], &sum);
                    if (over) {
                        ++wide_sums;
                        break;
                    }
                    if (sum < 0)
                        break;
                }
            }
        }
        CHECK_THROWS_AS(m.pieces_containing(Vector(c + 1, Rational(1))), std::logic_error);
    }
    CHECK(boundary > 100);
    CHECK(inside > 100);
    CHECK(wide_sums > 5);
}
