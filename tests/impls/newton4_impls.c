// SPDX-License-Identifier: GPL-3.0-or-later
/* newton4_impls.c -- float implementations of the 4-ball cradle law (proofs/newton4/law.json:
 * equal masses, e = 1, so u+ = sort(u-)) in contact velocities gamma = (u2-u1, u3-u2, u4-u3),
 * the way simulators write them. For `impactcert fuzz --law proofs/newton4/law.json --impl`.
 * C ABI: void f(const double* gamma_minus, double* gamma_plus), 3 doubles each.
 *
 *   newton4_sorted          correct, not correctly rounded: rebuilds ball velocities by
 *                           summation (rounding), sorts them, takes differences, in units
 *                           scaled down by 4 when the input is near the overflow threshold
 *                           (exact). Passes --max-rel-error 1e-12, fails --max-ulps 0.
 *   newton4_tolerance       WRONG: pairwise exchanges with an absolute tolerance (a contact
 *                           with gamma_k > -1e-9 counts as separating): at small velocities
 *                           nothing is exchanged and approaching contacts stay negative.
 *   newton4_two_sweeps      WRONG: two sweeps of pairwise impacts, left to right; some
 *                           orderings of four balls need three.
 *   newton4_impulse         WRONG near overflow: the impulse form u_k += (u_{k+1} - u_k) of an
 *                           equal-mass exchange; the difference overflows for large opposite
 *                           velocities whose exact result is finite.
 */
#include <math.h>

static void to_balls(const double* g, double* u) {
    u[0] = 0;
    u[1] = g[0];
    u[2] = u[1] + g[1];
    u[3] = u[2] + g[2];
}

static void to_contacts(const double* u, double* g) {
    g[0] = u[1] - u[0];
    g[1] = u[2] - u[1];
    g[2] = u[3] - u[2];
}

void newton4_sorted(const double* in, double* out) {
    double u[4], g[3];
    const double big = fmax(fabs(in[0]), fmax(fabs(in[1]), fabs(in[2])));
    const double scale = big > 0x1p1020 ? 0.25 : 1.0; /* sums of three stay finite */
    for (int k = 0; k < 3; ++k)
        g[k] = in[k] * scale;
    to_balls(g, u);
    for (int i = 1; i < 4; ++i) /* insertion sort */
        for (int j = i; j > 0 && u[j] < u[j - 1]; --j) {
            const double t = u[j];
            u[j] = u[j - 1];
            u[j - 1] = t;
        }
    to_contacts(u, out);
    for (int k = 0; k < 3; ++k)
        out[k] /= scale;
}

void newton4_tolerance(const double* in, double* out) {
    double u[4];
    to_balls(in, u);
    for (int sweep = 0; sweep < 3; ++sweep)
        for (int k = 0; k < 3; ++k)
            if (u[k + 1] - u[k] < -1e-9) { /* approaching beyond a tolerance */
                const double t = u[k];
                u[k] = u[k + 1];
                u[k + 1] = t;
            }
    to_contacts(u, out);
}

void newton4_two_sweeps(const double* in, double* out) {
    double u[4];
    to_balls(in, u);
    for (int sweep = 0; sweep < 2; ++sweep)
        for (int k = 0; k < 3; ++k)
            if (u[k + 1] < u[k]) {
                const double t = u[k];
                u[k] = u[k + 1];
                u[k + 1] = t;
            }
    to_contacts(u, out);
}

void newton4_impulse(const double* in, double* out) {
    double u[4];
    to_balls(in, u);
    for (int sweep = 0; sweep < 3; ++sweep)
        for (int k = 0; k < 3; ++k) {
            const double rel = u[k + 1] - u[k]; /* overflows for large opposite velocities */
            if (rel < 0 || isnan(rel)) {
                u[k] += rel;
                u[k + 1] -= rel;
            }
        }
    to_contacts(u, out);
}

/* Ball velocities (fuzz --velocities): u- -> u+, 4 doubles each.
 *   newton4_balls_sorted    correct and exact: u+ = sort(u-) (equal masses, e = 1).
 *   newton4_balls_one_sweep WRONG: a single left-to-right sweep of pairwise exchanges. */
void newton4_balls_sorted(const double* in, double* out) {
    for (int i = 0; i < 4; ++i)
        out[i] = in[i];
    for (int i = 1; i < 4; ++i)
        for (int j = i; j > 0 && out[j] < out[j - 1]; --j) {
            const double t = out[j];
            out[j] = out[j - 1];
            out[j - 1] = t;
        }
}

void newton4_balls_one_sweep(const double* in, double* out) {
    for (int i = 0; i < 4; ++i)
        out[i] = in[i];
    for (int k = 0; k < 3; ++k)
        if (out[k + 1] < out[k]) {
            const double t = out[k];
            out[k] = out[k + 1];
            out[k + 1] = t;
        }
}
