// SPDX-License-Identifier: GPL-3.0-or-later
// atan2_law.cpp -- a deliberately WRONG float implementation of the paper's law, for the fuzzer
// to catch. It classifies gamma- by its angle atan2(g2, g1) against rounded multiples of pi/4
// instead of by exact sign tests. Near the rays (-1, 1) and (1, -1) the rounded angle and the
// rounded boundary disagree with the exact ordering, so points a few ulps off those rays get the
// neighbouring cone's matrix: a negative gamma+ and a classification error.
// Interface: the fuzzer's C ABI, void f(const double* gamma_minus, double* gamma_plus).
#include <cmath>

extern "C" void impactcert_atan2_law(const double* in, double* out) {
    const double g1 = in[0], g2 = in[1], s = g1 + g2;
    const double pi = 3.141592653589793;
    const double angle = std::atan2(g2, g1); // [-pi, pi]
    if (angle >= 0 && angle <= pi / 2) {          // I
        out[0] = g1, out[1] = g2;
    } else if (angle > pi / 2 && angle <= 3 * pi / 4) { // IIa
        out[0] = -g1, out[1] = s;
    } else if (angle > 3 * pi / 4) {              // IIb
        out[0] = g2, out[1] = -s;
    } else if (angle <= -pi / 2) {                // III
        out[0] = -g2, out[1] = -g1;
    } else if (angle <= -pi / 4) {                // IVb
        out[0] = -s, out[1] = g1;
    } else {                                      // IVa
        out[0] = s, out[1] = -g2;
    }
}
