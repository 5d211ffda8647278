#include "obligations.hpp"

#include "copositivity.hpp"
#include "fan.hpp"
#include "json.hpp"

#include <algorithm>
#include <functional>
#include <optional>
#include <stdexcept>

namespace impactcert {

const char* to_string(Verdict v) {
    switch (v) {
    case Verdict::proved: return "proved";
    case Verdict::refuted: return "refuted";
    case Verdict::skipped: return "skipped";
    case Verdict::undecided: return "undecided";
    }
    return "?";
}

bool VerifyReport::passed() const {
    return std::all_of(obligations.begin(), obligations.end(), [](const ObligationResult& o) {
        return !o.claimed || o.verdict == Verdict::proved;
    });
}

const char* VerifyReport::verdict() const {
    bool undecided = false;
    for (const auto& o : obligations) {
        if (!o.claimed)
            continue;
        if (o.verdict == Verdict::refuted)
            return "refuted";
        undecided = undecided || o.verdict != Verdict::proved;
    }
    return undecided ? "undecided" : "proved";
}

int VerifyReport::exit_status() const {
    const std::string v = verdict();
    return v == "proved" ? 0 : v == "refuted" ? 1 : 3;
}

const ObligationResult& VerifyReport::at(const std::string& id) const {
    for (const auto& o : obligations)
        if (o.id == id)
            return o;
    throw std::out_of_range("no obligation " + id);
}

namespace {

// Internal consistency: a refutation whose witness does not witness is a bug in impactcert.
void ensure(bool ok, const char* what) {
    if (!ok)
        throw std::logic_error(std::string("internal witness check failed: ") + what);
}

bool nonnegative(const Vector& v) {
    return std::all_of(v.begin(), v.end(), [](const Rational& x) { return sign_of(x) != Sign::negative; });
}

// The outcome of one obligation before bookkeeping.
struct Outcome {
    bool proved = true;
    std::size_t checks = 0;
    std::string method;
    Json counterexample;
    Json data = Json::object();
};

Outcome refute(Outcome o, Json witness) {
    o.proved = false;
    o.counterexample = std::move(witness);
    return o;
}

Json certificate_json(const CopositivityResult& r) {
    Json c;
    c["method"] = to_string(r.method);
    switch (r.method) {
    case CopositivityMethod::nonnegative_entries:
        break;
    case CopositivityMethod::psd_plus_nonnegative:
        c["N"] = to_json(r.N);
        [[fallthrough]];
    case CopositivityMethod::psd:
        c["L"] = to_json(r.ldl.L);
        c["D"] = to_json(r.ldl.D);
        break;
    case CopositivityMethod::kkt_enumeration: {
        Json cands = Json::array();
        for (const auto& k : r.candidates) {
            Json support = Json::array();
            for (auto i : k.support)
                support.push_back(i);
            cands.push_back(Json{{"support", support}, {"x", to_json(k.x)}, {"value", to_json(k.value)}});
        }
        c["candidates"] = cands;
        c["minimum"] = to_json(r.minimum);
        break;
    }
    }
    return c;
}

class Prover {
  public:
    Prover(const Model& m, const Limits& limits, const Progress& progress, const std::vector<std::string>* only)
        : m_(m), c_(m.contacts()), pieces_(m.pieces()), limits_(limits), progress_(progress), only_(only) {}

    VerifyReport run() {
        VerifyReport report;
        report.law = m_.law().name;
        for (const char* id : kObligationIds) {
            const auto start = std::chrono::steady_clock::now();
            ObligationResult r;
            r.id = id;
            r.claimed = m_.claimed(id);
            if (only_ && std::find(only_->begin(), only_->end(), r.id) == only_->end()) {
                r.verdict = Verdict::skipped;
                r.method = "not requested";
            } else if (!m_.applies(id)) {
                r.verdict = Verdict::skipped;
                r.method = "nothing declared";
            } else {
                try {
                    Outcome o = dispatch(r.id);
                    r.verdict = o.proved ? Verdict::proved : Verdict::refuted;
                    r.checks = o.checks;
                    r.method = o.method;
                    r.counterexample = std::move(o.counterexample);
                    r.data = std::move(o.data);
                } catch (const LimitExceeded& e) {
                    r.verdict = Verdict::undecided;
                    r.method = "exact decision beyond a limit";
                    r.limit = std::string(e.what()) + " (raise it with " + e.option + ")";
                    r.data = Json::object();
                }
            }
            r.elapsed = std::chrono::steady_clock::now() - start;
            report.obligations.push_back(std::move(r));
        }
        return report;
    }

  private:
    const Model& m_;
    std::size_t c_;
    const std::vector<Piece>& pieces_;
    const Limits& limits_;
    const Progress& progress_;
    const std::vector<std::string>* only_;
    std::optional<FanResult> fan_;
    std::optional<LimitExceeded> fan_limit_; // the fan's decision exceeded a limit
    std::optional<Outcome> p1_;
    std::optional<LimitExceeded> p1_limit_;
    std::optional<DomainResult> domain_;

    void report_progress(const std::string& id, std::size_t done, std::size_t total) const {
        if (progress_)
            progress_(id, std::to_string(done) + "/" + std::to_string(total));
    }

    const std::string& name(std::size_t p) const { return pieces_[p].name; }

    Outcome dispatch(const std::string& id) {
        if (id == "fan") return fan();
        if (id == "P1") return p1();
        if (id == "P2") return p2();
        if (id == "P3") return p3();
        if (id == "kinematic") return kinematic();
        if (id == "kinetic") return kinetic();
        if (id == "energetic") return energetic();
        if (id == "identities") return identities();
        if (id == "single-impacts") return single_impacts();
        if (id == "nonexpansive") return nonexpansive();
        if (id == "nonexpansive-lemma") return nonexpansive_lemma();
        if (id == "outcomes") return outcomes();
        throw std::logic_error("unknown obligation " + id);
    }

    // -----------------------------------------------------------------------------------------
    // fan

    const FanResult& fan_result() {
        if (fan_limit_)
            throw *fan_limit_;
        if (!fan_) {
            try {
                fan_ = check_fan(m_, limits_);
            } catch (const LimitExceeded& e) {
                fan_limit_ = e;
                throw;
            }
        }
        return *fan_;
    }

    const DomainResult& domain() {
        if (!domain_)
            domain_ = check_domain(m_, fan_result());
        return *domain_;
    }

    Json names_of(const std::vector<std::size_t>& ps) const {
        Json out = Json::array();
        for (auto p : ps)
            out.push_back(name(p));
        return out;
    }

    Outcome fan() {
        const FanResult& f = fan_result();
        Outcome o;
        o.checks = f.checks;
        o.method = f.method;
        Json points = Json::array();
        for (const auto& p : f.test_points)
            points.push_back(to_json(p));
        if (f.method == "angular-sectors") {
            Json rays = Json::array();
            for (const auto& r : f.rays_by_angle)
                rays.push_back(to_json(r));
            o.data["rays_by_angle"] = rays;
            o.data["sector_points"] = points;
        } else if (f.method == "facet-matching") {
            Json facets = Json::array();
            for (const auto& fc : f.facets) {
                Json rays = Json::array();
                for (const auto& r : fc.rays)
                    rays.push_back(to_json(r));
                facets.push_back(Json{{"rays", rays}, {"pieces", names_of(fc.pieces)}});
            }
            o.data["facets"] = facets;
            o.data["generic_point"] = points.at(0);
        } else {
            Json planes = Json::array();
            for (const auto& n : f.hyperplanes)
                planes.push_back(to_json(n));
            o.data["hyperplanes"] = planes;
            if (f.method == "walls")
                o.data["generic_point"] = points.at(0);
            else
                o.data["chamber_points"] = points;
        }
        if (!f.proved) {
            const std::size_t k = *f.failing;
            const Vector& x = f.test_points[k];
            const auto& cov = f.covering[k];
            // Re-validate: a point in no closed cone, or in two interiors.
            ensure(cov.size() >= 2 || m_.pieces_containing(x).empty(), "fan point");
            return refute(o, Json{{"gamma", to_json(x)}, {"interior_of", names_of(cov)},
                                  {"reason", cov.empty() ? "gamma lies in no cone (the cones leave a gap)"
                                                         : "gamma lies in the interiors of " +
                                                               std::to_string(cov.size()) +
                                                               " cones (they overlap)"}});
        }
        return o;
    }

    // Obligations that need S to be a function on R^c: refuted by a point where S is undefined
    // or two-valued on an open set (SPEC section 3, witness rules); nothing when S is one.
    std::optional<Json> domain_witness() {
        const DomainResult& d = domain();
        if (d.function)
            return std::nullopt;
        const Vector& x = *d.point;
        if (d.interior_of.empty()) {
            ensure(m_.pieces_containing(x).empty(), "domain gap");
        } else {
            bool differ = false;
            for (auto a : d.interior_of)
                for (auto b : d.interior_of)
                    differ = differ || pieces_[a].Q * x != pieces_[b].Q * x;
            ensure(differ, "domain two-valued");
        }
        return Json{{"via", "fan"}, {"gamma", to_json(x)}, {"interior_of", names_of(d.interior_of)},
                    {"reason", d.reason}};
    }

    // -----------------------------------------------------------------------------------------
    // P1: continuity wherever two cones meet

    Json p1_witness(std::size_t i, std::size_t j, const Vector& x) {
        const Vector qi = pieces_[i].Q * x, qj = pieces_[j].Q * x;
        ensure(qi != qj, "P1 values differ");
        const auto in = m_.pieces_containing(x);
        ensure(std::find(in.begin(), in.end(), i) != in.end() && std::find(in.begin(), in.end(), j) != in.end(),
               "P1 point in both cones");
        return Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"gamma", to_json(x)},
                    {"image_a", to_json(qi)}, {"image_b", to_json(qj)}};
    }

    Outcome p1() {
        if (p1_limit_)
            throw *p1_limit_;
        if (p1_)
            return *p1_;
        // The fast path of the fan is decided before its chamber enumeration, so a fan beyond
        // its limit means the cones do not meet face to face: P1 then needs intersections.
        bool face_to_face = false, walls = false;
        try {
            face_to_face = fan_result().fast_path;
            walls = fan_result().method == "walls";
        } catch (const LimitExceeded&) {
        }
        try {
            p1_ = face_to_face ? p1_shared_rays() : p1_intersections(walls);
        } catch (const LimitExceeded& e) {
            p1_limit_ = e;
            throw;
        }
        return *p1_;
    }

    // The cones form a fan meeting face to face: agreement on shared rays.
    Outcome p1_shared_rays() {
        Outcome o;
        o.method = "products on shared rays";
        for (std::size_t i = 0; i < pieces_.size() && o.proved; ++i)
            for (std::size_t j = i + 1; j < pieces_.size() && o.proved; ++j)
                for (std::size_t a = 0; a < c_ && o.proved; ++a) {
                    const auto id = pieces_[i].ray_ids[a];
                    const auto& rj = pieces_[j].ray_ids;
                    if (std::find(rj.begin(), rj.end(), id) == rj.end())
                        continue;
                    const Vector& v = m_.rays()[id];
                    const Vector qi = pieces_[i].Q * v, qj = pieces_[j].Q * v;
                    ++o.checks;
                    o.data["shared"].push_back(Json{{"piece_a", name(i)}, {"piece_b", name(j)},
                                                    {"ray", to_json(v)}, {"image_a", to_json(qi)},
                                                    {"image_b", to_json(qj)}});
                    if (qi != qj)
                        o = refute(o, p1_witness(i, j, v));
                }
        return o;
    }

    // Any cones: for every pair with different matrices, the extreme rays of C_i ∩ C_j.
    // With a tiling proved by walls, only pairs across a common facet hyperplane.
    Outcome p1_intersections(bool across_walls) {
        Outcome o;
        o.method = across_walls ? "extreme rays of intersections across walls" : "extreme rays of pairwise intersections";
        std::vector<std::pair<std::size_t, std::size_t>> pairs;
        if (across_walls)
            pairs = wall_pairs(m_);
        else
            for (std::size_t i = 0; i < pieces_.size(); ++i)
                for (std::size_t j = i + 1; j < pieces_.size(); ++j)
                    if (pieces_[i].Q != pieces_[j].Q)
                        pairs.emplace_back(i, j);
        const std::size_t per_pair = intersection_subsets(c_);
        if (!pairs.empty() && per_pair > limits_.max_subsets / pairs.size())
            throw LimitExceeded("the intersections of " + std::to_string(pairs.size()) +
                                    " pairs of cones need " + std::to_string(per_pair) +
                                    " constraint subsets each, more than " +
                                    std::to_string(limits_.max_subsets) + " in all",
                                "--max-subsets");
        o.data["intersections"] = Json::array();
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const auto [i, j] = pairs[k];
            const auto rays = intersection_rays(m_, i, j, o.checks);
            if (k % 256 == 0)
                report_progress("P1", k, pairs.size());
            Json listed = Json::array();
            for (const auto& r : rays)
                listed.push_back(to_json(r));
            o.data["intersections"].push_back(Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"rays", listed}});
            for (const auto& r : rays)
                if (pieces_[i].Q * r != pieces_[j].Q * r)
                    return refute(o, p1_witness(i, j, r));
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // P2: Q^T H Q = H

    Outcome p2() {
        Outcome o;
        o.method = "Q^T H Q = H";
        const Matrix& H = m_.H();
        for (std::size_t p = 0; p < pieces_.size(); ++p) {
            const Matrix& Q = pieces_[p].Q;
            const Matrix QtHQ = transpose(Q) * H * Q;
            const Matrix D = QtHQ - H;
            ++o.checks;
            o.data["QtHQ"].push_back(Json{{"piece", name(p)}, {"matrix", to_json(QtHQ)}});
            if (D == Matrix(c_, c_))
                continue;
            // A symmetric D != 0 has x^T D x != 0 at some e_k or e_k + e_l.
            Vector x;
            for (std::size_t k = 0; k < c_ && x.empty(); ++k)
                if (sign_of(D(k, k)) != Sign::zero)
                    x = unit_vector(c_, k);
            for (std::size_t k = 0; k < c_ && x.empty(); ++k)
                for (std::size_t l = k + 1; l < c_ && x.empty(); ++l)
                    if (sign_of(D(k, l)) != Sign::zero)
                        x = unit_vector(c_, k) + unit_vector(c_, l);
            const Rational lhs = m_.energy(Q * x), rhs = m_.energy(x);
            ensure(lhs != rhs, "P2");
            return refute(o, Json{{"piece", name(p)}, {"gamma", to_json(x)},
                                  {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // P3: each ray onto a distinct positive axis

    Outcome p3() {
        Outcome o;
        o.method = "images of rays";
        for (std::size_t p = 0; p < pieces_.size(); ++p) {
            std::vector<bool> hit(c_, false);
            for (std::size_t a = 0; a < c_; ++a) {
                const Vector r = pieces_[p].R.column(a);
                const Vector img = pieces_[p].Q * r;
                ++o.checks;
                o.data["images"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"image", to_json(img)}});
                std::size_t nonzero = 0, axis = 0;
                for (std::size_t k = 0; k < c_; ++k)
                    if (sign_of(img[k]) != Sign::zero) {
                        ++nonzero;
                        axis = k;
                    }
                std::string reason;
                if (nonzero != 1 || sign_of(img[axis]) != Sign::positive)
                    reason = "the image of the ray is not on a positive axis";
                else if (hit[axis])
                    reason = "two rays map to the same axis";
                if (!reason.empty())
                    return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                          {"image", to_json(img)}, {"reason", reason}});
                hit[axis] = true;
            }
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // kinematic: gamma+ >= 0 everywhere

    Outcome kinematic() {
        Outcome o;
        o.method = "images of rays >= 0, with fan";
        for (std::size_t p = 0; p < pieces_.size(); ++p)
            for (std::size_t a = 0; a < c_; ++a) {
                const Vector r = pieces_[p].R.column(a);
                const Vector img = pieces_[p].Q * r;
                ++o.checks;
                o.data["images"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"image", to_json(img)}});
                if (!nonnegative(img))
                    return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                          {"image", to_json(img)}});
            }
        if (auto w = domain_witness())
            return refute(o, std::move(*w));
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // kinetic: Lambda = H (Q - I) gamma >= 0 on each cone

    Outcome kinetic() {
        Outcome o;
        o.method = "impulses at rays";
        const Matrix I = Matrix::identity(c_);
        for (std::size_t p = 0; p < pieces_.size(); ++p) {
            const Matrix K = m_.H() * (pieces_[p].Q - I);
            for (std::size_t a = 0; a < c_; ++a) {
                const Vector r = pieces_[p].R.column(a);
                const Vector impulse = K * r;
                ++o.checks;
                o.data["impulses"].push_back(Json{{"piece", name(p)}, {"ray", to_json(r)}, {"impulse", to_json(impulse)}});
                if (!nonnegative(impulse))
                    return refute(o, Json{{"piece", name(p)}, {"ray", to_json(r)},
                                          {"impulse", to_json(impulse)}});
            }
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // energetic: |Q x|_H <= |x|_H on each cone

    Outcome energetic() {
        Outcome o;
        o.method = "copositivity of R^T (H - Q^T H Q) R";
        for (std::size_t p = 0; p < pieces_.size(); ++p) {
            const Piece& pc = pieces_[p];
            const Matrix B = transpose(pc.R) * (m_.H() - transpose(pc.Q) * m_.H() * pc.Q) * pc.R;
            const auto cop = decide_copositivity(B, limits_.max_faces);
            o.checks += cop.method == CopositivityMethod::kkt_enumeration ? cop.faces : 1;
            o.data["pieces"].push_back(Json{{"piece", name(p)}, {"B", to_json(B)}, {"certificate", certificate_json(cop)}});
            if (!cop.copositive) {
                const Vector gamma = pc.R * cop.witness;
                const Rational lhs = m_.energy(pc.Q * gamma), rhs = m_.energy(gamma);
                ensure(lhs > rhs && nonnegative(pc.R_inv * gamma), "energetic");
                return refute(o, Json{{"piece", name(p)}, {"gamma", to_json(gamma)},
                                      {"lhs", to_json(lhs)}, {"rhs", to_json(rhs)}});
            }
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // identities: declared factorisations

    Outcome identities() {
        Outcome o;
        o.method = "exact matrix products";
        const auto& decls = m_.law().identities;
        for (std::size_t i = 0; i < decls.size(); ++i) {
            const Matrix& lhs = pieces_[m_.piece_index(decls[i].lhs)].Q;
            Matrix product = Matrix::identity(c_);
            Json names = Json::array();
            for (const auto& f : decls[i].product) {
                product = product * pieces_[m_.piece_index(f)].Q;
                names.push_back(f);
            }
            ++o.checks;
            o.data["products"].push_back(Json{{"lhs", decls[i].lhs}, {"product", names},
                                              {"lhs_matrix", to_json(lhs)}, {"product_matrix", to_json(product)}});
            if (lhs == product)
                continue;
            std::size_t col = 0;
            while (lhs.column(col) == product.column(col))
                ++col;
            const Vector e = unit_vector(c_, col);
            return refute(o, Json{{"identity", i}, {"lhs", decls[i].lhs}, {"product", names},
                                  {"gamma", to_json(e)}, {"lhs_image", to_json(lhs * e)},
                                  {"product_image", to_json(product * e)}});
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // single-impacts: piece = Q^(k)(e), derived from M and W

    Outcome single_impacts() {
        Outcome o;
        o.method = "Q^(k)(e) = I - (1+e) G e_k e_k^T / G_kk";
        const auto& decls = m_.law().single_impacts;
        for (const auto& d : decls) {
            const Matrix& Q = pieces_[m_.piece_index(d.piece)].Q;
            const Matrix impact = m_.single_impact(static_cast<std::size_t>(d.contact - 1), d.restitution);
            ++o.checks;
            o.data["impacts"].push_back(Json{{"piece", d.piece}, {"contact", d.contact},
                                             {"restitution", to_json(d.restitution)}, {"impact", to_json(impact)}});
            if (Q == impact)
                continue;
            std::size_t col = 0;
            while (Q.column(col) == impact.column(col))
                ++col;
            const Vector e = unit_vector(c_, col);
            return refute(o, Json{{"piece", d.piece}, {"contact", d.contact},
                                  {"restitution", to_json(d.restitution)}, {"gamma", to_json(e)},
                                  {"piece_image", to_json(Q * e)},
                                  {"impact_image", to_json(impact * e)}});
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // nonexpansive, pairwise: A copositive for every ordered pair

    Json pair_witness(std::size_t i, std::size_t j, const Vector& gamma_a, const Vector& gamma_b) {
        const Rational lhs = m_.energy(pieces_[i].Q * gamma_a - pieces_[j].Q * gamma_b);
        const Rational rhs = m_.energy(gamma_a - gamma_b);
        ensure(lhs > rhs, "nonexpansive lhs > rhs");
        ensure(m_.in_interior(i, gamma_a) && m_.in_interior(j, gamma_b), "nonexpansive interiors");
        return Json{{"piece_a", name(i)},         {"piece_b", name(j)},
                    {"gamma_a", to_json(gamma_a)}, {"gamma_b", to_json(gamma_b)},
                    {"lhs", to_json(lhs)},         {"rhs", to_json(rhs)}};
    }

    Outcome nonexpansive() {
        Outcome o;
        o.method = "S a function, then copositive pair forms";
        // Where S is undefined or two-valued on an open set it is not non-expansive: that
        // witness comes first, and spares the pair forms. A fan beyond its limit leaves the
        // pairs to decide a refutation.
        std::optional<LimitExceeded> fan_limit;
        try {
            if (auto w = domain_witness())
                return refute(o, std::move(*w));
        } catch (const LimitExceeded& e) {
            fan_limit = e;
        }
        std::size_t by_method[4] = {0, 0, 0, 0};
        auto method_summary = [&] {
            return "copositive pair forms: " + std::to_string(by_method[0]) + " A>=0, " +
                   std::to_string(by_method[1]) + " PSD, " + std::to_string(by_method[2]) + " PSD+N, " +
                   std::to_string(by_method[3]) + " KKT";
        };
        const Matrix& H = m_.H();
        for (std::size_t i = 0; i < pieces_.size(); ++i)
            for (std::size_t j = 0; j < pieces_.size(); ++j) {
                if (j == 0 && i % 16 == 0)
                    report_progress("nonexpansive", i * pieces_.size(), pieces_.size() * pieces_.size());
                // z = (s, t): a = R_i s, b = R_j t;  a - b = B1 z,  S(a) - S(b) = B2 z.
                Matrix B1(c_, 2 * c_), B2(c_, 2 * c_);
                const Matrix QRi = pieces_[i].Q * pieces_[i].R, QRj = pieces_[j].Q * pieces_[j].R;
                for (std::size_t r = 0; r < c_; ++r)
                    for (std::size_t k = 0; k < c_; ++k) {
                        B1(r, k) = pieces_[i].R(r, k);
                        B1(r, c_ + k) = -pieces_[j].R(r, k);
                        B2(r, k) = QRi(r, k);
                        B2(r, c_ + k) = -QRj(r, k);
                    }
                const Matrix A = transpose(B1) * H * B1 - transpose(B2) * H * B2;
                const auto cop = decide_copositivity(A, limits_.max_faces);
                o.checks += cop.method == CopositivityMethod::kkt_enumeration ? cop.faces : 1;
                ++by_method[static_cast<int>(cop.method)];
                o.method = method_summary();
                o.data["pairs"].push_back(Json{{"piece_a", name(i)}, {"piece_b", name(j)}, {"A", to_json(A)},
                                               {"certificate", certificate_json(cop)}});
                if (cop.copositive)
                    continue;
                const Vector z = interior_witness(A, cop.witness);
                const Vector s(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(c_));
                const Vector t(z.begin() + static_cast<std::ptrdiff_t>(c_), z.end());
                return refute(o, pair_witness(i, j, pieces_[i].R * s, pieces_[j].R * t));
            }
        if (fan_limit)
            throw *fan_limit;
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // nonexpansive-lemma: fan + P1 + every piece non-expansive (H - Q^T H Q PSD)

    Outcome nonexpansive_lemma() {
        Outcome o;
        o.method = "fan + P1 + H - Q^T H Q PSD per piece";
        if (auto w = domain_witness())
            return refute(o, std::move(*w));
        const Outcome continuity = p1();
        o.checks += continuity.checks;
        if (!continuity.proved) {
            Json w = continuity.counterexample;
            w["via"] = "P1";
            return refute(o, std::move(w));
        }
        for (std::size_t p = 0; p < pieces_.size(); ++p) {
            const Piece& pc = pieces_[p];
            const Matrix B = m_.H() - transpose(pc.Q) * m_.H() * pc.Q;
            const auto ldl = ldl_psd(B);
            ++o.checks;
            if (ldl.psd) {
                o.data["pieces"].push_back(Json{{"piece", name(p)}, {"matrix", to_json(B)},
                                                {"L", to_json(ldl.L)}, {"D", to_json(ldl.D)}});
                continue;
            }
            // Two interior points of the same cone, a - b along the expanding direction x.
            const Vector& x = ldl.witness;
            const Vector centre = pc.R * Vector(c_, Rational(1));
            Rational spread = 1;
            for (const auto& coeff : pc.R_inv * x)
                spread = std::max(spread, abs_of(coeff) + 1);
            const Rational eps = Rational(1) / (2 * spread);
            return refute(o, pair_witness(p, p, centre + eps * x, centre));
        }
        return o;
    }

    // -----------------------------------------------------------------------------------------
    // outcomes: declared experiments in ball velocities

    Outcome outcomes() {
        Outcome o;
        o.method = "exact impacts in ball velocities";
        for (const auto& decl : m_.law().outcomes) {
            const Vector gamma = m_.contact_velocities(decl.u_minus);
            const auto containing = m_.pieces_containing(gamma);
            if (containing.empty())
                return refute(o, Json{{"outcome", decl.name}, {"u_minus", to_json(decl.u_minus)},
                                      {"gamma_minus", to_json(gamma)},
                                      {"reason", "gamma- lies in no cone"}});
            // On a boundary every piece containing gamma- must give the declared u+.
            Json by_piece = Json::array();
            std::optional<std::size_t> wrong;
            for (auto p : containing) {
                const Vector u_plus =
                    m_.post_impact_velocities(decl.u_minus, gamma, pieces_[p].Q * gamma);
                ++o.checks;
                by_piece.push_back(Json{{"piece", name(p)}, {"u_plus", to_json(u_plus)}});
                if (u_plus != decl.u_plus && !wrong)
                    wrong = by_piece.size() - 1;
            }
            o.data["outcomes"].push_back(Json{{"outcome", decl.name}, {"gamma_minus", to_json(gamma)},
                                              {"pieces", by_piece}});
            if (wrong)
                return refute(o, Json{{"outcome", decl.name}, {"u_minus", to_json(decl.u_minus)},
                                      {"u_plus_declared", to_json(decl.u_plus)},
                                      {"piece", by_piece[*wrong]["piece"]},
                                      {"u_plus", by_piece[*wrong]["u_plus"]},
                                      {"pieces_at_gamma", by_piece}});
        }
        return o;
    }
};

} // namespace

VerifyReport verify(const Model& model, const Limits& limits, const Progress& progress,
                    const std::vector<std::string>* only) {
    return Prover(model, limits, progress, only).run();
}

} // namespace impactcert
