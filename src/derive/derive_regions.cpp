// SPDX-License-Identifier: GPL-3.0-or-later
#include "derive/derive_regions.hpp"

#include "prover/obligations.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <map>
#include <set>

namespace impactcert::derive_detail {

namespace {

// The coefficients of a PPL generator or constraint on the c space dimensions.
template <class Row>
Vector vector_of(const Row& g, std::size_t c) {
    Vector v(c);
    for (std::size_t k = 0; k < c; ++k) {
        const mpz_class z(g.coefficient(PPL::Variable(static_cast<PPL::dimension_type>(k))));
        v[k] = Rational(CGAL::Gmpz(z.get_mpz_t()));
    }
    return v;
}


struct Cone {
    std::vector<Vector> rays;        // extreme rays, primitive, sorted
    std::vector<Vector> constraints; // facet normals a (a . x >= 0)
    bool has_lines = false;
};

Cone describe(const PPL::C_Polyhedron& P, std::size_t c) {
    Cone out;
    std::set<Vector> rays;
    for (const auto& g : P.minimized_generators()) {
        if (g.is_line())
            out.has_lines = true;
        else if (g.is_ray())
            rays.insert(primitive_ray(vector_of(g, c)));
    }
    out.rays.assign(rays.begin(), rays.end());
    for (const auto& k : P.minimized_constraints())
        if (k.is_inequality())
            out.constraints.push_back(vector_of(k, c));
    return out;
}


// Pulling triangulation of the face `face` (indices into rays, of dimension dim): the first ray
// of the face coned over the triangulations of the face's facets that do not contain it.
// The facets of a face G of a pointed cone are its maximal proper faces, and every face of G is
// G ∩ {a . x = 0} for a facet normal a of the cone; so the facets are the inclusion-maximal
// proper sets G ∩ Z(a), found from the incidences (Z(a): the rays with a . r = 0, computed
// once) without any rank computation (proofs/README.md, "Derivation", triangulation).
using RaySet = std::vector<bool>;

void triangulate(const std::vector<RaySet>& zero_sets, const std::vector<std::size_t>& face, std::size_t dim,
                 std::vector<std::vector<std::size_t>>& out) {
    if (face.size() == dim) {
        out.push_back(face);
        return;
    }
    const std::size_t apex = face.front();
    // The distinct proper faces G ∩ Z(a).
    std::set<std::vector<std::size_t>> proper;
    for (const auto& zero : zero_sets) {
        std::vector<std::size_t> on;
        for (auto r : face)
            if (zero[r])
                on.push_back(r);
        if (on.size() < face.size())
            proper.insert(std::move(on));
    }
    auto subset = [](const std::vector<std::size_t>& a, const std::vector<std::size_t>& b) {
        return a.size() < b.size() && std::includes(b.begin(), b.end(), a.begin(), a.end());
    };
    std::set<std::vector<std::size_t>> facets;
    for (const auto& f : proper) {
        if (std::binary_search(f.begin(), f.end(), apex))
            continue;
        bool maximal = true;
        for (const auto& g : proper)
            if (subset(f, g)) {
                maximal = false;
                break;
            }
        if (maximal)
            facets.insert(f);
    }
    for (const auto& f : facets) {
        std::vector<std::vector<std::size_t>> sub;
        triangulate(zero_sets, f, dim - 1, sub);
        for (auto& t : sub) {
            t.insert(t.begin(), apex);
            out.push_back(std::move(t));
        }
    }
}

bool key_less(const Region& a, const Region& b) {
    return a.key.size() != b.key.size() ? a.key.size() < b.key.size() : a.key < b.key;
}

} // namespace

// Stable sort by key through a permutation: a PPL polyhedron is copied, not moved, so each
// region is copied once instead of n log n times.
void sort_by_key(std::vector<Region>& regions) {
    std::vector<std::size_t> order(regions.size());
    for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return key_less(regions[a], regions[b]); });
    std::vector<Region> sorted;
    sorted.reserve(regions.size());
    for (const auto i : order)
        sorted.push_back(std::move(regions[i]));
    regions = std::move(sorted);
}

// PPL switches the FPU to rounding upward when it is initialised and expects that mode while it
// works (for its inexact coefficient types, unused here); the rest of impactcert (the float law,
// the fuzzer's error-free transformations) needs round-to-nearest. So the mode PPL wants is set
// only while a derivation runs, and the caller's mode is restored on every way out.
PplScope::PplScope() {
    static const bool ready = [] {
        PPL::initialize(); // saves the caller's rounding mode, sets PPL's
        PPL::restore_pre_PPL_rounding();
        return true;
    }();
    (void)ready;
    PPL::set_rounding_for_PPL();
}

PplScope::~PplScope() { PPL::restore_pre_PPL_rounding(); }

PPL::Linear_Expression form(const Vector& a) {
    const Vector p = primitive_ray(a); // a positive multiple with integer entries
    PPL::Linear_Expression e;
    for (std::size_t k = 0; k < p.size(); ++k)
        if (sign_of(p[k]) != Sign::zero)
            e += PPL::Coefficient(mpz_class(mpq_numref(p[k].mpq()))) * PPL::Variable(static_cast<PPL::dimension_type>(k));
    return e;
}

PPL::Constraint nonneg(const Vector& a) { return form(a) >= 0; }

Vector generator_vector(const PPL::Generator& g, std::size_t c) { return vector_of(g, c); }

std::optional<Vector> constraint_vector(const PPL::Constraint& k, std::size_t c) {
    if (k.is_tautological())
        return std::nullopt; // e.g. PPL's 1 > 0 of a not-necessarily-closed polyhedron
    if (k.inhomogeneous_term() != 0)
        throw std::logic_error("derive: a cone with an inhomogeneous constraint");
    return vector_of(k, c);
}

PPL::C_Polyhedron cone_of(std::size_t c, const std::vector<Vector>& constraints) {
    PPL::C_Polyhedron p(static_cast<PPL::dimension_type>(c), PPL::UNIVERSE);
    for (const auto& a : constraints)
        if (!is_zero(a))
            p.add_constraint(nonneg(a));
    return p;
}

bool full_dimensional(const PPL::C_Polyhedron& p, std::size_t c) {
    return p.affine_dimension() == static_cast<PPL::dimension_type>(c);
}

Vector interior_point(const PPL::C_Polyhedron& p, std::size_t c) {
    const Cone d = describe(p, c);
    Vector x(c);
    for (const auto& r : d.rays)
        x = x + r;
    return x;
}

std::optional<TilingDefect> tiling_defect(const Law& law) {
    const Model model(law);
    const std::vector<std::string> only{"fan"};
    const VerifyReport report = verify(model, Limits{}, {}, &only);
    const ObligationResult& fan = report.at("fan");
    if (fan.verdict == Verdict::undecided)
        throw DeriveLimit("the fan of the derived law is undecided: " + fan.limit);
    if (fan.verdict != Verdict::refuted)
        return std::nullopt;
    TilingDefect out;
    for (const auto& x : fan.counterexample.at("gamma"))
        out.gamma.push_back(*parse_rational(x.get<std::string>()));
    out.reason = fan.counterexample.at("reason").get<std::string>();
    return out;
}

std::vector<OutcomeDecl> unit_velocity_outcomes(std::size_t n,
                                                const std::function<std::optional<Vector>(const Vector&)>& simulate) {
    std::vector<OutcomeDecl> out;
    for (std::size_t i = 0; i < n; ++i)
        for (const int s : {-1, 1}) {
            const Vector u = Rational(s) * unit_vector(n, i);
            if (const auto up = simulate(u))
                out.push_back(OutcomeDecl{std::string("u") + std::to_string(i + 1) + (s < 0 ? " = -1" : " = +1"), u, *up});
        }
    return out;
}

void remove_overlaps(std::vector<Region>& regions, std::size_t c) {
    sort_by_key(regions);
    std::vector<Region> out;
    for (auto& region : regions) {
        std::vector<Region> parts{std::move(region)};
        for (const Region& a : out) {
            if (!(a.M == parts.front().M))
                continue;
            std::vector<Region> next;
            for (auto& part : parts) {
                PPL::C_Polyhedron meet = part.cone;
                meet.intersection_assign(a.cone);
                if (!full_dimensional(meet, c)) {
                    next.push_back(std::move(part));
                    continue;
                }
                if (a.cone.contains(part.cone))
                    continue; // inside a: dropped
                // part \ a, piece by piece over a's facets
                std::vector<Vector> facets;
                for (const auto& k : a.cone.minimized_constraints())
                    if (const auto v = constraint_vector(k, c)) {
                        if (k.is_equality())
                            throw std::logic_error("remove_overlaps: a full-dimensional region with an equality");
                        facets.push_back(*v);
                    }
                PPL::C_Polyhedron rest = part.cone;
                for (const auto& f : facets) {
                    PPL::C_Polyhedron piece = rest;
                    piece.add_constraint(nonneg(Rational(-1) * f)); // f <= 0
                    if (full_dimensional(piece, c))
                        next.push_back(Region{piece, part.M, part.key, part.name});
                    rest.add_constraint(nonneg(f));
                }
            }
            parts = std::move(next);
            if (parts.empty())
                break;
        }
        // parts of one region keep its key; several get distinct names (NAME~1, NAME~2, ...)
        for (std::size_t i = 0; i < parts.size(); ++i) {
            if (parts.size() > 1)
                parts[i].name += "~" + std::to_string(i + 1);
            out.push_back(std::move(parts[i]));
        }
    }
    regions = std::move(out);
}

RegionBudget::RegionBudget(std::size_t max_mb)
    : max_bytes_(max_mb > (SIZE_MAX >> 20) ? SIZE_MAX : max_mb << 20) {}

std::size_t RegionBudget::bytes_of(const Region& r) {
    return sizeof(Region) + r.cone.total_memory_in_bytes() + matrix_bytes(r.M) +
           r.key.size() * sizeof(std::size_t) + r.name.size();
}

void RegionBudget::add(std::size_t bytes, const char* what) {
    held_ = bytes > SIZE_MAX - held_ ? SIZE_MAX : held_ + bytes;
    peak_ = std::max(peak_, held_);
    if (held_ > max_bytes_)
        throw DeriveLimit(std::string("the ") + what + " held need more than " + std::to_string(max_bytes_ >> 20) +
                          " MB (raise it with --max-memory)");
}

namespace {

// Merging (proofs/README.md, "Derivation", merging): the helpers, on primitive integer vectors.
using RegionInts = std::vector<mpz_class>; // a primitive (integer) vector
RegionInts region_ints(const Vector& v) {
    RegionInts out;
    for (const auto& x : v)
        out.emplace_back(mpq_numref(x.mpq()));
    return out;
}
int region_dot_sign(const RegionInts& a, const RegionInts& b) {
    thread_local mpz_class scratch;
    scratch = 0;
    for (std::size_t k = 0; k < a.size(); ++k)
        mpz_addmul(scratch.get_mpz_t(), a[k].get_mpz_t(), b[k].get_mpz_t());
    return sgn(scratch);
}

} // namespace

void merge_group(std::vector<Region>& group, std::size_t c) {
    // Merging (proofs/README.md, "Derivation", merging). Two full-dimensional cones A, B with
    // disjoint interiors and a convex union are separated by a hyperplane H = {n . x = 0} that
    // holds a facet of each: n is a facet normal of A and -n one of B; and then A ∩ H = B ∩ H.
    // Both are cheap necessary conditions (facet normals and extreme rays, computed once per
    // shape); the decision is exact: A ∪ B is convex iff the hull's parts on the two sides of H
    // are A and B. A pair found not mergeable is not tested again until one of them changes.
    struct Shape {
        std::set<Vector> normals;                 // facet normals, primitive
        std::vector<std::pair<Vector, RegionInts>> facets; // each normal, and its negation as integers
        std::vector<RegionInts> normal_ints;
        std::vector<RegionInts> rays; // extreme rays (lines left out: the filter only weakens)
        std::size_t version = 0;
    };
    std::size_t next_version = 0;
    auto shape_of = [&](const PPL::C_Polyhedron& p) {
        Shape sh;
        const Cone d = describe(p, c);
        for (const auto& a : d.constraints)
            sh.normals.insert(primitive_ray(a));
        for (const auto& n : sh.normals) {
            sh.facets.emplace_back(Rational(-1) * n, region_ints(n));
            sh.normal_ints.push_back(region_ints(n));
        }
        for (const auto& r : d.rays)
            sh.rays.push_back(region_ints(r));
        sh.version = next_version++;
        return sh;
    };
    auto inside = [&](const RegionInts& r, const Shape& sh) {
        for (const auto& a : sh.normal_ints)
            if (region_dot_sign(a, r) < 0)
                return false;
        return true;
    };
    auto merge = [&](const PPL::C_Polyhedron& a, const PPL::C_Polyhedron& b, const Shape& sa,
                     const Shape& sb) -> std::optional<PPL::C_Polyhedron> {
        std::optional<PPL::C_Polyhedron> hull;
        for (const auto& [minus, n] : sa.facets) {
            if (!sb.normals.count(minus))
                continue;
            bool same_facet = true;
            for (const auto& r : sa.rays)
                if (same_facet && region_dot_sign(n, r) == 0)
                    same_facet = inside(r, sb);
            for (const auto& r : sb.rays)
                if (same_facet && region_dot_sign(n, r) == 0)
                    same_facet = inside(r, sa);
            if (!same_facet)
                continue;
            if (!hull) {
                hull = a;
                hull->poly_hull_assign(b);
            }
            PPL::C_Polyhedron upper = *hull, lower = *hull;
            upper.add_constraint(nonneg(Rational(-1) * minus));
            lower.add_constraint(nonneg(minus));
            if (a.contains(upper) && b.contains(lower))
                return hull;
        }
        return std::nullopt;
    };
    if (group.size() > 1) {
        // The first pair (a, b), a < b, in order, that merges is merged, until none does;
        // regions stay at their places (a merged-away one is marked), so that the order is
        // that of the list, and a pair is only looked at when b has a facet normal opposite
        // to one of a's (the other pairs fail the first necessary condition).
        std::vector<Shape> shapes;
        for (const auto& r : group)
            shapes.push_back(shape_of(r.cone));
        std::vector<bool> alive(group.size(), true);
        std::map<Vector, std::set<std::size_t>> having; // facet normal -> regions
        for (std::size_t r = 0; r < group.size(); ++r)
            for (const auto& n : shapes[r].normals)
                having[n].insert(r);
        std::set<std::pair<std::size_t, std::size_t>> apart; // versions known not mergeable
        for (bool changed = true; changed;) {
            changed = false;
            for (std::size_t a = 0; a < group.size() && !changed; ++a) {
                if (!alive[a])
                    continue;
                std::set<std::size_t> candidates;
                for (const auto& facet : shapes[a].facets)
                    if (auto it = having.find(facet.first); it != having.end())
                        for (auto b : it->second)
                            if (b > a)
                                candidates.insert(b);
                for (const std::size_t b : candidates) {
                    const auto versions = std::make_pair(shapes[a].version, shapes[b].version);
                    if (apart.count(versions))
                        continue;
                    if (auto hull = merge(group[a].cone, group[b].cone, shapes[a], shapes[b])) {
                        for (const std::size_t r : {a, b})
                            for (const auto& n : shapes[r].normals)
                                having[n].erase(r);
                        group[a].cone = *hull;
                        shapes[a] = shape_of(group[a].cone);
                        for (const auto& n : shapes[a].normals)
                            having[n].insert(a);
                        alive[b] = false;
                        changed = true;
                        break;
                    }
                    apart.insert(versions);
                }
            }
        }
        std::vector<Region> kept;
        for (std::size_t r = 0; r < group.size(); ++r)
            if (alive[r])
                kept.push_back(std::move(group[r]));
        group = std::move(kept);
    }
}

std::vector<PieceDecl> region_pieces(const Region& region, std::size_t c) {
    std::vector<PPL::C_Polyhedron> pointed;
    if (describe(region.cone, c).has_lines) {
        // Not pointed: split by the orthants first.
        for (std::size_t mask = 0; mask < (std::size_t{1} << c); ++mask) {
            PPL::C_Polyhedron part = region.cone;
            for (std::size_t k = 0; k < c; ++k) {
                Vector e = unit_vector(c, k);
                if (mask & (std::size_t{1} << k))
                    e = Rational(-1) * e;
                part.add_constraint(nonneg(e));
            }
            if (full_dimensional(part, c))
                pointed.push_back(part);
        }
    } else {
        pointed.push_back(region.cone);
    }
    std::vector<std::vector<Vector>> simplices;
    for (const auto& part : pointed) {
        const Cone d = describe(part, c);
        std::vector<std::size_t> all(d.rays.size());
        for (std::size_t i = 0; i < all.size(); ++i)
            all[i] = i;
        std::vector<RaySet> zero_sets;
        std::vector<RegionInts> ray_ints;
        for (const auto& r : d.rays)
            ray_ints.push_back(region_ints(r));
        for (const auto& a : d.constraints) {
            const RegionInts normal = region_ints(a); // PPL's coefficients: integers
            RaySet zero(d.rays.size());
            for (std::size_t r = 0; r < d.rays.size(); ++r)
                zero[r] = region_dot_sign(normal, ray_ints[r]) == 0;
            zero_sets.push_back(std::move(zero));
        }
        std::vector<std::vector<std::size_t>> tri;
        triangulate(zero_sets, all, c, tri);
        for (const auto& t : tri) {
            std::vector<Vector> rs;
            for (auto i : t)
                rs.push_back(d.rays[i]);
            simplices.push_back(rs);
        }
    }
    std::vector<PieceDecl> out;
    for (std::size_t s = 0; s < simplices.size(); ++s) {
        PieceDecl piece;
        piece.name = simplices.size() == 1 ? region.name : region.name + "." + std::to_string(s + 1);
        piece.Q = region.M;
        piece.rays = simplices[s];
        out.push_back(std::move(piece));
    }
    return out;
}

std::string map_key(const Matrix& M) {
    std::string key;
    for (std::size_t i = 0; i < M.rows(); ++i)
        key += to_string(M.row(i)) + ";";
    return key;
}

std::vector<WrittenPiece> add_region_pieces(std::vector<Region>& regions, std::size_t c, Law& law,
                                           const DeriveProgress& progress, RegionBudget* budget, bool merge) {
    sort_by_key(regions);
    // Regions with the same matrix (the braid relation Q1 Q2 Q1 = Q2 Q1 Q2 makes "121" and "212"
    // one map) are merged where their union is convex (merge_group). The merged piece keeps the
    // first name.
    std::map<std::string, std::vector<Region>> groups;
    std::vector<std::string> order;
    for (auto& region : regions) {
        std::string key = map_key(region.M);
        if (!groups.count(key))
            order.push_back(key);
        groups[key].push_back(std::move(region));
    }
    std::vector<Region> merged;
    std::size_t group_index = 0;
    for (const auto& key : order) {
        if (progress && group_index % 256 == 0)
            progress("merge", group_index, order.size());
        ++group_index;
        auto& group = groups[key];
        if (merge)
            merge_group(group, c);
        for (auto& r : group)
            merged.push_back(std::move(r));
    }
    sort_by_key(merged);
    regions = std::move(merged);
    if (!merge) { // regions of one name (modes told apart only by an orthant) kept apart: NAME#2, ...
        std::map<std::string, std::size_t> seen;
        for (auto& region : regions)
            if (const std::size_t k = ++seen[region.name]; k > 1)
                region.name += "#" + std::to_string(k);
    }

    std::vector<WrittenPiece> written;
    for (std::size_t index = 0; index < regions.size(); ++index) {
        if (progress && index % 256 == 0)
            progress("pieces", index, regions.size());
        for (auto& piece : region_pieces(regions[index], c)) {
            if (budget) {
                std::size_t bytes = sizeof(PieceDecl) + piece.name.size() + matrix_bytes(piece.Q);
                for (const auto& r : *piece.rays)
                    bytes += vector_bytes(r);
                budget->add(bytes, "regions and pieces");
            }
            written.push_back({piece.name, index});
            law.pieces.push_back(std::move(piece));
        }
    }
    return written;
}

} // namespace impactcert::derive_detail
