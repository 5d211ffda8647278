// SPDX-License-Identifier: GPL-3.0-or-later
// Planar scenes (scene.hpp): exact contact detection and the columns of W from lever arms.
#include "model/scene.hpp"
#include "model/scene_common.hpp"

#include "base/errors.hpp"
#include "base/json_read.hpp"

#include <algorithm>
#include <map>
#include <optional>

namespace impactcert {

namespace jr = json_read;
using jr::ReadJson;

namespace {

struct P2 {
    Rational x, y;
};
P2 operator+(const P2& a, const P2& b) { return {a.x + b.x, a.y + b.y}; }
P2 operator-(const P2& a, const P2& b) { return {a.x - b.x, a.y - b.y}; }
P2 operator*(const Rational& s, const P2& a) { return {s * a.x, s * a.y}; }
Rational dot(const P2& a, const P2& b) { return a.x * b.x + a.y * b.y; }
Rational cross(const P2& a, const P2& b) { return a.x * b.y - a.y * b.x; }
bool operator==(const P2& a, const P2& b) { return a.x == b.x && a.y == b.y; }
std::string text(const P2& p) { return "(" + to_string(p.x) + ", " + to_string(p.y) + ")"; }

// The rational square root of q >= 0, when it is rational.
std::optional<Rational> rational_sqrt(const Rational& q) {
    if (sign_of(q) == Sign::negative)
        return std::nullopt;
    mpz_class num(mpq_numref(q.mpq())), den(mpq_denref(q.mpq()));
    if (!mpz_perfect_square_p(num.get_mpz_t()) || !mpz_perfect_square_p(den.get_mpz_t()))
        return std::nullopt;
    mpz_class rn, rd;
    mpz_sqrt(rn.get_mpz_t(), num.get_mpz_t());
    mpz_sqrt(rd.get_mpz_t(), den.get_mpz_t());
    return Rational(CGAL::Gmpz(rn.get_mpz_t())) / Rational(CGAL::Gmpz(rd.get_mpz_t()));
}

P2 get_point(const ReadJson& j, const std::string& path) {
    const Vector v = jr::get_vector(j, path);
    if (v.size() != 2)
        input_error(path, "expected a point [x, y], got " + std::to_string(v.size()) + " numbers");
    return {v[0], v[1]};
}

P2 get_unit(const ReadJson& j, const std::string& path) {
    const P2 n = get_point(j, path);
    if (dot(n, n) != Rational(1))
        input_error(path, "not a unit vector: its squared length is " + to_string(dot(n, n)) +
                              " (give a rational unit normal, e.g. [\"3/5\", \"4/5\"])");
    return n;
}

// A shape is a convex core -- one point (a disk), two (a segment, a capsule) or a convex polygon
// (counter-clockwise, strictly convex) -- and a radius r >= 0 around it (a disk's radius, a
// capsule's, a polygon's skin): the set of points within r of the core.
struct Shape {
    std::vector<P2> core; // world positions
    Rational r;
    std::string path;
    bool polygon() const { return core.size() >= 3; }
};
struct Body {
    std::string name;
    Rational m, J;
    P2 c;
    std::vector<Shape> shapes;
};

struct Boundary {
    std::string name;
    P2 p, n;
};

struct Contact {
    int i = -1, j = -1; // body indices; -1: a boundary (only ever i)
    P2 p, n;            // the point and the unit normal from i to j
    std::string name, path;
    std::optional<Rational> mu, e;
};

// The closest point of segment [a, b] to q.
P2 closest_on_segment(const P2& a, const P2& b, const P2& q) {
    const P2 d = b - a;
    const Rational len2 = dot(d, d);
    if (sign_of(len2) == Sign::zero)
        return a;
    Rational t = dot(q - a, d) / len2;
    if (sign_of(t) == Sign::negative)
        t = 0;
    if (t > Rational(1))
        t = 1;
    return a + t * d;
}

bool on_segment(const P2& a, const P2& b, const P2& q) {
    const P2 d = b - a;
    if (sign_of(cross(d, q - a)) != Sign::zero)
        return false;
    const Rational t = dot(q - a, d);
    return sign_of(t) != Sign::negative && t <= dot(d, d);
}

// Squared distance from q to the core (a point, a segment, or a polygon's boundary or inside).
Rational squared_distance(const Shape& s, const P2& q) {
    if (s.core.size() == 1)
        return dot(q - s.core[0], q - s.core[0]);
    Rational best;
    bool inside = s.polygon();
    for (std::size_t k = 0; k < s.core.size(); ++k) {
        const P2& a = s.core[k];
        const P2& b = s.core[(k + 1) % s.core.size()];
        if (s.core.size() == 2 && k == 1)
            break;
        const P2 c = closest_on_segment(a, b, q);
        const Rational d2 = dot(q - c, q - c);
        if (k == 0 || d2 < best)
            best = d2;
        if (s.polygon() && sign_of(cross(b - a, q - a)) == Sign::negative)
            inside = false;
    }
    return inside ? Rational(0) : best;
}

bool on_shape(const Shape& s, const P2& q) {
    if (s.polygon() && sign_of(s.r) == Sign::zero) {
        // on the boundary of a polygon: on one of its edges
        for (std::size_t k = 0; k < s.core.size(); ++k)
            if (on_segment(s.core[k], s.core[(k + 1) % s.core.size()], q))
                return true;
        return false;
    }
    return squared_distance(s, q) == s.r * s.r;
}

// The edges of a core: none for a point, one for a segment, n for a polygon.
std::vector<std::pair<P2, P2>> edges(const Shape& s) {
    std::vector<std::pair<P2, P2>> out;
    if (s.core.size() == 2)
        out.push_back({s.core[0], s.core[1]});
    else if (s.polygon())
        for (std::size_t k = 0; k < s.core.size(); ++k)
            out.push_back({s.core[k], s.core[(k + 1) % s.core.size()]});
    return out;
}

// Whether the cores' interiors overlap (a polygon's interior, or a segment crossing another
// properly): no edge normal of either core separates them, touching allowed (max <= min).
bool cores_overlap(const Shape& s, const Shape& t) {
    if (!s.polygon() && !t.polygon()) {
        if (s.core.size() == 2 && t.core.size() == 2) {
            // two segments cross properly: each one's end points strictly on both sides of the other
            auto sides = [](const P2& a, const P2& b, const P2& p, const P2& q) {
                return static_cast<int>(sign_of(cross(b - a, p - a))) * static_cast<int>(sign_of(cross(b - a, q - a)));
            };
            return sides(s.core[0], s.core[1], t.core[0], t.core[1]) < 0 && sides(t.core[0], t.core[1], s.core[0], s.core[1]) < 0;
        }
        return false; // a point has no interior; touching is found by the distance
    }
    for (const Shape* owner : {&s, &t})
        for (const auto& [a, b] : edges(*owner)) {
            const P2 axis{b.y - a.y, a.x - b.x}; // an edge normal, unnormalised
            Rational smin, smax, tmin, tmax;
            for (std::size_t k = 0; k < s.core.size(); ++k) {
                const Rational v = dot(s.core[k], axis);
                if (k == 0 || v < smin)
                    smin = v;
                if (k == 0 || v > smax)
                    smax = v;
            }
            for (std::size_t k = 0; k < t.core.size(); ++k) {
                const Rational v = dot(t.core[k], axis);
                if (k == 0 || v < tmin)
                    tmin = v;
                if (k == 0 || v > tmax)
                    tmax = v;
            }
            if (!(smax > tmin) || !(tmax > smin))
                return false; // separated or touching along this axis
        }
    return true;
}

// Reads a shape of a body centred at c: "disk" (radius, optional "center"), "segment" (two end
// points) or "polygon" (three or more vertices, convex), each offset from the centre, with an
// optional "radius" (a capsule, a polygon's skin).
Shape read_shape(const ReadJson& js, const std::string& sp, const P2& c) {
    jr::expect_object(js, sp, {"disk", "segment", "polygon", "center", "radius"}, {});
    Shape shape;
    shape.path = sp;
    const int kinds = js.contains("disk") + js.contains("segment") + js.contains("polygon");
    if (kinds != 1)
        input_error(sp, "expected exactly one of \"disk\" (a radius), \"segment\" (two end points) and \"polygon\" (its vertices)");
    if (js.contains("disk")) {
        if (js.contains("radius"))
            input_error(sp + ".radius", "a disk's radius is \"disk\"");
        shape.r = jr::get_rational(js["disk"], sp + ".disk");
        if (sign_of(shape.r) != Sign::positive)
            input_error(sp + ".disk", "radius must be positive, got " + to_string(shape.r));
        shape.core.push_back(c + (js.contains("center") ? get_point(js["center"], sp + ".center") : P2{}));
        return shape;
    }
    if (js.contains("center"))
        input_error(sp + ".center", js.contains("segment") ? "a segment has end points, not a centre"
                                                           : "a polygon has vertices, not a centre");
    if (js.contains("radius")) {
        shape.r = jr::get_rational(js["radius"], sp + ".radius");
        if (sign_of(shape.r) == Sign::negative)
            input_error(sp + ".radius", "must be >= 0, got " + to_string(shape.r));
    }
    if (js.contains("segment")) {
        jr::expect_array(js["segment"], sp + ".segment");
        if (js["segment"].size() != 2)
            input_error(sp + ".segment", "expected two end points (offsets from the body's centre)");
        for (std::size_t k = 0; k < 2; ++k)
            shape.core.push_back(c + get_point(js["segment"][k], idx(sp + ".segment", k)));
        if (shape.core[0] == shape.core[1])
            input_error(sp + ".segment", "the end points coincide");
        return shape;
    }
    jr::expect_array(js["polygon"], sp + ".polygon");
    const std::size_t n = js["polygon"].size();
    if (n < 3 || n > 64)
        input_error(sp + ".polygon", "expected 3 to 64 vertices (offsets from the body's centre), got " + std::to_string(n));
    for (std::size_t k = 0; k < n; ++k)
        shape.core.push_back(c + get_point(js["polygon"][k], idx(sp + ".polygon", k)));
    // Strictly convex, either orientation (made counter-clockwise), simple (turning once).
    Sign turn = Sign::zero;
    for (std::size_t k = 0; k < n; ++k) {
        const P2& a = shape.core[k];
        const P2& b = shape.core[(k + 1) % n];
        const P2& d = shape.core[(k + 2) % n];
        const Sign t = sign_of(cross(b - a, d - b));
        if (t == Sign::zero)
            input_error(idx(sp + ".polygon", (k + 1) % n), "three consecutive vertices on a line (or repeated): give a strictly convex polygon");
        if (turn != Sign::zero && t != turn)
            input_error(idx(sp + ".polygon", (k + 1) % n), "the polygon is not convex here");
        turn = t;
    }
    // A star polygon turns one way at every vertex too, but winds more than once: convexity is
    // checked as "every other vertex strictly on the inner side of every edge".
    for (std::size_t k = 0; k < n; ++k)
        for (std::size_t m = 0; m < n; ++m) {
            if (m == k || m == (k + 1) % n)
                continue;
            if (sign_of(cross(shape.core[(k + 1) % n] - shape.core[k], shape.core[m] - shape.core[k])) != turn)
                input_error(sp + ".polygon", "the polygon is not convex (or its edges cross)");
        }
    if (turn == Sign::negative)
        std::reverse(shape.core.begin(), shape.core.end());
    return shape;
}
// Where a shape touches a boundary: its core's vertices at distance exactly r from the line
// (two for an edge lying on it), each as (point, the boundary's normal). InputError when the
// shape reaches beyond the boundary (an overlap at the impact).
std::vector<std::pair<P2, P2>> touch_boundary(const Shape& s, const Boundary& bd) {
    Rational lowest;
    for (std::size_t k = 0; k < s.core.size(); ++k) {
        const Rational h = dot(s.core[k] - bd.p, bd.n);
        if (k == 0 || h < lowest)
            lowest = h;
    }
    if (lowest < s.r)
        input_error(s.path, "reaches beyond the boundary " + in_quotes(bd.name) + ": its core is at distance " +
                                to_string(lowest) + " from it, less than its radius " + to_string(s.r) +
                                " (the shapes of a scene touch, never overlap)");
    std::vector<std::pair<P2, P2>> out;
    if (lowest == s.r)
        for (const P2& v : s.core)
            if (dot(v - bd.p, bd.n) == s.r)
                out.push_back({v - s.r * bd.n, bd.n});
    return out;
}

// The contact normal from core `from` across its edge [a, b] towards core `to`: usable when `to`
// lies on one side of the edge's line and off it somewhere (not when `to` lies on the line: two
// segments end to end in a line have no normal), and, for a polygon, on its outer side. The
// unit normal when the edge's length is rational, nothing when it is not (usable, irrational).
struct EdgeNormal {
    bool usable = false;
    std::optional<P2> normal;
};

std::optional<Rational> rational_length(const P2& d) { return rational_sqrt(dot(d, d)); }

EdgeNormal normal_from_edge(const Shape& from, const P2& a, const P2& b, const Shape& to) {
    bool left = false, right = false;
    for (const P2& o : to.core) {
        const Sign t = sign_of(cross(b - a, o - a));
        left = left || t == Sign::positive;
        right = right || t == Sign::negative;
    }
    if (left == right)
        return {}; // on both sides, or on the line
    if (left && from.polygon())
        return {}; // the inner side of a counter-clockwise polygon
    EdgeNormal out;
    out.usable = true;
    const P2 d = b - a;
    if (const auto len = rational_length(d)) {
        const P2 outward = (Rational(1) / *len) * P2{d.y, -d.x}; // the right-hand side of a -> b
        out.normal = right ? outward : Rational(-1) * outward;
    }
    return out;
}

// Where two shapes of different bodies touch (centres cs, ct): each contact as (point, unit
// normal from s's body to t's). The cores' closest pairs are found among each vertex of one and
// each edge (or the point) of the other; the shapes touch where that distance equals the sum of
// the radii. With a positive sum the normal is the closest pair's direction (rational: its length
// is the sum); with none, the touching cores' common edge line gives it. InputError naming both
// shapes for an overlap, an undefined normal or irrational geometry.
std::vector<std::pair<P2, P2>> touch(const Shape& s, const Shape& t) {
    const std::string where = s.path + " and " + t.path;
    if (cores_overlap(s, t))
        input_error(where, "the shapes overlap at the impact (their cores' interiors meet); a scene's shapes touch");
    auto features = [](const Shape& sh) {
        auto e = edges(sh);
        if (e.empty())
            e.push_back({sh.core[0], sh.core[0]});
        return e;
    };
    std::optional<Rational> best;
    std::vector<std::pair<P2, P2>> pairs; // closest points (on s's core, on t's)
    auto consider = [&](const P2& p, const P2& q) {
        const Rational d2 = dot(q - p, q - p);
        if (!best || d2 < *best) {
            best = d2;
            pairs.clear();
        }
        if (d2 == *best && std::find_if(pairs.begin(), pairs.end(), [&](const auto& x) { return x.first == p && x.second == q; }) == pairs.end())
            pairs.push_back({p, q});
    };
    for (const P2& v : s.core)
        for (const auto& [a, b] : features(t))
            consider(v, closest_on_segment(a, b, v));
    for (const P2& w : t.core)
        for (const auto& [a, b] : features(s))
            consider(closest_on_segment(a, b, w), w);
    const Rational sum = s.r + t.r;
    if (*best < sum * sum)
        input_error(where, "the shapes overlap at the impact: their cores are " + to_string(*best) +
                               " apart squared, less than the square of their radii's sum " + to_string(sum));
    std::vector<std::pair<P2, P2>> out;
    if (*best > sum * sum)
        return out;
    if (sign_of(sum) == Sign::positive) {
        for (const auto& [p, q] : pairs) {
            const P2 n = (Rational(1) / sum) * (q - p);
            out.push_back({p + s.r * n, n});
        }
        return out;
    }
    // Touching cores: one normal for all the touching points, from an edge through one of them
    // whose line has the other core on one side (an edge of irrational length is named only when
    // no other edge gives the normal).
    std::optional<P2> normal;
    std::optional<std::pair<P2, P2>> irrational;
    for (const auto& [x, unused] : pairs) {
        (void)unused;
        for (int side = 0; side < 2; ++side) {
            const Shape& from = side == 0 ? s : t;
            const Shape& to = side == 0 ? t : s;
            for (const auto& [a, b] : edges(from)) {
                if (!on_segment(a, b, x))
                    continue;
                const EdgeNormal e = normal_from_edge(from, a, b, to);
                if (!e.usable)
                    continue;
                if (!e.normal) {
                    if (!irrational)
                        irrational = {a, b};
                    continue;
                }
                const P2 n = side == 0 ? *e.normal : Rational(-1) * *e.normal; // from s to t
                if (normal && !(*normal == n))
                    input_error(where, "touch at " + text(x) + " with two possible normals, " + text(*normal) + " and " +
                                           text(n) + ": the normal is not defined (list this contact)");
                normal = n;
            }
        }
    }
    if (!normal && irrational) {
        const P2 d = irrational->second - irrational->first;
        input_error(where, "touch along the edge from " + text(irrational->first) + " to " + text(irrational->second) +
                               " of length sqrt(" + to_string(dot(d, d)) + "), not rational: the unit normal is irrational");
    }
    if (!normal)
        input_error(where, "touch at " + text(pairs.front().first) +
                               " where no edge line separates them (corners, or segments end to end): the normal is not "
                               "defined (list this contact)");
    for (const auto& [x, unused] : pairs) {
        (void)unused;
        out.push_back({x, *normal});
    }
    return out;
}

} // namespace

namespace scene_common {

ContactValues contact_values(const ReadJson& doc, const std::map<std::string, int>& index,
                             const std::vector<ContactRef>& contacts) {
    std::optional<Rational> mu0, e0;
    if (doc.contains("friction"))
        mu0 = jr::get_rational(doc["friction"], "$.friction");
    if (doc.contains("restitution"))
        e0 = jr::get_rational(doc["restitution"], "$.restitution");
    std::map<std::pair<int, int>, std::pair<std::optional<Rational>, std::optional<Rational>>> pairs;
    if (doc.contains("pairs")) {
        jr::expect_array(doc["pairs"], "$.pairs");
        for (std::size_t k = 0; k < doc["pairs"].size(); ++k) {
            const std::string pp = idx("$.pairs", k);
            const ReadJson& jp = doc["pairs"][k];
            jr::expect_object(jp, pp, {"bodies", "mu", "restitution"}, {"bodies"});
            const auto [a, b] = two_ends(jp["bodies"], pp + ".bodies", index, "a pair");
            auto& entry = pairs[{std::min(a, b), std::max(a, b)}];
            if (jp.contains("mu"))
                entry.first = jr::get_rational(jp["mu"], pp + ".mu");
            if (jp.contains("restitution"))
                entry.second = jr::get_rational(jp["restitution"], pp + ".restitution");
        }
    }
    ContactValues out;
    const std::size_t c = contacts.size();
    out.mu.assign(c, Rational(0));
    out.restitution.assign(c, Rational(0));
    std::vector<bool> has_e(c, false);
    for (std::size_t k = 0; k < c; ++k) {
        const ContactRef& ct = contacts[k];
        const auto pair = pairs.find({std::min(ct.i, ct.j), std::max(ct.i, ct.j)});
        std::optional<Rational> mu = ct.mu, e = ct.e;
        // where each value was given, for the message
        std::string mu_at = ct.path + ".mu", e_at = ct.path + ".restitution";
        if (!mu && pair != pairs.end() && pair->second.first) {
            mu = pair->second.first;
            mu_at = "$.pairs (" + ct.name + ")";
        }
        if (!e && pair != pairs.end() && pair->second.second) {
            e = pair->second.second;
            e_at = "$.pairs (" + ct.name + ")";
        }
        if (!mu && mu0) {
            mu = mu0;
            mu_at = "$.friction";
        }
        if (!e && e0) {
            e = e0;
            e_at = "$.restitution";
        }
        if (mu && sign_of(*mu) == Sign::negative)
            input_error(mu_at, "friction coefficient must be >= 0, got " + to_string(*mu));
        if (mu)
            out.mu[k] = *mu;
        if (e) {
            if (sign_of(*e) == Sign::negative || *e > Rational(1))
                input_error(e_at, "restitution must be in [0, 1], got " + to_string(*e));
            out.any_restitution = true;
            out.restitution[k] = *e;
            has_e[k] = true;
        }
        // A second contact of the same pair is named with its index: "box/ground #2".
        std::string name = ct.name;
        for (int copy = 2; std::find(out.names.begin(), out.names.end(), name) != out.names.end(); ++copy)
            name = ct.name + " #" + std::to_string(copy);
        out.names.push_back(name);
    }
    if (out.any_restitution)
        for (std::size_t k = 0; k < c; ++k)
            if (!has_e[k])
                input_error(contacts[k].path, "contact " + std::to_string(k + 1) + " (" + contacts[k].name +
                                                  ") has no restitution, other contacts have one: give it for every contact "
                                                  "(per contact, per pair, or \"restitution\" for the scene)");
    return out;
}

std::pair<int, int> two_ends(const ReadJson& names, const std::string& path, const std::map<std::string, int>& index,
                             const std::string& what) {
    jr::expect_array(names, path);
    if (names.size() != 2)
        input_error(path, "expected two names" + std::string(what == "a contact" ? " (the normal points from the first to the second)" : ""));
    int ends[2];
    for (int e = 0; e < 2; ++e) {
        const std::string place = idx(path, static_cast<std::size_t>(e));
        const std::string nm = jr::get_string(names[e], place);
        const auto it = index.find(nm);
        if (it == index.end())
            input_error(place, "no body or boundary " + in_quotes(nm));
        ends[e] = it->second;
    }
    if (ends[0] == ends[1] || (ends[0] < 0 && ends[1] < 0))
        input_error(path, what + (what == "a pair" ? " is two bodies" : " is between two bodies") + ", or a body and a boundary");
    return {ends[0], ends[1]};
}

Listed read_listed(const ReadJson& jc, const std::string& path, const std::map<std::string, int>& index) {
    jr::expect_object(jc, path, {"bodies", "point", "normal", "mu", "restitution"}, {"bodies", "point", "normal"});
    Listed out;
    std::tie(out.i, out.j) = two_ends(jc["bodies"], path + ".bodies", index, "a contact");
    if (out.j < 0) { // a boundary second: swapped, so that a boundary is always i
        std::swap(out.i, out.j);
        out.flip = true;
    }
    if (jc.contains("mu"))
        out.mu = jr::get_rational(jc["mu"], path + ".mu");
    if (jc.contains("restitution"))
        out.e = jr::get_rational(jc["restitution"], path + ".restitution");
    return out;
}

void check_scene_mechanics(const ReadJson& doc, const System& out) {
    try {
        make_mechanics(out, Dependent::allow); // dependent columns: refused by the commands that need full rank
    } catch (const InputError& err) {
        // In the scene's own terms: its place ($.contacts where listed, else the scene), the
        // contacts it has, and no path of a system file ($.contacts.friction) the scene lacks.
        std::string why = err.what();
        if (why.rfind("$.", 0) == 0)
            if (const auto colon = why.find(": "); colon != std::string::npos)
                why = why.substr(colon + 2);
        const std::size_t c = out.contact_names.size();
        std::string list;
        for (std::size_t k = 0; k < c && k < 6; ++k)
            list += (k ? "; " : "") + std::to_string(k + 1) + ": " + out.contact_names[k];
        input_error(doc.contains("contacts") && !doc["contacts"].is_string() ? "$.contacts" : "$",
                    "the scene's contacts (" + list + (c > 6 ? "; ..." : "") + "): " + why);
    }
}

} // namespace scene_common

System parse_scene(const ReadJson& doc) {
    if (doc.contains("dimension")) {
        const ReadJson& d = doc["dimension"];
        if (!d.is_number_integer() || (d.get<long long>() != 2 && d.get<long long>() != 3))
            input_error("$.dimension", "expected 2 (the plane, the default) or 3 (space)");
        if (d.get<long long>() == 3)
            return parse_scene_3d(doc);
    }
    jr::expect_object(doc, "$", {"format", "name", "dimension", "bodies", "boundaries", "contacts", "friction", "restitution", "pairs"},
                  {"format", "name", "bodies"});
    System out;
    out.name = jr::get_string(doc["name"], "$.name");
    if (out.name.empty())
        input_error("$.name", "empty scene name");
    std::vector<Body> bodies;
    std::map<std::string, int> index; // bodies >= 0, boundaries -(k + 2)
    jr::expect_array(doc["bodies"], "$.bodies");
    if (doc["bodies"].empty())
        input_error("$.bodies", "no bodies");
    for (std::size_t b = 0; b < doc["bodies"].size(); ++b) {
        const std::string bp = idx("$.bodies", b);
        const ReadJson& jb = doc["bodies"][b];
        jr::expect_object(jb, bp, {"name", "mass", "inertia", "position", "shapes"}, {"name", "mass", "inertia", "position"});
        Body body;
        body.name = jr::get_string(jb["name"], bp + ".name");
        body.m = jr::get_rational(jb["mass"], bp + ".mass");
        body.J = jr::get_rational(jb["inertia"], bp + ".inertia");
        body.c = get_point(jb["position"], bp + ".position");
        if (body.name.empty() || !index.emplace(body.name, static_cast<int>(b)).second)
            input_error(bp + ".name", "empty or repeated name " + in_quotes(body.name));
        if (sign_of(body.m) != Sign::positive)
            input_error(bp + ".mass", "must be positive, got " + to_string(body.m));
        if (sign_of(body.J) != Sign::positive)
            input_error(bp + ".inertia", "must be positive, got " + to_string(body.J));
        if (jb.contains("shapes")) {
            jr::expect_array(jb["shapes"], bp + ".shapes");
            for (std::size_t s = 0; s < jb["shapes"].size(); ++s)
                body.shapes.push_back(read_shape(jb["shapes"][s], idx(bp + ".shapes", s), body.c));
        }
        bodies.push_back(body);
    }
    std::vector<Boundary> boundaries;
    if (doc.contains("boundaries")) {
        jr::expect_array(doc["boundaries"], "$.boundaries");
        for (std::size_t k = 0; k < doc["boundaries"].size(); ++k) {
            const std::string kp = idx("$.boundaries", k);
            const ReadJson& jk = doc["boundaries"][k];
            jr::expect_object(jk, kp, {"name", "point", "normal"}, {"name", "point", "normal"});
            Boundary bd{jr::get_string(jk["name"], kp + ".name"), get_point(jk["point"], kp + ".point"),
                        get_unit(jk["normal"], kp + ".normal")};
            if (bd.name.empty() || !index.emplace(bd.name, -static_cast<int>(k) - 2).second)
                input_error(kp + ".name", "empty or repeated name " + in_quotes(bd.name));
            boundaries.push_back(bd);
        }
    }
    auto name_of = [&](int i) { return i >= 0 ? bodies[static_cast<std::size_t>(i)].name : boundaries[static_cast<std::size_t>(-i - 2)].name; };

    // Contacts.
    std::vector<Contact> contacts;
    const bool find = !doc.contains("contacts") || (doc["contacts"].is_string() && doc["contacts"].get<std::string>() == "find");
    if (find) {
        if (doc.contains("contacts") && !doc["contacts"].is_string())
            input_error("$.contacts", "expected \"find\" or a list of contacts");
        auto add = [&](int i, int j, const P2& p, const P2& n, const std::string& where) {
            // One contact per point of a pair of bodies: a vertex shared by two shapes of a body
            // (two segments of an outline) is found by each, and counted once.
            for (const Contact& other : contacts)
                if (other.i == i && other.j == j && other.p == p) {
                    if (!(other.n == n))
                        input_error(where, "touches at " + text(p) + " with the normal " + text(n) + ", and " + other.path +
                                               " there with " + text(other.n) + ": the normal is not defined (list this contact)");
                    return;
                }
            contacts.push_back(Contact{i, j, p, n, name_of(i) + "/" + name_of(j), where, {}, {}});
        };
        for (std::size_t i = 0; i < bodies.size(); ++i)
            for (const Shape& sh : bodies[i].shapes) {
                for (std::size_t k = 0; k < boundaries.size(); ++k)
                    for (const auto& [p, n] : touch_boundary(sh, boundaries[k]))
                        add(-static_cast<int>(k) - 2, static_cast<int>(i), p, n, sh.path);
                for (std::size_t j = i + 1; j < bodies.size(); ++j)
                    for (const Shape& t : bodies[j].shapes)
                        for (const auto& [p, n] : touch(sh, t))
                            add(static_cast<int>(i), static_cast<int>(j), p, n, sh.path + " and " + t.path);
            }
        if (contacts.empty())
            input_error("$.contacts", "no two shapes touch (distance exactly zero): no contact found");
    } else {
        jr::expect_array(doc["contacts"], "$.contacts");
        if (doc["contacts"].empty())
            input_error("$.contacts", "no contacts");
        for (std::size_t k = 0; k < doc["contacts"].size(); ++k) {
            const std::string cp = idx("$.contacts", k);
            const ReadJson& jc = doc["contacts"][k];
            const scene_common::Listed listed = scene_common::read_listed(jc, cp, index);
            Contact c;
            c.p = get_point(jc["point"], cp + ".point");
            c.n = get_unit(jc["normal"], cp + ".normal");
            if (listed.flip)
                c.n = Rational(-1) * c.n;
            c.path = cp;
            c.i = listed.i;
            c.j = listed.j;
            c.mu = listed.mu;
            c.e = listed.e;
            c.name = name_of(c.i) + "/" + name_of(c.j);
            // The point must be exactly on a shape of each end (where it has shapes) or on the boundary.
            for (const int e : {c.i, c.j}) {
                if (e < 0) {
                    const Boundary& bd = boundaries[static_cast<std::size_t>(-e - 2)];
                    if (sign_of(dot(c.p - bd.p, bd.n)) != Sign::zero)
                        input_error(cp + ".point", text(c.p) + " is not on the boundary " + in_quotes(bd.name) +
                                                       " (its distance is " + to_string(dot(c.p - bd.p, bd.n)) + ", not 0)");
                    if (dot(c.n, bd.n) != Rational(1))
                        input_error(cp + ".normal", "a contact with boundary " + in_quotes(bd.name) + " has its normal");
                    continue;
                }
                const Body& body = bodies[static_cast<std::size_t>(e)];
                if (body.shapes.empty())
                    continue;
                bool on = false;
                for (const Shape& s : body.shapes)
                    on = on || on_shape(s, c.p);
                if (!on)
                    input_error(cp + ".point", text(c.p) + " is not on a shape of " + in_quotes(body.name) +
                                                   " (a declared contact must be at distance exactly zero)");
            }
            contacts.push_back(c);
        }
    }

    const std::size_t n = 3 * bodies.size(), c = contacts.size();
    out.masses.resize(n);
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        out.masses[3 * b] = out.masses[3 * b + 1] = bodies[b].m;
        out.masses[3 * b + 2] = bodies[b].J;
        for (const char* v : {".vx", ".vy", ".omega"})
            out.velocity_names.push_back(bodies[b].name + v);
    }
    Matrix W(n, c);
    // The column of direction d at point p for the contact (i, j).
    auto column = [&](const Contact& k, const P2& d) {
        Vector col(n);
        for (const int e : {k.i, k.j}) {
            if (e < 0)
                continue;
            const Rational s = e == k.j ? Rational(1) : Rational(-1);
            const std::size_t b = static_cast<std::size_t>(e);
            col[3 * b] += s * d.x;
            col[3 * b + 1] += s * d.y;
            col[3 * b + 2] += s * cross(k.p - bodies[b].c, d);
        }
        return col;
    };
    std::vector<scene_common::ContactRef> refs;
    for (const Contact& ct : contacts)
        refs.push_back({ct.i, ct.j, ct.name, ct.path, ct.mu, ct.e});
    const scene_common::ContactValues values = scene_common::contact_values(doc, index, refs);
    for (std::size_t k = 0; k < c; ++k) {
        const Contact& ct = contacts[k];
        const Vector col = column(ct, ct.n);
        for (std::size_t r = 0; r < n; ++r)
            W(r, k) = col[r];
        if (sign_of(values.mu[k]) == Sign::positive) // its tangent (n_y, -n_x), Box2D's
            out.friction.push_back(FrictionDecl{k, values.mu[k], {column(ct, P2{ct.n.y, -ct.n.x})}, Rational(0)});
    }
    out.contact_names = values.names;
    if (values.any_restitution)
        out.restitution = values.restitution;
    out.W = W;
    scene_common::check_scene_mechanics(doc, out);
    return out;
}

} // namespace impactcert
