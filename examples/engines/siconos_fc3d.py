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
import json
import sys

import numpy as np
import siconos.numerics as sn

SOLVERS = {"nsgs": sn.SICONOS_FRICTION_3D_NSGS, "nsn-ac": sn.SICONOS_FRICTION_3D_NSN_AC,
           "nsn-fb": sn.SICONOS_FRICTION_3D_NSN_FB, "prox": sn.SICONOS_FRICTION_3D_PROX,
           "admm": sn.SICONOS_FRICTION_3D_ADMM}


def fail(message):
    sys.stderr.write("siconos_fc3d: " + message + "\n")
    sys.exit(2)


def rational(x, where):
    try:
        if isinstance(x, int):
            return float(x)
        num, _, den = str(x).partition("/")
        return float(num) / (float(den) if den else 1.0)
    except (ValueError, ZeroDivisionError):
        fail(f"{where}: not a rational: {x!r}")


def main(argv):
    opts = {"--system": None, "--restitution": "1", "--restitution-on": "all", "--solver": "nsgs",
            "--iterations": "1000", "--tolerance": "1e-12"}
    args = list(argv)
    while args:
        flag = args.pop(0)
        if flag not in opts or not args:
            fail("usage: siconos_fc3d.py --system FILE [--restitution E] [--restitution-on all|approaching] "
                 "[--solver " + "|".join(SOLVERS) + "] [--iterations K] [--tolerance T]")
        opts[flag] = args.pop(0)
    if not opts["--system"]:
        fail("--system FILE is required")
    try:
        doc = json.load(open(opts["--system"]))
    except (OSError, ValueError) as e:
        fail(f"{opts['--system']}: {e}")
    contacts = doc.get("contacts") if isinstance(doc, dict) else None
    W_rows = contacts.get("W") if isinstance(contacts, dict) else None
    if not W_rows:
        fail("the system has no contacts.W (give the head of a law derived from a scene in space)")
    n, c = len(W_rows), len(W_rows[0])
    WN = np.array([[rational(x, "W") for x in row] for row in W_rows])
    if "M" in doc:
        M = np.array([[rational(x, "M") for x in row] for row in doc["M"]])
    else:
        M = np.diag([rational(x, "masses") for x in doc["masses"]])
    friction = {f["contact"] - 1: f for f in contacts.get("friction", [])}
    if sorted(friction) != list(range(c)) or any(len(f["tangents"]) != 2 for f in friction.values()):
        fail("every contact needs friction with two tangents (a system in space)")
    mu = np.array([rational(friction[k]["mu"], "mu") for k in range(c)])
    e = rational(opts["--restitution"], "--restitution")
    if opts["--restitution-on"] not in ("all", "approaching"):
        fail("--restitution-on: all or approaching")
    approaching = opts["--restitution-on"] == "approaching"
    if opts["--solver"] not in SOLVERS:
        fail("--solver: " + ", ".join(SOLVERS))
    # Per contact k: (normal, tangent 1, tangent 2), interleaved as Siconos orders them.
    Wc = np.empty((n, 3 * c))
    Wc[:, 0::3] = WN
    for t in (0, 1):
        Wc[:, 1 + t::3] = np.array([[rational(x, "tangent") for x in friction[k]["tangents"][t]] for k in range(c)]).T
    Minv_W = np.linalg.solve(M, Wc)
    G = Wc.T @ Minv_W
    for lineno, line in enumerate(sys.stdin, 1):
        try:
            u = np.array([float.fromhex(t) if "x" in t.lower() else float(t) for t in line.split()])
        except ValueError:
            fail(f"line {lineno}: not a number")
        if u.size != n or not np.all(np.isfinite(u)):
            fail(f"line {lineno}: expected {n} finite numbers")
        gamma = Wc.T @ u
        q = gamma.copy()
        for k in range(c):
            if not approaching or gamma[3 * k] < 0:
                q[3 * k] = (1 + e) * gamma[3 * k]
        problem = sn.FrictionContactProblem(3, c, G, q, mu)
        options = sn.SolverOptions(SOLVERS[opts["--solver"]])
        options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = int(opts["--iterations"])
        options.dparam[sn.SICONOS_DPARAM_TOL] = float(opts["--tolerance"])
        r, v = np.zeros(3 * c), np.zeros(3 * c)
        info = sn.fc3d_driver(problem, r, v, options)
        if info != 0:  # the answer is printed as the solver left it, as an engine would use it
            sys.stderr.write(f"siconos_fc3d: line {lineno}: the solver reports failure (info {info})\n")
        up = u + Minv_W @ r
        sys.stdout.write(" ".join("%.17g" % x for x in up) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1:])
