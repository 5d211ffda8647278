/* SPDX-License-Identifier: GPL-3.0-or-later */
/* zoo.c -- the catalogue of tests/impls/zoo.py in C: a plain solver of the 4-ball cradle of equal
 * masses (pairwise exchanges of approaching neighbours, sweep after sweep) with one planted bug
 * per function. For each BUG: zoo_BUG_g (contact velocities gamma- -> gamma+, law mode) and
 * zoo_BUG_u (ball velocities u- -> u+, consistency mode), void f(const double* in, double* out),
 * as `impactcert fuzz --impl libimpactcert_zoo.so:SYMBOL` loads them. zoo_correct_*: no bug. */
#include <math.h>

enum bug { correct, threshold, reltol, one_sweep, two_sweeps, plastic, restitution, last_contact, reversed_order,
           separating, float32, leak, stale, mass, early_exit };

static double f32(double x) { /* IEEE conversion, overflow to infinity (a plain cast would be undefined) */
    if (isnan(x) || isinf(x))
        return x;
    if (fabs(x) >= 0x1.ffffffp127)
        return x > 0 ? INFINITY : -INFINITY;
    return (double)(float)x;
}

static void solve(const double* in, double* u, enum bug b) {
    double initial[4], masses[4] = {1, 1, 1, b == mass ? 1.001 : 1};
    for (int i = 0; i < 4; ++i)
        initial[i] = u[i] = b == float32 ? f32(in[i]) : in[i];
    const int sweeps = b == one_sweep ? 1 : b == two_sweeps ? 2 : 4, last = b == last_contact ? 2 : 3;
    double big = 0;
    for (int i = 0; i < 4; ++i)
        big = fmax(big, fabs(u[i]));
    for (int sweep = 0; sweep < sweeps; ++sweep) {
        int stop = 0;
        for (int k = 0; k < last && !stop; ++k) {
            double gamma = b == stale ? initial[k + 1] - initial[k] : u[k + 1] - u[k];
            if (b == float32)
                gamma = f32(gamma);
            const double limit = b == threshold ? -1e-6 : b == reltol ? -1e-9 * big : 0.0;
            int approaching = gamma < limit;
            if (b == separating && k == 0 && sweep == sweeps - 1)
                approaching = gamma != 0;
            if (!approaching) {
                if (b == early_exit && k == 0)
                    stop = 1;
                continue;
            }
            const double x = u[k], y = u[k + 1];
            if (b == plastic) {
                u[k] = u[k + 1] = (x + y) / 2;
            } else if (b == restitution) {
                u[k] = (x + y) / 2 - 0.9 * (x - y) / 2;
                u[k + 1] = (x + y) / 2 + 0.9 * (x - y) / 2;
            } else if (b == leak) {
                u[k] = y;
                u[k + 1] = x * (1 - 1e-4);
            } else if (b == mass) {
                const double m1 = masses[k], m2 = masses[k + 1];
                u[k] = ((m1 - m2) * x + 2 * m2 * y) / (m1 + m2);
                u[k + 1] = ((m2 - m1) * y + 2 * m1 * x) / (m1 + m2);
            } else {
                u[k] = y;
                u[k + 1] = x;
            }
        }
        if (stop)
            break;
    }
    if (b == reversed_order) /* descending: a sort with the comparison the wrong way round */
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j + 1 < 4 - i; ++j)
                if (u[j] < u[j + 1]) {
                    const double t = u[j];
                    u[j] = u[j + 1];
                    u[j + 1] = t;
                }
    if (b == float32)
        for (int i = 0; i < 4; ++i)
            u[i] = f32(u[i]);
}

static void from_gamma(const double* g, double* out, enum bug b) {
    const double in[4] = {0, g[0], g[0] + g[1], g[0] + g[1] + g[2]};
    double u[4];
    solve(in, u, b);
    for (int k = 0; k < 3; ++k)
        out[k] = u[k + 1] - u[k];
}

#define ZOO(name)                                                                                        \
    void zoo_##name##_g(const double* in, double* out);                                                  \
    void zoo_##name##_u(const double* in, double* out);                                                  \
    void zoo_##name##_g(const double* in, double* out) { from_gamma(in, out, name); }                    \
    void zoo_##name##_u(const double* in, double* out) { solve(in, out, name); }

ZOO(correct)
ZOO(threshold)
ZOO(reltol)
ZOO(one_sweep)
ZOO(two_sweeps)
ZOO(plastic)
ZOO(restitution)
ZOO(last_contact)
ZOO(reversed_order)
ZOO(separating)
ZOO(float32)
ZOO(leak)
ZOO(stale)
ZOO(mass)
ZOO(early_exit)
