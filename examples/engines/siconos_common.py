# SPDX-License-Identifier: GPL-3.0-or-later
"""siconos_common.py -- what siconos_fc2d.py and siconos_fc3d.py share: the command line, the
mechanics read from a system or a law's head, and the loop that poses each impact as Siconos's
frictional contact problem of dimension 2 or 3 and answers u+ (see either script's docstring)."""
import json
import sys

import numpy as np
import siconos.numerics as sn


def run(argv, dim, solvers, driver, tuned):
    """dim 2 (one tangent per contact) or 3 (two); solvers: name -> Siconos id; driver:
    sn.fc2d_driver or sn.fc3d_driver; tuned: the solvers that take --iterations and --tolerance."""
    name = f"siconos_fc{dim}d"

    def fail(message):
        sys.stderr.write(f"{name}: {message}\n")
        sys.exit(2)

    def rational(x, where):
        try:
            if isinstance(x, int):
                return float(x)
            num, _, den = str(x).partition("/")
            return float(num) / (float(den) if den else 1.0)
        except (ValueError, ZeroDivisionError):
            fail(f"{where}: not a rational: {x!r}")

    opts = {"--system": None, "--restitution": "1", "--restitution-on": "all", "--solver": next(iter(solvers)),
            "--iterations": "1000", "--tolerance": "1e-12"}
    args = list(argv)
    while args:
        flag = args.pop(0)
        if flag not in opts or not args:
            fail(f"usage: {name}.py --system FILE [--restitution E] [--restitution-on all|approaching] "
                 f"[--solver {'|'.join(solvers)}] [--iterations K] [--tolerance T]")
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
        fail("the system has no contacts.W (give W and friction, or the head of a law derived from a scene)")
    n, c = len(W_rows), len(W_rows[0])
    WN = np.array([[rational(x, "W") for x in row] for row in W_rows])
    if "M" in doc:
        M = np.array([[rational(x, "M") for x in row] for row in doc["M"]])
    else:
        M = np.diag([rational(x, "masses") for x in doc["masses"]])
    friction = {f["contact"] - 1: f for f in contacts.get("friction", [])}
    if sorted(friction) != list(range(c)) or any(len(f["tangents"]) != dim - 1 for f in friction.values()):
        fail("every contact needs friction with " + ("one tangent (a planar system)" if dim == 2 else
                                                     "two tangents (a system in space)"))
    mu = np.array([rational(friction[k]["mu"], "mu") for k in range(c)])
    e = rational(opts["--restitution"], "--restitution")
    if opts["--restitution-on"] not in ("all", "approaching"):
        fail("--restitution-on: all or approaching")
    approaching = opts["--restitution-on"] == "approaching"
    if opts["--solver"] not in solvers:
        fail("--solver: " + ", ".join(solvers))
    # Per contact k: the normal, then its tangents, interleaved as Siconos orders them.
    Wc = np.empty((n, dim * c))
    Wc[:, 0::dim] = WN
    for t in range(dim - 1):
        Wc[:, 1 + t::dim] = np.array([[rational(x, "tangent") for x in friction[k]["tangents"][t]] for k in range(c)]).T
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
            if not approaching or gamma[dim * k] < 0:
                q[dim * k] = (1 + e) * gamma[dim * k]
        problem = sn.FrictionContactProblem(dim, c, G, q, mu)
        options = sn.SolverOptions(solvers[opts["--solver"]])
        if opts["--solver"] in tuned:
            options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = int(opts["--iterations"])
            options.dparam[sn.SICONOS_DPARAM_TOL] = float(opts["--tolerance"])
        r, v = np.zeros(dim * c), np.zeros(dim * c)
        info = driver(problem, r, v, options)
        if info != 0:  # the answer is printed as the solver left it, as an engine would use it
            sys.stderr.write(f"{name}: line {lineno}: the solver reports failure (info {info})\n")
        up = u + Minv_W @ r
        sys.stdout.write(" ".join("%.17g" % x for x in up) + "\n")
        sys.stdout.flush()
