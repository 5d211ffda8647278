// SPDX-License-Identifier: GPL-3.0-or-later
// fuzz_reference.hpp -- the exact value of any law at double inputs, correctly rounded, fast.
//
// Contract:
//   - A LawReference is built from a validated Model, in one of two spaces: contact velocities
//     (x = gamma-, y = gamma+, c doubles each) or ball velocities (x = u-, y = u+, n doubles
//     each; y = A_p x with A_p = I + M^-1 W H (Q_p - I) W^T on the cone {x : R_p^-1 W^T x >= 0}).
//   - eval(x) returns the pieces whose closed cones contain x and, for each distinct value, the
//     double nearest to the exact value (ties to even; +-inf beyond the double range, as IEEE
//     rounding gives). When the law is declared continuous on a tiling (`fan` and `P1` proved),
//     the first piece containing x is the only one evaluated; otherwise every containing piece
//     is, and values that differ are all kept (S is several-valued on such a boundary).
//   - The fast path is exact: every sign and rounding is decided with error-free transformations
//     (eft.hpp) on integer rows; whatever it cannot decide exactly (inputs spanning more than
//     ~970 binades, results outside the normal range, rows with entries >= 2^53) goes through GMP.
//     eval_exact() is the GMP path alone: the naive reference, used by tests and benchmarks.
//   - exact_value(x, piece) gives the exact rational output, for the rare exact comparisons the
//     fuzzer makes (a stated error bound, a tolerance at its edge).
#pragma once

#include "exact/eft.hpp"
#include "model/law.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace impactcert::fuzz {

inline constexpr std::size_t kMaxDim = 32;   // inputs and outputs of at most 32 doubles
inline constexpr std::size_t kMaxValues = 4; // distinct values kept where a law is several-valued

struct RefPoint {
    bool in_domain = false;     // some piece contains x (false only in a gap of a law not a tiling)
    bool slow = false;          // decided through GMP
    std::size_t values = 0;     // distinct values kept (1 for a continuous law)
    std::size_t piece[kMaxValues] = {};
    double value[kMaxValues][kMaxDim] = {};
    bool exact[kMaxValues][kMaxDim] = {}; // value equals the exact value (no rounding); see set_want_exact
};

class LawReference {
  public:
    LawReference(const Model& model, bool velocities, bool continuous_tiling);

    std::size_t in_dim() const { return in_dim_; }
    std::size_t out_dim() const { return out_dim_; }
    bool velocities() const { return velocities_; }
    bool fast_path() const { return fast_; } // every row fits the integer kernels
    const Model& model() const { return model_; }

    // Requires IEEE round-to-nearest (std::fesetround(FE_TONEAREST); the fuzzer's threads and
    // explain() set it). want_exact: fill RefPoint::exact (false: the flags of simple rows are left true; the
    // fuzzer needs them only to check a stated bound).
    void eval(const double* x, RefPoint& out, bool want_exact = true) const;
    void eval_exact(const double* x, RefPoint& out) const;
    Vector exact_value(const double* x, std::size_t piece) const;
    bool contains(std::size_t piece, const double* x) const; // exact, closed cone
    // The correctly rounded value of piece p's formula at x (whether or not x lies in its cone):
    // a diagnostic for "the output is another piece's formula".
    void formula(std::size_t piece, const double* x, double* y) const;

    // Input-space geometry for the generators (doubles, informational, not exact):
    struct Geometry {
        std::vector<std::vector<double>> rays;             // rays of the cones, in input space
        std::vector<std::vector<std::size_t>> piece_rays;  // per piece: its rays (indices)
        std::vector<std::vector<std::size_t>> facet_rays;  // per facet (piece p's side i is p c + i): its rays
        std::vector<std::vector<double>> facet_normals;    // per facet: an inward normal
        std::vector<std::vector<double>> kernel;           // velocities: directions all cones contain
        bool integer_rays = false;                         // rays are exact small integers
    };
    const Geometry& geometry() const { return geometry_; }

  private:
    struct Row { // compact: a simple row inline, or the index of a general one
        int terms;   // as eft::IntRow::terms; -1: general, see `general`
        std::uint32_t i0, i1;
        double a0, a1;
        std::uint32_t general;
    };
    struct Kernel { // the integer rows of one piece (fast path)
        std::vector<Row> facets, values;
        std::vector<eft::IntRow> general;
    };
    const Model& model_;
    bool velocities_, continuous_, fast_ = true;
    std::size_t in_dim_ = 0, out_dim_ = 0;
    std::vector<Matrix> facets_; // per piece: rows are inward facet normals (input space)
    std::vector<Matrix> maps_;   // per piece: the output map (input -> output)
    std::vector<Kernel> kernels_;
    // Cones share facet hyperplanes. When there are at most 64 distinct ones (up to sign), each
    // sign is decided once per point into masks `neg`, `pos`; piece p contains x iff
    // (neg & not_neg_[p]) | (pos & not_pos_[p]) == 0. With at most 7 of them and a continuous
    // tiling, first_piece_[neg | pos << k] is the first piece containing x (-1: none).
    std::vector<eft::IntRow> planes_;     // first non-zero entry positive
    std::vector<Row> plane_rows_;         // compact forms (general ones index planes_)
    std::vector<std::uint64_t> not_neg_, not_pos_;
    std::vector<std::int32_t> first_piece_;
    Geometry geometry_;

    bool fast_eval(const double* x, RefPoint& out, bool want_exact) const;
    static Row compact(const eft::IntRow& r, std::vector<eft::IntRow>& general);
    void build_planes();
};

} // namespace impactcert::fuzz
