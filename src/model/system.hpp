// SPDX-License-Identifier: GPL-3.0-or-later
// system.hpp -- mechanical systems beyond chains (SPEC section 8).
//
// Contract:
//   - A System is what the head of a law file says: a name, a mass matrix (diagonal `masses`, or
//     a symmetric positive definite `M`) and contacts (`chain`, or an explicit W, n x c).
//   - Mechanics is a validated system with everything derived: M, M^-1, W, G = W^T M^-1 W and
//     H = G^-1. make_mechanics throws InputError naming the JSON path of the first defect
//     ("$.M: not positive definite (pivot 2 is -1/3)", "$.contacts.W: rank 1 < 2 contacts").
//     Model (law.hpp) is built on it, so a law and a system are validated by the same rules.
//   - chain_system: --masses M1,...,Mn and --walls none|left|right|both: a left wall is contact 1
//     with gamma_1 = u_1 (W column e_1), a right wall the last contact with gamma_c = -u_n (W
//     column -e_n), the chain's contacts in between.
//   - parse_system_text / load_system_file: the format `impactcert-system/1`, or a law file
//     (its pieces and declarations ignored: only the head is read, by the same strict rules).
#pragma once

#include "exact/matrix.hpp"

#include <optional>
#include <string>
#include <vector>

namespace impactcert {

inline constexpr const char* kSystemFormat = "impactcert-system/1";

// Coulomb friction at one contact (SPEC section 9): its tangent columns (one in the plane, two
// in space: each bounded separately by mu Lambda_N), mu >= 0 and the tangential restitution
// e_T in [0, 1] of Coulomb's law at an impact (xi_T = gamma_T+ + e_T gamma_T-).
struct FrictionDecl {
    std::size_t contact = 0;      // 0-based: the column of the normals it belongs to
    Rational mu;
    std::vector<Vector> tangents; // each n entries: the columns of W it adds
    Rational restitution_tangential; // e_T (0 unless given)
    // A polygonal friction cone (two tangents; proofs/README.md, "Polygonal friction cones"):
    // {Lambda_T : a_j . Lambda_T <= mu Lambda_N} with the facets a_j (2-vectors in the tangents'
    // coordinates, counterclockwise). Absent: each tangent bounded by mu Lambda_N on its own (the box).
    std::optional<std::vector<Vector>> facets = std::nullopt;
};

// The friction polygon of a contact, validated: facets a_j counterclockwise, each an edge, and
// vertex j = the intersection of facets j and j + 1 (a_j . v_j = a_{j+1} . v_j = 1), so that the
// polygon is {x : a_j . x <= 1} = conv{v_j}.
struct FrictionPolygon {
    std::vector<Vector> a, v;
    bool empty() const { return a.empty(); }
};
// Throws InputError naming `where` unless the facets (at least three, at most kMaxFacets) are listed
// counterclockwise, each turn less than a half turn (bounded, the origin inside), and every vertex
// strictly inside the other facets (each facet an edge, no three through a point).
FrictionPolygon friction_polygon(const std::vector<Vector>& facets, const std::string& where);
inline constexpr std::size_t kMaxFacets = 1024; // facets of one friction polygon (the format's bound)
// MuJoCo's pyramidal cone of condim 3: |Lambda_T1| + |Lambda_T2| <= mu Lambda_N (facets (+-1, +-1)).
std::vector<Vector> pyramid_facets();

struct System {
    std::string name;
    std::vector<Rational> masses; // diagonal mass matrix, or empty when M is given
    std::optional<Matrix> M;      // symmetric positive definite, n x n
    std::optional<Matrix> W;      // n x c; absent: "chain" (the normals)
    std::vector<FrictionDecl> friction; // strictly increasing contacts; empty: frictionless
    // From a scene (scene.hpp): each contact's restitution (empty: none given); names of the
    // velocities (one per coordinate, "disk.vx") and of the contacts ("disk/ground"), or empty.
    std::vector<Rational> restitution;
    std::vector<std::string> contact_names;
    std::vector<std::string> velocity_names;
    std::string origin = std::string(); // the file it was read from (load_system_file), named by later errors
};

// One tangent column of W: the contact (normal column) it belongs to, mu and e_T.
struct Tangent {
    std::size_t contact = 0;
    Rational mu, e_T;
};

struct Mechanics {
    // W = [W_N W_T]: the normals (columns 0 .. normals-1), then the tangents in the order of the
    // friction declarations; G and H are (normals + tangents) square.
    Matrix M, M_inv, W, G, H;
    bool diagonal = true; // M is diagonal
    std::size_t normals = 0;
    std::vector<Tangent> tangents; // tangent j is column normals + j
    // Per normal contact: its friction polygon (empty: the box, or frictionless); a polygon's
    // contact has exactly two tangents.
    std::vector<FrictionPolygon> polygons;
    bool has_polygons() const {
        for (const auto& p : polygons)
            if (!p.empty())
                return true;
        return false;
    }
    // Dependent columns (proofs/README.md, "Redundant contacts"): `basis` lists the columns of W
    // kept, in order, each one independent of those kept before it (the pivot columns of W's
    // reduced row echelon form; r = rank W of them), and W = W_B C with C (r x d) the non-zero
    // rows of that echelon form (C's basis columns are unit vectors). G_B = W_B^T M^-1 W_B is
    // positive definite and H_B = G_B^-1. Full column rank: basis = all, C = I, G_B = G, H_B = H.
    // With dependent columns G is singular and H is empty: a law lives on gamma_B = W_B^T u.
    std::vector<std::size_t> basis;
    Matrix C, G_B, H_B;
    bool redundant() const { return basis.size() < W.cols(); }
    std::size_t balls() const { return M.rows(); }
    std::size_t contacts() const { return W.cols(); } // the dimension of gamma: normals + tangents
    bool has_friction() const { return !tangents.empty(); }
    // |u|_M^2 = u^T M u (twice the kinetic energy).
    Rational energy2(const Vector& u) const { return bilinear(u, M, u); }
};

// Validates and derives; throws InputError naming $.masses, $.M or $.contacts.W.
// Friction: every contact exists and appears once (ascending), mu >= 0, e_T in [0, 1], each
// tangent has n entries. [W_N W_T] must have full column rank (InputError naming
// $.contacts.friction, or the scene's contacts when `scene`) unless `dependent` allows
// dependent columns (`derive newton` and `verify` read such systems; the others do not yet).
enum class Dependent { refuse, allow };
Mechanics make_mechanics(const std::vector<Rational>& masses, const std::optional<Matrix>& M,
                         const std::optional<Matrix>& W, const std::vector<FrictionDecl>& friction = {},
                         Dependent dependent = Dependent::refuse, bool scene = false);
Mechanics make_mechanics(const System& s, Dependent dependent = Dependent::refuse);

enum class Walls { none, left, right, both };
Walls parse_walls(const std::string& text); // InputError naming --walls
const char* to_string(Walls walls);

// A chain of balls, with walls. Validated (InputError names --masses).
System chain_system(const std::vector<Rational>& masses, Walls walls);

System parse_system_text(const std::string& text, const std::string& origin);
System load_system_file(const std::string& path);

// The head of a law file (format, name, masses or M, contacts) as JSON, in canonical order.
std::string describe_system(const System& s); // "3 balls, 2 contacts (chain)" etc.

// The two-ball impact matrix at contact k (0-based) with restitution e, from G alone:
// Q^(k)(e) = I - (1+e) G e_k e_k^T / G_kk.
Matrix two_body_impact(const Matrix& G, std::size_t k, const Rational& e);

} // namespace impactcert
