// SPDX-License-Identifier: MIT
// impactcert/float_law.hpp -- Leine & Winandy's 3-ball Newton's cradle law in IEEE double.
//
// Header-only, no allocation, no exceptions. Install with the impactcert package and use as
//     find_package(impactcert REQUIRED)  +  target_link_libraries(app PRIVATE impactcert::float_law)
//     #include <impactcert/float_law.hpp>
//
// Guarantees (SPEC section 5; impactcert's fuzzer and tests check them against exact rationals):
//   - Classification is exact: the cone is chosen by the signs of g1, g2 and fl(g1 + g2), and the
//     sign of fl(g1 + g2) is the sign of g1 + g2 for all finite doubles (a rounded sum is zero
//     only when the exact sum is).
//   - Every output component is +-g1, +-g2 or +-fl(g1 + g2): at most one rounding, so the result
//     is correctly rounded (0 ulp error), and gamma+ >= 0 holds exactly (-0 counts as 0).
//   - No overflow: g1 + g2 is an output only when g1 and g2 have opposite signs, and then it is
//     no larger in magnitude than either. Every finite input has a finite result.
//   - Non-finite input (NaN, +-inf) is rejected by `S_checked`; `S` and `S_batch` assume finite
//     input (their result is then unspecified but they never trap).
//   - Needs IEEE semantics: do not compile with -ffast-math (it may reorder or drop the signs).
#pragma once

#include <cmath>
#include <cstddef>

namespace impactcert::fp {

// The six cones of SPEC section 2, in counter-clockwise order.
enum class Cone { I, IIa, IIb, III, IVb, IVa };

// Exact classification (half-open on shared rays; on a shared ray the law is continuous, so
// either neighbour gives the same value, up to the sign of zero).
inline Cone classify(double g1, double g2) {
    const double s = g1 + g2;
    if (g1 >= 0 && g2 >= 0)
        return Cone::I;
    if (g1 < 0 && g2 >= 0)
        return s >= 0 ? Cone::IIa : Cone::IIb;
    if (g1 < 0 && g2 < 0)
        return Cone::III;
    return s >= 0 ? Cone::IVa : Cone::IVb;
}

// gamma+ = S(gamma-), scalar form with branches (the reference shape of the law).
inline void S(double g1, double g2, double* out) {
    const double s = g1 + g2;
    switch (classify(g1, g2)) {
    case Cone::I: out[0] = g1; out[1] = g2; return;
    case Cone::IIa: out[0] = -g1; out[1] = s; return;
    case Cone::IIb: out[0] = g2; out[1] = -s; return;
    case Cone::III: out[0] = -g2; out[1] = -g1; return;
    case Cone::IVb: out[0] = -s; out[1] = g1; return;
    case Cone::IVa: out[0] = s; out[1] = -g2; return;
    }
}

// Same law, without branches, for arrays. With a = |g1|, b = |g2|: the law is (a, b) when
// g1, g2 >= 0, (b, a) when both are negative, and when the signs differ
// (min(a, b), |a - b|) if g1 < 0 <= g2 and (|a - b|, min(a, b)) if g2 < 0 <= g1; |a - b| is the
// correctly rounded |g1 + g2| (the signs differ, so it is the same single rounding). Every
// operation is a sign-mask selection, so a loop over arrays vectorises. Equal in value to S()
// (+0 where S() may give -0), never negative, never -0.
inline void S_branchless(double g1, double g2, double& o1, double& o2) {
    const double a = std::fabs(g1), b = std::fabs(g2);
    const double m = b < a ? b : a, d = std::fabs(a - b);
    const bool p1 = g1 >= 0, same = p1 == (g2 >= 0);
    const double same1 = p1 ? a : b, same2 = p1 ? b : a;
    const double diff1 = p1 ? d : m, diff2 = p1 ? m : d;
    o1 = same ? same1 : diff1;
    o2 = same ? same2 : diff2;
}

// Batch form: out1[i], out2[i] = S(g1[i], g2[i]). Arrays may not alias. With GCC on x86-64 an
// AVX2 clone is selected at load time where the CPU has it (4 doubles per vector, else 2).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(IMPACTCERT_NO_TARGET_CLONES)
__attribute__((target_clones("avx2", "default")))
#endif
inline void S_batch(const double* __restrict g1, const double* __restrict g2, double* __restrict out1,
                    double* __restrict out2, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
        S_branchless(g1[i], g2[i], out1[i], out2[i]);
}

// Checked scalar form: false (and out untouched) when an input is NaN or infinite.
inline bool S_checked(double g1, double g2, double* out) {
    if (!std::isfinite(g1) || !std::isfinite(g2))
        return false;
    S(g1, g2, out);
    return true;
}

// Ball-velocity form for three equal masses: u+ = sort(u-), exactly (no arithmetic at all).
inline void sort_velocities(double* u) {
    auto order = [](double& a, double& b) {
        const double lo = b < a ? b : a, hi = b < a ? a : b;
        a = lo;
        b = hi;
    };
    order(u[0], u[1]);
    order(u[1], u[2]);
    order(u[0], u[1]);
}

} // namespace impactcert::fp
