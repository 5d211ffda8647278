#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Impact maps with Coulomb friction for the consistency fuzzer's tests (ball/body velocities).

Usage: friction_impls.py SYSTEM_OR_LAW.json MODE E [approaching]
Protocol of `impactcert fuzz --impl-cmd`: one line of doubles in (hex or decimal), one line out.
The system (M, W, friction) is read from the file's head; the Newton law with friction
(restitution E on every contact, e_T of the file) is solved exactly by the independent oracle
(tests/oracles/friction_lcp.py) and rounded to doubles. Modes:
  exact       that law (consistent up to rounding, unless the law itself gains energy)
  reversed    the tangential impulses of the exact answer reversed (friction pushes the slip)
  excess      the tangential impulses doubled (beyond mu Lambda_N where the contact slides)
  frictionless the tangential impulses dropped (a sliding contact without friction)
  half-e      the Newton law with friction at restitution E/2 (a solver that halves restitution)
  contact-tangent-off  in contact velocities (square W: u- = W^-T gamma-): the exact gamma+ with
               its tangential components 1% too large (the normals exact), for law-mode fuzzing
"""
import json
import os
import sys
from fractions import Fraction as F

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "oracles"))
from friction_lcp import System, solve  # noqa: E402


def parse(token):
    return float.fromhex(token) if "0x" in token.lower() else float(token)


def load(path):
    doc = json.load(open(path))
    M = [[F(x) for x in row] for row in doc["M"]] if "M" in doc else None
    if M is None:
        m = [F(x) for x in doc["masses"]]
        M = [[m[i] if i == j else F(0) for j in range(len(m))] for i in range(len(m))]
    W = doc["contacts"]["W"]
    normals = [[F(W[i][k]) for i in range(len(W))] for k in range(len(W[0]))]
    fr = [(f["contact"] - 1, F(f["mu"]), F(f.get("restitution_tangential", "0")), f["tangents"])
          for f in doc["contacts"].get("friction", [])]
    return System(M, normals, fr)


def main():
    S = load(sys.argv[1])
    mode = sys.argv[2]
    e = F(sys.argv[3])
    approaching = len(sys.argv) > 4 and sys.argv[4] == "approaching"
    N = len(S.normals)
    for line in sys.stdin:
        u = [F(parse(t)) for t in line.split()]
        if mode == "contact-tangent-off":
            gm = u
            u = solve([list(c) for c in S.columns], gm)  # rows W^T: W^T u = gamma
            sols = S.solutions(u, [e] * N, approaching=approaching)
            gp = S.velocities(sols[0]) if len(sols) == 1 else None
            if gp is None:
                sys.stdout.write("not a function here\n")
            else:
                out = [float(x) if k < N else float(x) * 1.01 for k, x in enumerate(gp)]
                sys.stdout.write(" ".join(x.hex() for x in out) + "\n")
            sys.stdout.flush()
            continue
        sols = S.solutions(u, [e / 2 if mode == "half-e" else e] * N, approaching=approaching)
        if len(sols) != 1:
            sys.stdout.write("not a function here\n")
            sys.stdout.flush()
            continue
        up = sols[0]
        if mode not in ("exact", "half-e"):
            # impulse in generalized coordinates: M (u+ - u-) = W Lambda; split off the tangents'.
            du = [a - b for a, b in zip(up, u)]
            Mdu = [sum(S.M[i][j] * du[j] for j in range(S.n)) for i in range(S.n)]
            # Lambda from W Lambda = M du (least squares is exact here: W has full column rank)
            cols = S.columns
            G = [[sum(cols[a][i] * cols[b][i] for i in range(S.n)) for b in range(S.d)] for a in range(S.d)]
            rhs = [sum(cols[a][i] * Mdu[i] for i in range(S.n)) for a in range(S.d)]
            lam = solve(G, rhs)
            factor = {"reversed": F(-1), "excess": F(2), "frictionless": F(0)}[mode]
            dl = [F(0)] * S.d
            for j in range(N, S.d):
                dl[j] = (factor - 1) * lam[j]
            # u+ += M^-1 W dl
            Wdl = [sum(cols[k][i] * dl[k] for k in range(S.d)) for i in range(S.n)]
            x = solve(S.M, Wdl)
            up = [a + b for a, b in zip(up, x)]
        sys.stdout.write(" ".join(float(x).hex() for x in up) + "\n")
        sys.stdout.flush()


main()
