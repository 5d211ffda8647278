// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz/fuzz_reference.hpp"

#include "exact/exact_double.hpp"

#include "fuzz/float_eval.hpp" // nearest_double
#include "fuzz/fuzz_impl.hpp"   // same_values

#include <gmp.h>

#include <algorithm>
#include <cassert>
#include <cfenv>
#if defined(__x86_64__) && defined(__SSE2__)
#include <xmmintrin.h>
#endif
#include <cmath>

namespace impactcert::fuzz {

namespace {

bool fits53(const mpz_t z) { return mpz_sizeinbase(z, 2) <= 53; } // |z| < 2^53

// lcm of the denominators of `row`, then the integer numerators; for a sign-only row the common
// factor is divided out as well. False when an entry or the denominator needs 53 bits or more.
bool to_int_row(const Vector& row, bool keep_denominator, eft::IntRow& out) {
    if (row.size() > eft::kMaxTerms)
        return false;
    mpz_t d, g, t;
    mpz_inits(d, g, t, nullptr);
    mpz_set_ui(d, 1);
    for (const auto& q : row)
        mpz_lcm(d, d, mpq_denref(q.mpq()));
    std::vector<Rational> ints;
    mpz_set_ui(g, 0);
    for (const auto& q : row) {
        Rational v = q * Rational(d);
        mpz_gcd(g, g, mpq_numref(v.mpq()));
        ints.push_back(v);
    }
    if (keep_denominator)
        mpz_gcd(g, g, d);
    bool ok = true;
    out.m = row.size();
    if (mpz_sgn(g) == 0) { // the zero row
        for (std::size_t j = 0; j < row.size(); ++j)
            out.a[j] = 0;
        out.d = 1;
    } else {
        for (std::size_t j = 0; j < row.size(); ++j) {
            mpz_divexact(t, mpq_numref(ints[j].mpq()), g);
            ok = ok && fits53(t);
            out.a[j] = ok ? mpz_get_d(t) : 0;
        }
        if (keep_denominator) {
            mpz_divexact(t, d, g);
            ok = ok && fits53(t);
            out.d = ok ? mpz_get_d(t) : 1;
        } else {
            out.d = 1;
        }
    }
    mpz_clears(d, g, t, nullptr);
    return ok;
}

std::vector<double> to_doubles(const Vector& v) {
    std::vector<double> out;
    for (const auto& q : v)
        out.push_back(nearest_double(q));
    return out;
}


inline void keep_value(RefPoint& out, std::size_t piece, const double* y, const bool* exact, std::size_t m) {
    for (std::size_t v = 0; v < out.values; ++v)
        if (same_values(out.value[v], y, m))
            return;
    if (out.values == kMaxValues)
        return;
    out.piece[out.values] = piece;
    for (std::size_t i = 0; i < m; ++i) { // short: a loop beats a call to memmove
        out.value[out.values][i] = y[i];
        out.exact[out.values][i] = exact[i];
    }
    ++out.values;
}

} // namespace

LawReference::Row LawReference::compact(const eft::IntRow& r, std::vector<eft::IntRow>& general) {
    // Simple rows are evaluated branch-free as a0 x_i0 + a1 x_i1, with a1 = 0 (one term) and
    // a0 = 0 (none): adding an exact zero changes nothing but the sign of a zero.
    Row row{r.terms, static_cast<std::uint32_t>(r.i0), static_cast<std::uint32_t>(r.i1),
            r.terms >= 1 ? r.a[r.i0] : 0.0, r.terms >= 2 ? r.a[r.i1] : 0.0, 0};
    if (r.terms < 0) {
        row.general = static_cast<std::uint32_t>(general.size());
        general.push_back(r);
    }
    return row;
}

void LawReference::build_planes() {
    std::vector<std::uint64_t> not_neg, not_pos;
    std::vector<eft::IntRow> planes;
    for (std::size_t p = 0; p < facets_.size(); ++p) {
        std::uint64_t nn = 0, np = 0;
        for (std::size_t i = 0; i < facets_[p].rows(); ++i) {
            eft::IntRow r;
            if (!to_int_row(facets_[p].row(i), false, r))
                return;
            std::size_t lead = 0;
            while (lead < r.m && r.a[lead] == 0)
                ++lead;
            const bool flip = lead < r.m && r.a[lead] < 0;
            if (flip)
                for (std::size_t j = 0; j < r.m; ++j)
                    r.a[j] = -r.a[j];
            r.prepare();
            std::size_t d = 0;
            while (d < planes.size() && !std::equal(r.a, r.a + r.m, planes[d].a))
                ++d;
            if (d == planes.size()) {
                if (planes.size() == 64)
                    return; // too many: the per-piece scan is used
                planes.push_back(r);
            }
            (flip ? np : nn) |= std::uint64_t{1} << d;
        }
        not_neg.push_back(nn);
        not_pos.push_back(np);
    }
    planes_ = std::move(planes);
    not_neg_ = std::move(not_neg);
    not_pos_ = std::move(not_pos);
    for (std::size_t d = 0; d < planes_.size(); ++d) {
        const eft::IntRow& r = planes_[d];
        Row row{r.terms, static_cast<std::uint32_t>(r.i0), static_cast<std::uint32_t>(r.i1),
                r.terms >= 1 ? r.a[r.i0] : 0.0, r.terms >= 2 ? r.a[r.i1] : 0.0, static_cast<std::uint32_t>(d)};
        plane_rows_.push_back(row);
    }
    const std::size_t k = planes_.size();
    if (continuous_ && k <= 7) {
        first_piece_.assign(std::size_t{1} << (2 * k), -1);
        for (std::size_t index = 0; index < first_piece_.size(); ++index) {
            const std::uint64_t neg = index & ((std::uint64_t{1} << k) - 1), pos = index >> k;
            for (std::size_t p = 0; p < not_neg_.size(); ++p)
                if (((neg & not_neg_[p]) | (pos & not_pos_[p])) == 0) {
                    first_piece_[index] = static_cast<std::int32_t>(p);
                    break;
                }
        }
    }
}

LawReference::LawReference(const Model& model, bool velocities, bool continuous_tiling)
    : model_(model), velocities_(velocities), continuous_(continuous_tiling) {
    const std::size_t c = model.contacts(), n = model.balls();
    in_dim_ = out_dim_ = velocities ? n : c;
    if (in_dim_ > kMaxDim)
        throw InputError("the fuzzer handles laws of at most " + std::to_string(kMaxDim) + " " +
                         (velocities ? "balls" : "contacts") + " (this one has " + std::to_string(in_dim_) + ")");
    const Matrix Wt = transpose(model.W());
    const Matrix lift = model.M_inv() * model.W() * model.H(); // n x c: gamma -> a u with W^T u = gamma
    for (const auto& piece : model.pieces()) {
        Matrix F = velocities ? piece.R_inv * Wt : piece.R_inv;
        Matrix A = velocities ? Matrix::identity(n) + lift * (piece.Q - Matrix::identity(c)) * Wt : piece.Q;
        Kernel k;
        for (std::size_t i = 0; i < F.rows(); ++i) {
            eft::IntRow r;
            fast_ = to_int_row(F.row(i), false, r) && fast_;
            r.prepare();
            k.facets.push_back(compact(r, k.general));
        }
        for (std::size_t i = 0; i < A.rows(); ++i) {
            eft::IntRow r;
            fast_ = to_int_row(A.row(i), true, r) && fast_;
            r.prepare();
            k.values.push_back(compact(r, k.general));
        }
        facets_.push_back(std::move(F));
        maps_.push_back(std::move(A));
        kernels_.push_back(std::move(k));
    }
    build_planes();
    // Geometry for the generators.
    geometry_.integer_rays = true;
    for (const auto& r : model.rays()) {
        const Vector v = velocities ? primitive_ray(lift * r) : r;
        for (const auto& q : v)
            geometry_.integer_rays = geometry_.integer_rays && mpz_cmp_ui(mpq_denref(q.mpq()), 1) == 0 &&
                                     mpz_sizeinbase(mpq_numref(q.mpq()), 2) <= 40;
        geometry_.rays.push_back(to_doubles(v));
    }
    for (std::size_t p = 0; p < model.pieces().size(); ++p) {
        const auto& piece = model.pieces()[p];
        geometry_.piece_rays.emplace_back(piece.ray_ids.begin(), piece.ray_ids.begin() + static_cast<std::ptrdiff_t>(c));
        for (std::size_t i = 0; i < c; ++i) {
            std::vector<std::size_t> ids;
            for (std::size_t j = 0; j < c; ++j)
                if (j != i)
                    ids.push_back(piece.ray_ids[j]);
            geometry_.facet_rays.push_back(ids);
            std::vector<double> normal = to_doubles(facets_[p].row(i));
            double big = 0;
            for (double x : normal)
                big = std::max(big, std::fabs(x));
            for (double& x : normal)
                x = big > 0 ? x / big : 0;
            geometry_.facet_normals.push_back(normal);
        }
    }
    if (velocities) {
        std::vector<Vector> rows;
        for (std::size_t i = 0; i < Wt.rows(); ++i)
            rows.push_back(Wt.row(i));
        for (const auto& k : null_space(rows, n))
            geometry_.kernel.push_back(to_doubles(k));
    }
}

namespace {

// The simple rows (eft::IntRow::prepare): exact by IEEE arithmetic itself.
inline double simple_value(int, double a0, double a1, double x0, double x1) { return a0 * x0 + a1 * x1; }

// IEEE round-to-nearest in effect? (SSE control word on x86-64: one instruction.)
[[maybe_unused]] inline bool round_to_nearest() {
#if defined(__x86_64__) && defined(__SSE2__)
    return (_mm_getcsr() & 0x6000u) == 0;
#else
    return std::fegetround() == FE_TONEAREST;
#endif
}

} // namespace

bool LawReference::fast_eval(const double* x, RefPoint& out, bool want_exact) const {
    // The scaled copy of x is made only when a row needs it (simple rows work on x itself).
    double xs[kMaxDim];
    int k = 0;
    int scaled = 0; // 0 not yet, 1 done, -1 impossible
    auto ensure_scaled = [&] {
        if (scaled == 0)
            scaled = eft::scale_into_safe_range(x, in_dim_, xs, k) ? 1 : -1;
        return scaled > 0;
    };
    // The exact sign of a facet row at x: simple rows by one IEEE operation, rows of 0/+-1 by a
    // filter on x itself, others on the scaled copy; kUndecided when x cannot be scaled (GMP).
    constexpr int kUndecided = 2;
    auto facet_sign = [&](const Row& row, const std::vector<eft::IntRow>& general) {
        if (row.terms >= 0) {
            const double v = simple_value(row.terms, row.a0, row.a1, x[row.i0], x[row.i1]);
            return v > 0 ? 1 : v < 0 ? -1 : 0;
        }
        const eft::IntRow& g = general[row.general];
        const int quick = g.unit ? g.unit_sign(x) : kUndecided;
        if (quick != kUndecided)
            return quick;
        return ensure_scaled() ? g.sign(xs) : kUndecided;
    };
    for (std::size_t j = 0; j < in_dim_; ++j)
        if (!std::isfinite(x[j]))
            return false;
    out.in_domain = false;
    out.slow = false;
    out.values = 0;
    double y[kMaxDim];
    bool exact[kMaxDim];
    // The sign of every distinct facet plane, once.
    std::uint64_t neg = 0, pos = 0;
    for (std::size_t d = 0; d < plane_rows_.size(); ++d) {
        // Simple rows straight from the double: no branch on the sign (this is the hot loop).
        const Row& row = plane_rows_[d];
        double sign;
        if (row.terms >= 0) {
            sign = simple_value(row.terms, row.a0, row.a1, x[row.i0], x[row.i1]);
        } else {
            const int exact_sign = facet_sign(row, planes_);
            if (exact_sign == kUndecided)
                return false;
            sign = exact_sign;
        }
        neg |= static_cast<std::uint64_t>(sign < 0) << d;
        pos |= static_cast<std::uint64_t>(sign > 0) << d;
    }
    std::size_t first = 0;
    if (!first_piece_.empty()) { // a table look-up (continuous tiling, few planes)
        const std::int32_t p = first_piece_[neg | pos << plane_rows_.size()];
        if (p < 0)
            return true; // in no cone
        first = static_cast<std::size_t>(p);
    }
    for (std::size_t p = first; p < kernels_.size(); ++p) {
        const Kernel& kp = kernels_[p];
        bool inside = true;
        if (!not_neg_.empty()) {
            if ((neg & not_neg_[p]) | (pos & not_pos_[p]))
                continue;
        } else {
            for (const Row& row : kp.facets) {
                const int sign = facet_sign(row, kp.general);
                if (sign == kUndecided)
                    return false;
                if (sign < 0) {
                    inside = false;
                    break;
                }
            }
        }
        if (!inside)
            continue;
        out.in_domain = true;
        for (std::size_t i = 0; i < out_dim_; ++i) {
            const Row& row = kp.values[i];
            if (row.terms >= 0) {
                y[i] = simple_value(row.terms, row.a0, row.a1, x[row.i0], x[row.i1]);
                exact[i] = true; // terms == 0: the value 0
                if (!want_exact) {
                } else if (row.terms == 1) {
                    exact[i] = std::fabs(row.a0) == 1 || std::fma(row.a0, x[row.i0], -y[i]) == 0;
                } else if (row.terms == 2) {
                    double sum, err;
                    eft::two_sum(row.a0 * x[row.i0], row.a1 * x[row.i1], sum, err);
                    exact[i] = std::isfinite(sum) && err == 0;
                }
            } else if (!ensure_scaled() || !kp.general[row.general].nearest(xs, k, y[i], exact[i])) {
                return false;
            }
        }
        keep_value(out, p, y, exact, out_dim_);
        if (continuous_)
            break;
    }
    return true;
}

void LawReference::eval(const double* x, RefPoint& out, bool want_exact) const {
    // The fast path is exact only under IEEE round-to-nearest: reading the control word costs
    // as much as a classification, so it is checked once per thread and call site batch by
    // the callers (fuzz::run per chunk, explain); here only in debug builds.
    assert(round_to_nearest());
    if (fast_ && fast_eval(x, out, want_exact))
        return;
    eval_exact(x, out);
}

bool LawReference::contains(std::size_t piece, const double* x) const {
    Vector xr;
    for (std::size_t j = 0; j < in_dim_; ++j)
        xr.push_back(exact_double(x[j], "fuzz reference"));
    const Vector s = facets_[piece] * xr;
    return std::all_of(s.begin(), s.end(), [](const Rational& t) { return sign_of(t) != Sign::negative; });
}

Vector LawReference::exact_value(const double* x, std::size_t piece) const {
    Vector xr;
    for (std::size_t j = 0; j < in_dim_; ++j)
        xr.push_back(exact_double(x[j], "fuzz reference"));
    return maps_[piece] * xr;
}

namespace {

// In-place GMP arithmetic for the exact path: no allocation per point once warmed up.
struct ExactScratch {
    std::vector<Rational> x;
    Rational acc, term;
};

// acc = sum_j row_j x_j (mpq in place).
void exact_row(const Matrix& A, std::size_t i, ExactScratch& s) {
    mpq_set_ui(s.acc.mpq(), 0, 1);
    for (std::size_t j = 0; j < A.cols(); ++j) {
        if (mpq_sgn(A(i, j).mpq()) == 0 || mpq_sgn(s.x[j].mpq()) == 0)
            continue;
        mpq_mul(s.term.mpq(), A(i, j).mpq(), s.x[j].mpq());
        mpq_add(s.acc.mpq(), s.acc.mpq(), s.term.mpq());
    }
}

} // namespace

void LawReference::eval_exact(const double* x, RefPoint& out) const {
    out.in_domain = false;
    out.slow = true;
    out.values = 0;
    thread_local ExactScratch s;
    s.x.resize(in_dim_);
    for (std::size_t j = 0; j < in_dim_; ++j)
        set_exact(s.x[j].mpq(), x[j], "fuzz reference"); // exact: a finite double is a dyadic rational
    double y[kMaxDim];
    bool exact[kMaxDim];
    for (std::size_t p = 0; p < facets_.size(); ++p) {
        bool inside = true;
        for (std::size_t i = 0; i < facets_[p].rows() && inside; ++i) {
            exact_row(facets_[p], i, s);
            inside = mpq_sgn(s.acc.mpq()) >= 0;
        }
        if (!inside)
            continue;
        out.in_domain = true;
        for (std::size_t i = 0; i < out_dim_; ++i) {
            exact_row(maps_[p], i, s);
            y[i] = nearest_double(s.acc);
            exact[i] = std::isfinite(y[i]) && mpq_cmp(exact_double(y[i], "fuzz reference").mpq(), s.acc.mpq()) == 0;
        }
        keep_value(out, p, y, exact, out_dim_);
        if (continuous_)
            break;
    }
}

void LawReference::formula(std::size_t piece, const double* x, double* y) const {
    double xs[kMaxDim];
    int k = 0;
    if (fast_ && eft::scale_into_safe_range(x, in_dim_, xs, k)) {
        bool ok = true, exact = false;
        for (std::size_t i = 0; i < out_dim_ && ok; ++i)
        {
            const Row& row = kernels_[piece].values[i];
            if (row.terms >= 0)
                y[i] = simple_value(row.terms, row.a0, row.a1, x[row.i0], x[row.i1]);
            else
                ok = kernels_[piece].general[row.general].nearest(xs, k, y[i], exact);
        }
        if (ok)
            return;
    }
    const Vector v = exact_value(x, piece);
    for (std::size_t i = 0; i < out_dim_; ++i)
        y[i] = nearest_double(v[i]);
}

} // namespace impactcert::fuzz
