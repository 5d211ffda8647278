#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""siconos_fc3d.py -- Siconos's three-dimensional frictional contact solvers (Debian's
python3-siconos, siconos.numerics.fc3d_driver) as an `impactcert fuzz --impl-cmd` driver: Coulomb's
law with the circular cone, which `impactcert fuzz --cone circular` checks.

It reads the mechanics of a system in space with two tangents per contact -- the head of a law
file (M, W, the friction declarations), e.g. what `impactcert derive newton --system SCENE -o LAW`
writes for a scene with "dimension": 3 -- and, for each stdin line of body velocities u- (decimals
or hex floats), poses the impact as Siconos's frictional contact problem at the velocity level:
    v = G r + q,  G = W^T M^-1 W (per contact: normal, first tangent, second tangent),
    q_N = (1 + e) gamma_N-  (restitution on every contact, or --restitution-on approaching: only
    where gamma_N- < 0, else gamma_N-),  q_T = gamma_T-,
    r in the cone |r_T| <= mu r_N, v_N >= 0, r_N v_N = 0, and r_T = -mu r_N v_T / |v_T| where
    v_T != 0 (Siconos's formulation with De Saxce's modified velocity),
solves it with --solver nsgs (default), nsn-ac (semismooth Newton on Alart-Curnier's function),
nsn-fb (on Fischer-Burmeister's), prox or admm (--iterations K and --tolerance T), and answers
u+ = u- + M^-1 W r, printed with %.17g. Every contact must have friction with two tangents and one
mu. A solver's failure (fc3d_driver's info != 0) is said on stderr and its answer printed as it
is. --restitution defaults to 1. Bad input: one line on stderr, exit 2.
"""
import sys

import siconos.numerics as sn

from siconos_common import run

SOLVERS = {"nsgs": sn.SICONOS_FRICTION_3D_NSGS, "nsn-ac": sn.SICONOS_FRICTION_3D_NSN_AC,
           "nsn-fb": sn.SICONOS_FRICTION_3D_NSN_FB, "prox": sn.SICONOS_FRICTION_3D_PROX,
           "admm": sn.SICONOS_FRICTION_3D_ADMM}

if __name__ == "__main__":
    run(sys.argv[1:], 3, SOLVERS, sn.fc3d_driver, tuned=set(SOLVERS))
