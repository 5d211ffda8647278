#!/usr/bin/env python3
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
import json
import sys

import numpy as np
import siconos.numerics as sn


def fail(message):
    sys.stderr.write("siconos_fc2d: " + message + "\n")
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
            fail("usage: siconos_fc2d.py --system FILE [--restitution E] [--restitution-on all|approaching] "
                 "[--solver nsgs|lemke|enum] [--iterations K] [--tolerance T]")
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
        fail("the system has no contacts.W (a chain by its masses is not driven: give W and friction)")
    n, c = len(W_rows), len(W_rows[0])
    WN = np.array([[rational(x, "W") for x in row] for row in W_rows])
    if "M" in doc:
        M = np.array([[rational(x, "M") for x in row] for row in doc["M"]])
    else:
        M = np.diag([rational(x, "masses") for x in doc["masses"]])
    friction = {f["contact"] - 1: f for f in contacts.get("friction", [])}
    if sorted(friction) != list(range(c)) or any(len(f["tangents"]) != 1 for f in friction.values()):
        fail("every contact needs friction with one tangent (a planar system)")
    WT = np.array([[rational(x, "tangent") for x in friction[k]["tangents"][0]] for k in range(c)]).T
    mu = np.array([rational(friction[k]["mu"], "mu") for k in range(c)])
    e = rational(opts["--restitution"], "--restitution")
    approaching = opts["--restitution-on"] == "approaching"
    if opts["--restitution-on"] not in ("all", "approaching"):
        fail("--restitution-on: all or approaching")
    solvers = {"nsgs": sn.SICONOS_FRICTION_2D_NSGS, "lemke": sn.SICONOS_FRICTION_2D_LEMKE,
               "enum": sn.SICONOS_FRICTION_2D_ENUM}
    if opts["--solver"] not in solvers:
        fail("--solver: nsgs, lemke or enum")
    # Per contact k: (normal, tangent), interleaved as Siconos orders them.
    Wc = np.empty((n, 2 * c))
    Wc[:, 0::2] = WN
    Wc[:, 1::2] = WT
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
            if not approaching or gamma[2 * k] < 0:
                q[2 * k] = (1 + e) * gamma[2 * k]
        problem = sn.FrictionContactProblem(2, c, G, q, mu)
        options = sn.SolverOptions(solvers[opts["--solver"]])
        if opts["--solver"] == "nsgs":
            options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = int(opts["--iterations"])
            options.dparam[sn.SICONOS_DPARAM_TOL] = float(opts["--tolerance"])
        r, v = np.zeros(2 * c), np.zeros(2 * c)
        info = sn.fc2d_driver(problem, r, v, options)
        if info != 0:  # the answer is printed as the solver left it, as an engine would use it
            sys.stderr.write(f"siconos_fc2d: line {lineno}: the solver reports failure (info {info})\n")
        up = u + Minv_W @ r
        sys.stdout.write(" ".join("%.17g" % x for x in up) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv[1:])
