// SPDX-License-Identifier: GPL-3.0-or-later
// Scenes in space (scene.hpp, "dimension": 3): spheres and boxes with rational rotations, planes,
// contacts found exactly, two tangents per rough contact (ODE's friction box).
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

// A named namespace (the unity build puts this file beside scene.cpp, whose helpers are in an
// anonymous one): names here hide those.
namespace scene3 {

struct P3 {
    Rational x, y, z;
};
P3 operator+(const P3& a, const P3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
P3 operator-(const P3& a, const P3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
P3 operator*(const Rational& s, const P3& a) { return {s * a.x, s * a.y, s * a.z}; }
Rational dot(const P3& a, const P3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
P3 cross(const P3& a, const P3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
bool operator==(const P3& a, const P3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
std::string text(const P3& p) { return "(" + to_string(p.x) + ", " + to_string(p.y) + ", " + to_string(p.z) + ")"; }
Rational coord(const P3& p, int k) { return k == 0 ? p.x : k == 1 ? p.y : p.z; }

P3 get_point(const ReadJson& j, const std::string& path) {
    const Vector v = jr::get_vector(j, path);
    if (v.size() != 3)
        input_error(path, "expected a point [x, y, z], got " + std::to_string(v.size()) + " numbers");
    return {v[0], v[1], v[2]};
}

P3 get_unit(const ReadJson& j, const std::string& path) {
    const P3 n = get_point(j, path);
    if (dot(n, n) != Rational(1))
        input_error(path, "not a unit vector: its squared length is " + to_string(dot(n, n)) +
                              " (give a rational unit normal, e.g. [\"2/3\", \"2/3\", \"1/3\"])");
    return n;
}

// A rotation: columns are the body's axes in the world; R^T R = I and det R = 1, exactly.
struct Rotation {
    P3 col[3];
    P3 apply(const P3& v) const { return v.x * col[0] + v.y * col[1] + v.z * col[2]; }
    P3 inverse_apply(const P3& v) const { return {dot(col[0], v), dot(col[1], v), dot(col[2], v)}; }
};

Rotation get_rotation(const ReadJson& j, const std::string& path) {
    jr::expect_array(j, path);
    if (j.size() != 3)
        input_error(path, "expected a 3 x 3 rotation matrix (rows)");
    Rational m[3][3];
    for (std::size_t r = 0; r < 3; ++r) {
        const Vector row = jr::get_vector(j[r], idx(path, r));
        if (row.size() != 3)
            input_error(idx(path, r), "expected 3 numbers");
        for (int c = 0; c < 3; ++c)
            m[r][c] = row[static_cast<std::size_t>(c)];
    }
    Rotation R;
    for (int c = 0; c < 3; ++c)
        R.col[c] = {m[0][c], m[1][c], m[2][c]};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
            if (dot(R.col[a], R.col[b]) != Rational(a == b ? 1 : 0))
                input_error(path, "not a rotation: its columns are not orthonormal (R^T R != I; rational rotations come "
                                  "from Pythagorean quadruples or quaternions with rational entries)");
    if (dot(cross(R.col[0], R.col[1]), R.col[2]) != Rational(1))
        input_error(path, "not a rotation: its determinant is -1 (a reflection)");
    return R;
}

struct Shape {
    bool sphere = true;
    Rational r; // sphere
    P3 c;       // world centre
    P3 h;       // box: half extents along the body's axes
    Rotation R; // box: the body's rotation
    std::string path;
};

struct Body {
    std::string name;
    Rational m;
    Rational I[3][3]; // about the centre, in the world's axes
    P3 c;
    Rotation R;
    std::vector<Shape> shapes;
};

struct Plane {
    std::string name;
    P3 p, n;
};

struct Contact {
    int i = -1, j = -1; // body indices; a plane (-(k + 2)) only ever i
    P3 p, n;            // point, unit normal from i to j
    std::string name, path;
    std::optional<Rational> mu, e;
};

std::vector<P3> box_vertices(const Shape& s) {
    std::vector<P3> out;
    for (int a : {-1, 1})
        for (int b : {-1, 1})
            for (int c : {-1, 1})
                out.push_back(s.c + s.R.apply(P3{Rational(a) * s.h.x, Rational(b) * s.h.y, Rational(c) * s.h.z}));
    return out;
}

// The point of box s nearest to q (q itself when inside), and whether q is strictly inside.
std::pair<P3, bool> nearest_on_box(const Shape& s, const P3& q) {
    const P3 local = s.R.inverse_apply(q - s.c);
    Rational out[3];
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        const Rational x = coord(local, k), h = coord(s.h, k);
        out[k] = x < -h ? -h : x > h ? h : x;
        inside = inside && -h < x && x < h;
    }
    return {s.c + s.R.apply(P3{out[0], out[1], out[2]}), inside};
}

// Two rational unit tangents orthogonal to the rational unit normal n: the images of e1, e2
// under the reflection exchanging e3 and n (I - 2 v v^T / v.v, v = n - e3), rational and
// orthonormal; e1, e2 themselves when n = e3.
std::pair<P3, P3> tangents_of(const P3& n) {
    const P3 e1{1, 0, 0}, e2{0, 1, 0}, e3{0, 0, 1};
    const P3 v = n - e3;
    const Rational vv = dot(v, v);
    if (sign_of(vv) == Sign::zero)
        return {e1, e2};
    auto reflect = [&](const P3& x) { return x - (Rational(2) * dot(v, x) / vv) * v; };
    return {reflect(e1), reflect(e2)};
}

System parse(const ReadJson& doc) {
    jr::expect_object(doc, "$", {"format", "name", "dimension", "bodies", "boundaries", "contacts", "friction", "friction_cone",
                                 "restitution", "pairs"},
                      {"format", "name", "dimension", "bodies"});
    System out;
    // "friction_cone": "box" (default: each tangent bounded on its own), "pyramid" (MuJoCo's
    // pyramidal cone, |Lambda_T1| + |Lambda_T2| <= mu Lambda_N) or {"facets": [[a1, a2], ...]}.
    std::optional<std::vector<Vector>> facets;
    if (doc.contains("friction_cone")) {
        const ReadJson& fc = doc["friction_cone"];
        if (fc.is_string()) {
            const std::string name = fc.get<std::string>();
            if (name == "pyramid")
                facets = pyramid_facets();
            else if (name != "box")
                input_error("$.friction_cone", "expected \"box\", \"pyramid\" or {\"facets\": [...]}, got \"" + name + "\"");
        } else {
            jr::expect_object(fc, "$.friction_cone", {"facets"}, {"facets"});
            jr::expect_array(fc["facets"], "$.friction_cone.facets");
            facets.emplace();
            for (std::size_t j = 0; j < fc["facets"].size(); ++j)
                facets->push_back(jr::get_vector(fc["facets"][j], idx("$.friction_cone.facets", j)));
        }
        if (facets)
            (void)friction_polygon(*facets, "$.friction_cone.facets"); // named in the scene's terms
    }
    out.name = jr::get_string(doc["name"], "$.name");
    if (out.name.empty())
        input_error("$.name", "empty scene name");
    std::vector<Body> bodies;
    std::map<std::string, int> index;
    jr::expect_array(doc["bodies"], "$.bodies");
    if (doc["bodies"].empty())
        input_error("$.bodies", "no bodies");
    for (std::size_t b = 0; b < doc["bodies"].size(); ++b) {
        const std::string bp = idx("$.bodies", b);
        const ReadJson& jb = doc["bodies"][b];
        jr::expect_object(jb, bp, {"name", "mass", "inertia", "position", "rotation", "shapes"}, {"name", "mass", "inertia", "position"});
        Body body;
        body.name = jr::get_string(jb["name"], bp + ".name");
        body.m = jr::get_rational(jb["mass"], bp + ".mass");
        body.c = get_point(jb["position"], bp + ".position");
        body.R = jb.contains("rotation") ? get_rotation(jb["rotation"], bp + ".rotation")
                                         : Rotation{{P3{1, 0, 0}, P3{0, 1, 0}, P3{0, 0, 1}}};
        if (body.name.empty() || !index.emplace(body.name, static_cast<int>(b)).second)
            input_error(bp + ".name", "empty or repeated name " + in_quotes(body.name));
        if (sign_of(body.m) != Sign::positive)
            input_error(bp + ".mass", "must be positive, got " + to_string(body.m));
        // The inertia about the centre in the body's axes: three principal moments, or a 3 x 3
        // symmetric positive definite matrix; turned into the world's axes, R I R^T.
        Rational Ib[3][3] = {};
        const ReadJson& ji = jb["inertia"];
        jr::expect_array(ji, bp + ".inertia");
        if (ji.size() == 3 && !ji[0].is_array()) {
            const Vector d = jr::get_vector(ji, bp + ".inertia");
            for (int k = 0; k < 3; ++k) {
                Ib[k][k] = d[static_cast<std::size_t>(k)];
                if (sign_of(Ib[k][k]) != Sign::positive)
                    input_error(idx(bp + ".inertia", static_cast<std::size_t>(k)), "a principal moment must be positive");
            }
        } else {
            if (ji.size() != 3)
                input_error(bp + ".inertia", "expected three principal moments or a 3 x 3 matrix");
            for (std::size_t r = 0; r < 3; ++r) {
                const Vector row = jr::get_vector(ji[r], idx(bp + ".inertia", r));
                if (row.size() != 3)
                    input_error(idx(bp + ".inertia", r), "expected 3 numbers");
                for (int c = 0; c < 3; ++c)
                    Ib[r][c] = row[static_cast<std::size_t>(c)];
            }
            for (int a = 0; a < 3; ++a)
                for (int c = 0; c < 3; ++c)
                    if (Ib[a][c] != Ib[c][a])
                        input_error(bp + ".inertia", "not symmetric");
            // positive definite: leading principal minors > 0
            const Rational m1 = Ib[0][0], m2 = Ib[0][0] * Ib[1][1] - Ib[0][1] * Ib[1][0];
            const Rational m3 = Ib[0][0] * (Ib[1][1] * Ib[2][2] - Ib[1][2] * Ib[2][1]) -
                                Ib[0][1] * (Ib[1][0] * Ib[2][2] - Ib[1][2] * Ib[2][0]) +
                                Ib[0][2] * (Ib[1][0] * Ib[2][1] - Ib[1][1] * Ib[2][0]);
            if (sign_of(m1) != Sign::positive || sign_of(m2) != Sign::positive || sign_of(m3) != Sign::positive)
                input_error(bp + ".inertia", "not positive definite");
        }
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) {
                Rational s;
                for (int k = 0; k < 3; ++k)
                    for (int l = 0; l < 3; ++l)
                        s = s + coord(body.R.col[k], a) * Ib[k][l] * coord(body.R.col[l], c);
                body.I[a][c] = s;
            }
        if (jb.contains("shapes")) {
            jr::expect_array(jb["shapes"], bp + ".shapes");
            for (std::size_t s = 0; s < jb["shapes"].size(); ++s) {
                const std::string sp = idx(bp + ".shapes", s);
                const ReadJson& js = jb["shapes"][s];
                jr::expect_object(js, sp, {"sphere", "box", "center"}, {});
                Shape shape;
                shape.path = sp;
                if (js.contains("sphere") == js.contains("box"))
                    input_error(sp, "expected exactly one of \"sphere\" (a radius) and \"box\" (three half extents)");
                const P3 offset = js.contains("center") ? get_point(js["center"], sp + ".center") : P3{};
                shape.c = body.c + body.R.apply(offset);
                shape.R = body.R;
                if (js.contains("sphere")) {
                    shape.r = jr::get_rational(js["sphere"], sp + ".sphere");
                    if (sign_of(shape.r) != Sign::positive)
                        input_error(sp + ".sphere", "radius must be positive, got " + to_string(shape.r));
                } else {
                    shape.sphere = false;
                    const Vector h = jr::get_vector(js["box"], sp + ".box");
                    if (h.size() != 3)
                        input_error(sp + ".box", "expected three half extents");
                    for (const auto& x : h)
                        if (sign_of(x) != Sign::positive)
                            input_error(sp + ".box", "half extents must be positive");
                    shape.h = {h[0], h[1], h[2]};
                }
                body.shapes.push_back(shape);
            }
        }
        bodies.push_back(body);
    }
    std::vector<Plane> planes;
    if (doc.contains("boundaries")) {
        jr::expect_array(doc["boundaries"], "$.boundaries");
        for (std::size_t k = 0; k < doc["boundaries"].size(); ++k) {
            const std::string kp = idx("$.boundaries", k);
            const ReadJson& jk = doc["boundaries"][k];
            jr::expect_object(jk, kp, {"name", "point", "normal"}, {"name", "point", "normal"});
            Plane pl{jr::get_string(jk["name"], kp + ".name"), get_point(jk["point"], kp + ".point"),
                     get_unit(jk["normal"], kp + ".normal")};
            if (pl.name.empty() || !index.emplace(pl.name, -static_cast<int>(k) - 2).second)
                input_error(kp + ".name", "empty or repeated name " + in_quotes(pl.name));
            planes.push_back(pl);
        }
    }
    auto name_of = [&](int i) { return i >= 0 ? bodies[static_cast<std::size_t>(i)].name : planes[static_cast<std::size_t>(-i - 2)].name; };

    std::vector<Contact> contacts;
    if (doc.contains("contacts") && doc["contacts"].is_string() && doc["contacts"].get<std::string>() != "find")
        input_error("$.contacts", "expected \"find\" or a list of contacts");
    const bool find = !doc.contains("contacts") || doc["contacts"].is_string();
    if (find) {
        auto add = [&](int i, int j, const P3& p, const P3& n, const std::string& where) {
            // One contact per point of a pair of bodies (shapes of one body meeting there); two
            // normals at one point leave the contact undefined.
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
            for (const Shape& s : bodies[i].shapes) {
                for (std::size_t k = 0; k < planes.size(); ++k) {
                    const Plane& pl = planes[k];
                    const int pi = -static_cast<int>(k) - 2;
                    if (s.sphere) {
                        const Rational h = dot(s.c - pl.p, pl.n);
                        if (h < s.r)
                            input_error(s.path, "reaches beyond the plane " + in_quotes(pl.name) + " (distance " + to_string(h) +
                                                    " < radius " + to_string(s.r) + "): the shapes of a scene touch, never overlap");
                        if (h == s.r)
                            add(pi, static_cast<int>(i), s.c - s.r * pl.n, pl.n, s.path);
                        continue;
                    }
                    const auto vs = box_vertices(s);
                    Rational lowest = dot(vs[0] - pl.p, pl.n);
                    for (const auto& v : vs)
                        lowest = std::min(lowest, dot(v - pl.p, pl.n));
                    if (sign_of(lowest) == Sign::negative)
                        input_error(s.path, "reaches beyond the plane " + in_quotes(pl.name) + " (a corner at distance " +
                                                to_string(lowest) + "): the shapes of a scene touch, never overlap");
                    if (sign_of(lowest) == Sign::zero)
                        for (const auto& v : vs)
                            if (sign_of(dot(v - pl.p, pl.n)) == Sign::zero)
                                add(pi, static_cast<int>(i), v, pl.n, s.path);
                }
                for (std::size_t j = i + 1; j < bodies.size(); ++j)
                    for (const Shape& t : bodies[j].shapes) {
                        const std::string where = s.path + " and " + t.path;
                        if (!s.sphere && !t.sphere) {
                            // Surely apart when the centres are farther than the half diagonals'
                            // sum: |c| > |h| + |k| follows from |c|^2 > 2 (|h|^2 + |k|^2).
                            const P3 d = t.c - s.c;
                            if (dot(d, d) > Rational(2) * (dot(s.h, s.h) + dot(t.h, t.h)))
                                continue;
                            input_error(where, "contacts between two boxes are not found: list them (\"contacts\": point "
                                               "and normal)");
                        }
                        if (s.sphere && t.sphere) {
                            const P3 d = t.c - s.c;
                            const Rational sum = s.r + t.r;
                            if (dot(d, d) < sum * sum)
                                input_error(where, "the spheres overlap");
                            if (dot(d, d) == sum * sum) {
                                const P3 n = (Rational(1) / sum) * d;
                                add(static_cast<int>(i), static_cast<int>(j), s.c + s.r * n, n, where);
                            }
                            continue;
                        }
                        const Shape& sphere = s.sphere ? s : t;
                        const Shape& box = s.sphere ? t : s;
                        const auto [q, inside] = nearest_on_box(box, sphere.c);
                        const P3 d = sphere.c - q;
                        if (inside || dot(d, d) < sphere.r * sphere.r)
                            input_error(where, "the sphere and the box overlap");
                        if (dot(d, d) == sphere.r * sphere.r) {
                            const P3 n = (Rational(1) / sphere.r) * d; // from the box's body to the sphere's
                            add(static_cast<int>(i), static_cast<int>(j), q, s.sphere ? Rational(-1) * n : n, where);
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
            if (c.i < 0) {
                const Plane& pl = planes[static_cast<std::size_t>(-c.i - 2)];
                if (sign_of(dot(c.p - pl.p, pl.n)) != Sign::zero)
                    input_error(cp + ".point", text(c.p) + " is not on the plane " + in_quotes(pl.name));
                if (!(c.n == pl.n))
                    input_error(cp + ".normal", "a contact with plane " + in_quotes(pl.name) + " has its normal");
            }
            // The point must lie on the surface of a shape of each body that has shapes.
            for (const int e : {c.i, c.j}) {
                if (e < 0 || bodies[static_cast<std::size_t>(e)].shapes.empty())
                    continue;
                bool on = false;
                for (const Shape& sh : bodies[static_cast<std::size_t>(e)].shapes) {
                    if (sh.sphere) {
                        on = on || dot(c.p - sh.c, c.p - sh.c) == sh.r * sh.r;
                        continue;
                    }
                    const P3 local = sh.R.inverse_apply(c.p - sh.c);
                    bool inside = true, face = false;
                    for (int axis = 0; axis < 3; ++axis) {
                        const Rational x = coord(local, axis), h = coord(sh.h, axis);
                        inside = inside && -h <= x && x <= h;
                        face = face || x == h || x == -h;
                    }
                    on = on || (inside && face);
                }
                if (!on)
                    input_error(cp + ".point", text(c.p) + " is not on a shape of " + in_quotes(bodies[static_cast<std::size_t>(e)].name) +
                                                   " (a declared contact must be at distance exactly zero)");
            }
            contacts.push_back(c);
        }
    }

    const std::size_t n = 6 * bodies.size(), c = contacts.size();
    Matrix M(n, n);
    for (std::size_t b = 0; b < bodies.size(); ++b) {
        for (int k = 0; k < 3; ++k)
            M(6 * b + static_cast<std::size_t>(k), 6 * b + static_cast<std::size_t>(k)) = bodies[b].m;
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < 3; ++k)
                M(6 * b + 3 + static_cast<std::size_t>(a), 6 * b + 3 + static_cast<std::size_t>(k)) = bodies[b].I[a][k];
        for (const char* v : {".vx", ".vy", ".vz", ".wx", ".wy", ".wz"})
            out.velocity_names.push_back(bodies[b].name + v);
    }
    bool diagonal = true;
    for (std::size_t a = 0; a < n; ++a)
        for (std::size_t k = 0; k < n; ++k)
            diagonal = diagonal && (a == k || sign_of(M(a, k)) == Sign::zero);
    if (diagonal)
        for (std::size_t a = 0; a < n; ++a)
            out.masses.push_back(M(a, a));
    else
        out.M = M;
    // The column of direction d at point p for contact k: d . (v_j(p) - v_i(p)), v_b(p) = v_b +
    // w_b x (p - c_b), so that the angular part is (p - c_b) x d.
    auto column = [&](const Contact& k, const P3& d) {
        Vector col(n);
        for (const int e : {k.i, k.j}) {
            if (e < 0)
                continue;
            const Rational s = e == k.j ? Rational(1) : Rational(-1);
            const std::size_t b = static_cast<std::size_t>(e);
            const P3 arm = cross(k.p - bodies[b].c, d);
            for (int q = 0; q < 3; ++q) {
                col[6 * b + static_cast<std::size_t>(q)] += s * coord(d, q);
                col[6 * b + 3 + static_cast<std::size_t>(q)] += s * coord(arm, q);
            }
        }
        return col;
    };
    Matrix W(n, c);
    std::vector<scene_common::ContactRef> refs;
    for (const Contact& ct : contacts)
        refs.push_back({ct.i, ct.j, ct.name, ct.path, ct.mu, ct.e});
    const scene_common::ContactValues values = scene_common::contact_values(doc, index, refs);
    for (std::size_t k = 0; k < c; ++k) {
        const Contact& ct = contacts[k];
        const Vector col = column(ct, ct.n);
        for (std::size_t r = 0; r < n; ++r)
            W(r, k) = col[r];
        if (sign_of(values.mu[k]) == Sign::positive) {
            const auto [t1, t2] = tangents_of(ct.n);
            out.friction.push_back(FrictionDecl{k, values.mu[k], {column(ct, t1), column(ct, t2)}, Rational(0), facets});
        }
    }
    out.contact_names = values.names;
    if (values.any_restitution)
        out.restitution = values.restitution;
    out.W = W;
    scene_common::check_scene_mechanics(doc, out);
    return out;
}

} // namespace scene3

System parse_scene_3d(const ReadJson& doc) { return scene3::parse(doc); }

} // namespace impactcert
