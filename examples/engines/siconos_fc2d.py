# SPDX-License-Identifier: GPL-3.0-or-later
"""siconos_fc2d.py -- Siconos's two-dimensional frictional contact solvers (Debian's
python3-siconos, siconos.numerics.fc2d_driver) as an `impactcert fuzz --impl-cmd` driver.

It reads the mechanics of a planar system with one tangent per contact -- an impactcert-system/1
file or the head of a law file (M or the masses, W, the friction declarations), e.g. what
`impactcert derive newton --system SCENE -o LAW` writes for a scene -- and, for each stdin line
of body velocities u- (decimals or hex floats), poses the impact as Siconos's frictional contact problem at the velocity
level:
    v = G r + q,  G = W^T M^-1 W (per contact: normal, tangent),
    q_N = (1 + e) gamma_N-  (restitution on every contact, or --restitution-on approaching: only
    where gamma_N- < 0, else gamma_N-),  q_T = gamma_T-,
    0 <= v_N _|_ r_N >= 0 and Coulomb's law in the plane (|r_T| <= mu r_N, r_T opposing v_T),
solves it with --solver nsgs (default), lemke or enum (--iterations K and --tolerance T for
nsgs), and answers u+ = u- + M^-1 W r, printed with %.17g. Converged, that is the Newton law with
friction (e_T = 0) that `impactcert derive newton --system ... --restitution E` derives.
Every contact must have friction (one tangent each). A solver's failure (fc2d_driver's info != 0)
is said on stderr and its answer printed as it is. --restitution defaults to 1 (a law's head
carries none). Bad input: one line on stderr, exit 2.
"""
import sys

import siconos.numerics as sn

from siconos_common import run

if __name__ == "__main__":
    run(sys.argv[1:], 2, {"nsgs": sn.SICONOS_FRICTION_2D_NSGS, "lemke": sn.SICONOS_FRICTION_2D_LEMKE,
                          "enum": sn.SICONOS_FRICTION_2D_ENUM}, sn.fc2d_driver, tuned={"nsgs"})
