// SPDX-License-Identifier: GPL-3.0-or-later
// stream_verify.cpp -- verify --stream (stream.hpp): every obligation of a compact law by passes
// over the ids of its pieces. The lemmas are in proofs/README.md, "Streamed laws"; the symmetry
// reductions in "Symmetries"; the fan criterion in "fan" (Check, any c).
//
//   symmetries   (i) before the expansion (an input error, as Model); (ii) by construction;
//                (iii) at every (piece, symmetry) while closing (stream_store.cpp).
//   fan          facet matching on the facets of the orbit representatives (Lemma ST1), and one
//                point interior to a representative and in no other closed cone (Lemma ST2):
//                stream_fan.cpp.
//   P1           face to face (the fan): all pieces containing a ray give it one image.
//   P3, kinematic, kinetic   every piece, through memos by image id and (ray, image) ids.
//   P2, energetic            the listed pieces, by verify() on them (Lemma S3).
//   identities, single-impacts   verify() on a model of the pieces they name.
//   nonexpansive the pairs (representative, any piece); with P2 each form has zero diagonal
//                blocks, so it is copositive iff its off-diagonal block is >= 0 (Lemma ST3),
//                whose entries are differences of two Gram tables.
//   nonexpansive-lemma   fan + P1 + H - Q^T H Q PSD on the listed pieces.
//   outcomes     the first piece containing gamma- (one value: P1).
#include "exact/copositivity.hpp"
#include "prover/stream.hpp"
#include "prover/stream_decide.hpp"
#include "prover/stream_store.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <set>
#include <unordered_map>

namespace impactcert {

namespace stream {

using intk::i128;


Json Streamed::pair_witness(u32 a, u32 b, const Matrix& Qa, const Matrix& Qb, const Vector& ga, const Vector& gb) const {
    const Model& m = ex_.base;
    const Rational lhs = m.energy(Qa * ga - Qb * gb), rhs = m.energy(ga - gb);
    ensure(lhs > rhs, "nonexpansive lhs > rhs");
    ensure(in_interior(a, ga) && in_interior(b, gb), "nonexpansive interiors");
    return Json{{"piece_a", ex_.name(a)}, {"piece_b", ex_.name(b)}, {"gamma_a", to_json(ga)},
                {"gamma_b", to_json(gb)},   {"lhs", to_json(lhs)},      {"rhs", to_json(rhs)}};
}

void Streamed::symmetries() {
    Decision d;
    d.method = "closure of the listed pieces (streamed; its time includes the expansion): Q_sigma(i) P r = P' Q_i r at every (piece, symmetry)";
    d.checks = ex_.symmetry_checks + (n_ - ex_.base.pieces().size());
    if (ex_.failure) {
        const auto& f = *ex_.failure;
        const SymmetryDecl& sym = ex_.law.symmetries[f.symmetry];
        const Vector r = ex_.ray(ex_.store.rays(f.piece)[f.position]);
        const Vector lhs = ex_.Q(f.image_piece) * (sym.P * r);
        const Vector rhs = sym.P_prime * ex_.images[ex_.store.images(f.piece)[f.position]];
        ensure(lhs != rhs, "symmetries: Q_sigma(i) P r != P' Q_i r");
        d = refuted(d, Json{{"symmetry", sym.name}, {"piece", ex_.name(f.piece)}, {"image_piece", ex_.name(f.image_piece)},
                            {"gamma", to_json(r)}, {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
    }
    d_["symmetries"] = d;
}

void Streamed::by_rays() {
    std::vector<u32> first_image(ex_.rays.size(), kNone), owner(ex_.rays.size(), kNone);
    std::vector<int> axis(ex_.images.size(), -2); // -2 unknown, -1 on no positive axis, else the axis
    std::vector<signed char> nonneg(ex_.images.size(), -1);
    std::unordered_map<std::uint64_t, bool> impulse_ok;
    const Matrix& H = ex_.base.H();
    std::optional<Json> p1_witness;
    std::optional<u32> p3_fail, kinematic_fail, kinetic_fail;
    std::vector<char> seen(c_);
    for (u32 j = 0; j < n_; ++j) {
        report("P1", j);
        const u32* rays = ex_.store.rays(j);
        const u32* imgs = ex_.store.images(j);
        std::fill(seen.begin(), seen.end(), 0);
        bool p3 = true, kin = true, kinetic = true;
        for (std::size_t k = 0; k < c_; ++k) {
            const u32 r = rays[k], im = imgs[k];
            if (first_image[r] == kNone) {
                first_image[r] = im;
                owner[r] = j;
            } else if (first_image[r] != im && !p1_witness) {
                const Vector v = ex_.ray(r);
                const Vector& a = ex_.images[first_image[r]];
                const Vector& b = ex_.images[im];
                ensure(a != b, "P1 values differ");
                p1_witness = Json{{"piece_a", ex_.name(owner[r])}, {"piece_b", ex_.name(j)}, {"gamma", to_json(v)},
                                  {"image_a", to_json(a)}, {"image_b", to_json(b)}};
            }
            if (axis[im] == -2) {
                const Vector& v = ex_.images[im];
                axis[im] = -1;
                std::size_t nonzero = 0;
                for (std::size_t i = 0; i < c_; ++i)
                    if (sign_of(v[i]) != Sign::zero) {
                        ++nonzero;
                        axis[im] = sign_of(v[i]) == Sign::positive ? static_cast<int>(i) : -1;
                    }
                if (nonzero != 1)
                    axis[im] = -1;
                nonneg[im] = std::all_of(v.begin(), v.end(), [](const Rational& x) { return sign_of(x) != Sign::negative; });
            }
            if (axis[im] < 0 || seen[static_cast<std::size_t>(axis[im])]++)
                p3 = false;
            kin = kin && nonneg[im];
            const std::uint64_t key = (std::uint64_t{r} << 32) | im;
            const auto it = impulse_ok.find(key);
            bool ok = false;
            if (it != impulse_ok.end()) {
                ok = it->second;
            } else {
                const Vector impulse = H * (ex_.images[im] - ex_.ray(r));
                ok = std::all_of(impulse.begin(), impulse.end(), [](const Rational& x) { return sign_of(x) != Sign::negative; });
                if (impulse_ok.size() < (std::size_t{1} << 20)) // a bounded memo: beyond it, computed each time
                    impulse_ok.emplace(key, ok);
            }
            kinetic = kinetic && ok;
        }
        if (!p3 && !p3_fail)
            p3_fail = j;
        if (!kin && !kinematic_fail)
            kinematic_fail = j;
        if (!kinetic && !kinetic_fail)
            kinetic_fail = j;
    }
    const std::size_t checks = n_ * c_;
    Decision p1{Verdict::proved, checks, "shared rays (face to face by the fan; streamed, every ray)", {}, {}};
    if (p1_witness)
        d_["P1"] = refuted(p1, *p1_witness);
    else if (!proved("fan"))
        d_["P1"] = undecided(p1, "the shared rays decide P1 only with the fan proved facet to facet");
    else
        d_["P1"] = p1;
    Decision p3{Verdict::proved, checks, "images of rays on distinct positive axes (streamed, every piece, in P1's pass)", {}, {}};
    d_["P3"] = p3_fail ? refuted(p3, piece_witness(*p3_fail, "P3")) : p3;
    Decision kinematic{Verdict::proved, checks, "images of rays >= 0, with fan (streamed, every piece, in P1's pass)", {}, {}};
    if (kinematic_fail)
        d_["kinematic"] = refuted(kinematic, piece_witness(*kinematic_fail, "kinematic"));
    else if (!proved("fan"))
        d_["kinematic"] = undecided(kinematic, "kinematic needs the fan, which --stream did not prove");
    else
        d_["kinematic"] = kinematic;
    Decision kinetic{Verdict::proved, checks, "impulses at rays (streamed, every piece, in P1's pass)", {}, {}};
    d_["kinetic"] = kinetic_fail ? refuted(kinetic, piece_witness(*kinetic_fail, "kinetic")) : kinetic;
}

void Streamed::by_listed() {
    const std::string by_symmetries = ", on the listed pieces, by the symmetries (streamed)";
    {
        Law listed = side_law();
        listed.pieces = ex_.law.pieces;
        const VerifyReport r = side_verify(std::move(listed), {"P2", "energetic"});
        for (const char* id : {"P2", "energetic"}) {
            const ObligationResult& o = r.at(id);
            Decision d{o.verdict, o.checks, o.method + by_symmetries, o.counterexample, o.limit};
            if (o.verdict == Verdict::proved && !proved("symmetries"))
                d = undecided(d, "the listed pieces decide " + std::string(id) + " only through the symmetries, which are refuted");
            d_[id] = d;
        }
    }
    if (ex_.law.identities.empty() && ex_.law.single_impacts.empty())
        return;
    Law named = side_law();
    named.identities = ex_.law.identities;
    named.single_impacts = ex_.law.single_impacts;
    std::vector<std::string> names;
    for (const auto& id : ex_.law.identities) {
        names.push_back(id.lhs);
        names.insert(names.end(), id.product.begin(), id.product.end());
    }
    for (const auto& si : ex_.law.single_impacts)
        names.push_back(si.piece);
    std::set<std::string> added;
    for (const auto& name : names)
        if (added.insert(name).second)
            named.pieces.push_back(ex_.decl(*ex_.resolve(name))); // resolved before (verify_stream)
    const VerifyReport r = side_verify(std::move(named), {"identities", "single-impacts"});
    for (const char* id : {"identities", "single-impacts"}) {
        const ObligationResult& o = r.at(id);
        d_[id] = Decision{o.verdict, o.checks, o.method + " (streamed: the named pieces)", o.counterexample, o.limit};
    }
}

// Lemma ST3: with Q_i^T H Q_i = H for every piece, the pair form of (i, j) is
// [[0, B], [B^T, 0]] with B_ab = (Q_i r_a)^T H (Q_j s_b) - r_a^T H s_b, copositive iff B >= 0.
void Streamed::nonexpansive() {
    Decision d;
    d.method = "pair forms with zero diagonal blocks (P2), off-diagonal block >= 0 by Gram tables; the pairs of "
               "one piece per orbit, by the symmetries (streamed)";
    for (const char* need : {"symmetries", "fan", "P1", "P2"})
        if (!proved(need)) {
            d_["nonexpansive"] =
                undecided(d, std::string("--stream decides nonexpansive only for a law whose symmetries, fan, P1 and P2 "
                                         "are proved; ") + need + " is not");
            return;
        }
    const Matrix& H = ex_.base.H();
    // The tables: per representative, c entries per ray and per image, as rationals and int64.
    const std::size_t table_bytes = (ex_.rays.size() + ex_.images.size()) * c_ * (sizeof(Rational) + 64 + sizeof(i64));
    const std::size_t max_bytes = limits_.max_memory_mb > (SIZE_MAX >> 20) ? SIZE_MAX : limits_.max_memory_mb << 20;
    if (ex_.bytes + table_bytes > max_bytes) {
        d_["nonexpansive"] = undecided(d, "its Gram tables need " + std::to_string((table_bytes >> 20) + 1) +
                                              " MB more than the store, beyond --max-memory (raise it with --max-memory)");
        return;
    }
    for (const u32 i : ex_.representatives) {
        // T_ray[id * c + a] = r_a^T H ray(id), T_img[id * c + a] = (Q_i r_a)^T H image(id), over one denominator.
        std::vector<Vector> h_ray, h_img;
        for (std::size_t a = 0; a < c_; ++a) {
            h_ray.push_back(H * ex_.ray(ex_.store.rays(i)[a]));
            h_img.push_back(H * ex_.images[ex_.store.images(i)[a]]);
        }
        std::vector<Rational> g_ray(ex_.rays.size() * c_), g_img(ex_.images.size() * c_);
        mpz_class l = 1;
        for (std::size_t id = 0; id < ex_.rays.size(); ++id) {
            const Vector v = ex_.ray(static_cast<u32>(id));
            for (std::size_t a = 0; a < c_; ++a) {
                g_ray[id * c_ + a] = dot(h_ray[a], v);
                mpz_lcm(l.get_mpz_t(), l.get_mpz_t(), mpq_denref(g_ray[id * c_ + a].mpq()));
            }
        }
        for (std::size_t id = 0; id < ex_.images.size(); ++id)
            for (std::size_t a = 0; a < c_; ++a) {
                g_img[id * c_ + a] = dot(h_img[a], ex_.images[id]);
                mpz_lcm(l.get_mpz_t(), l.get_mpz_t(), mpq_denref(g_img[id * c_ + a].mpq()));
            }
        const Rational L{CGAL::Gmpz(l.get_mpz_t())};
        std::vector<i64> t_ray(g_ray.size()), t_img(g_img.size());
        auto scale = [&](const std::vector<Rational>& g, std::vector<i64>& t) { // L g: integers
            for (std::size_t k = 0; k < g.size(); ++k) {
                const Rational x = g[k] * L;
                const auto v = intk::to_i64(mpq_numref(x.mpq()));
                if (!v)
                    return false;
                t[k] = *v;
            }
            return true;
        };
        const bool fits = scale(g_ray, t_ray) && scale(g_img, t_img);
        for (u32 j = 0; j < n_; ++j) {
            report("nonexpansive", j);
            ++d.checks;
            const u32* rays = ex_.store.rays(j);
            const u32* imgs = ex_.store.images(j);
            for (std::size_t b = 0; b < c_; ++b)
                for (std::size_t a = 0; a < c_; ++a) {
                    const bool negative = fits ? static_cast<i128>(t_img[imgs[b] * c_ + a]) - t_ray[rays[b] * c_ + a] < 0
                                               : g_img[imgs[b] * c_ + a] < g_ray[rays[b] * c_ + a];
                    if (negative) // fan, P1 and P2 proved: the nonexpansive lemma makes every form copositive
                        throw std::logic_error("--stream: a pair form with a negative entry although the fan, P1 and P2 "
                                               "are proved (contradicts the nonexpansive lemma)");
                }
        }
    }
    d_["nonexpansive"] = d;
}

void Streamed::nonexpansive_lemma() {
    Decision d;
    d.method = "fan + P1 + H - Q^T H Q PSD per piece, on the listed pieces, by the symmetries (streamed)";
    if (d_.at("P1").verdict == Verdict::refuted) {
        Json w = d_.at("P1").counterexample;
        w["via"] = "P1";
        d_["nonexpansive-lemma"] = refuted(d, w);
        return;
    }
    for (const char* need : {"symmetries", "fan", "P1"})
        if (!proved(need)) {
            d_["nonexpansive-lemma"] = undecided(d, std::string("the lemma needs ") + need + ", which --stream did not prove");
            return;
        }
    const Model& m = ex_.base;
    for (u32 p = 0; p < m.pieces().size(); ++p) {
        const Piece& pc = m.pieces()[p];
        const auto ldl = ldl_psd(m.H() - transpose(pc.Q) * m.H() * pc.Q);
        ++d.checks;
        if (ldl.psd)
            continue;
        // Two interior points of the same cone, a - b along the expanding direction.
        const auto [a, b] = interior_pair_along(pc, ldl.witness);
        d_["nonexpansive-lemma"] = refuted(d, pair_witness(p, p, pc.Q, pc.Q, a, b));
        return;
    }
    d_["nonexpansive-lemma"] = d;
}

std::map<std::string, Decision> Streamed::run() {
    auto timed = [&](void (Streamed::*phase)(), const char* id) {
        const auto start = std::chrono::steady_clock::now();
        (this->*phase)();
        d_.at(id).elapsed = std::chrono::steady_clock::now() - start;
    };
    timed(&Streamed::symmetries, "symmetries");
    timed(&Streamed::membership, "fan");
    timed(&Streamed::by_rays, "P1");
    timed(&Streamed::by_listed, "P2");
    timed(&Streamed::nonexpansive, "nonexpansive");
    timed(&Streamed::nonexpansive_lemma, "nonexpansive-lemma");
    // outcomes
    Decision d;
    d.method = "exact impacts in ball velocities, at the first piece containing gamma- (one value by P1; streamed)";
    const Model& m = ex_.base;
    for (std::size_t o = 0; o < ex_.law.outcomes.size() && d.verdict == Verdict::proved; ++o) {
        const auto& decl = ex_.law.outcomes[o];
        const Vector gamma = m.contact_velocities(decl.u_minus);
        ++d.checks;
        if (outcome_piece_[o] == kNone) {
            d = refuted(d, Json{{"outcome", decl.name}, {"u_minus", to_json(decl.u_minus)},
                                {"gamma_minus", to_json(gamma)}, {"reason", "gamma- lies in no cone"}});
            break;
        }
        const u32 p = outcome_piece_[o];
        const auto x = solve(ex_.R(p), gamma);
        ensure(x && std::all_of(x->begin(), x->end(), [](const Rational& v) { return sign_of(v) != Sign::negative; }),
               "outcomes: gamma- in the piece");
        const Vector u_plus = m.post_impact_velocities(decl.u_minus, gamma, ex_.Q(p) * gamma);
        if (u_plus != decl.u_plus) {
            Json by_piece = Json::array();
            by_piece.push_back(Json{{"piece", ex_.name(p)}, {"u_plus", to_json(u_plus)}});
            d = refuted(d, Json{{"outcome", decl.name}, {"u_minus", to_json(decl.u_minus)},
                                {"u_plus_declared", to_json(decl.u_plus)}, {"piece", ex_.name(p)},
                                {"u_plus", to_json(u_plus)}, {"pieces_at_gamma", by_piece}});
        }
    }
    if (d.verdict == Verdict::proved && !proved("P1"))
        d = undecided(d, "one piece per gamma- decides the outcomes only with P1 proved");
    d_["outcomes"] = d;
    return d_;
}

} // namespace stream

using stream::Expansion;
using stream::kMaxOrbits;
using stream::Streamed;

StreamResult verify_stream(const Law& law, const Limits& limits, const Progress& progress) {
    if (!law.representatives_only) {
        const Model validated(law, limits.max_pieces, limits.max_memory_mb); // bad input first, as verify()
        throw StreamRefused("the law lists every piece (--stream expands laws given by orbit representatives, "
                            "\"pieces_listed\": \"orbit-representatives\")");
    }
    // The listed pieces alone, validated as Model validates them (mechanics, pieces, symmetries);
    // the declarations after the pieces are validated after the expansion, in Model's order.
    Law listed = law;
    listed.representatives_only = false;
    listed.identities.clear();
    listed.single_impacts.clear();
    listed.outcomes.clear();
    listed.claims.reset();
    const Model base(listed, limits.max_pieces, limits.max_memory_mb);
    if (law.symmetries.empty())
        input_error("$.pieces_listed", "orbit representatives need \"symmetries\"");
    if (base.contacts() > 250)
        throw StreamRefused("more than 250 contacts");
    const auto start = std::chrono::steady_clock::now();
    Expansion ex(law, base, limits, progress);
    const auto expanded = std::chrono::steady_clock::now() - start;
    validate_declarations(law, base.balls(), base.contacts(),
                          [&](const std::string& name) { return ex.resolve(name).has_value(); });
    if (ex.representatives.size() > kMaxOrbits) // the passes cost (orbits) x (pieces)
        throw StreamRefused(std::to_string(ex.representatives.size()) + " orbits of pieces (--stream is for laws with few "
                            "orbits; at most " + std::to_string(kMaxOrbits) + ")");

    Streamed s(ex, limits, progress);
    const auto decisions = s.run();
    StreamResult out;
    out.report.law = law.name;
    for (const char* id : kObligationIds) {
        ObligationResult r;
        r.id = id;
        r.claimed = law_claims(law, id);
        r.data = Json::object();
        if (!law_applies(law, id)) {
            r.verdict = Verdict::skipped;
            r.method = "nothing declared";
        } else {
            const stream::Decision& d = decisions.at(id);
            r.verdict = d.verdict;
            r.checks = d.checks;
            r.method = d.method;
            r.counterexample = d.counterexample;
            r.limit = d.limit;
            r.elapsed = d.elapsed + (r.id == "symmetries" ? expanded : std::chrono::nanoseconds{0});
        }
        out.report.obligations.push_back(std::move(r));
    }
    out.balls = base.balls();
    out.contacts = ex.c;
    out.pieces = ex.store.size();
    out.rays = ex.rays.size();
    out.images = ex.images.size();
    out.bytes = ex.bytes;
    return out;
}

} // namespace impactcert
