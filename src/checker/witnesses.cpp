// SPDX-License-Identifier: GPL-3.0-or-later
// The Checker's counterexamples (proofs/README.md, "Counterexample shapes" and the witness
// rules): each re-validated from scratch as a point, and required to be the canonical one.
#include "checker.hpp"

#include "copositivity_evidence.hpp"

#include <algorithm>
#include <cstddef>

namespace impactcert_check::detail {

// ---- counterexamples, re-validated from scratch
// A borrowed witness ("via") only where SPEC section 3 allows it: "fan" (S undefined or
// two-valued on an open set) on kinematic, nonexpansive and nonexpansive-lemma; "P1" (a
// discontinuity) on nonexpansive-lemma. Every witness is checked by itself, never by
// consulting the verdict it borrows from.
void Checker::check_witness(const std::string& id, const Json& w, const std::string& wp, bool local) {
    if (!w.is_object())
        malformed(wp, "expected an object");
    const std::string via = w.contains("via") ? str(field(w, wp, "via"), at(wp, "via")) : "";
    if (!via.empty()) {
        const bool allowed = (via == "fan" && (id == "kinematic" || id == "nonexpansive" || id == "nonexpansive-lemma")) ||
                             (via == "P1" && id == "nonexpansive-lemma");
        require(allowed, at(wp, "via"), "a witness of \"" + via + "\" does not refute " + id);
    }
    if (via == "fan") {
        expect_keys(w, wp, {"via", "gamma", "interior_of", "reason"});
        str(field(w, wp, "reason"), at(wp, "reason"));
        require(holds("fan") != Truth::undecided, at(wp, "via"), "the fan is undecided");
        const auto canonical = domain_witness();
        require(canonical.has_value(), at(wp, "via"), "S is a function on R^c: nothing to borrow");
        const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
        // By itself: gamma in no closed cone, or interior to two cones whose images differ.
        const auto inside = law_.interiors(g);
        bool shows = false;
        if (inside.empty()) {
            shows = true;
            for (std::size_t p = 0; p < P(); ++p)
                shows = shows && !law_.in_cone(p, g);
        }
        for (auto a : inside)
            for (auto b : inside)
                shows = shows || mul(pc(a).Q_, g) != mul(pc(b).Q_, g);
        require(shows, at(wp, "gamma"), "S is defined and single-valued near gamma");
        require(w == *canonical, wp, "is not the canonical witness (the first test point where S is not a function)");
        if (id == "kinematic")
            require(local, wp, "a ray's image is negative: that is the canonical witness");
        return;
    }
    if (id == "symmetries") {
        check_symmetries_witness(w, wp);
        return;
    }
    if (id == "coulomb") {
        check_coulomb_witness(w, wp);
        return;
    }
    if (id == "fan") {
        expect_keys(w, wp, {"gamma", "interior_of", "reason"});
        str(field(w, wp, "reason"), at(wp, "reason"));
        const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
        const auto inside = law_.interiors(g);
        bool gap = inside.empty();
        for (std::size_t p = 0; p < P() && gap; ++p)
            gap = !law_.in_cone(p, g);
        require(gap || inside.size() >= 2, at(wp, "gamma"), "is neither in a gap nor in two interiors");
        std::size_t first = 0;
        while (first < fan_cover_.size() && fan_cover_[first] == 1)
            ++first;
        require(first < fan_points_.size() && g == fan_points_[first], at(wp, "gamma"),
                "is not the first test point of the fan check covered k != 1 times");
        const auto listed = listed_names(field(w, wp, "interior_of"), at(wp, "interior_of"));
        std::vector<std::string> names;
        for (auto p : inside)
            names.push_back(name(p));
        require(listed == names, at(wp, "interior_of"), "are not the cones whose interior contains gamma");
        return;
    }
    if (id == "P1" || via == "P1") {
        expect_keys(w, wp, {"piece_a", "piece_b", "gamma", "image_a", "image_b"}, {"via"});
        const std::size_t a = law_.piece(field(w, wp, "piece_a"), at(wp, "piece_a"));
        const std::size_t b = law_.piece(field(w, wp, "piece_b"), at(wp, "piece_b"));
        const Vec v = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        require(v.size() == law_.c && law_.in_cone(a, v) && law_.in_cone(b, v), at(wp, "gamma"),
                "is not in both closed cones");
        expect_vec(w, wp, "image_a", mul(pc(a).Q_, v), "Q_a gamma");
        expect_vec(w, wp, "image_b", mul(pc(b).Q_, v), "Q_b gamma");
        require(mul(pc(a).Q_, v) != mul(pc(b).Q_, v), at(wp, "gamma"), "both pieces agree on it");
        if (via == "P1") {
            require(s_is_a_function(at(wp, "via")), at(wp, "via"), "S is not a function: the canonical witness is the fan's");
            require(holds("P1") == Truth::refuted, at(wp, "via"), "P1 is not refuted");
            Json own = w;
            own.erase("via");
            require(own == field(obl_[1], "$.obligations[1]", "counterexample"), wp, "is not P1's counterexample");
            return;
        }
        // Canonical: the failing entry that ends P1's evidence (whose keys evidence() has
        // checked; which list it is follows from the law, not from the keys present).
        if (!face_to_face() && !field(obl_[1], "$.obligations[1]", "data").contains("shared")) {
            const Json& e = last_entry("P1", "intersections");
            require(e.at("piece_a") == w.at("piece_a") && e.at("piece_b") == w.at("piece_b"), wp,
                    "is not the first pair that fails");
            Vec first;
            for (const auto& r : intersection_rays(a, b))
                if (first.empty() && mul(pc(a).Q_, r) != mul(pc(b).Q_, r))
                    first = r;
            require(v == first, at(wp, "gamma"), "is not the first extreme ray where the pieces differ");
        } else {
            const Json& e = last_entry("P1", "shared");
            require(e.at("piece_a") == w.at("piece_a") && e.at("piece_b") == w.at("piece_b") &&
                        e.at("ray") == w.at("gamma"),
                    wp, "is not the first shared ray where the pieces differ");
        }
        return;
    }
    if (id == "nonexpansive" || id == "nonexpansive-lemma") {
        const bool across = id == "nonexpansive" && w.contains("discontinuity");
        if (across)
            expect_keys(w, wp, {"piece_a", "piece_b", "gamma_a", "gamma_b", "lhs", "rhs", "discontinuity"});
        else
            expect_keys(w, wp, {"piece_a", "piece_b", "gamma_a", "gamma_b", "lhs", "rhs"});
        const std::size_t a = law_.piece(field(w, wp, "piece_a"), at(wp, "piece_a"));
        const std::size_t b = law_.piece(field(w, wp, "piece_b"), at(wp, "piece_b"));
        const Vec ga = vec(field(w, wp, "gamma_a"), at(wp, "gamma_a"));
        const Vec gb = vec(field(w, wp, "gamma_b"), at(wp, "gamma_b"));
        require(ga.size() == law_.c && gb.size() == law_.c, wp, "wrong size");
        require(law_.in_interior(a, ga), at(wp, "gamma_a"), "not in the interior of piece_a's cone");
        require(law_.in_interior(b, gb), at(wp, "gamma_b"), "not in the interior of piece_b's cone");
        const Q lhs = law_.energy(sub(mul(pc(a).Q_, ga), mul(pc(b).Q_, gb)));
        const Q rhs = law_.energy(sub(ga, gb));
        require(rat(field(w, wp, "lhs"), at(wp, "lhs")) == lhs, at(wp, "lhs"), "is not |S(a) - S(b)|_H^2");
        require(rat(field(w, wp, "rhs"), at(wp, "rhs")) == rhs, at(wp, "rhs"), "is not |a - b|_H^2");
        require(lhs > rhs, wp, "lhs <= rhs: not a violation");
        Vec ca, cb;
        if (id == "nonexpansive" && holds("P1") == Truth::refuted) {
            if (holds("fan") != Truth::undecided)
                require(!domain_witness(), wp, "S is not a function: the canonical witness is the fan's");
            // Near P1's ray v: v + eps R 1 in each cone, the first eps = 1/2, 1/4, ... that
            // violates the claim (proofs/README.md, Lemma D); P1's witness has been checked.
            require(across, wp, "P1 is refuted: the canonical witness lies across its discontinuity");
            const Json& p1w = field(obl_[1], "$.obligations[1]", "counterexample");
            require(p1w.at("piece_a") == w.at("piece_a") && p1w.at("piece_b") == w.at("piece_b"), wp,
                    "are not the pieces of P1's counterexample");
            const Vec v = vec(p1w.at("gamma"), "$.obligations[1].counterexample.gamma");
            expect_vec(w, wp, "discontinuity", v, "P1's ray");
            // The first k >= 1 with A 4^k + B 2^k + C > 0, where lhs - rhs at eps = 2^-k is
            // A + B eps + C eps^2 (A = |D|^2, B = 2 D.H delta, C = |delta|^2 - |rho|^2), in integers.
            const Vec da = mul(pc(a).R, Vec(law_.c, Q(1))), db = mul(pc(b).R, Vec(law_.c, Q(1)));
            const Vec D = sub(mul(pc(a).Q_, v), mul(pc(b).Q_, v));
            const Vec delta = sub(mul(pc(a).Q_, da), mul(pc(b).Q_, db)), rho = sub(da, db);
            const Q A = law_.energy(D), C = law_.energy(delta) - law_.energy(rho);
            Q B = 0;
            const Vec Hdelta = mul(law_.H, delta);
            for (std::size_t k = 0; k < law_.c; ++k)
                B += 2 * D[k] * Hdelta[k];
            require(sgn(A) > 0, at(wp, "discontinuity"), "the pieces agree on P1's ray");
            mpz_class L = 1;
            for (const Q* x : std::initializer_list<const Q*>{&A, &B, &C})
                mpz_lcm(L.get_mpz_t(), L.get_mpz_t(), x->get_den_mpz_t());
            const mpz_class ia = L / A.get_den() * A.get_num(), ib = L / B.get_den() * B.get_num(),
                            ic = L / C.get_den() * C.get_num();
            std::size_t k = 1;
            for (mpz_class value, term;; ++k) {
                mpz_mul_2exp(value.get_mpz_t(), ia.get_mpz_t(), 2 * k);
                mpz_mul_2exp(term.get_mpz_t(), ib.get_mpz_t(), k);
                value += term + ic;
                if (sgn(value) > 0)
                    break;
            }
            Q eps = 1;
            mpz_mul_2exp(eps.get_den_mpz_t(), eps.get_den_mpz_t(), k); // 1 / 2^k
            ca = v;
            cb = v;
            for (std::size_t i = 0; i < law_.c; ++i) {
                ca[i] += eps * da[i];
                cb[i] += eps * db[i];
            }
        } else if (id == "nonexpansive") {
            require(!across, at(wp, "discontinuity"), "P1 is not refuted");
            if (holds("fan") != Truth::undecided)
                require(!domain_witness(), wp, "S is not a function: the canonical witness is the fan's");
            const Json& entry = pair_entry_ ? *pair_entry_ : last_entry("nonexpansive", "pairs");
            require(entry.at("piece_a") == w.at("piece_a") && entry.at("piece_b") == w.at("piece_b"), wp,
                    "is not the first pair that fails");
            const Mat A = pair_form(a, b);
            const Vec z = moved_inside(A, kkt_minimiser(entry.at("certificate"), wp, 2 * law_.c), wp);
            ca = mul(pc(a).R, Vec(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(law_.c)));
            cb = mul(pc(b).R, Vec(z.begin() + static_cast<std::ptrdiff_t>(law_.c), z.end()));
        } else {
            require(s_is_a_function(wp) && holds("P1") == Truth::proved, wp,
                    "S is not a continuous function: the canonical witness is borrowed");
            require(a == b, wp, "the lemma's witness lies in one cone");
            const std::size_t lemma = index_of("nonexpansive-lemma");
            const Json& data = field(obl_[lemma], at("$.obligations", lemma), "data");
            const std::size_t listed = data.is_object() && data.contains("pieces") ? data.at("pieces").size() : 0;
            const auto ps = firsts();
            require(listed < ps.size() && a == ps[listed], at(wp, "piece_a"), "is not the first piece that fails");
            const auto x = psd_witness(sub(law_.H, QtHQ(a)));
            require(x.has_value(), at(wp, "piece_a"), "H - Q^T H Q is PSD for this piece");
            const Vec centre = mul(pc(a).R, Vec(law_.c, Q(1)));
            Q spread = 1;
            for (const auto& coeff : mul(pc(a).R_inv, *x))
                spread = std::max(spread, Q(abs(coeff) + 1));
            const Q eps = 1 / (2 * spread);
            ca = centre;
            for (std::size_t i = 0; i < law_.c; ++i)
                ca[i] += eps * (*x)[i];
            cb = centre;
        }
        require(ga == ca && gb == cb, wp, "is not the canonical witness");
        return;
    }
    if (id == "P2" || id == "energetic") {
        expect_keys(w, wp, {"piece", "gamma", "lhs", "rhs"});
        const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
        const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
        Vec canonical;
        if (id == "P2") {
            const Json& data = field(obl_[2], "$.obligations[2]", "data");
            const std::size_t listed = field(data, "$.obligations[2].data", "QtHQ").size();
            const auto ps = firsts();
            require(listed >= 1 && listed <= ps.size() && p == ps[listed - 1], at(wp, "piece"),
                    "is not the first piece that fails");
            const Mat D = sub(QtHQ(p), law_.H);
            for (std::size_t k = 0; k < law_.c && canonical.empty(); ++k)
                if (sgn(D[k][k]) != 0) {
                    canonical.assign(law_.c, Q(0));
                    canonical[k] = 1;
                }
            for (std::size_t k = 0; k < law_.c && canonical.empty(); ++k)
                for (std::size_t l = k + 1; l < law_.c && canonical.empty(); ++l)
                    if (sgn(D[k][l]) != 0) {
                        canonical.assign(law_.c, Q(0));
                        canonical[k] = canonical[l] = 1;
                    }
        } else {
            const Json& entry = last_entry("energetic", "pieces");
            require(entry.at("piece") == w.at("piece"), at(wp, "piece"), "is not the first piece that fails");
            canonical = mul(pc(p).R, kkt_minimiser(entry.at("certificate"), wp, law_.c));
        }
        require(g == canonical, at(wp, "gamma"), "is not the canonical witness");
        const Q lhs = law_.energy(mul(pc(p).Q_, g)), rhs = law_.energy(g);
        require(rat(field(w, wp, "lhs"), at(wp, "lhs")) == lhs, at(wp, "lhs"), "is not |Q gamma|_H^2");
        require(rat(field(w, wp, "rhs"), at(wp, "rhs")) == rhs, at(wp, "rhs"), "is not |gamma|_H^2");
        if (id == "P2")
            require(lhs != rhs, wp, "energy is conserved at gamma");
        else
            require(law_.in_cone(p, g) && lhs > rhs, wp, "not an energy increase inside the cone");
        return;
    }
    if (id == "P3" || id == "kinematic" || id == "kinetic") {
        if (id == "P3") {
            expect_keys(w, wp, {"piece", "ray", "image", "reason"});
            str(field(w, wp, "reason"), at(wp, "reason"));
        } else {
            expect_keys(w, wp, {"piece", "ray", id == "kinetic" ? "impulse" : "image"});
        }
        const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
        const Vec r = vec(field(w, wp, "ray"), at(wp, "ray"));
        require(r.size() == law_.c && law_.is_ray_of(p, r), at(wp, "ray"), "is not a ray of the piece");
        const Vec img = mul(pc(p).Q_, r);
        if (id == "kinetic") {
            const Vec impulse = law_.impulse_at(p, r);
            expect_vec(w, wp, "impulse", impulse, law_.redundant ? "L ray" : "H (Q - I) ray");
            require(!law_.impulse_admissible(impulse) || !law_.impulse_consistent(p, r), at(wp, "ray"),
                    law_.tangents.empty() ? "impulse is non-negative" : "impulse is in the friction cone");
            return;
        }
        if (id == "kinematic") {
            const Vec all = law_.all_coordinates(img);
            expect_vec(w, wp, "image", all, law_.redundant ? "C^T Q ray" : "Q ray");
            require(!law_.normals_nonneg(all), at(wp, "ray"), "image is non-negative");
            return;
        }
        expect_vec(w, wp, "image", img, "Q ray"); // P3
        std::size_t nz = 0;
        for (const auto& x : img)
            nz += sgn(x) != 0 ? 1 : 0;
        bool clash = false;
        for (const auto& other : pc(p).rays)
            clash = clash || (other != primitive(r) && primitive(mul(pc(p).Q_, other)) == primitive(img));
        require(nz != 1 || !nonneg(img) || clash, at(wp, "ray"), "maps onto a positive axis of its own");
        return;
    }
    if (id == "identities") {
        expect_keys(w, wp, {"identity", "lhs", "product", "gamma", "lhs_image", "product_image"});
        const std::size_t i = natural(field(w, wp, "identity"), at(wp, "identity"));
        require(i < law_.identities.size(), at(wp, "identity"), "no such identity");
        const Identity& d = law_.identities[i];
        require(field(w, wp, "lhs") == d.lhs_json && field(w, wp, "product") == d.product_json, wp, "is not that identity");
        const Vec e = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        require(e.size() == law_.c, at(wp, "gamma"), "wrong size");
        const Vec rhs = mul(identity_product(i), e);
        const Vec lhs = mul(pc(d.lhs).Q_, e);
        expect_vec(w, wp, "lhs_image", lhs, "Q_lhs gamma");
        expect_vec(w, wp, "product_image", rhs, "the product applied to gamma");
        require(lhs != rhs, at(wp, "gamma"), "both sides agree on it");
        return;
    }
    if (id == "single-impacts") {
        expect_keys(w, wp, {"piece", "contact", "restitution", "gamma", "piece_image", "impact_image"});
        const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
        const std::size_t k = natural(field(w, wp, "contact"), at(wp, "contact"));
        const Q e = rat(field(w, wp, "restitution"), at(wp, "restitution"));
        bool declared = false;
        for (const auto& d : law_.single_impacts)
            declared = declared || (d.piece == p && d.contact == k && d.restitution == e);
        require(declared, wp, "is not a declared single impact");
        const Vec g = vec(field(w, wp, "gamma"), at(wp, "gamma"));
        require(g.size() == law_.c, at(wp, "gamma"), "wrong size");
        const Vec piece_image = mul(pc(p).Q_, g), impact_image = mul(law_.impact(k - 1, e), g);
        expect_vec(w, wp, "piece_image", piece_image, "Q gamma");
        expect_vec(w, wp, "impact_image", impact_image, "Q^(k)(e) gamma");
        require(piece_image != impact_image, at(wp, "gamma"), "the piece and the impact agree on it");
        return;
    }
    if (id == "outcomes") {
        if (w.contains("piece"))
            expect_keys(w, wp, {"outcome", "u_minus", "u_plus_declared", "piece", "u_plus", "pieces_at_gamma"});
        else
            expect_keys(w, wp, {"outcome", "u_minus", "gamma_minus", "reason"});
        const std::string oname = str(field(w, wp, "outcome"), at(wp, "outcome"));
        const OutcomeDecl* decl = nullptr;
        for (const auto& d : law_.outcomes)
            if (d.name == oname)
                decl = &d;
        require(decl != nullptr, at(wp, "outcome"), "no such outcome");
        const Vec& u = decl->u_minus;
        const Vec g = mul(tr(law_.W), u);
        expect_vec(w, wp, "u_minus", u, "the outcome's u-");
        if (!w.contains("piece")) {
            str(field(w, wp, "reason"), at(wp, "reason"));
            expect_vec(w, wp, "gamma_minus", g, "W^T u-");
            for (std::size_t p = 0; p < P(); ++p)
                require(!law_.in_cone(p, g), wp, "gamma- lies in a cone");
            return;
        }
        expect_vec(w, wp, "u_plus_declared", decl->u_plus, "the declared u+");
        const std::size_t p = law_.piece(field(w, wp, "piece"), at(wp, "piece"));
        require(law_.in_cone(p, g), at(wp, "piece"), "gamma- is not in this piece's cone");
        const Vec up = law_.u_plus(u, g, mul(pc(p).Q_, g));
        expect_vec(w, wp, "u_plus", up, "the piece's post-impact velocities");
        require(up != decl->u_plus, at(wp, "piece"), "gives the declared u+");
        require(!check_outcome_pieces(field(w, wp, "pieces_at_gamma"), at(wp, "pieces_at_gamma"), u, g, decl->u_plus),
                at(wp, "pieces_at_gamma"), "all give the declared u+");
        return;
    }
    malformed(wp, "unknown obligation");
}

} // namespace impactcert_check::detail
