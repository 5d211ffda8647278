// SPDX-License-Identifier: GPL-3.0-or-later
// The Checker's symmetries (proofs/README.md, "Symmetries"): each declared (P, P') re-decided
// from the law (P^T H P = H, P'^T H P' = H, P C_i = C_sigma(i) by primitive rays,
// Q_sigma(i) P r = P' Q_i r on the rays of C_i), the orbits of pieces under the group the
// permutations generate (least piece of each), the canonical witness of a failure, and the
// evidence of the obligation. The other obligations take their reduced lists from firsts().
#include "checker.hpp"

#include <numeric>

namespace impactcert_check::detail {

namespace {

Json jvec(const Vec& v) {
    Json a = Json::array();
    for (const auto& x : v)
        a.push_back(x.get_str());
    return a;
}

Json jmat(const Mat& m) {
    Json a = Json::array();
    for (const auto& row : m)
        a.push_back(jvec(row));
    return a;
}

} // namespace

const Checker::SymmetryCheck& Checker::symmetry_check() {
    if (sym_)
        return *sym_;
    SymmetryCheck s;
    const std::size_t c = law_.c;
    std::map<std::vector<std::size_t>, std::size_t> by_rays;
    for (std::size_t p = 0; p < P(); ++p) {
        std::vector<std::size_t> ids;
        for (const auto& r : pc(p).rays)
            ids.push_back(ray_id(r));
        std::sort(ids.begin(), ids.end());
        by_rays.emplace(ids, p);
    }
    for (std::size_t g = 0; g < law_.symmetries.size() && s.witness.is_null(); ++g) {
        const Symmetry& sym = law_.symmetries[g];
        Json evidence = Json::object();
        evidence["symmetry"] = sym.name;
        for (const char* which : {"P", "P_prime"}) {
            const Mat& m = std::string(which) == "P" ? sym.P : sym.P_prime;
            const Mat mtHm = mul(mul(tr(m), law_.H), m);
            evidence[std::string(which) == "P" ? "PtHP" : "P_primetHP_prime"] = jmat(mtHm);
            // The first of e_k, then e_k + e_l (k < l), along which |m x|_H != |x|_H.
            const Mat D = sub(mtHm, law_.H);
            Vec x;
            for (std::size_t k = 0; k < c && x.empty(); ++k)
                if (sgn(D[k][k]) != 0) {
                    x = Vec(c, 0);
                    x[k] = 1;
                }
            for (std::size_t k = 0; k < c && x.empty(); ++k)
                for (std::size_t l = k + 1; l < c && x.empty(); ++l)
                    if (sgn(D[k][l]) != 0) {
                        x = Vec(c, 0);
                        x[k] = x[l] = 1;
                    }
            if (x.empty())
                continue;
            s.witness = Json{{"symmetry", sym.name}, {"matrix", which}, {"gamma", jvec(x)},
                             {"lhs", law_.energy(mul(m, x)).get_str()}, {"rhs", law_.energy(x).get_str()}};
            break;
        }
        if (!s.witness.is_null()) {
            s.failing = g;
            break;
        }
        std::vector<std::size_t> sigma(P());
        for (std::size_t p = 0; p < P() && s.witness.is_null(); ++p) {
            std::vector<Vec> image, Pr; // primitive images, and P r itself (for (iii))
            std::vector<std::size_t> ids;
            bool known = true;
            for (const auto& r : pc(p).rays) {
                Pr.push_back(mul(sym.P, r));
                image.push_back(primitive(Pr.back()));
                const auto it = law_.ray_index.find(image.back());
                known = known && it != law_.ray_index.end();
                ids.push_back(known ? it->second : 0);
            }
            std::sort(ids.begin(), ids.end());
            const auto found = known ? by_rays.find(ids) : by_rays.end();
            if (found == by_rays.end()) {
                Json rays = Json::array();
                for (const auto& r : image)
                    rays.push_back(jvec(r));
                s.witness = Json{{"symmetry", sym.name}, {"piece", name(p)}, {"image_rays", rays}};
                break;
            }
            const std::size_t q = found->second;
            sigma[p] = q;
            for (std::size_t k = 0; k < pc(p).rays.size(); ++k) {
                const Vec& r = pc(p).rays[k];
                const Vec lhs = mul(pc(q).Q_, Pr[k]), rhs = mul(sym.P_prime, mul(pc(p).Q_, r));
                if (lhs != rhs) {
                    s.witness = Json{{"symmetry", sym.name}, {"piece", name(p)}, {"image_piece", name(q)},
                                     {"gamma", jvec(r)}, {"lhs", jvec(lhs)}, {"rhs", jvec(rhs)}};
                    break;
                }
            }
        }
        if (!s.witness.is_null()) {
            s.failing = g;
            break;
        }
        Json perm = Json::array();
        for (auto q : sigma)
            perm.push_back(q);
        evidence["permutation"] = std::move(perm);
        s.evidence.push_back(std::move(evidence));
        s.sigma.push_back(std::move(sigma));
    }
    if (s.witness.is_null() && !law_.symmetries.empty()) {
        std::vector<std::size_t> parent(P());
        std::iota(parent.begin(), parent.end(), std::size_t{0});
        auto find = [&](std::size_t x) {
            while (parent[x] != x)
                x = parent[x] = parent[parent[x]];
            return x;
        };
        for (const auto& sigma : s.sigma)
            for (std::size_t p = 0; p < P(); ++p) {
                const std::size_t a = find(p), b = find(sigma[p]);
                if (a != b)
                    parent[std::max(a, b)] = std::min(a, b);
            }
        for (std::size_t p = 0; p < P(); ++p)
            if (find(p) == p)
                s.representatives.push_back(p);
        s.hold = true;
    }
    sym_ = std::move(s);
    return *sym_;
}

std::vector<std::size_t> Checker::firsts() {
    const SymmetryCheck& s = symmetry_check();
    if (s.hold)
        return s.representatives;
    std::vector<std::size_t> all(P());
    std::iota(all.begin(), all.end(), std::size_t{0});
    return all;
}

std::vector<std::size_t> Checker::orthant_firsts() {
    // Every P' a non-negative monomial matrix (one non-zero entry, positive, per row and
    // column): then P' maps the orthant onto itself and P3, kinematic reduce to one piece per orbit.
    bool keeps = symmetry_check().hold;
    for (const Symmetry& sym : law_.symmetries)
        for (std::size_t r = 0; r < law_.c && keeps; ++r) {
            std::size_t in_row = 0, in_column = 0;
            for (std::size_t k = 0; k < law_.c; ++k) {
                keeps = keeps && sgn(sym.P_prime[r][k]) >= 0 && sgn(sym.P_prime[k][r]) >= 0;
                in_row += sgn(sym.P_prime[r][k]) != 0 ? 1 : 0;
                in_column += sgn(sym.P_prime[k][r]) != 0 ? 1 : 0;
            }
            keeps = keeps && in_row == 1 && in_column == 1;
        }
    if (keeps)
        return symmetry_check().representatives;
    std::vector<std::size_t> all(P());
    std::iota(all.begin(), all.end(), std::size_t{0});
    return all;
}

bool Checker::symmetries_evidence(const Json& data, const std::string& dp) {
    const SymmetryCheck& s = symmetry_check();
    if (s.hold)
        expect_keys(data, dp, {"symmetries", "orbit_representatives"});
    else
        expect_keys(data, dp, {}, {"symmetries"});
    const Json& l = data.contains("symmetries") ? list(data, dp, "symmetries") : Json::array();
    // Every symmetry before the first failing one, in order, each exactly as recomputed.
    require(l.size() == s.evidence.size(), at(dp, "symmetries"),
            s.hold ? "is incomplete" : "must list the symmetries before the first that fails, and only those");
    for (std::size_t g = 0; g < l.size(); ++g) {
        // Indices are JSON integers ("1.0" compares equal to 1 in JSON, but is malformed here).
        const std::string gp = at(at(dp, "symmetries"), g);
        if (l[g].is_object() && l[g].contains("permutation") && l[g].at("permutation").is_array())
            for (std::size_t k = 0; k < l[g].at("permutation").size(); ++k)
                natural(l[g].at("permutation")[k], at(at(gp, "permutation"), k));
        require(l[g] == s.evidence[g], gp, "is not the symmetry's P^T H P, P'^T H P' and permutation of the pieces");
    }
    if (s.hold) {
        std::vector<std::string> names;
        for (auto p : s.representatives)
            names.push_back(name(p));
        require(listed_names(field(data, dp, "orbit_representatives"), at(dp, "orbit_representatives")) == names,
                at(dp, "orbit_representatives"), "are not the least pieces of the orbits");
    }
    return s.hold;
}

void Checker::check_symmetries_witness(const Json& w, const std::string& wp) {
    const SymmetryCheck& s = symmetry_check();
    require(!s.hold, wp, "every symmetry holds");
    // The canonical witness was recomputed from the law: each of its shapes shows the claim
    // false by itself (a point where |P x|_H != |x|_H; an image cone that is no piece's; a ray
    // where Q_sigma(i) P r != P' Q_i r).
    require(w == s.witness, wp, "is not the first failure of the first symmetry that fails");
}

} // namespace impactcert_check::detail
