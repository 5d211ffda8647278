// SPDX-License-Identifier: GPL-3.0-or-later
// box2d_inprocess.cpp -- Box2D's Newton's cradle (box2d_cradle.hpp) fuzzed in-process through
// the library (impactcert::api::fuzz_consistency): the consistency run that
//   impactcert fuzz --masses 1,1,1 --velocities --impl-cmd box2d_cradle --max-rel-error 1e-5 --range 1e-3..60
// makes through a pipe, with Box2D called directly on each batch of ball velocities.
//
// Usage: box2d_inprocess [--samples N] [--seed S] [--restitution E] [--reference approaching]
//                        [--json]
// Prints the run's summary (or, with --json, the report `impactcert fuzz --json` prints); exit 0
// no violation, 1 violations, 2 bad input, 3 nothing checked.
#include "box2d_cradle.hpp"

#include <impactcert/impactcert.hpp>

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

namespace ic = impactcert::api;

int main(int argc, char** argv) {
    ic::ConsistencyOptions o;
    o.velocities = true;
    o.max_rel_error = 1e-5;
    o.range = "1e-3..60";
    o.samples = 2000;
    o.name = "Box2D in-process (box2d_inprocess)";
    bool json = false;
    box2d_cradle::Options engine;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (flag == "--json") {
            json = true;
            continue;
        }
        if (i + 1 >= argc) {
            std::fprintf(stderr, "box2d_inprocess: %s needs a value\n", flag.c_str());
            return 2;
        }
        const std::string value = argv[++i];
        if (flag == "--samples")
            o.samples = std::strtoull(value.c_str(), nullptr, 10);
        else if (flag == "--seed")
            o.seed = std::strtoull(value.c_str(), nullptr, 10);
        else if (flag == "--restitution") {
            engine.restitution = std::strtof(value.c_str(), nullptr);
            o.restitution = ic::Vector{mpq_class(value)};
        } else if (flag == "--reference")
            o.reference = value;
        else {
            std::fprintf(stderr, "box2d_inprocess: unknown option %s\n", flag.c_str());
            return 2;
        }
    }
    try {
        // Each call: a batch of points of 3 ball velocities; one Box2D world per point.
        const ic::FuzzResult r = ic::fuzz_consistency(
            ic::System::chain({1, 1, 1}),
            [&engine](const double* in, double* out, std::size_t count) {
                std::vector<double> u(3);
                for (std::size_t p = 0; p < count; ++p) {
                    u.assign(in + 3 * p, in + 3 * p + 3);
                    const std::vector<float> v = box2d_cradle::impact(engine, u);
                    for (std::size_t k = 0; k < 3; ++k)
                        out[3 * p + k] = static_cast<double>(v[k]);
                }
            },
            o);
        if (json)
            std::cout << r.json;
        else
            std::cout << "box2d_inprocess: " << r.samples << " samples, " << r.violating << " with findings: "
                      << r.verdict << "\n";
        return r.exit_status;
    } catch (const ic::Error& e) {
        std::cerr << "box2d_inprocess: " << e.what() << "\n";
        return e.exit_status();
    }
}
