// checked_law.hpp -- the law inside a certificate, as the checker reads and re-derives it.
//
// Contract: read_law applies the prover's input rules (SPEC section 4: format, non-empty names,
// positive masses, c independent non-zero rays per piece, known pieces in declarations,
// restitutions in [0, 1], claims known, unrepeated and declared), so that a law the prover
// rejects is never verified, and derives M^-1, G = W^T M^-1 W, H = G^-1 and each piece's
// primitive rays, R and R^-1 with its own arithmetic (linalg.hpp). Errors name the JSON path.
#pragma once

#include "linalg.hpp"
#include "reading.hpp"

#include <algorithm>
#include <cstddef>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace impactcert_check::detail {

struct Piece {
    std::string name;
    Mat Q_, R, R_inv;
    std::vector<Vec> rays; // primitive
};

struct Identity {
    std::size_t lhs;
    std::vector<std::size_t> product;
    Json lhs_json, product_json; // as declared, for comparison with the evidence
};
struct SingleImpact {
    std::size_t piece, contact; // contact in 1..c
    Q restitution;
    Json piece_json;
};
struct OutcomeDecl {
    std::string name;
    Vec u_minus, u_plus;
};

struct Law {
    Json json;
    Vec masses;
    Mat W, M_inv, G, H;
    std::size_t n = 0, c = 0;
    std::vector<Piece> pieces;
    std::map<std::string, std::size_t> piece_index;
    std::vector<Vec> distinct_rays;     // in order of first appearance
    std::map<Vec, std::size_t> ray_index; // into distinct_rays
    std::vector<Identity> identities;
    std::vector<SingleImpact> single_impacts;
    std::vector<OutcomeDecl> outcomes;
    std::set<std::string> claimed_ids;
    bool claims_given = false;

    std::size_t piece(const Json& name, const std::string& path) const {
        const std::string s = str(name, path);
        const auto it = piece_index.find(s);
        if (it == piece_index.end())
            reject(path, "unknown piece \"" + s + "\"");
        return it->second;
    }
    bool in_cone(std::size_t p, const Vec& g) const { return nonneg(mul(pieces[p].R_inv, g)); }
    bool in_interior(std::size_t p, const Vec& g) const { return positive(mul(pieces[p].R_inv, g)); }
    std::vector<std::size_t> interiors(const Vec& g) const {
        std::vector<std::size_t> out;
        for (std::size_t p = 0; p < pieces.size(); ++p)
            if (in_interior(p, g))
                out.push_back(p);
        return out;
    }
    bool is_ray_of(std::size_t p, const Vec& v) const {
        const Vec pv = primitive(v);
        return std::find(pieces[p].rays.begin(), pieces[p].rays.end(), pv) != pieces[p].rays.end();
    }
    Q energy(const Vec& g) const { return form(H, g); }
    Mat impact(std::size_t k, const Q& e) const {
        Mat q = eye(c);
        for (std::size_t i = 0; i < c; ++i)
            q[i][k] -= (1 + e) * G[i][k] / G[k][k];
        return q;
    }
    Vec u_plus(const Vec& u, const Vec& gm, const Vec& gp) const {
        const Vec lambda = mul(H, sub(gp, gm));
        const Vec du = mul(M_inv, mul(W, lambda));
        Vec out = u;
        for (std::size_t i = 0; i < n; ++i)
            out[i] += du[i];
        return out;
    }
};

// The obligations, in the SPEC's order (the order of a certificate's "obligations").
inline const std::vector<std::string> kIds = {"fan", "P1", "P2", "P3", "kinematic", "kinetic", "energetic",
                                       "identities", "single-impacts", "nonexpansive", "nonexpansive-lemma",
                                       "outcomes"};

// Whether obligation `id` applies to the law (identities, single-impacts and outcomes need a
// non-empty declaration); read_law has checked that each declaration is an array when present.
bool applies(const Json& law, const std::string& id);

Law read_law(const Json& j, const std::string& path);

} // namespace impactcert_check::detail
