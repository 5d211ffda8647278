// SPDX-License-Identifier: GPL-3.0-or-later
// box2d_friction.cpp -- a planar scene in Box2D 2.4.1 with Coulomb friction and rotation, as an
// `impactcert fuzz --impl-cmd` driver. It reads the same scene file (impactcert-scene/1) as
// impactcert: bodies with disks, convex polygons, segments and capsules, fixed boundary lines,
// friction and restitution (the scene's, per pair, or per listed contact are not distinguished
// here: see below).
//
// What it computes: a fresh world without gravity, each body with its mass, moment of inertia and
// the scene's position, its disks as circle fixtures, its polygons as polygon fixtures (radius:
// the scene's skin; segments and capsules are refused: Box2D 2.4 collides no edge with an edge
// and has no capsule), each boundary as a long static edge through its point; the velocities (v_x, v_y, omega) of every body, in the scene's order, are
// set from one stdin line; one Box2D step (dt = 1/60, --iterations velocity iterations, one
// position iteration); the velocities after it are printed. Box2D's sequential-impulse solver
// resolves each contact's friction (clamped to mu times the contact's current normal impulse: the
// Coulomb box) and its normal impulse with a restitution target fixed before the iterations
// (approaching contacts only). Converged, that is the Newton law with friction with restitution on
// approaching contacts and e_T = 0 (docs/derive.md, "Friction"); `impactcert derive newton --system SCENE
// --restitution-on approaching` derives it exactly.
//
// Friction and restitution: set on every contact in Box2D's PreSolve from the scene (per pair of
// bodies if "pairs" gives them, else the scene's "friction" and "restitution"), so that Box2D's
// mixing rule (sqrt of the fixtures' friction) plays no part. restitutionThreshold is 0.
//
// Limits (Box2D's): float arithmetic (relative errors ~1e-7: fuzz with --max-rel-error 1e-5);
// a body moves at most 2 m and turns at most pi/2 per step (speeds above 120 m/s and spins above
// ~94 rad/s are clamped: keep --range within 0.01..10); a polygon has at most 8 vertices
// (b2_maxPolygonVertices), and Box2D may round a polygon's hull.
//
// The skin: Box2D gives every edge a radius of b2_polygonRadius (0.01 m) and puts a circle's
// contact point halfway between the surfaces, 0.005 m above the scene's line: the impulse then
// acts about a point 0.005 m off the scene's, which impactcert reports as it is (momentum: a
// change not made of the scene's contact impulses; coulomb: slip at the scene's point).
// --edge-radius 0 removes the skin, so that the engine solves the scene's geometry.
//
// Options: --scene FILE (required), --iterations K (default 8, Box2D's), --edge-radius R
// (default Box2D's b2_polygonRadius).
// Protocol: each stdin line holds 3 numbers per body (hex floats or decimals); each answer is
// one line printed with %.17g and flushed. A malformed line or scene is fatal (exit 2).
#include <box2d/box2d.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "driver_lines.hpp"

namespace {

[[noreturn]] void fail(const std::string& message) {
    std::fprintf(stderr, "box2d_friction: %s\n", message.c_str());
    std::exit(2);
}

// A scene rational ("p/q", a decimal, or a JSON integer) as a double.
double value(const nlohmann::json& j, const std::string& where) {
    if (j.is_number_integer())
        return j.get<double>();
    if (!j.is_string())
        fail(where + ": expected a rational");
    const std::string text = j.get<std::string>();
    const auto slash = text.find('/');
    char* end = nullptr;
    const double num = std::strtod(text.substr(0, slash).c_str(), &end);
    double den = 1;
    if (slash != std::string::npos)
        den = std::strtod(text.substr(slash + 1).c_str(), nullptr);
    if (!std::isfinite(num) || !std::isfinite(den) || den == 0)
        fail(where + ": bad number '" + text + "'");
    return num / den;
}

struct Scene {
    struct Disk {
        double r, cx, cy;
    };
    struct Outline { // a polygon (3 to 8 vertices), offsets from the centre, and its skin
        std::vector<double> x, y;
        double r = 0;
    };
    struct Body {
        std::string name;
        double m, J, x, y;
        std::vector<Disk> disks;
        std::vector<Outline> outlines;
    };
    struct Line {
        std::string name;
        double px, py, nx, ny;
    };
    std::vector<Body> bodies;
    std::vector<Line> lines;
    double mu = 0, e = 0;
    std::map<std::pair<std::string, std::string>, std::pair<double, double>> pairs; // name order
};

Scene read_scene(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        fail("cannot read " + path);
    nlohmann::json doc;
    try {
        in >> doc;
    } catch (const std::exception& e) {
        fail(path + ": " + e.what());
    }
    if (doc.value("format", "") != "impactcert-scene/1")
        fail(path + ": not an impactcert-scene/1 file");
    Scene s;
    for (const auto& b : doc.at("bodies")) {
        Scene::Body body{b.at("name").get<std::string>(), value(b.at("mass"), "mass"), value(b.at("inertia"), "inertia"),
                         value(b.at("position").at(0), "position"), value(b.at("position").at(1), "position"), {}, {}};
        if (b.contains("shapes"))
            for (const auto& shape : b.at("shapes")) {
                if (shape.contains("segment"))
                    fail(path + ": body " + body.name + ": a segment or capsule is not driven (Box2D 2.4 collides no edge "
                                "with an edge, and has no capsule)");
                if (shape.contains("polygon")) {
                    const auto& points = shape.at("polygon");
                    Scene::Outline o;
                    for (const auto& q : points) {
                        o.x.push_back(value(q.at(0), "vertex"));
                        o.y.push_back(value(q.at(1), "vertex"));
                    }
                    if (o.x.size() > b2_maxPolygonVertices)
                        fail(path + ": body " + body.name + ": Box2D's polygons have at most 8 vertices");
                    if (shape.contains("radius"))
                        o.r = value(shape.at("radius"), "radius");
                    body.outlines.push_back(o);
                    continue;
                }
                double cx = 0, cy = 0;
                if (shape.contains("center")) {
                    cx = value(shape.at("center").at(0), "center");
                    cy = value(shape.at("center").at(1), "center");
                }
                body.disks.push_back({value(shape.at("disk"), "disk"), cx, cy});
            }
        s.bodies.push_back(body);
    }
    if (doc.contains("boundaries"))
        for (const auto& l : doc.at("boundaries"))
            s.lines.push_back({l.at("name").get<std::string>(), value(l.at("point").at(0), "point"),
                               value(l.at("point").at(1), "point"), value(l.at("normal").at(0), "normal"),
                               value(l.at("normal").at(1), "normal")});
    if (doc.contains("contacts") && !doc.at("contacts").is_string())
        fail(path + ": listed contacts are not driven (Box2D finds its own)");
    if (doc.contains("friction"))
        s.mu = value(doc.at("friction"), "friction");
    if (doc.contains("restitution"))
        s.e = value(doc.at("restitution"), "restitution");
    if (doc.contains("pairs"))
        for (const auto& p : doc.at("pairs")) {
            std::string a = p.at("bodies").at(0), b = p.at("bodies").at(1);
            if (b < a)
                std::swap(a, b);
            s.pairs[{a, b}] = {p.contains("mu") ? value(p.at("mu"), "mu") : s.mu,
                               p.contains("restitution") ? value(p.at("restitution"), "restitution") : s.e};
        }
    return s;
}

// Friction and restitution of each contact from the scene (PreSolve runs before the solver).
class Mixer : public b2ContactListener {
  public:
    explicit Mixer(const Scene& s) : s_(s) {}
    void PreSolve(b2Contact* contact, const b2Manifold*) override {
        std::string a = name(contact->GetFixtureA()), b = name(contact->GetFixtureB());
        if (b < a)
            std::swap(a, b);
        const auto it = s_.pairs.find({a, b});
        contact->SetFriction(static_cast<float>(it != s_.pairs.end() ? it->second.first : s_.mu));
        contact->SetRestitution(static_cast<float>(it != s_.pairs.end() ? it->second.second : s_.e));
        contact->SetRestitutionThreshold(0.0f);
    }

  private:
    const Scene& s_;
    static std::string name(b2Fixture* f) { return reinterpret_cast<const char*>(f->GetUserData().pointer); }
};

std::vector<float> impact(const Scene& s, int iterations, float edge_radius, const std::vector<double>& u) {
    b2World world(b2Vec2(0.0f, 0.0f));
    world.SetAllowSleeping(false);
    Mixer mixer(s);
    world.SetContactListener(&mixer);
    for (const auto& l : s.lines) {
        b2BodyDef def; // static
        b2Body* ground = world.CreateBody(&def);
        b2EdgeShape edge;
        const float tx = static_cast<float>(-l.ny), ty = static_cast<float>(l.nx), L = 1000.0f;
        const float px = static_cast<float>(l.px), py = static_cast<float>(l.py);
        edge.SetTwoSided(b2Vec2(px - L * tx, py - L * ty), b2Vec2(px + L * tx, py + L * ty));
        edge.m_radius = edge_radius;
        b2FixtureDef fd;
        fd.shape = &edge;
        fd.userData.pointer = reinterpret_cast<uintptr_t>(l.name.c_str());
        ground->CreateFixture(&fd);
    }
    std::vector<b2Body*> bodies;
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
        const auto& b = s.bodies[i];
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position.Set(static_cast<float>(b.x), static_cast<float>(b.y));
        def.linearVelocity.Set(static_cast<float>(u[3 * i]), static_cast<float>(u[3 * i + 1]));
        def.angularVelocity = static_cast<float>(u[3 * i + 2]);
        def.allowSleep = false;
        b2Body* body = world.CreateBody(&def);
        for (const auto& d : b.disks) {
            b2CircleShape circle;
            circle.m_radius = static_cast<float>(d.r);
            circle.m_p.Set(static_cast<float>(d.cx), static_cast<float>(d.cy));
            b2FixtureDef fd;
            fd.shape = &circle;
            fd.density = 1.0f; // replaced by SetMassData
            fd.userData.pointer = reinterpret_cast<uintptr_t>(b.name.c_str());
            body->CreateFixture(&fd);
        }
        for (const auto& o : b.outlines) {
            b2FixtureDef fd;
            fd.density = 1.0f;
            fd.userData.pointer = reinterpret_cast<uintptr_t>(b.name.c_str());
            std::vector<b2Vec2> v;
            for (std::size_t k = 0; k < o.x.size(); ++k)
                v.push_back(b2Vec2(static_cast<float>(o.x[k]), static_cast<float>(o.y[k])));
            b2PolygonShape polygon;
            polygon.Set(v.data(), static_cast<int32>(v.size())); // the convex hull, as Box2D computes it
            polygon.m_radius = static_cast<float>(o.r);          // the scene's skin (0: none)
            fd.shape = &polygon;
            body->CreateFixture(&fd);
        }
        b2MassData mass;
        mass.mass = static_cast<float>(b.m);
        mass.center.SetZero();
        mass.I = static_cast<float>(b.J); // about the centre of mass (Box2D: about the body origin)
        body->SetMassData(&mass);
        bodies.push_back(body);
    }
    world.Step(1.0f / 60.0f, iterations, 1);
    std::vector<float> v;
    for (const b2Body* body : bodies) {
        v.push_back(body->GetLinearVelocity().x);
        v.push_back(body->GetLinearVelocity().y);
        v.push_back(body->GetAngularVelocity());
    }
    return v;
}

} // namespace

int main(int argc, char** argv) {
    std::string scene_path;
    int iterations = 8;
    float edge_radius = b2_polygonRadius;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (i + 1 >= argc)
            fail("usage: box2d_friction --scene FILE [--iterations K] [--edge-radius R]");
        const std::string v = argv[++i];
        if (flag == "--scene")
            scene_path = v;
        else if (flag == "--iterations") {
            char* end = nullptr;
            const long k = std::strtol(v.c_str(), &end, 10);
            if (*end != '\0' || k < 1 || k > 1000000)
                fail("bad --iterations '" + v + "'");
            iterations = static_cast<int>(k);
        } else if (flag == "--edge-radius") {
            char* end = nullptr;
            const double r = std::strtod(v.c_str(), &end);
            if (*end != '\0' || !(r >= 0 && r <= 1))
                fail("bad --edge-radius '" + v + "'");
            edge_radius = static_cast<float>(r);
        } else
            fail("unknown option '" + flag + "'");
    }
    if (scene_path.empty())
        fail("usage: box2d_friction --scene FILE [--iterations K] [--edge-radius R]");
    const Scene s = read_scene(scene_path);
    const std::size_t n = 3 * s.bodies.size();
    driver_lines::serve(n, [&](const std::vector<double>& u) { return impact(s, iterations, edge_radius, u); }, fail);
    return 0;
}
