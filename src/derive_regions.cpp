#include "derive_regions.hpp"

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

PPL::Linear_Expression form(const Vector& a) {
    const Vector p = primitive_ray(a); // a positive multiple with integer entries
    PPL::Linear_Expression e;
    for (std::size_t k = 0; k < p.size(); ++k)
        if (sign_of(p[k]) != Sign::zero)
            e += PPL::Coefficient(mpz_class(mpq_numref(p[k].mpq()))) * PPL::Variable(static_cast<PPL::dimension_type>(k));
    return e;
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

std::size_t rank_of(const std::vector<Vector>& vs, std::size_t c) {
    if (vs.empty())
        return 0;
    return c - null_space(vs, c).size();
}

// Pulling triangulation of the face `face` (indices into rays, of dimension dim): the first ray
// of the face coned over the triangulations of the face's facets that do not contain it.
void triangulate(const std::vector<Vector>& rays, const std::vector<std::size_t>& face, std::size_t dim,
                 const std::vector<Vector>& constraints, std::size_t c, std::vector<std::vector<std::size_t>>& out) {
    if (face.size() == dim) {
        out.push_back(face);
        return;
    }
    const std::size_t apex = face.front();
    std::set<std::vector<std::size_t>> facets;
    for (const auto& a : constraints) {
        if (sign_of(dot(a, rays[apex])) == Sign::zero)
            continue;
        std::vector<std::size_t> on;
        std::vector<Vector> vs;
        for (auto r : face)
            if (sign_of(dot(a, rays[r])) == Sign::zero) {
                on.push_back(r);
                vs.push_back(rays[r]);
            }
        if (rank_of(vs, c) == dim - 1)
            facets.insert(on);
    }
    for (const auto& f : facets) {
        std::vector<std::vector<std::size_t>> sub;
        triangulate(rays, f, dim - 1, constraints, c, sub);
        for (auto& s : sub) {
            s.insert(s.begin(), apex);
            out.push_back(std::move(s));
        }
    }
}

bool key_less(const Region& a, const Region& b) {
    return a.key.size() != b.key.size() ? a.key.size() < b.key.size() : a.key < b.key;
}

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

} // namespace

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

PPL::Constraint nonneg(const Vector& a) { return form(a) >= 0; }

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

std::vector<WrittenPiece> add_region_pieces(std::vector<Region>& regions, std::size_t c, Law& law) {
    sort_by_key(regions);
    // Regions with the same matrix (the braid relation Q1 Q2 Q1 = Q2 Q1 Q2 makes "121" and "212"
    // one map) are merged where their union is convex (the test below). The merged piece keeps
    // the first name.
    std::map<std::string, std::vector<Region>> groups;
    std::vector<std::string> order;
    for (auto& region : regions) {
        std::string key;
        for (std::size_t i = 0; i < c; ++i)
            key += to_string(region.M.row(i)) + ";";
        if (!groups.count(key))
            order.push_back(key);
        groups[key].push_back(std::move(region));
    }
    // Two full-dimensional cones with disjoint interiors and a convex union are separated by a
    // hyperplane containing a facet of each (proofs/README.md, "Derivation", merging): a pair
    // with no facet normal of one opposite to a facet normal of the other is not tested.
    auto normals = [&](const PPL::C_Polyhedron& p) {
        std::set<Vector> out;
        for (const auto& k : p.minimized_constraints())
            if (k.is_inequality())
                out.insert(primitive_ray(vector_of(k, c)));
        return out;
    };
    // Exact, and cheaper than the cover test of a powerset: with A in n . x >= 0 and B in
    // n . x <= 0 (n a facet normal of A, -n one of B), A ∪ B is convex iff the hull's parts on
    // the two sides are A and B (proofs/README.md, "Derivation", merging).
    auto merge = [&](const PPL::C_Polyhedron& a, const PPL::C_Polyhedron& b, const std::set<Vector>& fa,
                     const std::set<Vector>& fb) -> std::optional<PPL::C_Polyhedron> {
        std::optional<PPL::C_Polyhedron> hull;
        for (const auto& n : fa) {
            const Vector minus = Rational(-1) * n;
            if (!fb.count(minus))
                continue;
            if (!hull) {
                hull = a;
                hull->poly_hull_assign(b);
            }
            PPL::C_Polyhedron upper = *hull, lower = *hull;
            upper.add_constraint(nonneg(n));
            lower.add_constraint(nonneg(minus));
            if (a.contains(upper) && b.contains(lower))
                return hull;
        }
        return std::nullopt;
    };
    std::vector<Region> merged;
    for (const auto& key : order) {
        auto& group = groups[key];
        std::vector<std::set<Vector>> facets;
        if (group.size() > 1)
            for (const auto& r : group)
                facets.push_back(normals(r.cone));
        for (bool changed = true; changed;) {
            changed = false;
            for (std::size_t a = 0; a < group.size() && !changed; ++a)
                for (std::size_t b = a + 1; b < group.size() && !changed; ++b) {
                    if (auto hull = merge(group[a].cone, group[b].cone, facets[a], facets[b])) {
                        group[a].cone = *hull;
                        facets[a] = normals(group[a].cone);
                        group.erase(group.begin() + static_cast<std::ptrdiff_t>(b));
                        facets.erase(facets.begin() + static_cast<std::ptrdiff_t>(b));
                        changed = true;
                    }
                }
        }
        for (auto& r : group)
            merged.push_back(std::move(r));
    }
    sort_by_key(merged);
    regions = std::move(merged);

    std::vector<WrittenPiece> written;
    for (std::size_t index = 0; index < regions.size(); ++index) {
        const Region& region = regions[index];
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
            std::vector<std::vector<std::size_t>> tri;
            triangulate(d.rays, all, c, d.constraints, c, tri);
            for (const auto& t : tri) {
                std::vector<Vector> rs;
                for (auto i : t)
                    rs.push_back(d.rays[i]);
                simplices.push_back(rs);
            }
        }
        for (std::size_t s = 0; s < simplices.size(); ++s) {
            PieceDecl piece;
            piece.name = simplices.size() == 1 ? region.name : region.name + "." + std::to_string(s + 1);
            piece.Q = region.M;
            piece.rays = simplices[s];
            law.pieces.push_back(piece);
            written.push_back({piece.name, index});
        }
    }
    return written;
}

} // namespace impactcert::derive_detail
