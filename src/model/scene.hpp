// SPDX-License-Identifier: GPL-3.0-or-later
// scene.hpp -- planar scenes of rigid bodies (`impactcert-scene/1`, SPEC section 9), turned into
// a system (M, W with friction) exactly.
//
// Contract:
//   - A scene lists bodies (name, mass, moment of inertia about the centre of mass, the centre,
//     and shapes: disks (radius, centre offset) and segments (two end points, offsets from the
//     centre), all rational, in the configuration of the impact), fixed boundaries (lines: a point
//     and a unit normal pointing to the free side), and its contacts: "find" (every pair of shapes
//     of different bodies, or of a body and a boundary, whose distance is exactly zero) or a list
//     (bodies, point, unit normal from the first to the second).
//   - Coordinates are (x, y, theta) per body, in the order listed; M = diag(m, m, J) per body. A
//     contact at point p with unit normal n from body i to body j has gamma_N = n . (v_j(p) -
//     v_i(p)), v_b(p) = v_b + omega_b x (p - c_b): W's column has (n_x, n_y, (p - c_j) x n) at j
//     and minus the same at i (a boundary has no coordinates); its tangent t = (n_y, -n_x) (Box2D's) gives
//     the friction column the same way. mu and restitution: per contact, else per pair of bodies
//     ("pairs"), else the scene's defaults; mu = 0 means a frictionless contact (no tangent).
//   - Anything that needs an irrational number (a normal of irrational length, a listed point
//     not exactly on both shapes, a unit normal that is not of length 1) is an InputError naming
//     the place; so is a W of dependent columns (make_mechanics: e.g. two rough contacts on one
//     body with three coordinates).
#pragma once

#include "model/system.hpp"

#include <nlohmann/json.hpp>

#include <string>

namespace impactcert {

inline constexpr const char* kSceneFormat = "impactcert-scene/1";

// The scene as a system: its name, `masses` (m, m, J per body), W's normal columns, friction,
// the contacts' restitution (System::restitution), the names of its contacts ("disk/ground", a
// second one of a pair "box/ground #2") and velocities ("disk.vx", "disk.vy", "disk.omega").
System parse_scene(const nlohmann::json& doc);

// A scene in space ("dimension": 3; scene3d.cpp): bodies with a mass, an inertia about the centre
// (three principal moments or a symmetric positive definite 3 x 3 matrix, in the body's axes), a
// position and a rotation (a rational 3 x 3 matrix, R^T R = I, det 1, exactly), spheres and boxes
// (half extents along the body's axes), planes (a point and a rational unit normal). Coordinates
// (vx, vy, vz, wx, wy, wz) per body, in the world's axes; M = diag(m, m, m) and R I R^T per body.
// Contacts found exactly (sphere and plane, sphere and sphere, box and plane: every corner on it,
// sphere and box: the box's nearest point) or listed; two boxes must be listed. A rough contact has
// two tangents, each bounded by mu Lambda_N (ODE's friction box): the images of e1 and e2 under
// the reflection that exchanges e3 and the normal (rational and orthonormal).
System parse_scene_3d(const nlohmann::json& doc);

} // namespace impactcert
