// SPDX-License-Identifier: GPL-3.0-or-later
// The Checker's verdicts (holds), the limits an obligation can stop at, and the evidence of
// each obligation (proofs/README.md, "What the checker establishes", 2-4): every listed entry
// recomputed from the law, lists canonical (in order, ending at the first failing entry).
#include "checker.hpp"
#include "copositivity_evidence.hpp"
#include "tiling.hpp"

#include <algorithm>
#include <cstdint>
#include <exception>
#include <functional>
#include <numeric>
#include <new>
#include <thread>

namespace impactcert_check::detail {

// A block beyond the merged certificate's first failure (ExtraBlock): its entries are the pairs
// first, first + 1, ... of the single run's order, each checked by itself; the block is whole
// unless it ends at a failing pair (then its counterexample must be that pair's canonical one) or
// at a limit the prover can stop at.
void Checker::check_extra_block(const ExtraBlock& x) {
    const auto ps = firsts();
    const std::size_t total = ps.size() * P();
    require(x.first < total, at(x.path, "block"), "lies beyond the last pair");
    bool failed = false;
    std::size_t listed = 0;
    if (x.pairs) {
        const Json& l = *x.pairs;
        if (!l.is_array())
            malformed(at(x.path, "pairs"), "expected an array");
        listed = l.size();
        require(listed <= x.block_pairs && x.first + listed <= total, at(x.path, "pairs"), "more entries than the block has pairs");
        for (std::size_t t = 0; t < listed; ++t) {
            const std::size_t k = x.first + t;
            const std::size_t i = ps[k / P()], j = k % P();
            const std::string ep = at(at(x.path, "pairs"), t);
            require(!failed, ep, "follows a failing pair");
            expect_keys(l[t], ep, {"piece_a", "piece_b", "certificate"});
            expect_piece(l[t], ep, "piece_a", i);
            expect_piece(l[t], ep, "piece_b", j);
            failed = !check_copositive_evidence(pair_form(i, j), field(l[t], ep, "certificate"), at(ep, "certificate"),
                                                limits_.max_faces);
        }
    }
    if (x.counterexample) {
        require(x.pairs && failed, at(x.path, "counterexample"), "follows no failing pair of the block");
        pair_entry_ = &x.pairs->back();
        struct Reset {
            const Json*& p;
            ~Reset() { p = nullptr; }
        } reset{pair_entry_};
        check_witness("nonexpansive", *x.counterexample, at(x.path, "counterexample"), false);
    } else {
        require(!failed, at(x.path, "pairs"), "a pair fails, and the block shows no counterexample");
    }
    if (x.limit) {
        if (!x.limit->is_string())
            malformed(at(x.path, "limit"), "expected a string");
        could_be_undecided("nonexpansive", x.limit->get<std::string>(), at(x.path, "limit"));
    }
    if (x.pairs && !x.counterexample && !x.limit)
        require(listed == std::min(x.block_pairs, total - x.first), at(x.path, "pairs"),
                "the block is neither whole nor ended by a failure or a limit");
}

Checker::Truth Checker::holds(std::size_t k) {
    if (auto it = decided_.find(ids_of(law_)[k]); it != decided_.end())
        return it->second;
    // check() has validated the obligation's keys, and visits obligations in order: the
    // only ones reached from here out of order (fan, P1) come first.
    const Json& o = obl_[k];
    const std::string path = at("$.obligations", k);
    const std::string verdict = str(field(o, path, "verdict"), at(path, "verdict"));
    const Json& data = field(o, path, "data");
    if (!data.is_object())
        malformed(at(path, "data"), "expected an object");
    Truth truth;
    if (verdict == "undecided") {
        // A limit was reached: nothing is claimed, so nothing is checked but the shape, and
        // that the prover could have stopped there.
        require(data.empty(), at(path, "data"), "an undecided obligation carries no evidence");
        could_be_undecided(ids_of(law_)[k], str(field(o, path, "limit"), at(path, "limit")), at(path, "limit"));
        truth = Truth::undecided;
    } else {
        require(!o.contains("limit"), at(path, "limit"), "only an undecided obligation names a limit");
        // Every listed piece of evidence must be right, whatever the verdict.
        const bool local = evidence(ids_of(law_)[k], data, at(path, "data"));
        if (verdict == "refuted") {
            check_witness(ids_of(law_)[k], field(o, path, "counterexample"), at(path, "counterexample"), local);
            truth = Truth::refuted;
        } else if (verdict == "proved") {
            bool follows = local;
            if (ids_of(law_)[k] == "kinematic" || ids_of(law_)[k] == "nonexpansive" || ids_of(law_)[k] == "nonexpansive-lemma")
                follows = follows && s_is_a_function(path);
            if (ids_of(law_)[k] == "nonexpansive-lemma")
                follows = follows && holds("P1") == Truth::proved;
            require(follows, at(path, "verdict"), "\"proved\" does not follow from the evidence");
            truth = Truth::proved;
        } else {
            malformed(at(path, "verdict"), "unknown verdict");
        }
    }
    decided_[ids_of(law_)[k]] = truth;
    return truth;
}

// Whether the prover can have left obligation `id` undecided with this `limit` text. In the
// prover (src/prover/obligations/) only three decisions throw LimitExceeded: the fan's chamber
// enumeration (--max-chambers), P1's intersections (--max-subsets) and a KKT enumeration
// (--max-faces). So: fan by --max-chambers; P1 by --max-subsets (a fan beyond its limit only
// sends P1 to the intersections); kinematic by the fan's limit once every ray's image is
// non-negative; energetic by --max-faces, and coulomb with friction polygons (a polygon form's
// KKT enumeration) once the friction cone and Lemma F hold; nonexpansive by --max-faces, or by the fan's limit;
// nonexpansive-lemma by the fan's limit or, once S is a function, P1's. P2, P3, kinetic,
// identities, single-impacts and outcomes have no limit, so a refutation cannot hide there.
void Checker::could_be_undecided(const std::string& id, const std::string& limit, const std::string& path) {
    std::vector<std::string> options;
    if (id == "fan" || id == "kinematic")
        options = {"--max-chambers"};
    else if (id == "P1")
        options = {"--max-subsets"};
    else if (id == "energetic" || (id == "coulomb" && law_.has_polygons()))
        options = {"--max-faces"};
    else if (id == "nonexpansive")
        options = {"--max-faces", "--max-chambers"};
    else if (id == "nonexpansive-lemma")
        options = {"--max-chambers", "--max-subsets"};
    require(!options.empty(), path, "the prover decides " + id + " without a limit: it cannot be undecided");
    std::string option, expected;
    for (const auto& o : options) {
        const std::string tail = " (raise it with " + o + ")";
        if (limit.size() > tail.size() && limit.compare(limit.size() - tail.size(), tail.size(), tail) == 0)
            option = o;
        expected += (expected.empty() ? "" : " or ") + o;
    }
    require(!option.empty(), path, "names no limit that can stop " + id + " (expected \"... (raise it with " + expected + ")\")");
    if (id == "fan")
        require(law_.c != 2 && !facet_criterion() && !walls_tile() && !gap_point(), path,
                "the fan is decided without enumerating chambers");
    else if (option == "--max-chambers")
        require(holds("fan") == Truth::undecided, path, "the fan is not undecided");
    if (id == "kinematic")
        for (std::size_t p = 0; p < P(); ++p)
            for (const auto& r : pc(p).rays)
                require(law_.normals_nonneg(law_.all_coordinates(mul(pc(p).Q_, r))), path,
                        "a ray's image is negative: the prover refutes kinematic before it needs the fan");
    if (id == "coulomb")
        require(!first_coulomb_failure(), path,
                "the friction cone or Lemma F fails: the prover refutes coulomb before it needs a polygon form");
    if (id == "P1") {
        require(!face_to_face(), path, "the cones meet face to face: P1 is decided on shared rays, without a limit");
        require(!first_differing_shared_ray(), path, "two pieces differ on a shared ray: P1 is refuted without a limit");
    }
    if (id == "nonexpansive" && option == "--max-faces" && holds("fan") != Truth::undecided)
        require(!domain_witness(), path, "S is not a function: the prover refutes nonexpansive by the domain witness");
    if (id == "nonexpansive")
        require(holds("P1") != Truth::refuted, path, "P1 is refuted: the prover refutes nonexpansive near its discontinuity");
    if (id == "nonexpansive-lemma" && option == "--max-subsets")
        require(holds("fan") != Truth::undecided && !domain_witness() && holds("P1") == Truth::undecided, path,
                "P1 is decided, or S is not a function: the lemma does not stop at P1's limit");
}

// ---- evidence: checks each listed entry; returns true when the list is complete and the
// obligation holds on it.
bool Checker::evidence(const std::string& id, const Json& data, const std::string& dp) {
    const std::size_t c = law_.c;
    if (id == "fan") {
        if (law_.c == 2) {
            expect_keys(data, dp, {"rays_by_angle", "sector_points"});
            return fan_planar(data, dp);
        }
        if (facet_criterion()) {
            expect_keys(data, dp, {"facets", "generic_point"});
            return fan_facets(data, dp);
        }
        if (walls_tile()) {
            expect_keys(data, dp, {"hyperplanes", "generic_point"});
            const std::vector<Vec> planes = facet_hyperplanes();
            require(listed_rays(field(data, dp, "hyperplanes"), at(dp, "hyperplanes")) == planes, at(dp, "hyperplanes"),
                    "are not the facet hyperplanes (canonical normals, sorted)");
            const Vec x0 = vec(field(data, dp, "generic_point"), at(dp, "generic_point"));
            require(x0 == first_generic(planes, law_.c), at(dp, "generic_point"),
                    "is not the first point of the moment curve off every facet hyperplane");
            require(law_.interiors(x0).size() == 1, at(dp, "generic_point"), "is not covered once");
            fan_points_ = {x0};
            fan_cover_ = {1};
            return true;
        }
        if (const auto gap = gap_point()) {
            expect_keys(data, dp, {"facet", "gap_point"});
            const std::string fp = at(dp, "facet");
            const Json& facet = field(data, dp, "facet");
            expect_keys(facet, fp, {"rays", "pieces"});
            require(listed_rays(field(facet, fp, "rays"), at(fp, "rays")) == facet_rays(gap->ids), at(fp, "rays"),
                    "is not the first facet with one cone and a gap beside it");
            require(listed_names(field(facet, fp, "pieces"), at(fp, "pieces")) == std::vector<std::string>{name(gap->piece)},
                    at(fp, "pieces"), "is not the facet's one cone");
            require(vec(field(data, dp, "gap_point"), at(dp, "gap_point")) == gap->point, at(dp, "gap_point"),
                    "is not 2 (the sum of the facet's rays) - (the cone's other ray)");
            fan_points_ = {gap->point};
            fan_cover_ = {0};
            return false;
        }
        expect_keys(data, dp, {"hyperplanes", "chamber_points"});
        return fan_chambers(data, dp);
    }
    if (id == "P1" && !face_to_face() && !data.contains("shared")) {
        // The shared rays come first: the intersections are P1's evidence only when every
        // shared ray agrees.
        expect_keys(data, dp, {"intersections"});
        require(!first_differing_shared_ray(), at(dp, "intersections"),
                "two pieces differ on a shared ray: that is P1's canonical witness");
        return p1_intersections(data, dp);
    }
    if (id == "P1") {
        expect_keys(data, dp, {}, {"shared"});
        const Json& l = data.contains("shared") ? list(data, dp, "shared") : Json::array();
        // One more than listed: enough to tell a complete list from an incomplete one.
        const auto shared = shared_rays(l.size() + 1);
        require(l.size() <= shared.size(), at(dp, "shared"), "lists more rays than are shared");
        bool ok = true;
        for (std::size_t k = 0; k < l.size(); ++k) {
            const auto& [i, j, v] = shared[k];
            const std::string ep = at(at(dp, "shared"), k);
            expect_keys(l[k], ep, {"piece_a", "piece_b", "ray", "image_a", "image_b"});
            expect_piece(l[k], ep, "piece_a", i);
            expect_piece(l[k], ep, "piece_b", j);
            expect_vec(l[k], ep, "ray", v, "the shared ray");
            expect_vec(l[k], ep, "image_a", mul(pc(i).Q_, v), "Q_a ray");
            expect_vec(l[k], ep, "image_b", mul(pc(j).Q_, v), "Q_b ray");
            const bool this_ok = mul(pc(i).Q_, v) == mul(pc(j).Q_, v);
            ends_at_first_failure(this_ok, k, l.size(), at(dp, "shared"));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), shared.size(), at(dp, "shared"));
        require(face_to_face() || !ok, at(dp, "shared"),
                "the cones do not meet face to face: agreeing shared rays are not P1's evidence");
        return ok;
    }
    if (id == "P2") {
        expect_keys(data, dp, {"QtHQ"});
        const Json& l = list(data, dp, "QtHQ");
        const auto ps = firsts(); // one piece per orbit when the symmetries hold
        require(l.size() <= ps.size(), at(dp, "QtHQ"), "too many entries");
        bool ok = true;
        for (std::size_t k = 0; k < l.size(); ++k) {
            const std::size_t p = ps[k];
            const std::string ep = at(at(dp, "QtHQ"), k);
            expect_keys(l[k], ep, {"piece", "matrix"});
            expect_piece(l[k], ep, "piece", p);
            const Mat m = QtHQ(p);
            expect_mat(l[k], ep, "matrix", m, "Q^T H Q");
            const bool this_ok = m == law_.H;
            ends_at_first_failure(this_ok, k, l.size(), at(dp, "QtHQ"));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), ps.size(), at(dp, "QtHQ"));
        return ok;
    }
    if (id == "P3" || id == "kinematic" || id == "kinetic") {
        const char* key = id == "kinetic" ? "impulses" : "images";
        const char* value = id == "kinetic" ? "impulse" : "image";
        expect_keys(data, dp, {key});
        const Json& l = list(data, dp, key);
        // kinetic: every piece; P3 and kinematic: one per orbit when the symmetries allow it.
        std::vector<std::size_t> ps(P());
        std::iota(ps.begin(), ps.end(), std::size_t{0});
        if (id != "kinetic" && law_.tangents.empty() && !law_.redundant) // with friction (or dependent columns) the prover reduces nothing
            ps = orthant_firsts();
        require(l.size() <= ps.size() * c, at(dp, key), "too many entries");
        bool ok = true;
        for (std::size_t k = 0; k < l.size(); ++k) {
            const std::size_t p = ps[k / c];
            const Vec& r = pc(p).rays[k % c];
            const std::string ep = at(at(dp, key), k);
            expect_keys(l[k], ep, {"piece", "ray", value});
            expect_piece(l[k], ep, "piece", p);
            expect_vec(l[k], ep, "ray", r, "the piece's ray");
            const Vec img = mul(pc(p).Q_, r);
            bool this_ok = true;
            if (id == "kinetic") {
                const Vec impulse = law_.impulse_at(p, r);
                expect_vec(l[k], ep, "impulse", impulse, law_.redundant ? "L ray" : "H (Q - I) ray");
                this_ok = law_.impulse_admissible(impulse) && law_.impulse_consistent(p, r);
            } else if (id == "kinematic") {
                const Vec all = law_.all_coordinates(img);
                expect_vec(l[k], ep, "image", all, law_.redundant ? "C^T Q ray" : "Q ray");
                this_ok = law_.normals_nonneg(all);
            } else { // P3
                expect_vec(l[k], ep, "image", img, "Q ray");
                std::size_t nz = 0, axis = 0;
                for (std::size_t i = 0; i < c; ++i)
                    if (sgn(img[i]) != 0) {
                        ++nz;
                        axis = i;
                    }
                bool distinct = true;
                for (std::size_t other = k - k % c; other < k; ++other)
                    distinct = distinct && primitive(mul(pc(p).Q_, pc(p).rays[other % c])) != primitive(img);
                this_ok = nz == 1 && sgn(img[axis]) > 0 && distinct;
            }
            ends_at_first_failure(this_ok, k, l.size(), at(dp, key));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), ps.size() * c, at(dp, key));
        return ok;
    }
    if (id == "coulomb") {
        // Per tangent (Lemma F) by the checker itself; friction polygons by their forms' evidence.
        if (!law_.has_polygons() || first_coulomb_failure()) {
            require(data.empty(), dp, law_.has_polygons() ? "the linear part of coulomb fails: no polygon form is listed"
                                                           : "coulomb is decided by the checker itself: no evidence is listed");
            return !first_coulomb_failure();
        }
        expect_keys(data, dp, {"polygon_forms"});
        const Json& l = list(data, dp, "polygon_forms");
        const auto forms = polygon_forms();
        require(l.size() <= forms.size(), at(dp, "polygon_forms"), "too many entries");
        bool ok = true;
        for (std::size_t k = 0; k < l.size(); ++k) {
            const PolygonForm& f = forms[k];
            const std::string ep = at(at(dp, "polygon_forms"), k);
            expect_keys(l[k], ep, {"piece", "contact", "vertex", "A", "certificate"});
            expect_piece(l[k], ep, "piece", f.piece);
            require(natural(field(l[k], ep, "contact"), at(ep, "contact")) == f.contact + 1, at(ep, "contact"),
                    "is not the next contact with a friction polygon");
            require(natural(field(l[k], ep, "vertex"), at(ep, "vertex")) == f.vertex + 1, at(ep, "vertex"),
                    "is not the next vertex");
            const Mat A = polygon_form(f);
            expect_mat(l[k], ep, "A", A, "-(B + B^T) / 2, B(a, b) = (Lambda_T(r_a) - mu Lambda_N(r_a) v) . xi_T(r_b)");
            const bool this_ok =
                check_copositive_evidence(A, field(l[k], ep, "certificate"), at(ep, "certificate"), limits_.max_faces);
            ends_at_first_failure(this_ok, k, l.size(), at(dp, "polygon_forms"));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), forms.size(), at(dp, "polygon_forms"));
        return ok;
    }
    if (id == "energetic") {
        expect_keys(data, dp, {"pieces"});
        const Json& l = list(data, dp, "pieces");
        const auto ps = firsts(); // one piece per orbit when the symmetries hold
        require(l.size() <= ps.size(), at(dp, "pieces"), "too many entries");
        bool ok = true;
        for (std::size_t k = 0; k < l.size(); ++k) {
            const std::size_t p = ps[k];
            const std::string ep = at(at(dp, "pieces"), k);
            expect_keys(l[k], ep, {"piece", "B", "certificate"});
            expect_piece(l[k], ep, "piece", p);
            const Mat B = mul(mul(tr(pc(p).R), sub(law_.H, QtHQ(p))), pc(p).R);
            expect_mat(l[k], ep, "B", B, "R^T (H - Q^T H Q) R");
            const bool this_ok =
                check_copositive_evidence(B, field(l[k], ep, "certificate"), at(ep, "certificate"), limits_.max_faces);
            ends_at_first_failure(this_ok, k, l.size(), at(dp, "pieces"));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), ps.size(), at(dp, "pieces"));
        return ok;
    }
    if (id == "identities") {
        const auto& decls = law_.identities;
        expect_keys(data, dp, {"products"});
        const Json& l = list(data, dp, "products");
        require(l.size() <= decls.size(), at(dp, "products"), "too many entries");
        bool ok = true;
        for (std::size_t i = 0; i < l.size(); ++i) {
            const std::string ep = at(at(dp, "products"), i);
            expect_keys(l[i], ep, {"lhs", "product", "lhs_matrix", "product_matrix"});
            require(field(l[i], ep, "lhs") == decls[i].lhs_json && field(l[i], ep, "product") == decls[i].product_json, ep,
                    "is not the declared identity");
            const Mat& prod = identity_product(i);
            const Mat& lhs = pc(decls[i].lhs).Q_;
            expect_mat(l[i], ep, "lhs_matrix", lhs, "Q_lhs");
            expect_mat(l[i], ep, "product_matrix", prod, "the product");
            ends_at_first_failure(lhs == prod, i, l.size(), at(dp, "products"));
            ok = ok && lhs == prod;
        }
        complete_unless_failed(!ok, l.size(), decls.size(), at(dp, "products"));
        return ok;
    }
    if (id == "single-impacts") {
        const auto& decls = law_.single_impacts;
        expect_keys(data, dp, {"impacts"});
        const Json& l = list(data, dp, "impacts");
        require(l.size() <= decls.size(), at(dp, "impacts"), "too many entries");
        bool ok = true;
        for (std::size_t i = 0; i < l.size(); ++i) {
            const std::string ep = at(at(dp, "impacts"), i);
            expect_keys(l[i], ep, {"piece", "contact", "restitution", "impact"});
            require(field(l[i], ep, "piece") == decls[i].piece_json &&
                        natural(field(l[i], ep, "contact"), at(ep, "contact")) == decls[i].contact &&
                        rat(field(l[i], ep, "restitution"), at(ep, "restitution")) == decls[i].restitution,
                    ep, "is not the declared single impact");
            const Mat impact = law_.impact(decls[i].contact - 1, decls[i].restitution);
            expect_mat(l[i], ep, "impact", impact, "Q^(k)(e)");
            const bool this_ok = pc(decls[i].piece).Q_ == impact;
            ends_at_first_failure(this_ok, i, l.size(), at(dp, "impacts"));
            ok = ok && this_ok;
        }
        complete_unless_failed(!ok, l.size(), decls.size(), at(dp, "impacts"));
        return ok;
    }
    if (id == "nonexpansive") {
        // S undefined or two-valued: refuted before any pair is examined.
        if (holds("fan") != Truth::undecided && domain_witness()) {
            require(data.empty(), dp, "lists pairs although S is not a function");
            return false;
        }
        // A discontinuity (P1 refuted): refuted near its ray before any pair form.
        if (holds("P1") == Truth::refuted) {
            require(data.empty(), dp, "lists pairs although P1 found a discontinuity");
            return false;
        }
        const auto ps = firsts(); // one first piece per orbit when the symmetries hold
        if (symmetry_check().hold) {
            expect_keys(data, dp, {"first_pieces", "pairs"});
            std::vector<std::string> names;
            for (auto p : ps)
                names.push_back(name(p));
            require(listed_names(field(data, dp, "first_pieces"), at(dp, "first_pieces")) == names,
                    at(dp, "first_pieces"), "are not the least pieces of the orbits");
        } else {
            expect_keys(data, dp, {"pairs"});
        }
        const Json& l = list(data, dp, "pairs");
        require(l.size() <= ps.size() * P(), at(dp, "pairs"), "too many entries");
        // Each entry is checked by itself (by `jobs` threads, each taking every jobs-th entry);
        // the outcomes are then read in order, so the first failure reported is the one a
        // single thread would report.
        for (std::size_t p = 0; p < P(); ++p)
            pair_form(p, p); // fills the per-piece cache before any thread reads it
        const std::size_t count = l.size();
        std::vector<char> entry_ok(count, 0);
        std::vector<std::exception_ptr> error(count);
        auto check_entry = [&](std::size_t k) {
            const std::size_t i = ps[k / P()], j = k % P();
            const std::string ep = at(at(dp, "pairs"), k);
            expect_keys(l[k], ep, {"piece_a", "piece_b", "certificate"});
            expect_piece(l[k], ep, "piece_a", i);
            expect_piece(l[k], ep, "piece_b", j);
            const Mat A = pair_form(i, j); // recomputed from the law, never read
            entry_ok[k] = check_copositive_evidence(A, field(l[k], ep, "certificate"), at(ep, "certificate"),
                                                    limits_.max_faces);
        };
        // Share t checks the entries t, t + jobs, ... and stops at its first exception, kept in
        // error[k]: the reading below stops there, before any entry the share left unchecked, and
        // at most one exception per share is alive (hundreds, each holding memory, once used up
        // the runtime's reserve for exceptions under a memory cap). Each entry is reset before it
        // is checked, so a share can be run again.
        const std::size_t jobs = std::max<std::size_t>(1, std::min<std::size_t>(limits_.jobs, count));
        auto share = [&](std::size_t t, bool on_thread) {
            for (std::size_t k = t; k < count; k += jobs) {
                entry_ok[k] = 0;
                error[k] = nullptr;
                try {
                    check_entry(k);
                } catch (const std::bad_alloc&) {
                    if (on_thread)
                        throw; // run again on this thread, below
                    error[k] = std::current_exception();
                    return;
                } catch (...) {
                    error[k] = std::current_exception();
                    return;
                }
            }
        };
        // Shares 1.. on threads. A thread that cannot start (no memory for its stack under a cap)
        // leaves its share to this thread; one that starts and then runs out of memory (its own
        // heap, under the cap) has its share run again here after the joins. The result cannot
        // depend on how many threads started or finished: it is the single thread's.
        std::vector<char> again(jobs, 0);
        std::vector<std::size_t> here;
        here.reserve(jobs);
        here.push_back(0);
        std::vector<std::thread> threads;
        threads.reserve(jobs);
        for (std::size_t t = 1; t < jobs; ++t) {
            try {
                threads.emplace_back([&share, &again, t] {
                    try {
                        share(t, true);
                    } catch (...) {
                        again[t] = 1;
                    }
                });
            } catch (...) {
                here.push_back(t);
            }
        }
        for (const std::size_t t : here)
            share(t, false);
        for (auto& th : threads)
            th.join();
        for (std::size_t t = 1; t < jobs; ++t)
            if (again[t])
                share(t, false);
        bool ok = true;
        for (std::size_t k = 0; k < count; ++k) {
            if (error[k])
                std::rethrow_exception(error[k]);
            ends_at_first_failure(entry_ok[k] != 0, k, count, at(dp, "pairs"));
            ok = ok && entry_ok[k] != 0;
        }
        complete_unless_failed(!ok, l.size(), ps.size() * P(), at(dp, "pairs"));
        return ok;
    }
    if (id == "nonexpansive-lemma") {
        expect_keys(data, dp, {}, {"pieces"});
        const Json& l = data.contains("pieces") ? list(data, dp, "pieces") : Json::array();
        const auto ps = firsts(); // one piece per orbit when the symmetries hold
        require(l.size() <= ps.size(), at(dp, "pieces"), "too many entries");
        for (std::size_t k = 0; k < l.size(); ++k) {
            const std::size_t p = ps[k];
            const std::string ep = at(at(dp, "pieces"), k);
            expect_keys(l[k], ep, {"piece", "matrix", "L", "D"});
            expect_piece(l[k], ep, "piece", p);
            const Mat B = sub(law_.H, QtHQ(p));
            expect_mat(l[k], ep, "matrix", B, "H - Q^T H Q");
            check_psd_evidence(B, l[k], ep);
        }
        if (!s_is_a_function(at(dp, "pieces")) || holds("P1") != Truth::proved) {
            require(l.empty(), at(dp, "pieces"), "listed although S is not a function or P1 is not proved");
            return false;
        }
        if (l.size() < ps.size()) {
            require(psd_witness(sub(law_.H, QtHQ(ps[l.size()]))).has_value(), at(dp, "pieces"), "is incomplete");
            return false;
        }
        return true;
    }
    if (id == "symmetries")
        return symmetries_evidence(data, dp);
    if (id == "outcomes") {
        const auto& decls = law_.outcomes;
        expect_keys(data, dp, {}, {"outcomes"});
        const Json& l = data.contains("outcomes") ? list(data, dp, "outcomes") : Json::array();
        require(l.size() <= decls.size(), at(dp, "outcomes"), "too many entries");
        bool ok = true;
        for (std::size_t i = 0; i < l.size(); ++i) {
            const std::string ep = at(at(dp, "outcomes"), i);
            expect_keys(l[i], ep, {"outcome", "gamma_minus", "pieces"});
            require(str(field(l[i], ep, "outcome"), at(ep, "outcome")) == decls[i].name, at(ep, "outcome"),
                    "is not the declared outcome");
            const Vec& u = decls[i].u_minus;
            const Vec g = mul(tr(law_.W), u);
            expect_vec(l[i], ep, "gamma_minus", g, "W^T u-");
            const bool this_ok = check_outcome_pieces(field(l[i], ep, "pieces"), at(ep, "pieces"), u, g, decls[i].u_plus);
            ends_at_first_failure(this_ok, i, l.size(), at(dp, "outcomes"));
            ok = ok && this_ok;
        }
        if (l.size() < decls.size() && ok) {
            // Only an outcome whose gamma- lies in no cone ends the list without an entry.
            const Vec g = mul(tr(law_.W), decls[l.size()].u_minus);
            for (std::size_t q = 0; q < P(); ++q)
                require(!law_.in_cone(q, g), at(dp, "outcomes"), "is incomplete");
            return false;
        }
        return ok;
    }
    malformed(dp, "unknown obligation");
}

// The list of (piece, u+) for every piece containing gamma-; true when all give `declared`.
bool Checker::check_outcome_pieces(const Json& l, const std::string& lp, const Vec& u, const Vec& g, const Vec& declared) {
    std::vector<std::size_t> containing;
    for (std::size_t p = 0; p < P(); ++p)
        if (law_.in_cone(p, g))
            containing.push_back(p);
    require(l.is_array() && l.size() == containing.size(), lp, "is not the list of pieces containing gamma-");
    bool ok = !containing.empty();
    for (std::size_t k = 0; k < containing.size(); ++k) {
        const std::string ep = at(lp, k);
        expect_keys(l[k], ep, {"piece", "u_plus"});
        expect_piece(l[k], ep, "piece", containing[k]);
        const Vec up = law_.u_plus(u, g, mul(pc(containing[k]).Q_, g));
        expect_vec(l[k], ep, "u_plus", up, "the post-impact velocities");
        ok = ok && up == declared;
    }
    return ok;
}

// The last entry of another obligation's evidence list (evidence() has checked its keys).
const Json& Checker::last_entry(const std::string& id, const char* key) const {
    const std::size_t k = static_cast<std::size_t>(std::find(ids_of(law_).begin(), ids_of(law_).end(), id) - ids_of(law_).begin());
    const std::string dp = at(at("$.obligations", k), "data");
    const Json& data = field(obl_[k], at("$.obligations", k), "data");
    if (!data.is_object() || !data.contains(key) || !data.at(key).is_array() || data.at(key).empty())
        reject(dp, "the refutation's evidence is missing");
    return data.at(key).back();
}

// Entries of a product of identity factors grow with the number of factors: a bound on
// their size (bits of numerator and denominator), from the factors, checked before
// multiplying. Q = N / d with d the common denominator: a product of k factors has entries
// (N_1 ... N_k)_ij / (d_1 ... d_k) with |(N_1 ... N_k)_ij| <= c^(k-1) prod max |N_f|.
std::size_t Checker::factor_bits(std::size_t p) const {
    mpz_class d = 1, top = 0;
    for (const auto& row : pc(p).Q_)
        for (const auto& x : row)
            d = lcm(d, x.get_den());
    for (const auto& row : pc(p).Q_)
        for (const auto& x : row)
            top = std::max(top, mpz_class(abs(x.get_num()) * (d / x.get_den())));
    return mpz_sizeinbase(top.get_mpz_t(), 2) + mpz_sizeinbase(d.get_mpz_t(), 2) +
           mpz_sizeinbase(mpz_class(law_.c).get_mpz_t(), 2);
}

// Identity i's product, by balanced splitting: exact products are associative, and halves
// of equal length keep the operands balanced, so the cost is quasi-linear in the size of the
// result instead of quadratic in the number of factors (left to right, each factor
// multiplies an ever larger matrix). A product whose entries may exceed --max-product-bits
// (the checker's own limit: the prover multiplies without one) is not computed.
const Mat& Checker::identity_product(std::size_t i) {
    if (auto it = products_.find(i); it != products_.end())
        return it->second;
    const auto& factors = law_.identities[i].product;
    std::size_t bound = 0;
    for (auto f : factors)
        bound = std::min<std::size_t>(SIZE_MAX / 2, bound + factor_bits(f));
    if (bound > limits_.max_product_bits)
        undecided("--max-product-bits", at(at("$.law.identities", i), "product"),
                  "the product of " + std::to_string(factors.size()) + " factors may have entries of " +
                      std::to_string(bound) + " bits, more than " + std::to_string(limits_.max_product_bits));
    std::function<Mat(std::size_t, std::size_t)> product = [&](std::size_t lo, std::size_t hi) {
        if (hi - lo == 1)
            return pc(factors[lo]).Q_;
        const std::size_t mid = lo + (hi - lo) / 2;
        return mul(product(lo, mid), product(mid, hi));
    };
    return products_[i] = product(0, factors.size());
}

// A = B1^T H B1 - B2^T H B2 with B1 = [R_i, -R_j], B2 = [Q_i R_i, -Q_j R_j]: by blocks,
// [[E_i, -F], [-F^T, E_j]] with E_p = R_p^T H R_p - (Q R_p)^T H (Q R_p) and
// F = R_i^T H R_j - (Q R_i)^T H (Q R_j), from per-piece products computed once.
Mat Checker::pair_form(std::size_t i, std::size_t j) const {
    const std::size_t c = law_.c;
    auto data = [&](std::size_t p) -> const PairData& {
        if (pair_data_.size() < P())
            pair_data_.resize(P());
        auto& d = pair_data_[p];
        if (!d) {
            PairData e;
            e.R = pc(p).R;
            e.QR = mul(pc(p).Q_, pc(p).R);
            e.HR = mul(law_.H, e.R);
            e.HQR = mul(law_.H, e.QR);
            e.E = sub(mul(tr(e.R), e.HR), mul(tr(e.QR), e.HQR));
            d = std::move(e);
        }
        return *d;
    };
    const PairData &a = data(i), &b = data(j);
    const Mat F = sub(mul(tr(a.R), b.HR), mul(tr(a.QR), b.HQR));
    Mat A = zeros(2 * c, 2 * c);
    for (std::size_t r = 0; r < c; ++r)
        for (std::size_t k = 0; k < c; ++k) {
            A[r][k] = a.E[r][k];
            A[c + r][c + k] = b.E[r][k];
            A[r][c + k] = -F[r][k];
            A[c + k][r] = -F[r][k];
        }
    return A;
}

} // namespace impactcert_check::detail
