// SPDX-License-Identifier: GPL-3.0-or-later
// law.hpp -- a cone-wise linear impact law, as declared and as prepared for proof.
//
// Contract:
//   - `Law` is the declaration exactly as a law file (or the embedded default) states it.
//   - `Model` is a validated law with its mechanics derived: M^-1, W, G = W^T M^-1 W, H = G^-1,
//     and for every piece its ray matrix R (columns: primitive rays), R^-1 and the ids of its
//     rays in a table of distinct rays. Constructing a Model validates the law and throws
//     InputError naming the JSON path of the first defect; a Model is always consistent.
//   - Nothing here assumes c = 2.
#pragma once

#include "base/errors.hpp"
#include "exact/int_kernel.hpp"
#include "base/limits.hpp"
#include "exact/matrix.hpp"
#include "model/system.hpp"

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace impactcert {

// ---------------------------------------------------------------------------------------------
// Declaration

struct PieceDecl {
    std::string name;
    Matrix Q;                       // c x c
    std::optional<std::vector<Vector>> rays; // c rays; absent: the columns of Q^-1
    // Laws on dependent columns only (proofs/README.md, "Redundant contacts"): the impulse
    // Lambda = impulses * gamma_B on the piece, d x c (d = all columns of W, c = its rank).
    std::optional<Matrix> impulses = std::nullopt;
};

struct IdentityDecl {
    std::string lhs;                  // piece name
    std::vector<std::string> product; // piece names, left to right
};

struct SingleImpactDecl {
    std::string piece;
    int contact = 0;       // 1-based
    Rational restitution; // in [0, 1]
};

struct OutcomeDecl {
    std::string name;
    Vector u_minus; // n ball velocities
    Vector u_plus;  // n ball velocities, as declared
};

// A declared symmetry (proofs/README.md, "Symmetries"): P and P' rational c x c matrices with
// P^T H P = H, P'^T H P' = H, P mapping every cone onto a cone C_sigma(i) and
// Q_sigma(i) P = P' Q_i, so that S(P x) = P' S(x). Verified by the obligation `symmetries`.
// Generated piece names longer than this end the expansion with an input error (proofs/README.md,
// "Symmetries": the depth of the search bounds the name; a group of infinite order has no bound).
inline constexpr std::size_t kMaxGeneratedName = 4096;

struct SymmetryDecl {
    std::string name;
    Matrix P, P_prime;
};

struct Law {
    std::string name;
    std::string description;               // free text (note/description), informational
    std::vector<Rational> masses;          // n > 0 (diagonal M), or empty when M is given
    std::optional<Matrix> M;               // symmetric positive definite mass matrix (SPEC section 8)
    std::optional<Matrix> W;               // n x c; absent: "chain"
    std::vector<FrictionDecl> friction;    // SPEC section 9: W gains tangent columns (system.hpp)
    // "coordinates" (optional, informational): names of the n velocities and of the c normal
    // contacts, as a scene has them; empty when not given.
    std::vector<std::string> velocity_names, contact_names;
    std::vector<PieceDecl> pieces;
    std::vector<IdentityDecl> identities;
    std::vector<SingleImpactDecl> single_impacts;
    std::vector<OutcomeDecl> outcomes;
    std::optional<std::vector<std::string>> claims; // absent: every obligation that applies
    std::vector<SymmetryDecl> symmetries;
    // "pieces_listed": false ("all"): `pieces` is the whole law. true ("orbit-representatives"):
    // the law is `pieces` closed under the symmetries (Model::Model says how).
    bool representatives_only = false;
};

// ---------------------------------------------------------------------------------------------
// Obligation ids, in report order (SPEC section 3).

// `symmetries` comes last: it is evaluated first whenever another obligation uses it.
inline constexpr std::array<const char*, 13> kObligationIds = {
    "fan",        "P1",         "P2",           "P3",
    "kinematic",  "kinetic",    "energetic",    "identities",
    "single-impacts", "nonexpansive", "nonexpansive-lemma", "outcomes", "symmetries"};

// A law with friction (SPEC section 9) has one more obligation, `coulomb` (after `kinetic`), and
// P3 does not apply to it; a frictionless law has exactly the thirteen above, so its verdicts
// and certificates keep their shape.
inline constexpr std::array<const char*, 14> kFrictionObligationIds = {
    "fan",        "P1",         "P2",           "P3",
    "kinematic",  "kinetic",    "coulomb",      "energetic",    "identities",
    "single-impacts", "nonexpansive", "nonexpansive-lemma", "outcomes", "symmetries"};
std::vector<const char*> obligation_ids(bool friction);

bool is_obligation_id(const std::string& id);
// Whether the law declares anything for obligation id (identities, single impacts, outcomes,
// symmetries need declarations; the others always apply), and whether it claims it (no
// "claims": every one that applies).
bool law_applies(const Law& law, const std::string& id);
bool law_claims(const Law& law, const std::string& id);
// "claims": non-empty, known ids, each once, each applying; throws InputError naming the place.
void validate_claims(const Law& law);
// The declarations after the pieces, in Model's order: identities and single impacts (their
// pieces must exist), outcomes (n ball velocities), then the claims. Throws InputError.
void validate_declarations(const Law& law, std::size_t n, std::size_t c,
                           const std::function<bool(const std::string&)>& piece_exists);

// The symmetries of a compact law, before anything is generated (Model's and the stream's input
// rule, in this order for each symmetry): P and P' are H-isometries, and P has finite order --
// for c <= 32, decided by the characteristic polynomial of P, which has integer coefficients
// exactly when an H-isometry has finite order (proofs/README.md, "Compact laws", Lemma S0). A P
// of infinite order generates pieces without end; it is refused at once instead of by the
// growth of the generated numbers. Throws InputError.
void validate_compact_symmetries(const Law& law, const Matrix& H);
inline constexpr std::size_t kMaxOrderCheckContacts = 32;

// ---------------------------------------------------------------------------------------------
// Prepared law

struct Piece {
    std::string name;
    Matrix Q;                       // c x c, invertible
    Matrix R;                       // c x c, columns are the primitive rays
    Matrix R_inv;                   // R^-1: s = R_inv gamma are gamma's cone coordinates
    std::vector<std::size_t> ray_ids; // index into Model::rays() of each column of R
    std::optional<Matrix> L;          // dependent columns: Lambda = L gamma_B on the cone (d x c)
};

// Two points of the interior of the piece's cone whose difference is a positive multiple of x:
// a = R 1 + eps x and b = R 1, eps = 1 / (2 max(1, max_k |(R^-1 x)_k| + 1)), so that
// R^-1 a = 1 + eps R^-1 x > 0 (the lemma's witness for a piece that expands along x).
std::pair<Vector, Vector> interior_pair_along(const Piece& piece, const Vector& x);

class Model {
  public:
    // Validates; throws InputError. With law.representatives_only the pieces are closed under
    // the symmetries, breadth first: for each piece in order (the listed ones, then those
    // generated) and each symmetry in order, the cone P C is added, with Q' = P' Q P^-1 and
    // the name "<piece>.<symmetry>", unless a piece already has exactly those rays; more than
    // `max_pieces` pieces is an input error.
    // max_memory_mb bounds the generated pieces by the bytes of their numbers (96 per rational
    // plus its limbs), and a generated entry may have at most 16 times the bits of the listed
    // data plus 1,024: a group of finite order never needs more; one of infinite order (a
    // rational rotation) is stopped as soon as its numbers grow. Both are input errors naming
    // the option (as --max-pieces).
    explicit Model(Law law, std::size_t max_pieces = Limits{}.max_pieces,
                   std::size_t max_memory_mb = Limits{}.max_memory_mb);

    const Law& law() const { return law_; }
    std::size_t balls() const { return M_.rows(); }      // n
    std::size_t contacts() const { return W_.cols(); }   // c

    const Matrix& M() const { return M_; }
    const Matrix& M_inv() const { return M_inv_; }
    System system() const {
        return System{law_.name, law_.masses, law_.M, law_.W, law_.friction, {}, law_.contact_names, law_.velocity_names};
    }
    const Matrix& W() const { return W_; } // [W_N W_T]
    // Friction (SPEC section 9): gamma = (gamma_N, gamma_T), the normals first.
    std::size_t normals() const { return normals_; }
    const std::vector<Tangent>& tangents() const { return tangents_; } // tangent j is coordinate normals() + j
    bool has_friction() const { return !tangents_.empty(); }
    // Per normal contact: its friction polygon (empty: the box); proofs/README.md, "Polygonal friction cones".
    const std::vector<FrictionPolygon>& polygons() const { return polygons_; }
    bool has_polygons() const {
        for (const auto& p : polygons_)
            if (!p.empty())
                return true;
        return false;
    }
    const Matrix& G() const { return G_; }
    const Matrix& H() const { return H_; }
    // Dependent columns (proofs/README.md, "Redundant contacts"): W() is then W_B, the basis
    // columns of [W_N W_T] (their indices basis()), contacts() its rank c, G() and H() those of
    // W_B; the impulse has all d columns: Lambda in R^d with W_B C = [W_N W_T], gamma = C^T
    // gamma_B, and normals() and tangents() count the columns of all of W.
    bool redundant() const { return !basis_.empty(); }
    const std::vector<std::size_t>& basis() const { return basis_; }
    const Matrix& C() const { return C_; }
    const Matrix& full_W() const { return redundant() ? full_W_ : W_; }
    // InputError for the commands that do not read laws on dependent columns yet: "WHO does not
    // read laws on dependent contact columns (rank r of d) yet; verify, certify, report and
    // impactcert-check do".
    void require_independent_columns(const std::string& who) const;
    const std::vector<Piece>& pieces() const { return pieces_; }
    // The declared symmetries with P^-1 (P is invertible: checked on construction).
    const std::vector<Matrix>& symmetry_P_inv() const { return P_inv_; }
    const std::vector<Vector>& rays() const { return rays_; } // distinct, primitive
    std::size_t piece_index(const std::string& name) const;   // throws std::out_of_range

    // |x|_H^2 = x^T H x
    Rational energy(const Vector& gamma) const { return bilinear(gamma, H_, gamma); }

    // Pieces whose closed cone contains gamma (several on a boundary; none outside a gap).
    std::vector<std::size_t> pieces_containing(const Vector& gamma) const;
    // The values of S at gamma: Q_p gamma for every piece containing gamma, duplicates removed
    // (one value off the boundaries or for a continuous law; none in a gap of the cones).
    std::vector<Vector> values_at(const Vector& gamma) const;
    // True when gamma lies in the interior of piece p's cone.
    bool in_interior(std::size_t p, const Vector& gamma) const;

    // Whether the obligation is declared/applicable and whether it is claimed.
    bool applies(const std::string& id) const;
    bool claimed(const std::string& id) const;

    // Ball-velocity form: gamma = W^T u, and u+ from gamma- and gamma+ (SPEC section 3, outcomes).
    Vector contact_velocities(const Vector& u) const { return transpose(W_) * u; }
    Vector post_impact_velocities(const Vector& u_minus, const Vector& gamma_minus,
                                  const Vector& gamma_plus) const;
    // Two-ball impact matrix at contact k (0-based) with restitution e:
    // Q^(k)(e) = I - (1+e) G e_k e_k^T / G_kk.
    Matrix single_impact(std::size_t k, const Rational& e) const;

  private:
    Law law_;
    Matrix M_, M_inv_, W_, G_, H_;
    std::vector<std::size_t> basis_; // empty: full column rank
    Matrix C_, full_W_;
    std::size_t normals_ = 0;
    std::vector<Tangent> tangents_;
    std::vector<FrictionPolygon> polygons_;
    std::vector<Piece> pieces_;
    std::vector<Vector> rays_;
    std::vector<Matrix> P_inv_;
    std::map<Vector, std::size_t> ray_index_; // rays_ by value
    std::vector<std::optional<intk::IntMatrix>> r_inv_int_; // R_inv in int64 where it fits

    // gamma over a common denominator in int64, when it fits.
    static std::optional<std::vector<intk::i64>> scaled(const Vector& gamma);
    void require_contacts(const Vector& gamma) const;
    bool in_cone(std::size_t p, const Vector& gamma, const std::optional<std::vector<intk::i64>>& g,
                 bool interior) const;

    void add_piece(const std::string& name, const Matrix& Q, const std::vector<Vector>& primitive_rays,
                   const std::string& path);
};

} // namespace impactcert
