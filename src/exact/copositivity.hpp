// SPDX-License-Identifier: GPL-3.0-or-later
// copositivity.hpp -- exact decisions on quadratic forms: PSD (by LDL^T) and copositivity.
//
// Contract (proofs/README.md, "Exact copositivity", argues each step):
//   - ldl_psd(A): A symmetric. Decides A >= 0 (positive semidefinite). When PSD, returns
//     A = L diag(D) L^T exactly, L unit lower triangular, D >= 0. When not, returns x with
//     x^T A x < 0.
//   - decide_copositivity(A): A symmetric. Decides z^T A z >= 0 for all z >= 0. Cheap
//     certificates first (A >= 0 entrywise; A PSD; A = P + N with N the positive off-diagonal
//     part and P PSD), then the complete KKT enumeration over all 2^N - 1 faces of the simplex.
//     When not copositive, returns z >= 0 with sum z = 1 and z^T A z < 0 (the exact minimum).
//   - interior_witness(A, z): from z >= 0 with z^T A z < 0, a z' > 0 (every entry) with
//     z'^T A z' < 0.
// No floating point anywhere.
#pragma once

#include "base/limits.hpp"
#include "exact/matrix.hpp"

#include <vector>

namespace impactcert {

struct LdlResult {
    bool psd = false;
    Matrix L;        // unit lower triangular; meaningful when psd
    Vector D;        // diagonal, all >= 0 when psd
    Vector witness;  // when !psd: x^T A x < 0
};

LdlResult ldl_psd(const Matrix& A);

enum class CopositivityMethod { nonnegative_entries, psd, psd_plus_nonnegative, kkt_enumeration };
const char* to_string(CopositivityMethod m);

struct KktCandidate {
    std::vector<std::size_t> support; // J: indices where x > 0
    Vector x;                         // minimiser on the relative interior of face J, sum 1
    Rational value;                   // mu = x^T A_JJ x
};

struct CopositivityResult {
    bool copositive = false;
    CopositivityMethod method = CopositivityMethod::kkt_enumeration;
    LdlResult ldl;                       // the PSD part (psd, psd_plus_nonnegative)
    Matrix N;                            // the non-negative part (psd_plus_nonnegative)
    std::vector<KktCandidate> candidates; // every valid KKT candidate (kkt_enumeration)
    std::size_t faces = 0;               // faces of the simplex examined (kkt_enumeration)
    Vector witness;                      // when !copositive: z >= 0, sum 1, z^T A z < 0
    Rational minimum;                    // kkt_enumeration: min of z^T A z over the simplex
};

// Throws LimitExceeded (limits.hpp) when the KKT enumeration would examine more than
// `max_faces` faces (the cheap certificates are tried first, whatever the size).
// integer_kernel: solve the KKT faces in int64 where they fit (the same exact candidates; false
// for --no-integer-kernels).
CopositivityResult decide_copositivity(const Matrix& A, std::size_t max_faces = Limits{}.max_faces,
                                       bool integer_kernel = true);

Vector interior_witness(const Matrix& A, const Vector& z);

} // namespace impactcert
