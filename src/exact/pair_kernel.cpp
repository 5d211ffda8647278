// SPDX-License-Identifier: GPL-3.0-or-later
// pair_kernel.cpp -- see pair_kernel.hpp. No floating point: GMP to prepare, int64 and
// __int128 with overflow checks to decide.
#include "exact/pair_kernel.hpp"

#include "exact/int_kernel.hpp"

#include <gmp.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace impactcert {

namespace {

using intk::fits;
using intk::i128;
using intk::i64;
using intk::to_i64;

// Positive integer multiples of the columns of two matrices with the same number of columns:
// column k of both is multiplied by the least positive rational making both integral and
// coprime (lcm of denominators, divided by the gcd of the numerators). Nothing when an entry
// then does not fit int64.
bool scale_columns(const Matrix& a, const Matrix& b, std::vector<i64>& out_a, std::vector<i64>& out_b) {
    const std::size_t rows_a = a.rows(), rows_b = b.rows(), cols = a.cols();
    out_a.assign(rows_a * cols, 0);
    out_b.assign(rows_b * cols, 0);
    mpz_t l, g, t;
    mpz_inits(l, g, t, nullptr);
    bool ok = true;
    for (std::size_t k = 0; k < cols && ok; ++k) {
        mpz_set_ui(l, 1);
        mpz_set_ui(g, 0);
        auto visit = [&](const Rational& x) {
            mpz_lcm(l, l, mpq_denref(x.mpq()));
        };
        for (std::size_t r = 0; r < rows_a; ++r)
            visit(a(r, k));
        for (std::size_t r = 0; r < rows_b; ++r)
            visit(b(r, k));
        // numerators after multiplying by l: x * l = num * (l / den)
        auto scaled = [&](const Rational& x, mpz_t into) {
            mpz_divexact(into, l, mpq_denref(x.mpq()));
            mpz_mul(into, into, mpq_numref(x.mpq()));
        };
        for (std::size_t r = 0; r < rows_a; ++r) {
            scaled(a(r, k), t);
            mpz_gcd(g, g, t);
        }
        for (std::size_t r = 0; r < rows_b; ++r) {
            scaled(b(r, k), t);
            mpz_gcd(g, g, t);
        }
        if (mpz_sgn(g) == 0)
            mpz_set_ui(g, 1);
        auto put = [&](const Rational& x, i64& into) {
            scaled(x, t);
            mpz_divexact(t, t, g);
            const auto v = to_i64(t);
            if (!v)
                ok = false;
            else
                into = *v;
        };
        for (std::size_t r = 0; r < rows_a && ok; ++r)
            put(a(r, k), out_a[r * cols + k]);
        for (std::size_t r = 0; r < rows_b && ok; ++r)
            put(b(r, k), out_b[r * cols + k]);
    }
    mpz_clears(l, g, t, nullptr);
    return ok;
}

// out = x^T y (x: n x p, y: n x q, row-major), checked. False on overflow.
bool transpose_product(const std::vector<i64>& x, const std::vector<i64>& y, std::size_t n, std::size_t p,
                       std::size_t q, std::vector<i64>& out) {
    out.assign(p * q, 0);
    for (std::size_t a = 0; a < p; ++a)
        for (std::size_t b = 0; b < q; ++b) {
            i128 s = 0;
            for (std::size_t r = 0; r < n; ++r)
                if (__builtin_add_overflow(s, static_cast<i128>(x[r * p + a]) * y[r * q + b], &s))
                    return false;
            if (!fits(s))
                return false;
            out[a * q + b] = static_cast<i64>(s);
        }
    return true;
}

} // namespace

std::optional<bool> int_psd(std::vector<i64>& a, std::size_t n) {
    // Bareiss: after the pivots used so far (all positive), the trailing entries are the
    // rational Schur complement times the last pivot used, hence of the same signs; the
    // division by the previous pivot is exact (Sylvester's identity).
    i64 prev = 1;
    for (std::size_t k = 0; k < n; ++k) {
        const i64 p = a[k * n + k];
        if (p < 0)
            return false;
        if (p == 0) {
            for (std::size_t j = k + 1; j < n; ++j)
                if (a[k * n + j] != 0)
                    return false;
            continue; // zero row: nothing to eliminate
        }
        for (std::size_t j = k + 1; j < n; ++j) {
            const i128 ajk = a[j * n + k];
            for (std::size_t l = j; l < n; ++l) {
                i128 t;
                if (__builtin_sub_overflow(static_cast<i128>(p) * a[j * n + l], ajk * a[k * n + l], &t))
                    return std::nullopt;
                if (t % prev != 0)
                    throw std::logic_error("fraction-free elimination: inexact division");
                t /= prev;
                if (!fits(t))
                    return std::nullopt;
                a[j * n + l] = static_cast<i64>(t);
                a[l * n + j] = static_cast<i64>(t);
            }
        }
        prev = p;
    }
    return true;
}

PairKernel::PairKernel(const Model& m, bool enabled) : c_(m.contacts()), enabled_(enabled) {
    if (!enabled_)
        return;
    // d H, d the least common denominator of H's entries (a positive scale: Lemma K1).
    const auto H_int = intk::to_int(m.H());
    if (!H_int) {
        enabled_ = false;
        return;
    }
    const std::vector<i64>& Hs = H_int->a;
    pieces_.resize(m.pieces().size());
    for (std::size_t p = 0; p < m.pieces().size(); ++p) {
        const Piece& piece = m.pieces()[p];
        PieceData& d = pieces_[p];
        const Matrix QR = piece.Q * piece.R;
        if (!scale_columns(piece.R, QR, d.R, d.QR))
            continue;
        // HR = Hs R (H symmetric: Hs^T R), E = R^T Hs R - QR^T Hs QR.
        std::vector<i64> RtHR, QRtHQR;
        d.ok = transpose_product(Hs, d.R, c_, c_, c_, d.HR) && transpose_product(Hs, d.QR, c_, c_, c_, d.HQR) &&
               transpose_product(d.R, d.HR, c_, c_, c_, RtHR) && transpose_product(d.QR, d.HQR, c_, c_, c_, QRtHQR);
        if (!d.ok)
            continue;
        d.E.resize(c_ * c_);
        for (std::size_t k = 0; k < c_ * c_ && d.ok; ++k)
            d.ok = !__builtin_sub_overflow(RtHR[k], QRtHQR[k], &d.E[k]);
        auto max_abs = [](const std::vector<i64>& v) {
            i128 largest = 0;
            for (const i64 x : v)
                largest = std::max(largest, x < 0 ? -static_cast<i128>(x) : static_cast<i128>(x));
            return largest;
        };
        d.max_R = max_abs(d.R);
        d.max_QR = max_abs(d.QR);
        d.max_HR = max_abs(d.HR);
        d.max_HQR = max_abs(d.HQR);
        d.E_nonnegative = true;
        for (const i64 x : d.E)
            d.E_nonnegative = d.E_nonnegative && x >= 0;
    }
    if (std::all_of(pieces_.begin(), pieces_.end(), [](const PieceData& d) { return d.ok; }))
        build_gram(m, Hs);
}

void PairKernel::build_gram(const Model& m, const std::vector<i64>& Hs) {
    // At most 1,024 distinct rays and images: two tables of at most 8 MB.
    constexpr std::size_t kMaxIds = 1024;
    const std::size_t c = c_, pieces = m.pieces().size();
    if (m.rays().size() > kMaxIds)
        return;
    std::vector<std::vector<i64>> rays, images;
    for (const auto& r : m.rays()) {
        auto v = intk::to_int_vector(r);
        if (!v)
            return;
        rays.push_back(std::move(*v));
    }
    std::map<std::vector<i64>, std::uint32_t> image_index;
    std::vector<std::uint32_t> ray_of(pieces * c), image_of(pieces * c);
    for (std::size_t p = 0; p < pieces; ++p) {
        const Piece& piece = m.pieces()[p];
        for (std::size_t k = 0; k < c; ++k) {
            auto w = intk::to_int_vector(piece.Q * piece.R.column(k));
            if (!w)
                return; // an image that is not integral (or too large): no tables
            auto [it, added] = image_index.emplace(*w, static_cast<std::uint32_t>(images.size()));
            if (added) {
                if (images.size() == kMaxIds)
                    return;
                images.push_back(std::move(*w));
            }
            ray_of[p * c + k] = static_cast<std::uint32_t>(piece.ray_ids[k]);
            image_of[p * c + k] = it->second;
        }
    }
    // x^T Hs y for every pair of a table, checked.
    const intk::IntMatrix dH{c, c, Hs, 1};
    auto table = [&](const std::vector<std::vector<i64>>& vs, std::vector<i64>& out) {
        const std::size_t n = vs.size();
        out.assign(n * n, 0);
        std::vector<i64> hy(c);
        for (std::size_t b = 0; b < n; ++b) {
            if (!intk::apply(dH, vs[b].data(), hy.data()))
                return false;
            for (std::size_t a = 0; a < n; ++a) {
                i128 sum = 0;
                for (std::size_t r = 0; r < c; ++r)
                    if (__builtin_add_overflow(sum, static_cast<i128>(vs[a][r]) * hy[r], &sum))
                        return false;
                if (!fits(sum))
                    return false;
                out[a * n + b] = static_cast<i64>(sum);
            }
        }
        return true;
    };
    if (!table(rays, gram_rays_) || !table(images, gram_images_)) {
        gram_rays_.clear();
        gram_images_.clear();
        return;
    }
    rays_ = rays.size();
    images_ = images.size();
    ray_of_.swap(ray_of);
    image_of_.swap(image_of);
    gram_ = true;
}

std::optional<bool> PairKernel::gram_nonnegative(std::size_t i, std::size_t j) const {
    if (!gram_ || !pieces_[i].E_nonnegative || !pieces_[j].E_nonnegative)
        return std::nullopt;
    // -F_xy = (Q_i r_x)^T H (Q_j s_y) - r_x^T H s_y, times d: two table entries.
    const std::size_t c = c_;
    const std::uint32_t *ri = &ray_of_[i * c], *rj = &ray_of_[j * c], *ii = &image_of_[i * c], *ij = &image_of_[j * c];
    for (std::size_t x = 0; x < c; ++x)
        for (std::size_t y = 0; y < c; ++y)
            if (gram_images_[ii[x] * images_ + ij[y]] < gram_rays_[ri[x] * rays_ + rj[y]])
                return false;
    return true;
}

std::size_t PairKernel::pieces_in_kernel() const {
    std::size_t n = 0;
    for (const auto& p : pieces_)
        n += p.ok ? 1 : 0;
    return n;
}

std::optional<CopositivityMethod> PairKernel::decide(std::size_t i, std::size_t j, Scratch& s) const {
    if (!enabled_ || !pieces_[i].ok || !pieces_[j].ok)
        return std::nullopt;
    const PieceData &a = pieces_[i], &b = pieces_[j];
    const std::size_t c = c_, n = 2 * c_;
    // Lemma K4: the common case (every entry >= 0) ends here; anything else goes the full way.
    if (gram_nonnegative(i, j).value_or(false))
        return CopositivityMethod::nonnegative_entries;
    // F = R_i^T H R_j - QR_i^T H QR_j (all scaled); A = [[E_i, -F], [-F^T, E_j]]. When the
    // bounds of the entries show that no partial sum can leave int64 (c terms of two products,
    // each below the bound), F is computed in plain int64 (the common case, vectorised);
    // otherwise in __int128 with every step checked.
    // With each maximum below 2^62, each product is below 2^124 and their sum below 2^125 (no
    // __int128 overflow); c times the sum stays below 2^62 iff the sum is below floor(2^62 / c).
    const i128 limit = i128{1} << 62;
    const bool small = a.max_R < limit && b.max_HR < limit && a.max_QR < limit && b.max_HQR < limit &&
                       a.max_R * b.max_HR + a.max_QR * b.max_HQR < limit / static_cast<i128>(c);
    s.F.assign(c * c, 0);
    bool nonnegative = a.E_nonnegative && b.E_nonnegative;
    for (std::size_t x = 0; x < c; ++x)
        for (std::size_t y = 0; y < c; ++y) {
            i64 minus_f;
            if (small) {
                i64 f = 0;
                for (std::size_t r = 0; r < c; ++r)
                    f += a.R[r * c + x] * b.HR[r * c + y] - a.QR[r * c + x] * b.HQR[r * c + y];
                minus_f = -f;
            } else {
                i128 f = 0;
                for (std::size_t r = 0; r < c; ++r) {
                    const i128 term = static_cast<i128>(a.R[r * c + x]) * b.HR[r * c + y] -
                                      static_cast<i128>(a.QR[r * c + x]) * b.HQR[r * c + y];
                    if (__builtin_add_overflow(f, term, &f))
                        return std::nullopt;
                }
                f = -f;
                if (!fits(f))
                    return std::nullopt;
                minus_f = static_cast<i64>(f);
            }
            s.F[x * c + y] = minus_f;
            nonnegative = nonnegative && minus_f >= 0;
        }
    if (nonnegative)
        return CopositivityMethod::nonnegative_entries;
    s.A.assign(n * n, 0);
    for (std::size_t r = 0; r < c; ++r)
        for (std::size_t k = 0; k < c; ++k) {
            s.A[r * n + k] = a.E[r * c + k];
            s.A[(c + r) * n + c + k] = b.E[r * c + k];
            s.A[r * n + c + k] = s.F[r * c + k];
            s.A[(c + k) * n + r] = s.F[r * c + k];
        }
    s.C = s.A;
    const auto psd = int_psd(s.C, n);
    if (!psd)
        return std::nullopt;
    if (*psd)
        return CopositivityMethod::psd;
    // P = A with its positive off-diagonal entries set to zero (N holds them).
    bool any_positive_off_diagonal = false;
    s.C = s.A;
    for (std::size_t x = 0; x < n; ++x)
        for (std::size_t y = 0; y < n; ++y)
            if (x != y && s.C[x * n + y] > 0) {
                s.C[x * n + y] = 0;
                any_positive_off_diagonal = true;
            }
    if (!any_positive_off_diagonal)
        return std::nullopt;
    const auto split = int_psd(s.C, n);
    if (split && *split)
        return CopositivityMethod::psd_plus_nonnegative;
    return std::nullopt;
}

} // namespace impactcert
