// SPDX-License-Identifier: GPL-3.0-or-later
// Planar scenes (scene.hpp): exact contact detection and the columns of W from lever arms.
#include "model/scene.hpp"

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

struct Shape {
    bool disk = true;
    Rational r;  // disk
    P2 a, b;     // disk: a is the centre; segment: the end points (world positions)
    std::string path;
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

bool on_shape(const Shape& s, const P2& q) {
    if (s.disk)
        return dot(q - s.a, q - s.a) == s.r * s.r;
    return on_segment(s.a, s.b, q);
}

} // namespace

System parse_scene(const ReadJson& doc) {
    jr::expect_object(doc, "$", {"format", "name", "bodies", "boundaries", "contacts", "friction", "restitution", "pairs"},
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
            for (std::size_t s = 0; s < jb["shapes"].size(); ++s) {
                const std::string sp = idx(bp + ".shapes", s);
                const ReadJson& js = jb["shapes"][s];
                jr::expect_object(js, sp, {"disk", "segment", "center"}, {});
                Shape shape;
                shape.path = sp;
                if (js.contains("disk") == js.contains("segment"))
                    input_error(sp, "expected exactly one of \"disk\" (a radius) and \"segment\" (two end points)");
                if (js.contains("disk")) {
                    shape.r = jr::get_rational(js["disk"], sp + ".disk");
                    if (sign_of(shape.r) != Sign::positive)
                        input_error(sp + ".disk", "radius must be positive, got " + to_string(shape.r));
                    shape.a = body.c + (js.contains("center") ? get_point(js["center"], sp + ".center") : P2{});
                } else {
                    if (js.contains("center"))
                        input_error(sp + ".center", "a segment has end points, not a centre");
                    jr::expect_array(js["segment"], sp + ".segment");
                    if (js["segment"].size() != 2)
                        input_error(sp + ".segment", "expected two end points (offsets from the body's centre)");
                    shape.disk = false;
                    shape.a = body.c + get_point(js["segment"][0], sp + ".segment[0]");
                    shape.b = body.c + get_point(js["segment"][1], sp + ".segment[1]");
                    if (shape.a == shape.b)
                        input_error(sp + ".segment", "the end points coincide");
                }
                body.shapes.push_back(shape);
            }
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
            contacts.push_back(Contact{i, j, p, n, name_of(i) + "/" + name_of(j), where, {}, {}});
        };
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            for (std::size_t si = 0; si < bodies[i].shapes.size(); ++si) {
                const Shape& s = bodies[i].shapes[si];
                // against the boundaries
                for (std::size_t k = 0; k < boundaries.size(); ++k) {
                    const Boundary& bd = boundaries[k];
                    const int bi = -static_cast<int>(k) - 2;
                    if (s.disk) {
                        if (dot(s.a - bd.p, bd.n) == s.r)
                            add(bi, static_cast<int>(i), s.a - s.r * bd.n, bd.n, s.path);
                    } else {
                        for (const P2& e : {s.a, s.b})
                            if (sign_of(dot(e - bd.p, bd.n)) == Sign::zero)
                                add(bi, static_cast<int>(i), e, bd.n, s.path);
                    }
                }
                // against the shapes of later bodies
                for (std::size_t j = i + 1; j < bodies.size(); ++j)
                    for (const Shape& t : bodies[j].shapes) {
                        const std::string where = s.path + " and " + t.path;
                        if (s.disk && t.disk) {
                            const P2 d = t.a - s.a;
                            if (dot(d, d) == (s.r + t.r) * (s.r + t.r)) {
                                const P2 n = (Rational(1) / (s.r + t.r)) * d;
                                add(static_cast<int>(i), static_cast<int>(j), s.a + s.r * n, n, where);
                            }
                        } else if (s.disk != t.disk) {
                            const Shape& disk = s.disk ? s : t;
                            const Shape& seg = s.disk ? t : s;
                            const P2 q = closest_on_segment(seg.a, seg.b, disk.a);
                            if (dot(disk.a - q, disk.a - q) == disk.r * disk.r) {
                                // normal from the segment's body to the disk's
                                const P2 n = (Rational(1) / disk.r) * (disk.a - q);
                                if (s.disk)
                                    add(static_cast<int>(i), static_cast<int>(j), q, Rational(-1) * n, where);
                                else
                                    add(static_cast<int>(i), static_cast<int>(j), q, n, where);
                            }
                        } else {
                            // segment against segment: an end point of one on the other
                            for (int side = 0; side < 2; ++side) {
                                const Shape& edge = side == 0 ? s : t;
                                const Shape& tip = side == 0 ? t : s;
                                for (const P2& e : {tip.a, tip.b}) {
                                    if (!on_segment(edge.a, edge.b, e))
                                        continue;
                                    if (e == edge.a || e == edge.b)
                                        input_error(where, "two end points touch at " + text(e) +
                                                               ": the normal is not defined (list this contact)");
                                    const P2 d = edge.b - edge.a;
                                    const auto len = rational_sqrt(dot(d, d));
                                    if (!len)
                                        input_error(edge.path, "the segment's length is sqrt(" + to_string(dot(d, d)) +
                                                                   "), not rational: its unit normal is irrational");
                                    P2 n = (Rational(1) / *len) * P2{-d.y, d.x};
                                    // from the edge's body towards the tip's body (its centre's side)
                                    const P2 tip_centre = bodies[side == 0 ? j : i].c;
                                    const Sign toward = sign_of(dot(tip_centre - e, n));
                                    if (toward == Sign::zero)
                                        input_error(where, "the touching body's centre lies on the contact line: "
                                                           "the normal's direction is not defined (list this contact)");
                                    if (toward == Sign::negative)
                                        n = Rational(-1) * n;
                                    // normal from body i to body j
                                    add(static_cast<int>(i), static_cast<int>(j), e, side == 0 ? n : Rational(-1) * n, where);
                                }
                            }
                        }
                    }
            }
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
            jr::expect_object(jc, cp, {"bodies", "point", "normal", "mu", "restitution"}, {"bodies", "point", "normal"});
            jr::expect_array(jc["bodies"], cp + ".bodies");
            if (jc["bodies"].size() != 2)
                input_error(cp + ".bodies", "expected two names (the normal points from the first to the second)");
            int ends[2];
            for (int e = 0; e < 2; ++e) {
                const std::string nm = jr::get_string(jc["bodies"][e], idx(cp + ".bodies", static_cast<std::size_t>(e)));
                const auto it = index.find(nm);
                if (it == index.end())
                    input_error(idx(cp + ".bodies", static_cast<std::size_t>(e)), "no body or boundary " + in_quotes(nm));
                ends[e] = it->second;
            }
            if (ends[0] == ends[1] || (ends[0] < 0 && ends[1] < 0))
                input_error(cp + ".bodies", "a contact is between two bodies, or a body and a boundary");
            Contact c;
            c.p = get_point(jc["point"], cp + ".point");
            c.n = get_unit(jc["normal"], cp + ".normal");
            c.path = cp;
            if (ends[1] < 0) { // a boundary second: flip, so that a boundary is always i
                std::swap(ends[0], ends[1]);
                c.n = Rational(-1) * c.n;
            }
            c.i = ends[0];
            c.j = ends[1];
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
            if (jc.contains("mu"))
                c.mu = jr::get_rational(jc["mu"], cp + ".mu");
            if (jc.contains("restitution"))
                c.e = jr::get_rational(jc["restitution"], cp + ".restitution");
            contacts.push_back(c);
        }
    }

    // mu and restitution: the contact's, else its pair's, else the scene's.
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
            jr::expect_array(jp["bodies"], pp + ".bodies");
            if (jp["bodies"].size() != 2)
                input_error(pp + ".bodies", "expected two names");
            int ends[2];
            for (int e = 0; e < 2; ++e) {
                const std::string nm = jr::get_string(jp["bodies"][e], idx(pp + ".bodies", static_cast<std::size_t>(e)));
                const auto it = index.find(nm);
                if (it == index.end())
                    input_error(idx(pp + ".bodies", static_cast<std::size_t>(e)), "no body or boundary " + in_quotes(nm));
                ends[e] = it->second;
            }
            auto& entry = pairs[{std::min(ends[0], ends[1]), std::max(ends[0], ends[1])}];
            if (jp.contains("mu"))
                entry.first = jr::get_rational(jp["mu"], pp + ".mu");
            if (jp.contains("restitution"))
                entry.second = jr::get_rational(jp["restitution"], pp + ".restitution");
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
    bool any_e = false;
    std::vector<Rational> restitution(c);
    for (std::size_t k = 0; k < c; ++k) {
        const Contact& ct = contacts[k];
        const Vector col = column(ct, ct.n);
        for (std::size_t r = 0; r < n; ++r)
            W(r, k) = col[r];
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
        if (e) {
            if (sign_of(*e) == Sign::negative || *e > Rational(1))
                input_error(e_at, "restitution must be in [0, 1], got " + to_string(*e));
            any_e = true;
            restitution[k] = *e;
        }
        if (mu && sign_of(*mu) == Sign::positive)
            out.friction.push_back(FrictionDecl{k, *mu, {column(ct, P2{ct.n.y, -ct.n.x})}, Rational(0)});
        // A second contact of the same pair is named with its index: "box/ground #2".
        std::string name = ct.name;
        for (int copy = 2; std::find(out.contact_names.begin(), out.contact_names.end(), name) != out.contact_names.end(); ++copy)
            name = ct.name + " #" + std::to_string(copy);
        out.contact_names.push_back(name);
    }
    if (any_e) {
        for (std::size_t k = 0; k < c; ++k) {
            const Contact& ct = contacts[k];
            const auto pair = pairs.find({std::min(ct.i, ct.j), std::max(ct.i, ct.j)});
            if (!ct.e && !(pair != pairs.end() && pair->second.second) && !e0)
                input_error(ct.path, "contact " + std::to_string(k + 1) + " (" + ct.name +
                                         ") has no restitution, other contacts have one: give it for every contact "
                                         "(per contact, per pair, or \"restitution\" for the scene)");
        }
        out.restitution = restitution;
    }
    out.W = W;
    try {
        make_mechanics(out);
    } catch (const InputError& err) {
        // In the scene's own terms: its place ($.contacts where listed, else the scene), the
        // contacts it has, and no path of a system file ($.contacts.friction) the scene lacks.
        std::string why = err.what();
        if (why.rfind("$.contacts", 0) == 0)
            if (const auto colon = why.find(": "); colon != std::string::npos)
                why = why.substr(colon + 2);
        std::string list;
        for (std::size_t k = 0; k < c && k < 6; ++k)
            list += (k ? "; " : "") + std::to_string(k + 1) + ": " + contacts[k].name;
        input_error(doc.contains("contacts") ? "$.contacts" : "$",
                    "the scene's contacts (" + list + (c > 6 ? "; ..." : "") + "): " + why +
                        "; a body with more contact columns than velocities (redundant contacts) is not supported yet");
    }
    return out;
}

} // namespace impactcert
