// SPDX-License-Identifier: GPL-3.0-or-later
// cradle.cpp -- see cradle.hpp. Exact: small integer matrices built as Rationals.
#include "model/cradle.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace impactcert {

namespace {

// Contact velocities of ball velocities u: gamma_k = u_(k+1) - u_k.
Vector contacts_of(const Vector& u) {
    Vector gamma(u.size() - 1);
    for (std::size_t k = 0; k + 1 < u.size(); ++k)
        gamma[k] = u[k + 1] - u[k];
    return gamma;
}

// The map induced on contact velocities by a map `f` of ball velocities that commutes with
// adding a common velocity (up to sign): its columns are the images of the unit contact
// velocities, lifted to ball velocities with u_1 = 0.
template <class F> Matrix induced(std::size_t n, F f) {
    std::vector<Vector> columns;
    for (std::size_t j = 0; j + 1 < n; ++j) {
        Vector u(n, Rational(0));
        for (std::size_t i = j + 1; i < n; ++i)
            u[i] = 1; // gamma = e_j
        columns.push_back(contacts_of(f(u)));
    }
    return Matrix::from_columns(columns);
}

std::string ordering_name(const std::vector<std::size_t>& order) {
    std::string name;
    for (std::size_t i = 0; i < order.size(); ++i)
        name += (i ? "<=u" : "u") + std::to_string(order[i] + 1);
    return name;
}

PieceDecl ordering_piece(const std::vector<std::size_t>& order, std::string name) {
    const std::size_t n = order.size();
    std::vector<Vector> rays;
    for (std::size_t k = 1; k < n; ++k) {
        Vector u(n, Rational(0));
        for (std::size_t i = k; i < n; ++i)
            u[order[i]] = 1; // the n-k fastest balls
        rays.push_back(contacts_of(u));
    }
    // Q r_k = e_k: Q = R^-1.
    auto Q = inverse(Matrix::from_columns(rays));
    if (!Q)
        throw std::logic_error("cradle: the rays of an ordering are dependent");
    return PieceDecl{std::move(name), *Q, rays};
}

Vector sorted(Vector u) {
    std::sort(u.begin(), u.end());
    return u;
}

} // namespace

Law cradle_law(std::size_t n, CradleListing listing, bool symmetries) {
    if (n < 2 || n > 12)
        throw InputError("--balls: expected 2..12, got " + std::to_string(n));
    if (listing == CradleListing::representatives && !symmetries)
        throw InputError("--no-symmetries: orbit representatives need the symmetries (add --pieces all)");
    Law law;
    law.name = "cradle-" + std::to_string(n);
    law.description = "Equal-mass elastic " + std::to_string(n) +
                      "-ball Newton's cradle, S = sort the ball velocities: one cone per ordering of u- "
                      "(piece u2<=u1<=... is the cone where u2 <= u1 <= ...), derived by impactcert derive cradle.";
    law.masses = Vector(n, Rational(1));
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    if (listing == CradleListing::all) {
        do
            law.pieces.push_back(ordering_piece(order, ordering_name(order)));
        while (std::next_permutation(order.begin(), order.end()));
    } else {
        law.pieces.push_back(ordering_piece(order, "sorted"));
        law.representatives_only = true;
    }
    if (symmetries) {
        const std::size_t c = n - 1;
        for (std::size_t k = 0; k < c; ++k) {
            const Matrix P = induced(n, [k](Vector u) {
                std::swap(u[k], u[k + 1]);
                return u;
            });
            law.symmetries.push_back(SymmetryDecl{"s" + std::to_string(k + 1), P, Matrix::identity(c)});
        }
        const Matrix J = induced(n, [](Vector u) {
            std::reverse(u.begin(), u.end());
            for (auto& x : u)
                x = -x;
            return u;
        });
        law.symmetries.push_back(SymmetryDecl{"r", J, J});
    }
    // The swap of balls k, k+1 alone: the two-ball impact at contact k.
    for (std::size_t k = 0; k + 1 < n; ++k) {
        std::iota(order.begin(), order.end(), std::size_t{0});
        std::swap(order[k], order[k + 1]);
        law.single_impacts.push_back(SingleImpactDecl{
            listing == CradleListing::all ? ordering_name(order) : "sorted.s" + std::to_string(k + 1),
            static_cast<int>(k + 1), Rational(1)});
    }
    auto outcome = [&](const std::string& name, Vector u) {
        law.outcomes.push_back(OutcomeDecl{name, u, sorted(u)});
    };
    Vector u(n, Rational(0));
    u[0] = 1;
    outcome("one ball in", u);
    u[1] = 1;
    outcome("two balls in", u);
    u = Vector(n, Rational(0));
    u[0] = 1;
    u[n - 1] = -1;
    outcome("one ball in from each side", u);
    outcome("all moving together", Vector(n, Rational(1)));
    return law;
}

} // namespace impactcert
