// stream_verify.cpp -- verify --stream (stream.hpp): every obligation of a compact law by passes
// over the ids of its pieces. The lemmas are in proofs/README.md, "Streamed laws"; the symmetry
// reductions in "Symmetries"; the fan criterion in "fan" (Check, any c).
//
//   symmetries   (i) before the expansion (an input error, as Model); (ii) by construction;
//                (iii) at every (piece, symmetry) while closing (stream_store.cpp).
//   fan          facet matching on the facets of the orbit representatives (Lemma ST1), and one
//                point interior to a representative and in no other closed cone (Lemma ST2).
//   P1           face to face (the fan): all pieces containing a ray give it one image.
//   P3, kinematic, kinetic   every piece, through memos by image id and (ray, image) ids.
//   P2, energetic            the listed pieces, by verify() on them (Lemma S3).
//   identities, single-impacts   verify() on a model of the pieces they name.
//   nonexpansive the pairs (representative, any piece); with P2 each form has zero diagonal
//                blocks, so it is copositive iff its off-diagonal block is >= 0 (Lemma ST3),
//                whose entries are differences of two Gram tables.
//   nonexpansive-lemma   fan + P1 + H - Q^T H Q PSD on the listed pieces.
//   outcomes     the first piece containing gamma- (one value: P1).
#include "copositivity.hpp"
#include "stream.hpp"
#include "stream_store.hpp"

#include <algorithm>
#include <chrono>
#include <exception>
#include <map>
#include <thread>
#include <set>
#include <unordered_map>

namespace impactcert {

using stream::Expansion;
using stream::kNone;
using stream::u32;
using intk::i64;
using intk::i128;

namespace {

constexpr const char* kRerun = " (verify without --stream decides it, memory permitting)";
constexpr std::size_t kMaxOrbits = 64;

struct Decision {
    Verdict verdict = Verdict::proved;
    std::size_t checks = 0;
    std::string method;
    Json counterexample;
    std::string limit;
    std::chrono::nanoseconds elapsed{0}; // of the pass that decided it (shared passes: the first obligation)
};

Decision undecided(Decision d, const std::string& why) {
    d.verdict = Verdict::undecided;
    d.limit = why + kRerun;
    return d;
}

Decision refuted(Decision d, Json witness) {
    d.verdict = Verdict::refuted;
    d.counterexample = std::move(witness);
    return d;
}

void ensure(bool ok, const char* what) {
    if (!ok)
        throw std::logic_error(std::string("internal witness check failed (--stream): ") + what);
}

// The signs of R^-1 b for right-hand sides b (chosen columns of rhs), exactly: int64
// fraction-free elimination, else GMP.
class Signs {
  public:
    Signs(std::size_t c, const std::vector<std::vector<i64>>& rhs) : c_(c), rhs_(rhs) {}

    // signs[b][k] in {-1, 0, 1}: the sign of (R_p^-1 rhs[cols[b]])_k
    void of(const Expansion& ex, u32 p, const std::vector<std::size_t>& cols, std::vector<std::vector<int>>& signs) {
        const std::size_t w = c_ + cols.size();
        m_.assign(c_ * w, 0);
        for (std::size_t k = 0; k < c_; ++k) {
            const auto& r = ex.rays[ex.store.rays(p)[k]];
            for (std::size_t i = 0; i < c_; ++i)
                m_[i * w + k] = r[i];
        }
        for (std::size_t b = 0; b < cols.size(); ++b)
            for (std::size_t i = 0; i < c_; ++i)
                m_[i * w + c_ + b] = rhs_[cols[b]][i];
        i64 det = 0;
        signs.resize(cols.size());
        for (auto& v : signs)
            v.resize(c_);
        const auto e = intk::gauss_jordan(m_, c_, w, det);
        if (e == intk::Elimination::singular)
            throw std::logic_error("stream: a stored cone is not full-dimensional");
        if (e == intk::Elimination::solved) {
            const int sd = det > 0 ? 1 : -1;
            for (std::size_t b = 0; b < cols.size(); ++b)
                for (std::size_t k = 0; k < c_; ++k) {
                    const i64 v = m_[k * w + c_ + b];
                    signs[b][k] = v == 0 ? 0 : (v > 0 ? sd : -sd);
                }
            return;
        }
        const Matrix R = ex.R(p);
        for (std::size_t b = 0; b < cols.size(); ++b) {
            const auto x = solve(R, intk::to_vector(rhs_[cols[b]]));
            if (!x)
                throw std::logic_error("stream: a stored cone is not full-dimensional");
            for (std::size_t k = 0; k < c_; ++k)
                signs[b][k] = static_cast<int>(sign_of((*x)[k]));
        }
    }

  private:
    std::size_t c_;
    const std::vector<std::vector<i64>>& rhs_;
    std::vector<i64> m_;
};

// An integer vector of the direction of v (v scaled by the lcm of its denominators), in int64.
std::optional<std::vector<i64>> integral(const Vector& v) {
    mpz_class l = 1;
    for (const auto& x : v)
        mpz_lcm(l.get_mpz_t(), l.get_mpz_t(), mpq_denref(x.mpq()));
    Vector scaled;
    const Rational L{CGAL::Gmpz(l.get_mpz_t())};
    for (const auto& x : v)
        scaled.push_back(x * L);
    return intk::to_int_vector(scaled);
}

class Streamed {
  public:
    Streamed(Expansion& ex, const Limits& limits, const Progress& progress)
        : ex_(ex), c_(ex.c), n_(ex.store.size()), limits_(limits), progress_(progress) {}

    std::map<std::string, Decision> run();

  private:
    Expansion& ex_;
    std::size_t c_, n_;
    const Limits& limits_;
    const Progress& progress_;
    std::map<std::string, Decision> d_;

    void report(const char* id, std::size_t done) const {
        if (progress_ && done % 65536 == 0)
            progress_(id, std::to_string(done) + "/" + std::to_string(n_));
    }
    bool proved(const char* id) const { return d_.at(id).verdict == Verdict::proved; }

    Law side_law() const {
        Law s;
        s.name = ex_.law.name;
        s.masses = ex_.law.masses;
        s.M = ex_.law.M;
        s.W = ex_.law.W;
        return s;
    }
    // verify() on a model of the given pieces, for the obligations in `ids`.
    VerifyReport side_verify(Law law, const std::vector<std::string>& ids) const {
        Limits l = limits_;
        l.evidence = false;
        const Model m(std::move(law), limits_.max_pieces, limits_.max_memory_mb);
        return verify(m, l, {}, &ids);
    }
    // A per-piece check failed on piece p: verify()'s own witness, on the one-piece model.
    Json piece_witness(u32 p, const std::string& id) const {
        Law one = side_law();
        one.pieces.push_back(ex_.decl(p));
        const VerifyReport r = side_verify(std::move(one), {id});
        ensure(r.at(id).verdict == Verdict::refuted, "the one-piece model refutes what the stream refuted");
        return r.at(id).counterexample;
    }
    Json pair_witness(u32 a, u32 b, const Matrix& Qa, const Matrix& Qb, const Vector& ga, const Vector& gb) const;
    bool in_interior(u32 p, const Vector& x) const {
        const auto s = solve(ex_.R(p), x);
        return s && std::all_of(s->begin(), s->end(), [](const Rational& v) { return sign_of(v) == Sign::positive; });
    }

    void symmetries();
    void membership(); // fan and outcomes
    void by_rays();    // P1, P3, kinematic, kinetic
    void by_listed();  // P2, energetic, identities, single-impacts
    void nonexpansive();
    void nonexpansive_lemma();

    // membership's findings, for the outcomes
    std::vector<u32> outcome_piece_; // first piece containing gamma-, kNone if none
};

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

// Lemma ST1 (the facet criterion on the representatives' facets) and Lemma ST2 (a test point
// interior to one representative and in no other closed cone), with the outcomes' gamma- in the
// same pass.
void Streamed::membership() {
    constexpr std::size_t kPoints = 4;
    const u32 rep0 = ex_.representatives.front();
    // Test points p_t = R_rep0 (1, t, ..., t^(c-1)), t = 1..4: interior to C_rep0. The first
    // (the sum of the rays) must fit int64; a later one that does not is left out.
    std::vector<std::vector<i64>> rhs;
    for (std::size_t t = 1; t <= kPoints; ++t) {
        std::vector<i128> v(c_, 0);
        i128 power = 1;
        bool fits = true;
        for (std::size_t k = 0; k < c_ && fits; ++k) {
            const auto& r = ex_.rays[ex_.store.rays(rep0)[k]];
            for (std::size_t i = 0; i < c_ && fits; ++i) {
                v[i] += power * r[i]; // |power|, |r[i]| < 2^63 and |v[i]| < 2^63 before: no i128 overflow
                fits = intk::fits(v[i]);
            }
            if (k + 1 < c_) {
                power *= static_cast<i128>(t);
                fits = fits && intk::fits(power);
            }
        }
        if (!fits && t == 1)
            throw StreamRefused("the fan's test point (the sum of the first representative's rays) leaves int64");
        if (!fits)
            break;
        rhs.emplace_back(v.begin(), v.end());
    }
    const std::size_t point_count = rhs.size();
    const auto& outcomes = ex_.law.outcomes;
    for (std::size_t o = 0; o < outcomes.size(); ++o) {
        const auto g = integral(ex_.base.contact_velocities(outcomes[o].u_minus));
        if (!g)
            throw StreamRefused("gamma- of outcome " + in_quotes(outcomes[o].name) + " leaves int64 (--stream keeps it in int64)");
        rhs.push_back(*g);
    }
    const std::size_t outcome_column = point_count; // outcome o is column point_count + o
    // Facets of the representatives: pos[r][ray id] = 1 + the ray's position in representative r.
    const auto& reps = ex_.representatives;
    const std::size_t max_bytes = limits_.max_memory_mb > (SIZE_MAX >> 20) ? SIZE_MAX : limits_.max_memory_mb << 20;
    const std::size_t facet_bytes = reps.size() * ex_.rays.size();
    const bool facet_tables = ex_.bytes <= max_bytes && facet_bytes <= max_bytes - ex_.bytes;
    std::vector<std::vector<unsigned char>> pos(facet_tables ? reps.size() : 0,
                                                std::vector<unsigned char>(ex_.rays.size(), 0));
    for (std::size_t r = 0; r < pos.size(); ++r)
        for (std::size_t k = 0; k < c_; ++k)
            pos[r][ex_.store.rays(reps[r])[k]] = static_cast<unsigned char>(k + 1);

    // The exact solves, in `jobs` threads over consecutive ranges of pieces: each thread only
    // fills the flags of its own pieces (flags[j * width + b]: for a test point 2 interior, 1 on
    // the boundary, 0 outside; for an outcome 1 when the piece contains its gamma-, evaluated
    // until the range's first). Everything else is read from the flags in one pass in piece
    // order, so the result cannot depend on the threads.
    auto solve_all = [&](const std::vector<std::size_t>& points, bool with_outcomes, std::vector<unsigned char>& flags) {
        const std::size_t width = points.size() + (with_outcomes ? outcomes.size() : 0);
        flags.assign(n_ * width, 0);
        auto scan = [&](u32 lo, u32 hi, bool progress) {
            Signs signs_of(c_, rhs);
            std::vector<std::vector<int>> signs;
            std::vector<std::size_t> cols;
            std::vector<char> found(outcomes.size(), 0);
            std::size_t missing = with_outcomes ? outcomes.size() : 0;
            for (u32 j = lo; j < hi; ++j) {
                if (progress)
                    report("fan", j);
                cols = points;
                for (std::size_t o = 0; missing && o < outcomes.size(); ++o)
                    if (!found[o])
                        cols.push_back(outcome_column + o);
                signs_of.of(ex_, j, cols, signs);
                unsigned char* f = &flags[std::size_t{j} * width];
                for (std::size_t t = 0; t < points.size(); ++t) {
                    const bool inside = std::all_of(signs[t].begin(), signs[t].end(), [](int v) { return v > 0; });
                    const bool closed = std::all_of(signs[t].begin(), signs[t].end(), [](int v) { return v >= 0; });
                    f[t] = inside ? 2 : closed ? 1 : 0;
                }
                for (std::size_t b = points.size(); b < cols.size(); ++b)
                    if (std::all_of(signs[b].begin(), signs[b].end(), [](int v) { return v >= 0; })) {
                        const std::size_t o = cols[b] - outcome_column;
                        f[points.size() + o] = 1;
                        found[o] = 1;
                        --missing;
                    }
            }
        };
        const std::size_t jobs = std::max<std::size_t>(1, std::min<std::size_t>(limits_.jobs, n_ / 1024 + 1));
        std::vector<std::thread> threads;
        std::vector<std::exception_ptr> errors(jobs);
        try {
            for (std::size_t k = 1; k < jobs; ++k)
                threads.emplace_back([&, k] {
                    try {
                        scan(static_cast<u32>(n_ * k / jobs), static_cast<u32>(n_ * (k + 1) / jobs), false);
                    } catch (...) {
                        errors[k] = std::current_exception();
                    }
                });
        } catch (...) { // a thread that could not start: join the others, then report
            for (auto& t : threads)
                t.join();
            throw;
        }
        try {
            scan(0, static_cast<u32>(n_ / jobs), true);
        } catch (...) {
            errors[0] = std::current_exception();
        }
        for (auto& t : threads)
            t.join();
        for (auto& e : errors)
            if (e)
                std::rethrow_exception(e);
        return width;
    };
    // The pass in piece order: the pieces whose interior holds each test point, whether one has
    // it on its boundary, the first piece containing each gamma-, and the representatives'
    // facets (the pieces with c - 1 of their rays).
    std::vector<std::vector<u32>> interior_of;
    std::vector<bool> on_boundary;
    auto read_points = [&](const std::vector<unsigned char>& flags, std::size_t width, std::size_t count) {
        for (std::size_t t = 0; t < count; ++t) {
            interior_of.emplace_back();
            on_boundary.push_back(false);
            for (u32 j = 0; j < n_; ++j) {
                const unsigned char f = flags[std::size_t{j} * width + t];
                if (f == 2)
                    interior_of.back().push_back(j);
                else if (f == 1)
                    on_boundary.back() = true;
            }
        }
    };
    std::vector<unsigned char> flags;
    const std::size_t width = solve_all({0}, true, flags);
    read_points(flags, width, 1);
    outcome_piece_.assign(outcomes.size(), kNone);
    for (std::size_t o = 0; o < outcomes.size(); ++o)
        for (u32 j = 0; j < n_ && outcome_piece_[o] == kNone; ++j)
            if (flags[std::size_t{j} * width + 1 + o])
                outcome_piece_[o] = j;
    std::vector<std::vector<std::size_t>> facet_count(reps.size(), std::vector<std::size_t>(c_, 0));
    std::vector<std::vector<u32>> extra(reps.size(), std::vector<u32>(c_, kNone));
    std::vector<char> hit(c_);
    for (u32 j = 0; j < n_; ++j)
        for (std::size_t r = 0; r < pos.size(); ++r) {
            if (j == reps[r])
                continue;
            std::fill(hit.begin(), hit.end(), 0);
            std::size_t shared = 0;
            u32 other = kNone;
            for (std::size_t k = 0; k < c_; ++k) {
                const u32 id = ex_.store.rays(j)[k];
                if (pos[r][id]) {
                    hit[pos[r][id] - 1] = 1;
                    ++shared;
                } else {
                    other = id;
                }
            }
            if (shared + 1 != c_)
                continue;
            const auto missing = static_cast<std::size_t>(std::find(hit.begin(), hit.end(), 0) - hit.begin());
            if (facet_count[r][missing]++ == 0)
                extra[r][missing] = other;
        }
    // The other test points only when the first lies on another cone's boundary.
    if (on_boundary[0] && interior_of[0].size() == 1 && point_count > 1) {
        std::vector<std::size_t> more;
        for (std::size_t t = 1; t < point_count; ++t)
            more.push_back(t);
        const std::size_t w = solve_all(more, false, flags);
        read_points(flags, w, more.size());
    }

    Decision fan;
    fan.method = "facet-matching on the orbit representatives' facets, by the symmetries, and one point "
                 "interior to one cone only (streamed)";
    fan.checks = reps.size() * c_ + n_ * interior_of.size();
    // Two interiors that meet refute the tiling, whatever else holds (Lemma T).
    for (std::size_t t = 0; t < interior_of.size(); ++t) {
        ensure(std::find(interior_of[t].begin(), interior_of[t].end(), rep0) != interior_of[t].end(),
               "fan: the test point is interior to its representative");
        if (interior_of[t].size() > 1) {
            const Vector x = intk::to_vector(rhs[t]);
            Json names = Json::array();
            for (auto p : interior_of[t]) {
                ensure(in_interior(p, x), "fan: the test point is interior");
                names.push_back(ex_.name(p));
            }
            d_["fan"] = refuted(fan, Json{{"gamma", to_json(x)}, {"interior_of", names}});
            return;
        }
    }
    if (!proved("symmetries")) {
        d_["fan"] = undecided(fan, "--stream decides the fan through the symmetries, which are refuted");
        return;
    }
    if (!facet_tables) {
        d_["fan"] = undecided(fan, "the facet tables of " + std::to_string(reps.size()) + " orbits need " +
                                       std::to_string((facet_bytes >> 20) + 1) + " MB beyond --max-memory (raise it with --max-memory)");
        return;
    }
    for (std::size_t r = 0; r < reps.size(); ++r)
        for (std::size_t k = 0; k < c_; ++k) {
            bool matched = facet_count[r][k] == 1;
            if (matched) {
                std::vector<Vector> cols;
                for (std::size_t l = 0; l < c_; ++l)
                    if (l != k)
                        cols.push_back(ex_.ray(ex_.store.rays(reps[r])[l]));
                cols.push_back(ex_.ray(ex_.store.rays(reps[r])[k]));
                const Sign own = sign_of(determinant(Matrix::from_columns(cols)));
                cols.back() = ex_.ray(extra[r][k]);
                const Sign other = sign_of(determinant(Matrix::from_columns(cols)));
                matched = own != Sign::zero && other != Sign::zero && own != other;
            }
            if (!matched) {
                d_["fan"] = undecided(fan, "the facet of " + in_quotes(ex_.name(reps[r])) + " opposite its ray " +
                                               std::to_string(k + 1) + " is not matched by exactly one cone on its "
                                               "other side (--stream has only the facet-matching check)");
                return;
            }
        }
    for (std::size_t t = 0; t < interior_of.size(); ++t)
        if (!on_boundary[t]) { // interior to rep0 alone, and in no other closed cone
            d_["fan"] = fan;
            return;
        }
    d_["fan"] = undecided(fan, "each of the " + std::to_string(interior_of.size()) + " test points lies on the boundary of another cone");
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
        bool fits = true;
        for (std::size_t k = 0; k < g_ray.size() && fits; ++k) {
            const Rational x = g_ray[k] * L;
            const auto v = intk::to_i64(mpq_numref(x.mpq()));
            fits = v.has_value();
            t_ray[k] = v.value_or(0);
        }
        for (std::size_t k = 0; k < g_img.size() && fits; ++k) {
            const Rational x = g_img[k] * L;
            const auto v = intk::to_i64(mpq_numref(x.mpq()));
            fits = v.has_value();
            t_img[k] = v.value_or(0);
        }
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
        // Two interior points of the same cone, a - b along the expanding direction x.
        const Vector& x = ldl.witness;
        const Vector centre = pc.R * Vector(c_, Rational(1));
        Rational spread = 1;
        for (const auto& coeff : pc.R_inv * x)
            spread = std::max(spread, abs_of(coeff) + 1);
        const Rational eps = Rational(1) / (2 * spread);
        d_["nonexpansive-lemma"] = refuted(d, pair_witness(p, p, pc.Q, pc.Q, centre + eps * x, centre));
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

} // namespace

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
            const Decision& d = decisions.at(id);
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
