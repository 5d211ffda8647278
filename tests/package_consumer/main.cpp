// SPDX-License-Identifier: GPL-3.0-or-later
// Uses the installed header: one ball in, one ball out (gamma- = (-1, 0) -> gamma+ = (0, 1)).
#include <impactcert/float_law.hpp>

int main() {
    double out[2];
    impactcert::fp::S(-1.0, 0.0, out);
    double u[3] = {1.0, 0.0, 0.0};
    impactcert::fp::sort_velocities(u);
    return (out[0] == 0.0 && out[1] == 1.0 && u[0] == 0.0 && u[2] == 1.0) ? 0 : 1;
}
