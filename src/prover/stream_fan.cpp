// SPDX-License-Identifier: GPL-3.0-or-later
// stream_fan.cpp -- verify --stream: the fan (Lemmas ST1 and ST2 of proofs/README.md, "Streamed
// laws") and the pieces containing the outcomes' gamma-, in one membership pass over the pieces.
#include "prover/stream.hpp"
#include "base/parallel.hpp"
#include "prover/stream_decide.hpp"

#include <algorithm>
#include <exception>
#include <thread>

namespace impactcert::stream {

using intk::i128;

namespace {

// The signs of R^-1 b for right-hand sides b (chosen columns of rhs), exactly: int64
// fraction-free elimination, else GMP.
class MembershipSigns {
  public:
    MembershipSigns(std::size_t c, const std::vector<std::vector<i64>>& rhs) : c_(c), rhs_(rhs) {}

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

} // namespace

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
        const auto g = intk::to_int_scaled(ex_.base.contact_velocities(outcomes[o].u_minus));
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
            MembershipSigns signs_of(c_, rhs);
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
        // (A share run again by run_shares writes the same flags: scan only assigns them.)
        run_shares(jobs, [&](std::size_t k) {
            scan(static_cast<u32>(n_ * k / jobs), static_cast<u32>(n_ * (k + 1) / jobs), k == 0);
        });
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

} // namespace impactcert::stream
