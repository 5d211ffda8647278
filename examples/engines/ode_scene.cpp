// SPDX-License-Identifier: GPL-3.0-or-later
// ode_scene.cpp -- a scene in space (impactcert-scene/1, "dimension": 3) in the Open Dynamics
// Engine (ODE 0.16, Debian's libode-dev), as an `impactcert fuzz --impl-cmd` driver.
//
// What it computes: a fresh world without gravity, each body with its mass, inertia (in its own
// axes), position and rotation; spheres (dCreateSphere, offset by "center") and boxes (dCreateBox)
// as its geoms; each boundary plane as a dCreatePlane. From one stdin line, the velocities (vx, vy,
// vz, wx, wy, wz) of every body in the scene's order; the contacts ODE's collision finds; one step
// (dWorldStep: the big-matrix LCP, or dWorldQuickStep with --iterations K); the velocities after
// it, printed. Contact surfaces: restitution (dContactBounce, bounce_vel 0: approaching contacts
// only), friction as ODE's box (dContactApprox1: each direction bounded by mu times the normal
// force) along fdir1 = impactcert's first tangent of the contact (docs/formats.md) and fdir2 =
// normal x fdir1. Converged, that is the Newton law with friction with restitution on approaching
// contacts and e_T = 0: `impactcert derive newton --system SCENE --restitution-on approaching`.
//
// The gyroscopic term of the step (w x I w, which turns a spinning box's w without any contact) is
// switched off (dBodySetGyroscopicMode): an impact law maps velocities by impulses alone.
// Limits (ODE's): double arithmetic; the constraint force mixing --cfm (default 1e-12; ODE's own
// default 1e-5 makes every contact slightly soft) and error reduction (no penetration here, so
// none); a contact is found only where ODE's collision finds it (depth >= 0 in doubles).
// Options: --scene FILE (required), --iterations K (dWorldQuickStep; default: dWorldStep), --cfm C.
// Protocol: each stdin line holds 6 numbers per body; each answer is one line printed with %.17g
// and flushed. A malformed line or scene is fatal (exit 2).
#include <nlohmann/json.hpp>
#include <ode/ode.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "driver_lines.hpp"

namespace {

[[noreturn]] void fail(const std::string& message) {
    std::fprintf(stderr, "ode_scene: %s\n", message.c_str());
    std::exit(2);
}

double value(const nlohmann::json& j, const std::string& where) {
    if (j.is_number_integer())
        return j.get<double>();
    if (!j.is_string())
        fail(where + ": expected a rational");
    const std::string text = j.get<std::string>();
    const auto slash = text.find('/');
    const double num = std::strtod(text.substr(0, slash).c_str(), nullptr);
    const double den = slash == std::string::npos ? 1.0 : std::strtod(text.substr(slash + 1).c_str(), nullptr);
    if (!std::isfinite(num) || !std::isfinite(den) || den == 0)
        fail(where + ": bad number '" + text + "'");
    return num / den;
}

std::vector<double> vec(const nlohmann::json& j, std::size_t n, const std::string& where) {
    if (!j.is_array() || j.size() != n)
        fail(where + ": expected " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const auto& x : j)
        out.push_back(value(x, where));
    return out;
}

struct Scene {
    struct Shape {
        bool sphere = true;
        double r = 0, hx = 0, hy = 0, hz = 0;
        double cx = 0, cy = 0, cz = 0; // the shape's offset from the body's centre, in the body's axes
    };
    struct Body {
        std::string name;
        double m = 0, I[3][3] = {}, p[3] = {}, R[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        std::vector<Shape> shapes;
    };
    struct Plane {
        std::string name;
        double p[3], n[3];
    };
    std::vector<Body> bodies;
    std::vector<Plane> planes;
    double mu = 0, e = 0;
    std::map<std::pair<std::string, std::string>, std::pair<double, double>> pairs;
};

Scene read_scene_unchecked(const std::string& path);

// The scene, or one line on stderr and exit 2 (a missing key, a wrong type, a non-positive mass).
Scene read_scene(const std::string& path) {
    try {
        Scene s = read_scene_unchecked(path);
        for (const auto& b : s.bodies)
            if (!(b.m > 0) || !(b.I[0][0] > 0) || !(b.I[1][1] > 0) || !(b.I[2][2] > 0))
                fail(path + ": body " + b.name + ": mass and principal moments must be positive");
        return s;
    } catch (const nlohmann::json::exception& e) {
        fail(path + ": " + e.what());
    }
}

Scene read_scene_unchecked(const std::string& path) {
    std::ifstream in(path);
    if (!in)
        fail("cannot read " + path);
    nlohmann::json doc;
    try {
        in >> doc;
    } catch (const std::exception& e) {
        fail(path + ": " + e.what());
    }
    if (doc.value("format", "") != "impactcert-scene/1" || doc.value("dimension", 2) != 3)
        fail(path + ": not an impactcert-scene/1 file in space (\"dimension\": 3)");
    if (doc.contains("contacts") && !doc.at("contacts").is_string())
        fail(path + ": listed contacts are not driven (ODE finds its own)");
    Scene s;
    for (const auto& b : doc.at("bodies")) {
        Scene::Body body;
        body.name = b.at("name").get<std::string>();
        body.m = value(b.at("mass"), "mass");
        const auto& ji = b.at("inertia");
        if (ji.size() == 3 && !ji[0].is_array()) {
            const auto d = vec(ji, 3, "inertia");
            for (int k = 0; k < 3; ++k)
                body.I[k][k] = d[static_cast<std::size_t>(k)];
        } else {
            for (int r = 0; r < 3; ++r) {
                const auto row = vec(ji.at(static_cast<std::size_t>(r)), 3, "inertia");
                for (int c = 0; c < 3; ++c)
                    body.I[r][c] = row[static_cast<std::size_t>(c)];
            }
        }
        const auto p = vec(b.at("position"), 3, "position");
        for (int k = 0; k < 3; ++k)
            body.p[k] = p[static_cast<std::size_t>(k)];
        if (b.contains("rotation"))
            for (int r = 0; r < 3; ++r) {
                const auto row = vec(b.at("rotation").at(static_cast<std::size_t>(r)), 3, "rotation");
                for (int c = 0; c < 3; ++c)
                    body.R[r][c] = row[static_cast<std::size_t>(c)];
            }
        if (b.contains("shapes"))
            for (const auto& js : b.at("shapes")) {
                Scene::Shape sh;
                if (js.contains("center")) {
                    const auto c = vec(js.at("center"), 3, "center");
                    sh.cx = c[0];
                    sh.cy = c[1];
                    sh.cz = c[2];
                }
                if (js.contains("sphere")) {
                    sh.r = value(js.at("sphere"), "sphere");
                } else {
                    const auto h = vec(js.at("box"), 3, "box");
                    sh.sphere = false;
                    sh.hx = h[0];
                    sh.hy = h[1];
                    sh.hz = h[2];
                }
                body.shapes.push_back(sh);
            }
        s.bodies.push_back(body);
    }
    if (doc.contains("boundaries"))
        for (const auto& l : doc.at("boundaries")) {
            Scene::Plane pl;
            pl.name = l.at("name").get<std::string>();
            const auto p = vec(l.at("point"), 3, "point"), n = vec(l.at("normal"), 3, "normal");
            for (int k = 0; k < 3; ++k) {
                pl.p[k] = p[static_cast<std::size_t>(k)];
                pl.n[k] = n[static_cast<std::size_t>(k)];
            }
            s.planes.push_back(pl);
        }
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

// What a geom stands for: a body (its index in the scene) or a plane (-(k + 2)).
struct Owner {
    int index;
    const std::string* name;
};

struct World {
    const Scene* scene;
    dWorldID world;
    dJointGroupID joints;
};

// impactcert's first tangent of a contact with unit normal n (docs/formats.md): the image of e1
// under the reflection exchanging e3 and n.
void first_tangent(const double n[3], double t[3]) {
    const double v[3] = {n[0], n[1], n[2] - 1};
    const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    t[0] = 1;
    t[1] = 0;
    t[2] = 0;
    if (vv == 0)
        return;
    const double c = 2 * v[0] / vv;
    for (int k = 0; k < 3; ++k)
        t[k] -= c * v[k];
}

void near_callback(void* data, dGeomID g1, dGeomID g2) {
    World& w = *static_cast<World*>(data);
    const Owner* o1 = static_cast<const Owner*>(dGeomGetData(g1));
    const Owner* o2 = static_cast<const Owner*>(dGeomGetData(g2));
    if (o1->index == o2->index || (o1->index < 0 && o2->index < 0))
        return;
    // The scene's orientation: from the earlier owner (a plane first) to the later one.
    const bool flip = o2->index < o1->index;
    std::string a = *o1->name, b = *o2->name;
    if (b < a)
        std::swap(a, b);
    const auto it = w.scene->pairs.find({a, b});
    const double mu = it != w.scene->pairs.end() ? it->second.first : w.scene->mu;
    const double e = it != w.scene->pairs.end() ? it->second.second : w.scene->e;
    dContact contact[8];
    const int n = dCollide(g1, g2, 8, &contact[0].geom, sizeof(dContact));
    for (int k = 0; k < n; ++k) {
        dContact& c = contact[k];
        c.surface.mode = dContactBounce | (mu > 0 ? dContactApprox1 | dContactFDir1 : 0);
        c.surface.mu = mu;
        c.surface.bounce = e;
        c.surface.bounce_vel = 0;
        // ODE's normal points from g2 into g1; the scene's from the earlier owner to the later.
        double nrm[3] = {c.geom.normal[0], c.geom.normal[1], c.geom.normal[2]};
        if (!flip)
            for (double& x : nrm)
                x = -x;
        double t[3];
        first_tangent(nrm, t);
        c.fdir1[0] = t[0];
        c.fdir1[1] = t[1];
        c.fdir1[2] = t[2];
        dJointID j = dJointCreateContact(w.world, w.joints, &c);
        dJointAttach(j, dGeomGetBody(g1), dGeomGetBody(g2));
    }
}

std::vector<double> impact(const Scene& s, int iterations, double cfm, const std::vector<double>& u) {
    World w{&s, dWorldCreate(), dJointGroupCreate(0)};
    dWorldSetGravity(w.world, 0, 0, 0);
    dWorldSetCFM(w.world, cfm);
    dWorldSetERP(w.world, 0);
    if (iterations > 0)
        dWorldSetQuickStepNumIterations(w.world, iterations);
    dSpaceID space = dSimpleSpaceCreate(nullptr);
    std::vector<Owner> owners; // stable: reserved
    owners.reserve(s.planes.size() + s.bodies.size());
    std::vector<dBodyID> bodies;
    for (std::size_t k = 0; k < s.planes.size(); ++k) {
        const auto& pl = s.planes[k];
        owners.push_back({-static_cast<int>(k) - 2, &pl.name});
        const double d = pl.n[0] * pl.p[0] + pl.n[1] * pl.p[1] + pl.n[2] * pl.p[2];
        dGeomID g = dCreatePlane(space, pl.n[0], pl.n[1], pl.n[2], d);
        dGeomSetData(g, &owners.back());
    }
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
        const auto& b = s.bodies[i];
        owners.push_back({static_cast<int>(i), &b.name});
        dBodyID body = dBodyCreate(w.world);
        dMass m;
        dMassSetParameters(&m, b.m, 0, 0, 0, b.I[0][0], b.I[1][1], b.I[2][2], b.I[0][1], b.I[0][2], b.I[1][2]);
        dBodySetMass(body, &m);
        dBodySetGyroscopicMode(body, 0); // the step's w x I w torque is no impulse: left out
        dBodySetPosition(body, b.p[0], b.p[1], b.p[2]);
        dMatrix3 R = {b.R[0][0], b.R[0][1], b.R[0][2], 0, b.R[1][0], b.R[1][1], b.R[1][2], 0,
                      b.R[2][0], b.R[2][1], b.R[2][2], 0};
        dBodySetRotation(body, R);
        dBodySetLinearVel(body, u[6 * i], u[6 * i + 1], u[6 * i + 2]);
        dBodySetAngularVel(body, u[6 * i + 3], u[6 * i + 4], u[6 * i + 5]);
        for (const auto& sh : b.shapes) {
            dGeomID g = sh.sphere ? dCreateSphere(space, sh.r) : dCreateBox(space, 2 * sh.hx, 2 * sh.hy, 2 * sh.hz);
            dGeomSetBody(g, body);
            if (sh.cx != 0 || sh.cy != 0 || sh.cz != 0)
                dGeomSetOffsetPosition(g, sh.cx, sh.cy, sh.cz);
            dGeomSetData(g, &owners.back());
        }
        bodies.push_back(body);
    }
    dSpaceCollide(space, &w, &near_callback);
    const double dt = 1.0 / 60.0;
    if (iterations > 0)
        dWorldQuickStep(w.world, dt);
    else
        dWorldStep(w.world, dt);
    std::vector<double> v;
    for (dBodyID body : bodies) {
        const dReal* lin = dBodyGetLinearVel(body);
        const dReal* ang = dBodyGetAngularVel(body);
        for (int k = 0; k < 3; ++k)
            v.push_back(lin[k]);
        for (int k = 0; k < 3; ++k)
            v.push_back(ang[k]);
    }
    dJointGroupDestroy(w.joints);
    dSpaceDestroy(space);
    dWorldDestroy(w.world);
    return v;
}

} // namespace

int main(int argc, char** argv) {
    std::string scene_path;
    int iterations = 0;
    double cfm = 1e-12;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (i + 1 >= argc)
            fail("usage: ode_scene --scene FILE [--iterations K] [--cfm C]");
        const std::string v = argv[++i];
        char* end = nullptr;
        if (flag == "--scene") {
            scene_path = v;
        } else if (flag == "--iterations") {
            const long k = std::strtol(v.c_str(), &end, 10);
            if (*end != '\0' || k < 1 || k > 1000000)
                fail("bad --iterations '" + v + "'");
            iterations = static_cast<int>(k);
        } else if (flag == "--cfm") {
            cfm = std::strtod(v.c_str(), &end);
            if (*end != '\0' || !(cfm >= 0 && cfm <= 1))
                fail("bad --cfm '" + v + "'");
        } else {
            fail("unknown option '" + flag + "'");
        }
    }
    if (scene_path.empty())
        fail("usage: ode_scene --scene FILE [--iterations K] [--cfm C]");
    const Scene s = read_scene(scene_path);
    dInitODE2(0);
    const std::size_t n = 6 * s.bodies.size();
    driver_lines::serve(n, [&](const std::vector<double>& u) { return impact(s, iterations, cfm, u); }, fail);
    dCloseODE();
    return 0;
}
