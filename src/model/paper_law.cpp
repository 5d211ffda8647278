// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/paper_law.hpp"

#include <initializer_list>

namespace impactcert {

namespace {

Vector vec(std::initializer_list<int> xs) {
    Vector v;
    for (int x : xs)
        v.emplace_back(x);
    return v;
}

Matrix mat(std::initializer_list<int> r0, std::initializer_list<int> r1) {
    return Matrix::from_rows({vec(r0), vec(r1)});
}

PieceDecl piece(const char* name, Matrix Q, std::initializer_list<int> from,
                std::initializer_list<int> to) {
    return PieceDecl{name, std::move(Q), std::vector<Vector>{vec(from), vec(to)}};
}

} // namespace

Law paper_law() {
    Law law;
    law.name = "newton3-sequential";
    law.description = "Leine & Winandy (PAMM 2015): sequential impact law of the 3-ball Newton's "
                      "cradle, unit masses.";
    law.masses = vec({1, 1, 1});
    // Cones counter-clockwise from the first quadrant; rays as in SPEC section 2.
    law.pieces = {
        piece("I", mat({1, 0}, {0, 1}), {1, 0}, {0, 1}),
        piece("IIa", mat({-1, 0}, {1, 1}), {0, 1}, {-1, 1}),
        piece("IIb", mat({0, 1}, {-1, -1}), {-1, 1}, {-1, 0}),
        piece("III", mat({0, -1}, {-1, 0}), {-1, 0}, {0, -1}),
        piece("IVb", mat({-1, -1}, {1, 0}), {0, -1}, {1, -1}),
        piece("IVa", mat({1, 1}, {0, -1}), {1, -1}, {1, 0}),
    };
    law.identities = {
        {"IIb", {"IVa", "IIa"}},
        {"IVb", {"IIa", "IVa"}},
        {"III", {"IVa", "IIa", "IVa"}},
        {"III", {"IIa", "IVa", "IIa"}},
    };
    law.single_impacts = {
        {"IIa", 1, Rational(1)},
        {"IVa", 2, Rational(1)},
    };
    law.outcomes = {
        {"one ball in, one ball out", vec({1, 0, 0}), vec({0, 0, 1})},
        {"two balls in, two balls out", vec({1, 1, 0}), vec({0, 1, 1})},
        {"balls from both ends", vec({1, 0, -1}), vec({-1, 0, 1})},
        {"one ball in from the right", vec({0, 0, -1}), vec({-1, 0, 0})},
        {"no impact (common motion)", vec({1, 1, 1}), vec({1, 1, 1})},
    };
    std::vector<std::string> claims;
    for (const char* id : kObligationIds)
        if (std::string(id) != "symmetries") // the paper declares none
            claims.emplace_back(id);
    law.claims = claims;
    return law;
}

} // namespace impactcert
