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
    try {
        // A whole number of samples or a seed, exactly as the command line reads one.
        auto count = [](const std::string& flag, const std::string& text) {
            const mpq_class x = ic::parse_exact(text, flag);
            if (x.get_den() != 1 || sgn(x) < 0 || x.get_num() > mpz_class("18446744073709551615"))
                throw ic::InputError(flag + ": expected an integer in [0, 2^64 - 1], got \"" + text + "\"");
            return std::stoull(x.get_num().get_str());
        };
        for (int i = 1; i < argc; ++i) {
            const std::string flag = argv[i];
            if (flag == "--json") {
                json = true;
                continue;
            }
            if (i + 1 >= argc)
                throw ic::InputError(flag + ": needs a value");
            const std::string value = argv[++i];
            if (flag == "--samples")
                o.samples = count(flag, value);
            else if (flag == "--seed")
                o.seed = count(flag, value);
            else if (flag == "--restitution") {
                // Exact for the checker; Box2D takes it in float (within an ulp of float).
                const mpq_class e = ic::parse_exact(value, "--restitution");
                o.restitution = ic::Vector{e};
                engine.restitution = static_cast<float>(e.get_d());
            } else if (flag == "--reference")
                o.reference = value;
            else
                throw ic::InputError("unknown option " + flag);
        }
    } catch (const ic::Error& e) {
        std::cerr << "box2d_inprocess: " << e.what() << "\n";
        return e.exit_status();
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
            std::cout << "box2d_inprocess: " << r.samples << " samples, " << r.violating << " findings: " << r.verdict
                      << "\n";
        return r.exit_status;
    } catch (const ic::Error& e) {
        std::cerr << "box2d_inprocess: " << e.what() << "\n";
        return e.exit_status();
    }
}
