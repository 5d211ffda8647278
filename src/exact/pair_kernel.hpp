// SPDX-License-Identifier: GPL-3.0-or-later
// pair_kernel.hpp -- the pair forms of `nonexpansive` in machine integers (proofs/README.md,
// "Integer kernels").
//
// Contract: PairKernel scales a Model once: H by the least common denominator of its entries
// (d H), and each column r of each piece's ray matrix, together with its image Q_i r, by the
// least positive integer that makes both integral. The pair form of (i, j) then becomes
// D A D / d with D a positive diagonal matrix, which is copositive, PSD, entrywise >= 0 or
// PSD-plus-nonnegative exactly when A is (congruence by D, and D keeps every sign). decide(i, j)
// tries the cheap certificates of decide_copositivity in the same order, in int64 arithmetic
// with every product and sum checked for overflow (__int128 or __builtin_*_overflow). It
// returns the method that proves A copositive, or nothing: when an intermediate value does not
// fit, when none of the cheap certificates applies (the form may not be copositive, or needs
// the KKT enumeration), or when the kernel is disabled. The caller then decides A exactly over
// GMP, so verdicts, methods and witnesses are those of the rational path bit for bit.
// Thread-safe: decide() only reads the kernel (each call brings its own scratch).
#pragma once

#include "exact/copositivity.hpp"
#include "model/law.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace impactcert {

class PairKernel {
  public:
    // enabled = false: decide() always returns nothing (forces the GMP path everywhere).
    PairKernel(const Model& m, bool enabled);

    struct Scratch {
        std::vector<std::int64_t> A, C, F;
    };

    std::optional<CopositivityMethod> decide(std::size_t i, std::size_t j, Scratch& s) const;

    // How many pieces fit the kernel (their scaled data are int64); for reports and tests.
    std::size_t pieces_in_kernel() const;
    // Whether the Gram tables (Lemma K4) are in use; for tests.
    bool gram_tables() const { return gram_; }
    // The tables' answer for the pair (i, j): nothing without tables or when a diagonal block
    // has a negative entry; else whether every off-diagonal entry is >= 0 (then A >= 0).
    std::optional<bool> gram_nonnegative(std::size_t i, std::size_t j) const;

  private:
    std::size_t c_ = 0;
    bool enabled_ = false;
    // Gram tables (proofs/README.md, "Integer kernels", Lemma K4): when every image Q r of a ray
    // is integral and the distinct rays and images are few, the off-diagonal block of a pair form
    // is (Q_i r_x)^T H (Q_j s_y) - r_x^T H s_y, a difference of two table entries (times d).
    bool gram_ = false;
    std::size_t rays_ = 0, images_ = 0;
    std::vector<std::uint32_t> ray_of_, image_of_; // per piece, c ids
    std::vector<std::int64_t> gram_rays_, gram_images_; // d r^T H s, d w^T H v (row-major)
    void build_gram(const Model& m, const std::vector<std::int64_t>& Hs);
    struct PieceData {
        bool ok = false;
        std::vector<std::int64_t> R, QR, HR, HQR, E; // c x c row-major; E = R^T H R - QR^T H QR
        __extension__ __int128 max_R = 0, max_QR = 0, max_HR = 0, max_HQR = 0; // largest absolute entries
        bool E_nonnegative = false;
    };
    std::vector<PieceData> pieces_;
};

// int64 symmetric forms, exact: whether the n x n symmetric matrix `a` (row-major; destroyed)
// is positive semidefinite, by fraction-free symmetric elimination in the pivot order of
// ldl_psd. Nothing when an intermediate value overflows.
std::optional<bool> int_psd(std::vector<std::int64_t>& a, std::size_t n);

} // namespace impactcert
