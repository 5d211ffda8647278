#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The Newton law with the circular Coulomb cone for one contact whose Delassus block is
isotropic (a centred ball on a plane: G_NT = 0, G_TT = g I), in closed form, rounded to doubles:
an `impactcert fuzz --impl-cmd` implementation (ball velocities) for tests/circular_cone_test.py.

Usage: circular_ball.py LAW_OR_SYSTEM.json MODE E
One contact, restitution E where it approaches (else no impulse):
  Lambda_N = -(1 + E) gamma_N- / G_NN,
  stick:  Lambda_T = -gamma_T- / g            where |gamma_T-| <= g mu Lambda_N,
  slip:   Lambda_T = -mu Lambda_N gamma_T- / |gamma_T-|  otherwise (the slip keeps its direction),
  u+ = u- + M^-1 W Lambda, computed in fractions but for the square root, then rounded.
Modes: exact (the law), box (the slip's friction per tangent clipped to mu Lambda_N on its own:
the friction box), rotated (the slip's friction turned by 3/5, 4/5: not opposite the slip), mu2
(the law with mu doubled).
"""
import json
import math
import sys
from fractions import Fraction as F


def main():
    doc = json.load(open(sys.argv[1]))
    mode, e = sys.argv[2], F(sys.argv[3])
    m = [F(x) for x in doc["masses"]] if "masses" in doc else None
    if m is None:
        M = [[F(x) for x in row] for row in doc["M"]]
        if any(M[i][j] != 0 for i in range(len(M)) for j in range(len(M)) if i != j):
            sys.exit("circular_ball: a diagonal M only")
        m = [M[i][i] for i in range(len(M))]
    W = doc["contacts"]["W"]
    (fr,) = doc["contacts"]["friction"]
    cols = [[F(row[0]) for row in W]] + [[F(x) for x in t] for t in fr["tangents"]]
    mu = F(fr["mu"]) * (2 if mode == "mu2" else 1)
    G = [[sum(a[i] * b[i] / m[i] for i in range(len(m))) for b in cols] for a in cols]
    g = G[1][1]
    if G[0][1] or G[0][2] or G[1][2] or G[2][2] != g:
        sys.exit("circular_ball: the contact's Delassus block is not isotropic")
    for line in sys.stdin:
        u = [F(float.fromhex(t)) if "x" in t.lower() else F(float(t)) for t in line.split()]
        gamma = [sum(c[i] * u[i] for i in range(len(u))) for c in cols]
        lam = [0.0, 0.0, 0.0]
        if gamma[0] < 0:
            ln = -(1 + e) * gamma[0] / G[0][0]
            gt2 = gamma[1] ** 2 + gamma[2] ** 2
            if gt2 <= (g * mu * ln) ** 2:
                lam = [ln, -gamma[1] / g, -gamma[2] / g]
            else:
                norm = math.sqrt(gt2)
                t = [-float(mu * ln * gamma[1]) / norm, -float(mu * ln * gamma[2]) / norm]
                if mode == "box":
                    t = [max(-float(mu * ln), min(float(mu * ln), float(-gamma[k + 1] / g))) for k in (0, 1)]
                elif mode == "rotated":
                    t = [0.6 * t[0] - 0.8 * t[1], 0.8 * t[0] + 0.6 * t[1]]
                elif mode.startswith("tilt:"):
                    c, s = math.cos(float(mode[5:])), math.sin(float(mode[5:]))
                    t = [c * t[0] - s * t[1], s * t[0] + c * t[1]]
                lam = [ln] + [F(x) for x in t]
        up = [u[i] + sum(cols[k][i] * F(lam[k]) for k in range(3)) / m[i] for i in range(len(u))]
        sys.stdout.write(" ".join(float(x).hex() for x in up) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
