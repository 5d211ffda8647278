// SPDX-License-Identifier: GPL-3.0-or-later
#include "derive/derive_planar.hpp"

#include "derive/derive_regions.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace impactcert::derive_detail {

namespace {

struct IVec {
    mpz_class x, y;
    bool operator==(const IVec& o) const { return x == o.x && y == o.y; }
};

mpz_class det(const IVec& a, const IVec& b) { return a.x * b.y - a.y * b.x; }
mpz_class dot(const IVec& a, const IVec& b) { return a.x * b.x + a.y * b.y; }
bool is_zero(const IVec& a) { return a.x == 0 && a.y == 0; }
IVec neg(const IVec& a) { return {-a.x, -a.y}; }
bool same_direction(const IVec& a, const IVec& b) { return det(a, b) == 0 && sgn(dot(a, b)) > 0; }

// A convex cone of the plane: the whole plane, or a counter-clockwise chain of rays whose
// neighbours are less than pi apart (two rays: a pointed sector; three with the ends opposite:
// a half-plane).
struct Sector {
    bool plane = false;
    std::vector<IVec> rays;
};

// Drops repeated directions and rays inside the sector spanned by their neighbours.
void simplify(std::vector<IVec>& rays) {
    std::vector<IVec> out;
    for (auto& g : rays)
        if (out.empty() || !same_direction(out.back(), g))
            out.push_back(std::move(g));
    for (bool changed = true; changed && out.size() > 2;) {
        changed = false;
        for (std::size_t i = 1; i + 1 < out.size(); ++i)
            if (sgn(det(out[i - 1], out[i + 1])) > 0) {
                out.erase(out.begin() + static_cast<std::ptrdiff_t>(i));
                changed = true;
                break;
            }
    }
    rays = std::move(out);
}

// s ∩ {a . x >= 0}, a != 0.
Sector clip(const Sector& s, const IVec& a) {
    const IVec line{-a.y, a.x}; // a direction of a . x = 0
    if (s.plane)
        return Sector{false, {neg(line), a, line}};
    Sector out;
    const std::size_t n = s.rays.size();
    std::vector<int> side(n);
    for (std::size_t i = 0; i < n; ++i)
        side[i] = sgn(dot(a, s.rays[i]));
    for (std::size_t i = 0; i < n; ++i) {
        if (side[i] >= 0)
            out.rays.push_back(s.rays[i]);
        if (i + 1 < n && side[i] * side[i + 1] < 0) {
            // The line crosses the open arc from g_i to g_i+1 (less than pi): the one of
            // +-line inside it.
            out.rays.push_back(sgn(det(s.rays[i], line)) > 0 ? line : neg(line));
        }
    }
    simplify(out.rays);
    return out;
}

bool full_dimensional(const Sector& s) {
    if (s.plane)
        return true;
    for (std::size_t i = 0; i + 1 < s.rays.size(); ++i)
        if (sgn(det(s.rays[i], s.rays[i + 1])) > 0)
            return true;
    return false;
}

bool pointed(const Sector& s) { return !s.plane && s.rays.size() == 2; }

Vector primitive(const IVec& v) {
    mpz_class g;
    mpz_gcd(g.get_mpz_t(), v.x.get_mpz_t(), v.y.get_mpz_t());
    return Vector{Rational(CGAL::Gmpz(mpz_class(v.x / g).get_mpz_t())), Rational(CGAL::Gmpz(mpz_class(v.y / g).get_mpz_t()))};
}

IVec integer_ray(const Vector& v) {
    // v is primitive (integer entries).
    return IVec{mpz_class(mpq_numref(v[0].mpq())), mpz_class(mpq_numref(v[1].mpq()))};
}

// An integer matrix Z with denominator D > 0: M = Z / D.
struct IMat {
    mpz_class z[2][2];
    mpz_class d = 1;
    IVec row(std::size_t i) const { return {z[i][0], z[i][1]}; }
};

IMat integer_form(const Matrix& m) {
    IMat out;
    out.d = 1;
    for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j)
            mpz_lcm(out.d.get_mpz_t(), out.d.get_mpz_t(), mpq_denref(m(i, j).mpq()));
    for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j)
            out.z[i][j] = out.d / mpz_class(mpq_denref(m(i, j).mpq())) * mpz_class(mpq_numref(m(i, j).mpq()));
    return out;
}

IMat times(const IMat& a, const IMat& b) {
    IMat out;
    for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j)
            out.z[i][j] = a.z[i][0] * b.z[0][j] + a.z[i][1] * b.z[1][j];
    out.d = a.d * b.d;
    return out;
}

Matrix reduced(const IMat& m) {
    Matrix out(2, 2);
    for (std::size_t i = 0; i < 2; ++i)
        for (std::size_t j = 0; j < 2; ++j) {
            mpq_class q(m.z[i][j], m.d);
            q.canonicalize();
            out(i, j) = Rational(q.get_mpq_t());
        }
    return out;
}

std::size_t bit_bound(const IMat& m) {
    std::size_t bits = 0;
    for (const auto& row : m.z)
        for (const auto& x : row)
            bits = std::max(bits, mpz_sizeinbase(x.get_mpz_t(), 2));
    return bits + mpz_sizeinbase(m.d.get_mpz_t(), 2);
}

std::vector<Vector> chain_of(const Sector& s) {
    std::vector<Vector> out;
    for (const auto& g : s.rays)
        out.push_back(primitive(g));
    return out;
}

Sector sector_of(const PlanarRegion& r) {
    Sector s;
    s.plane = r.chain.empty();
    for (const auto& v : r.chain)
        s.rays.push_back(integer_ray(v));
    return s;
}

// The union of two interior-disjoint cones when it is convex: they share a boundary ray and
// together span at most pi (or both are half-planes: the plane).
std::optional<Sector> convex_union(const Sector& a, const Sector& b) {
    if (a.plane || b.plane)
        return std::nullopt;
    auto join = [](const Sector& first, const Sector& second) -> std::optional<Sector> {
        if (!same_direction(first.rays.back(), second.rays.front()))
            return std::nullopt;
        if (same_direction(second.rays.back(), first.rays.front()))
            return Sector{true, {}};
        Sector u;
        u.rays = first.rays;
        u.rays.insert(u.rays.end(), second.rays.begin() + 1, second.rays.end());
        // Convex when every turn is less than pi and the ends are at most pi apart.
        for (std::size_t i = 0; i + 1 < u.rays.size(); ++i)
            if (sgn(det(u.rays[i], u.rays[i + 1])) <= 0)
                return std::nullopt;
        const int ends = sgn(det(u.rays.front(), u.rays.back()));
        if (ends < 0 || (ends == 0 && sgn(dot(u.rays.front(), u.rays.back())) > 0))
            return std::nullopt;
        simplify(u.rays);
        return u;
    };
    if (auto u = join(a, b))
        return u;
    return join(b, a);
}

bool planar_key_less(const PlanarRegion& a, const PlanarRegion& b) {
    return a.key.size() != b.key.size() ? a.key.size() < b.key.size() : a.key < b.key;
}

} // namespace

PlanarResult planar_regions(const std::vector<Matrix>& Qk, ImpactRule rule, std::size_t max_impacts,
                            std::size_t max_bits, const std::function<std::string(const std::vector<std::size_t>&)>& names) {
    constexpr std::size_t c = 2;
    std::vector<IMat> Zk;
    for (const auto& q : Qk)
        Zk.push_back(integer_form(q));
    struct Node {
        Sector cone;
        IMat M;
        std::vector<std::size_t> key;
    };
    PlanarResult result;
    std::vector<Node> work;
    work.push_back({Sector{true, {}}, IMat{{{1, 0}, {0, 1}}, 1}, {}});
    while (!work.empty()) {
        Node node = std::move(work.back());
        work.pop_back();
        const IVec rows[2] = {node.M.row(0), node.M.row(1)};
        for (std::size_t branch = 0; branch <= c; ++branch) {
            Sector cell = node.cone;
            auto add = [&](const IVec& a) {
                if (!is_zero(a) && full_dimensional(cell))
                    cell = clip(cell, a);
            };
            if (branch == c) {
                add(rows[0]);
                add(rows[1]);
            } else {
                const std::size_t k = branch, j = 1 - branch;
                if (is_zero(rows[k]))
                    continue;
                if (rule == ImpactRule::most_negative && j < k && rows[j] == rows[k])
                    continue;
                add(neg(rows[k])); // gamma_k <= 0
                if (rule == ImpactRule::most_negative)
                    add(IVec{rows[j].x - rows[k].x, rows[j].y - rows[k].y}); // gamma_k <= gamma_j
                else if ((rule == ImpactRule::left_first && j < k) || (rule == ImpactRule::right_first && j > k))
                    add(rows[j]); // gamma_j >= 0
            }
            if (!full_dimensional(cell))
                continue;
            if (branch == c) {
                result.regions.push_back({cell.plane ? std::vector<Vector>{} : chain_of(cell), reduced(node.M), node.key,
                                          names(node.key)});
                continue;
            }
            if (node.key.size() == max_impacts) {
                result.too_long_cell = chain_of(cell);
                result.too_long_word = node.key;
                result.too_long_word.push_back(branch);
                return result;
            }
            auto word = node.key;
            word.push_back(branch);
            IMat next = times(Zk[branch], node.M);
            if (bit_bound(next) > max_bits)
                check_bits(reduced(next), max_bits, "the map of word " + names(word));
            work.push_back({std::move(cell), std::move(next), std::move(word)});
        }
    }
    return result;
}

std::vector<PlanarPiece> add_planar_pieces(std::vector<PlanarRegion>& regions, Law& law) {
    std::stable_sort(regions.begin(), regions.end(), planar_key_less);
    // Groups of one matrix in order of first appearance; within a group, the first pair (in
    // key order) whose union is convex is merged, until none is (the general path's order).
    std::map<std::vector<Rational>, std::size_t> group_of;
    std::vector<std::vector<PlanarRegion>> groups;
    for (auto& r : regions) {
        std::vector<Rational> key;
        for (std::size_t i = 0; i < 2; ++i)
            for (std::size_t j = 0; j < 2; ++j)
                key.push_back(r.M(i, j));
        auto [it, fresh] = group_of.try_emplace(std::move(key), groups.size());
        if (fresh)
            groups.emplace_back();
        groups[it->second].push_back(std::move(r));
    }
    std::vector<PlanarRegion> merged;
    for (auto& group : groups) {
        for (bool changed = true; changed;) {
            changed = false;
            for (std::size_t a = 0; a < group.size() && !changed; ++a)
                for (std::size_t b = a + 1; b < group.size() && !changed; ++b)
                    if (auto u = convex_union(sector_of(group[a]), sector_of(group[b]))) {
                        group[a].chain = u->plane ? std::vector<Vector>{} : chain_of(*u);
                        group.erase(group.begin() + static_cast<std::ptrdiff_t>(b));
                        changed = true;
                    }
        }
        for (auto& r : group)
            merged.push_back(std::move(r));
    }
    std::stable_sort(merged.begin(), merged.end(), planar_key_less);
    regions = std::move(merged);

    std::vector<PlanarPiece> written;
    for (std::size_t index = 0; index < regions.size(); ++index) {
        const PlanarRegion& region = regions[index];
        const Sector s = sector_of(region);
        std::vector<Sector> parts;
        if (pointed(s)) {
            parts.push_back(s);
        } else {
            // Not pointed: cut by the quadrants (bit k of the mask: x_k <= 0), in the general
            // path's order.
            for (std::size_t mask = 0; mask < 4; ++mask) {
                Sector part = s;
                for (std::size_t k = 0; k < 2 && full_dimensional(part); ++k) {
                    IVec e{k == 0 ? 1 : 0, k == 1 ? 1 : 0};
                    part = clip(part, (mask >> k) & 1 ? neg(e) : e);
                }
                if (full_dimensional(part))
                    parts.push_back(std::move(part));
            }
        }
        for (std::size_t p = 0; p < parts.size(); ++p) {
            if (!pointed(parts[p]))
                throw std::logic_error("planar derivation: a quadrant part is not a pointed sector");
            std::vector<Vector> rays = chain_of(parts[p]);
            std::sort(rays.begin(), rays.end());
            PieceDecl piece;
            piece.name = parts.size() == 1 ? region.name : region.name + "." + std::to_string(p + 1);
            piece.Q = region.M;
            piece.rays = std::move(rays);
            law.pieces.push_back(std::move(piece));
            written.push_back({law.pieces.back().name, index});
        }
    }
    return written;
}

} // namespace impactcert::derive_detail
