// SPDX-License-Identifier: GPL-3.0-or-later
#include "model/system.hpp"

#include "base/errors.hpp"

#include <stdexcept>
#include <utility>

namespace impactcert {

Matrix two_body_impact(const Matrix& G, std::size_t k, const Rational& e) {
    Matrix Q = Matrix::identity(G.rows());
    const Rational f = (Rational(1) + e) / G(k, k);
    for (std::size_t i = 0; i < G.rows(); ++i)
        Q(i, k) -= f * G(i, k);
    return Q;
}

FrictionPolygon friction_polygon(const std::vector<Vector>& facets, const std::string& where) {
    const std::size_t k = facets.size();
    if (k < 3)
        input_error(where, "a friction polygon needs at least three facets, got " + std::to_string(k));
    if (k > kMaxFacets) // each vertex is checked against every facet (k^2 products)
        input_error(where, "a friction polygon has at most " + std::to_string(kMaxFacets) + " facets, got " +
                               std::to_string(k));
    for (std::size_t j = 0; j < k; ++j) {
        if (facets[j].size() != 2)
            input_error(idx(where, j), "expected 2 entries (along the two tangents), got " + std::to_string(facets[j].size()));
        if (sign_of(facets[j][0]) == Sign::zero && sign_of(facets[j][1]) == Sign::zero)
            input_error(idx(where, j), "a facet's normal must not be zero");
    }
    // Counterclockwise, each turn strictly between 0 and a half turn, and once around in all: the
    // turns' cross products are positive and the directions' angles sum to one full turn (the
    // number of times the sequence crosses the positive x axis counterclockwise is 1).
    auto cross = [](const Vector& a, const Vector& b) { return a[0] * b[1] - a[1] * b[0]; };
    std::size_t crossings = 0;
    for (std::size_t j = 0; j < k; ++j) {
        const Vector& a = facets[j];
        const Vector& b = facets[(j + 1) % k];
        if (sign_of(cross(a, b)) != Sign::positive)
            input_error(idx(where, (j + 1) % k), "the facets must turn counterclockwise, each by less than a half turn "
                                                 "(a bounded polygon around the origin)");
        // Angles in [0, pi) are "upper", in [pi, 2 pi) "lower"; a turn of less than a half turn
        // from lower to upper passes the angle 0 once.
        auto upper = [](const Vector& x) {
            return sign_of(x[1]) == Sign::positive || (sign_of(x[1]) == Sign::zero && sign_of(x[0]) == Sign::positive);
        };
        if (!upper(a) && upper(b))
            ++crossings;
    }
    if (crossings != 1)
        input_error(where, "the facets must go once around the origin, counterclockwise");
    FrictionPolygon p;
    p.a = facets;
    for (std::size_t j = 0; j < k; ++j) {
        const Vector& a = facets[j];
        const Vector& b = facets[(j + 1) % k];
        const Rational det = cross(a, b); // > 0
        Vector v(2);
        v[0] = (b[1] - a[1]) / det; // [a; b] v = (1, 1)
        v[1] = (a[0] - b[0]) / det;
        for (std::size_t i = 0; i < k; ++i)
            if (i != j && i != (j + 1) % k && !(dot(facets[i], v) < Rational(1)))
                input_error(idx(where, i), "facet " + std::to_string(i + 1) + " is not an edge of the polygon (it passes through or "
                                           "cuts off the corner of facets " + std::to_string(j + 1) + " and " +
                                           std::to_string((j + 1) % k + 1) + ")");
        p.v.push_back(std::move(v));
    }
    return p;
}

std::vector<Vector> pyramid_facets() {
    return {Vector{Rational(1), Rational(1)}, Vector{Rational(-1), Rational(1)}, Vector{Rational(-1), Rational(-1)},
            Vector{Rational(1), Rational(-1)}};
}

Mechanics make_mechanics(const System& s, Dependent dependent) {
    try {
        return make_mechanics(s.masses, s.M, s.W, s.friction, dependent, !s.velocity_names.empty());
    } catch (const InputError& e) {
        if (s.origin.empty())
            throw;
        throw InputError(s.origin + ": " + e.what()); // read whole before: a later refusal (dependent columns)
    }
}

namespace {

// The pivot columns of W's reduced row echelon form (each column kept when independent of those
// kept before it) and C, its non-zero rows: W = W_B C exactly.
void reduce_columns(Mechanics& m) {
    Matrix a = m.W;
    const std::size_t n = a.rows(), c = a.cols();
    std::size_t row = 0;
    for (std::size_t col = 0; col < c && row < n; ++col) {
        std::size_t p = row;
        while (p < n && sign_of(a(p, col)) == Sign::zero)
            ++p;
        if (p == n)
            continue;
        for (std::size_t j = 0; j < c; ++j)
            std::swap(a(row, j), a(p, j));
        const Rational pivot = a(row, col);
        for (std::size_t j = 0; j < c; ++j)
            a(row, j) /= pivot;
        for (std::size_t i = 0; i < n; ++i)
            if (i != row && sign_of(a(i, col)) != Sign::zero) {
                const Rational f = a(i, col);
                for (std::size_t j = 0; j < c; ++j)
                    a(i, j) -= f * a(row, j);
            }
        m.basis.push_back(col);
        ++row;
    }
    m.C = Matrix(m.basis.size(), c);
    for (std::size_t i = 0; i < m.basis.size(); ++i)
        for (std::size_t j = 0; j < c; ++j)
            m.C(i, j) = a(i, j);
}

} // namespace

Mechanics make_mechanics(const std::vector<Rational>& masses, const std::optional<Matrix>& M,
                         const std::optional<Matrix>& W, const std::vector<FrictionDecl>& friction,
                         Dependent dependent, bool scene) {
    Mechanics m;
    if (M && !masses.empty())
        input_error("$", "give either \"masses\" or \"M\", not both");
    if (M) {
        const std::size_t n = M->rows();
        if (n == 0 || M->cols() != n)
            input_error("$.M", "expected a square matrix, got " + std::to_string(M->rows()) + "x" +
                                   std::to_string(M->cols()));
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < i; ++j)
                if ((*M)(i, j) != (*M)(j, i))
                    input_error(idx(idx("$.M", i), j), "M is not symmetric (" + to_string((*M)(i, j)) +
                                                           " != " + to_string((*M)(j, i)) + ")");
        // Positive definite iff the symmetric elimination meets only positive pivots (exact LDL^T).
        Matrix a = *M;
        for (std::size_t k = 0; k < n; ++k) {
            if (sign_of(a(k, k)) != Sign::positive)
                input_error("$.M", "not positive definite (pivot " + std::to_string(k + 1) + " is " +
                                       to_string(a(k, k)) + ")");
            for (std::size_t i = k + 1; i < n; ++i) {
                const Rational f = a(i, k) / a(k, k);
                for (std::size_t j = k; j < n; ++j)
                    a(i, j) -= f * a(k, j);
            }
        }
        m.M = *M;
        m.M_inv = *inverse(*M);
        for (std::size_t i = 0; i < n && m.diagonal; ++i)
            for (std::size_t j = 0; j < n; ++j)
                if (i != j && sign_of((*M)(i, j)) != Sign::zero)
                    m.diagonal = false;
    } else {
        const std::size_t n = masses.size();
        if (n == 0)
            input_error("$.masses", "no balls");
        for (std::size_t i = 0; i < n; ++i)
            if (sign_of(masses[i]) != Sign::positive)
                input_error(idx("$.masses", i), "mass must be positive, got " + to_string(masses[i]));
        m.M = Matrix(n, n);
        m.M_inv = Matrix(n, n);
        for (std::size_t i = 0; i < n; ++i) {
            m.M(i, i) = masses[i];
            m.M_inv(i, i) = Rational(1) / masses[i];
        }
    }
    const std::size_t n = m.M.rows();
    const std::string mass_path = M ? "$.M" : "$.masses";
    if (W) {
        if (W->rows() != n)
            input_error("$.contacts.W", "expected " + std::to_string(n) + " rows (one per ball), got " +
                                            std::to_string(W->rows()));
        if (W->cols() == 0)
            input_error("$.contacts.W", "no contacts");
        m.W = *W;
    } else {
        if (n < 2)
            input_error(mass_path, "a chain needs at least two balls");
        m.W = Matrix(n, n - 1);
        for (std::size_t k = 0; k + 1 < n; ++k) {
            m.W(k, k) = -1;
            m.W(k + 1, k) = 1;
        }
    }
    m.normals = m.W.cols();
    m.polygons.assign(m.normals, FrictionPolygon{});
    if (!friction.empty()) {
        const std::string fp = "$.contacts.friction";
        std::vector<Vector> tangent_columns;
        for (std::size_t i = 0; i < friction.size(); ++i) {
            const FrictionDecl& f = friction[i];
            const std::string at = idx(fp, i);
            if (f.contact >= m.normals)
                input_error(at + ".contact", "no contact " + std::to_string(f.contact + 1) + " (there are " +
                                                 std::to_string(m.normals) + ")");
            if (i > 0 && f.contact <= friction[i - 1].contact)
                input_error(at + ".contact", "contacts must be listed once each, in increasing order");
            if (sign_of(f.mu) == Sign::negative)
                input_error(at + ".mu", "friction coefficient must be >= 0, got " + to_string(f.mu));
            if (sign_of(f.restitution_tangential) == Sign::negative || f.restitution_tangential > Rational(1))
                input_error(at + ".restitution_tangential",
                            "must be in [0, 1], got " + to_string(f.restitution_tangential));
            if (f.tangents.empty() || f.tangents.size() > 2)
                input_error(at + ".tangents", "expected one tangent (planar) or two (spatial), got " +
                                                  std::to_string(f.tangents.size()));
            if (f.facets) {
                if (f.tangents.size() != 2)
                    input_error(at + ".facets", "a friction polygon needs two tangents, the contact has " +
                                                    std::to_string(f.tangents.size()));
                m.polygons[f.contact] = friction_polygon(*f.facets, at + ".facets");
            }
            for (std::size_t t = 0; t < f.tangents.size(); ++t) {
                if (f.tangents[t].size() != n)
                    input_error(idx(at + ".tangents", t), "expected " + std::to_string(n) + " entries (one per velocity), got " +
                                                              std::to_string(f.tangents[t].size()));
                tangent_columns.push_back(f.tangents[t]);
                m.tangents.push_back(Tangent{f.contact, f.mu, f.restitution_tangential});
            }
        }
        Matrix full(n, m.normals + tangent_columns.size());
        for (std::size_t i = 0; i < n; ++i) {
            for (std::size_t k = 0; k < m.normals; ++k)
                full(i, k) = m.W(i, k);
            for (std::size_t t = 0; t < tangent_columns.size(); ++t)
                full(i, m.normals + t) = tangent_columns[t][i];
        }
        m.W = std::move(full);
    }
    const std::size_t c = m.W.cols();
    reduce_columns(m);
    const std::size_t r = m.basis.size();
    if (r == 0)
        input_error(scene ? "$.contacts" : W ? "$.contacts.W" : "$.contacts", "every column is zero (rank 0): no contact moves anything");
    if (r < c && dependent == Dependent::refuse) {
        const std::string where = scene ? "$.contacts" : !friction.empty() ? "$.contacts.friction" : W ? "$.contacts.W" : "$.contacts";
        const std::string what = friction.empty() ? " contacts" : " columns (normals and tangents)";
        input_error(where, std::to_string(c) + what + " but rank " + std::to_string(r) +
                               (c > n ? " (" + std::to_string(n) + " velocities)" : std::string()) +
                               ": the columns are linearly dependent (derive newton reads such systems, and fuzz with --velocities)");
    }
    m.G = transpose(m.W) * m.M_inv * m.W;
    Matrix W_B(n, r);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t k = 0; k < r; ++k)
            W_B(i, k) = m.W(i, m.basis[k]);
    m.G_B = transpose(W_B) * m.M_inv * W_B;
    const auto H_B = inverse(m.G_B);
    if (!H_B)
        throw std::logic_error("make_mechanics: G_B singular on independent columns");
    m.H_B = *H_B;
    if (r == c)
        m.H = m.H_B;
    return m;
}

Walls parse_walls(const std::string& text) {
    if (text == "none")
        return Walls::none;
    if (text == "left")
        return Walls::left;
    if (text == "right")
        return Walls::right;
    if (text == "both")
        return Walls::both;
    throw InputError("--walls: expected none, left or right, got \"" + text + "\"");
}

const char* to_string(Walls walls) {
    switch (walls) {
    case Walls::none: return "none";
    case Walls::left: return "left";
    case Walls::right: return "right";
    case Walls::both: return "both";
    }
    return "?";
}

System chain_system(const std::vector<Rational>& masses, Walls walls) {
    System s;
    s.masses = masses;
    const std::size_t n = masses.size();
    const bool left = walls == Walls::left || walls == Walls::both;
    const bool right = walls == Walls::right || walls == Walls::both;
    if (n == 0 || (n == 1 && !left && !right))
        throw InputError("--masses: a chain needs at least two balls (or one ball and a wall), got " +
                         std::to_string(n));
    for (std::size_t i = 0; i < n; ++i)
        if (sign_of(masses[i]) != Sign::positive)
            throw InputError("--masses: mass " + std::to_string(i + 1) + " must be positive, got " +
                             to_string(masses[i]));
    if (left && right)
        throw InputError("--walls both: " + std::to_string(n) + " ball(s) touching both walls have " + std::to_string(n + 1) +
                         " contacts for " + std::to_string(n) + " velocities (a jammed chain: W has dependent columns)");
    s.name = "chain-" + std::to_string(n);
    if (walls == Walls::none)
        return s;
    s.name += std::string("-wall-") + to_string(walls);
    const std::size_t c = n - 1 + (left ? 1 : 0) + (right ? 1 : 0);
    Matrix W(n, c);
    std::size_t k = 0;
    if (left)
        W(0, k++) = 1; // gamma_1 = u_1: the ball leaves the wall on its left when u_1 > 0
    for (std::size_t i = 0; i + 1 < n; ++i, ++k) {
        W(i, k) = -1;
        W(i + 1, k) = 1;
    }
    if (right)
        W(n - 1, k++) = -1; // gamma_c = -u_n
    s.W = W;
    return s;
}

std::string describe_system(const System& s) {
    const Mechanics m = make_mechanics(s, Dependent::allow);
    std::string what = s.W ? "explicit W" : "chain";
    if (m.has_friction())
        what += ", " + std::to_string(m.tangents.size()) + " friction tangent" + (m.tangents.size() == 1 ? "" : "s");
    if (m.redundant())
        what += ", " + std::to_string(m.contacts()) + " columns of rank " + std::to_string(m.basis.size());
    return std::to_string(m.balls()) + " velocities, " + std::to_string(m.normals) + (m.normals == 1 ? " contact (" : " contacts (") + what +
           (m.diagonal ? "" : ", full mass matrix") + ")";
}

} // namespace impactcert
