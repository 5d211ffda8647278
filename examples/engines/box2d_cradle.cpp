// SPDX-License-Identifier: GPL-3.0-or-later
// box2d_cradle.cpp -- a Newton's cradle in Box2D 2.4.1, as an `impactcert fuzz --impl-cmd` driver.
//
// What it computes: n balls (circles of radius 0.5, exactly touching at x = 0, 1, 2, ...) with
// velocities (u_i, 0) and one Box2D step; it prints the x velocities after the step. That is
// Box2D's sequential-impulse solver (projected Gauss-Seidel on the contact impulses, K sweeps)
// with restitution as a velocity target fixed before the sweeps: contact k between balls k and
// k+1 must end with u+_{k+1} - u+_k >= -E (u_{k+1} - u_k) if it approaches (u_{k+1} < u_k), and
// >= 0 if not, with a non-negative impulse that vanishes where the inequality is strict. The
// sweeps converge to the solution of that complementarity problem: the simultaneous Newton law
// with restitution applied only to approaching contacts. With E = 1 it is not the sequential
// cradle law and does not conserve energy: 1 0 0 -> -1/3 2/3 2/3, and 0 1 -1 -> -2/3 -2/3 4/3
// (kinetic energy from 1 to 4/3).
//
// Box2D's own limits, which an exact check will see:
//   - Box2D works in float (b2Vec2, masses, impulses): relative errors of ~1e-7 at best, and
//     |u| below ~1e-38 loses accuracy or becomes 0. Use --max-rel-error, not --max-ulps.
//   - b2_maxTranslation: a body moves at most 2 m per step, so after solving Box2D scales any
//     velocity above 2 / dt = 120 m/s (dt = 1/60) down to 120 m/s, and above ~1e21 m/s (where
//     that test overflows in float) to 0. Give the fuzzer a --range well within 120: an output
//     can exceed the largest input (4/3 above). Near the float range (~1e38) the solver
//     overflows (NaN); beyond it (3.4e38) b2Assert aborts (Debian keeps assertions): a crash.
//   - restitutionThreshold defaults to 1 m/s (slower approaching contacts do not bounce): 0 here.
//   - The sweeps take the contacts newest first (right to left here). Box2D's default of 8
//     iterations leaves errors up to ~1e-4 for 3 balls, ~1e-1 for 5, and results that depend on
//     the order the bodies were created in: K = 200 here.
//
// Protocol: each stdin line holds n numbers (hex floats or decimals, strtod); each answer is one
// line of n numbers printed with %.17g and flushed. A malformed line is fatal (exit 2).
#include "box2d_cradle.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "driver_lines.hpp"

namespace {

using box2d_cradle::impact;
using box2d_cradle::Options;

[[noreturn]] void fail(const std::string& message) {
    std::fprintf(stderr, "box2d_cradle: %s\n", message.c_str());
    std::exit(2);
}

// One number that strtod consumes entirely, within [lo, hi] (and an integer if asked).
double number(const char* text, const char* what, double lo, double hi, bool integer = false) {
    char* end = nullptr;
    const double x = std::strtod(text, &end);
    if (end == text || *end != '\0' || !(x >= lo && x <= hi) || (integer && x != std::floor(x)))
        fail(std::string("bad ") + what + " '" + text + "'");
    return x;
}

Options parse_options(int argc, char** argv) {
    Options o;
    int balls = 3;
    bool masses = false;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) fail("usage: box2d_cradle [--balls N] [--restitution E] "
                                "[--iterations K] [--masses m1,m2,...]");
        const char* value = argv[++i];
        if (flag == "--balls") {
            balls = static_cast<int>(number(value, "--balls", 2, 10000, true));
        } else if (flag == "--restitution") {
            o.restitution = static_cast<float>(number(value, "--restitution", 0, 1));
        } else if (flag == "--iterations") {
            o.iterations = static_cast<int>(number(value, "--iterations", 1, 1e6, true));
        } else if (flag == "--masses") {
            o.masses.clear();
            std::string list = value;
            for (std::size_t start = 0;;) {
                const std::size_t comma = list.find(',', start);
                const std::string item = list.substr(start, comma - start);
                o.masses.push_back(static_cast<float>(number(item.c_str(), "mass", 1e-30, 1e30)));
                if (comma == std::string::npos) break;
                start = comma + 1;
            }
            if (o.masses.size() < 2) fail("--masses needs at least 2 masses");
            masses = true; // N is their number
        } else {
            fail("unknown option '" + flag + "'");
        }
    }
    if (!masses) o.masses.assign(static_cast<std::size_t>(balls), 1.0f);
    return o;
}

} // namespace

int main(int argc, char** argv) {
    const Options o = parse_options(argc, argv);
    const std::size_t n = o.masses.size();
    driver_lines::serve(n, [&](const std::vector<double>& u) { return impact(o, u); }, fail);
    return 0;
}
