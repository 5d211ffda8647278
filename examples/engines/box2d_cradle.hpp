// SPDX-License-Identifier: GPL-3.0-or-later
// box2d_cradle.hpp -- the Newton's cradle in Box2D 2.4.1 that box2d_cradle.cpp (an --impl-cmd
// driver) and box2d_inprocess.cpp (the library, in-process) both fuzz: box2d_cradle.cpp's header
// comment says what it computes and where Box2D's own limits lie.
#pragma once

#include <box2d/box2d.h>

#include <vector>

namespace box2d_cradle {

struct Options {
    std::vector<float> masses = std::vector<float>(3, 1.0f);
    float restitution = 1.0f;
    int iterations = 200;
};

// One impact: a fresh world (samples are independent), one step, the x velocities after it.
inline std::vector<float> impact(const Options& o, const std::vector<double>& u) {
    b2World world(b2Vec2(0.0f, 0.0f));
    world.SetAllowSleeping(false);
    b2CircleShape circle;
    circle.m_radius = 0.5f;
    b2FixtureDef fixture;
    fixture.shape = &circle;
    fixture.friction = 0.0f;
    fixture.restitution = o.restitution;
    fixture.restitutionThreshold = 0.0f;
    std::vector<b2Body*> bodies;
    for (std::size_t i = 0; i < u.size(); ++i) {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position.Set(static_cast<float>(i), 0.0f);
        def.linearVelocity.Set(static_cast<float>(u[i]), 0.0f);
        def.linearDamping = 0.0f;
        def.allowSleep = false;
        def.fixedRotation = true;
        b2Body* body = world.CreateBody(&def);
        body->CreateFixture(&fixture);
        b2MassData mass;
        mass.mass = o.masses[i];
        mass.center.SetZero();
        mass.I = 1.0f; // ignored: fixed rotation
        body->SetMassData(&mass);
        bodies.push_back(body);
    }
    world.Step(1.0f / 60.0f, o.iterations, 1);
    std::vector<float> v;
    for (const b2Body* body : bodies) v.push_back(body->GetLinearVelocity().x);
    return v;
}

} // namespace box2d_cradle
