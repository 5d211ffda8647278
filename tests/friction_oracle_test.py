#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""derive newton with friction against an independent oracle (tests/oracles/friction_lcp.py).

For each frictional system below (one contact with coupling, two disks, a rod, a disk in a
corner between a floor and a wall, and Kane's double pendulum): the CLI derives the Newton law
with friction (restitution on all contacts and on approaching ones); at random rational u- the
piece containing gamma- = W^T u- gives gamma+ = Q gamma-, which must equal W^T u+ for the only
solution the oracle finds by enumerating contact modes in body velocities. A system whose law is
not a function must exit 1 with a witness whose two solutions the oracle finds too; negative
controls: a wrong mu in the oracle must disagree, and a law file with a piece's matrix perturbed
must be caught.
Usage: friction_oracle_test.py IMPACTCERT SAMPLES_PER_LAW
"""
import json
import os
import shutil
import random
import subprocess
import sys
import tempfile
from fractions import Fraction as F

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "oracles"))
from friction_lcp import System, solve  # noqa: E402

CLI = sys.argv[1]
SAMPLES = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
rng = random.Random(20261126)
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def q(x):
    return str(F(x))


def kane_M(s1, c1, s2, c2):
    c12 = c1 * c2 + s1 * s2
    return [[F(4, 3), c12 / 2], [c12 / 2, F(1, 3)]]


# name: (M, normals (columns), friction [(contact, mu, e_T, [tangent columns])])
SYSTEMS = {
    # a rod (x, y, theta; mass 1, half-length 1, J = 1/3) touching the floor at one end, tilted
    # with cos = 3/5: G_NT != 0 (coupling)
    "rod": ([[1, 0, 0], [0, 1, 0], [0, 0, F(1, 3)]], [[0, 1, F(-3, 5)]], [(0, F(1, 2), 0, [[1, 0, F(4, 5)]])]),
    # one contact with coupling, square: 2 coordinates, full mass matrix
    "coupled": ([[2, F(1, 2)], [F(1, 2), 1]], [[1, F(1, 3)]], [(0, F(1, 3), F(1, 4), [[F(-1, 2), 1]])]),
    # two spinning disks (x, y, theta each; m = 1, 2; radii 1, 1/2; J = m r^2 / 2) touching along
    # the x axis: normal (1, 0) from disk 1 to disk 2, tangent (0, 1)
    "two-disks": ([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, F(1, 2), 0, 0, 0],
                   [0, 0, 0, 2, 0, 0], [0, 0, 0, 0, 2, 0], [0, 0, 0, 0, 0, F(1, 4)]],
                  [[-1, 0, 0, 1, 0, 0]], [(0, F(1, 2), 0, [[0, -1, -1, 0, 1, F(-1, 2)]])]),
    # a wall and two disks (m = 1, r = 1, J = 1/2 each; x, y, theta): disk 1 against the wall on
    # its left (normal (1, 0)), disk 2 against disk 1 on its right; both contacts rough
    "wall-disks": ([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, F(1, 2), 0, 0, 0],
                    [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, F(1, 2)]],
                   [[1, 0, 0, 0, 0, 0], [-1, 0, 0, 1, 0, 0]],
                   [(0, F(1, 2), 0, [[0, 1, -1, 0, 0, 0]]), (1, F(1, 4), 0, [[0, -1, -1, 0, 1, -1]])]),
    # Kane's double pendulum (proofs/kane): two uniform rods, sin/cos 7/25, 24/25 and 5/13, 12/13
    "kane": (kane_M(F(7, 25), F(24, 25), F(5, 13), F(12, 13)), [[F(7, 25), F(5, 13)]],
             [(0, F(1, 4), 0, [[F(24, 25), F(12, 13)]])]),
}


def system_json(name, M, normals, friction):
    n = len(M)
    W = [[q(normals[k][i]) for k in range(len(normals))] for i in range(n)]
    return {"format": "impactcert-system/1", "name": name, "M": [[q(x) for x in row] for row in M],
            "contacts": {"W": W, "friction": [
                dict({"contact": k + 1, "mu": q(mu), "tangents": [[q(x) for x in col] for col in cols]},
                     **({"restitution_tangential": q(eT)} if eT else {}))
                for (k, mu, eT, cols) in friction]}}


def run(args, expect):
    p = subprocess.run([CLI] + args, capture_output=True, text=True)
    if p.returncode != expect:
        fail(f"{' '.join(args)}: exit {p.returncode}, expected {expect}: {p.stderr.strip()}")
    return p


def pieces_of(law, _cache={}):
    """Each piece as (R^-1, Q) in fractions, once per law (None for a singular R: no point is
    located in it, as solve() would find). R^-1 comes from solve() on the unit vectors, so
    R^-1 gamma is the solution of R s = gamma that solve(R, gamma) would give."""
    key = id(law)
    if key not in _cache:
        pieces = []
        for piece in law["pieces"]:
            d = len(piece["rays"][0])
            R = [[F(r[i]) for r in piece["rays"]] for i in range(d)]
            cols = [solve(R, [F(int(i == j)) for i in range(d)]) for j in range(d)]
            Rinv = None if any(c is None for c in cols) else [[cols[j][i] for j in range(d)] for i in range(d)]
            pieces.append((Rinv, [[F(x) for x in row] for row in piece["Q"]]))
        _cache[key] = (law, pieces)  # law kept alive: its id cannot be reused
    return _cache[key][1]


def locate(law, gamma):
    """gamma+ by the law: the value Q gamma of every piece whose closed cone holds gamma."""
    values = []
    n = len(gamma)
    for Rinv, Q in pieces_of(law):
        if Rinv is None or any(sum(row[j] * gamma[j] for j in range(n)) < 0 for row in Rinv):
            continue
        v = [sum(Q[i][j] * gamma[j] for j in range(n)) for i in range(n)]
        if v not in values:
            values.append(v)
    return values


def rand_q():
    return F(rng.randint(-60, 60), rng.randint(1, 12))


tmp = tempfile.mkdtemp(prefix="impactcert-friction-")
try:
    compared = 0
    for name, (M, normals, friction) in SYSTEMS.items():
        sysfile = os.path.join(tmp, name + ".json")
        with open(sysfile, "w") as f:
            json.dump(system_json(name, M, normals, friction), f)
        S = System(M, normals, friction)
        e = [F(1, 2)] * len(normals) if name != "wall-disks" else [F(1, 2), F(1, 3)]
        for on in ("all", "approaching"):
            lawfile = os.path.join(tmp, f"{name}-{on}.json")
            p = run(["derive", "newton", "--system", sysfile, "--restitution", ",".join(q(x) for x in e),
                     "--restitution-on", on, "-o", lawfile], 0)
            if p.returncode != 0:
                continue
            law = json.load(open(lawfile))
            for _ in range(SAMPLES):
                u = [rand_q() for _ in range(S.n)]
                gm = S.velocities(u)
                sols = S.solutions(u, e, approaching=(on == "approaching"))
                if len(sols) != 1:
                    fail(f"{name}/{on}: u- = {u}: the oracle finds {len(sols)} solutions, the law claims one")
                    continue
                expected = S.velocities(sols[0])
                got = locate(law, gm)
                if got != [expected]:
                    fail(f"{name}/{on}: u- = {u}: law {got}, oracle {expected}")
                compared += 1
            # Negative control: one entry of Q changed, in the piece holding the last gamma- compared,
            # is caught (the law's side of the comparison can fail).
            k = next(i for i, (Rinv, _) in enumerate(pieces_of(law))
                     if Rinv is not None and all(sum(r[j] * gm[j] for j in range(len(gm))) >= 0 for r in Rinv))
            j = next(j for j in range(len(gm)) if gm[j] != 0)
            bad = json.loads(json.dumps(law))
            bad["pieces"][k]["Q"][0][j] = q(F(bad["pieces"][k]["Q"][0][j]) + 1)
            if locate(bad, gm) == [expected]:
                fail(f"{name}/{on}: Q of piece {k + 1} changed, and the comparison at {gm} still agrees")
            # Negative control: the oracle with another mu disagrees somewhere (the comparison can fail).
            wrong = System(M, normals, [(k, mu + 1 if mu else F(1), eT, cols) for (k, mu, eT, cols) in friction])
            differs = False
            for _ in range(400):
                u = [rand_q() for _ in range(S.n)]
                sols = wrong.solutions(u, e, approaching=(on == "approaching"))
                if len(sols) == 1 and locate(law, S.velocities(u)) != [wrong.velocities(sols[0])]:
                    differs = True
                    break
            if not differs:
                fail(f"{name}/{on}: the negative control (mu + 1 in the oracle) agrees with the law")
    print(f"compared {compared} random rational inputs with the oracle")

    # The sequential law with friction against a direct simulation in body velocities: while a
    # normal approaches, the rule picks one and the oracle solves that contact's law alone.
    def simulate(M, normals, friction, e, rule, u, limit=100):
        subs = []
        for k in range(len(normals)):
            fr = [(0, mu, eT, cols) for (kk, mu, eT, cols) in friction if kk == k]
            subs.append(System(M, [normals[k]], fr))
        S = System(M, normals, friction)
        for _ in range(limit + 1):
            g = S.velocities(u)[:len(normals)]
            approaching = [k for k in range(len(normals)) if g[k] < 0]
            if not approaching:
                return u
            if rule == "left-first":
                k = approaching[0]
            else:
                k = min(approaching, key=lambda i: (g[i], i))
            sols = subs[k].solutions(u, [e[k]])
            if len(sols) != 1:
                return None
            u = sols[0]
        return None

    seq_compared = 0
    for name in ("rod", "coupled", "wall-disks", "kane"):
        M, normals, friction = SYSTEMS[name]
        S = System(M, normals, friction)
        sysfile = os.path.join(tmp, name + ".json")
        e = [F(1, 2)] * len(normals)
        for rule in ("most-negative", "left-first"):
            lawfile = os.path.join(tmp, f"{name}-seq-{rule}.json")
            p = run(["derive", "sequential", "--system", sysfile, "--restitution", "1/2", "--rule", rule, "-o", lawfile], 0)
            if p.returncode != 0:
                continue
            law = json.load(open(lawfile))
            for _ in range(min(SAMPLES // 5, 150)):
                u = [rand_q() for _ in range(S.n)]
                up = simulate(M, normals, friction, e, rule, u)
                if up is None:
                    continue
                expected = S.velocities(up)
                got = locate(law, S.velocities(u))
                if got != [expected]:
                    fail(f"sequential {name}/{rule}: u- = {u}: law {got}, simulation {expected}")
                seq_compared += 1
    print(f"sequential law with friction: compared {seq_compared} random rational inputs with the simulation")
    if seq_compared < 4 * min(SAMPLES // 5, 150):
        fail(f"only {seq_compared} sequential comparisons")

    # Not a function: Kane's system at mu = 1/2 (G_NN - mu |G_NT| < 0): exit 1 with two solutions.
    M, normals, friction = SYSTEMS["kane"]
    for mu, expect in ((F(1, 2), 1), (F(442392, 954648), 1), (F(442391, 954648), 0)):
        fr = [(0, mu, 0, friction[0][3])]
        sysfile = os.path.join(tmp, "kane-mu.json")
        with open(sysfile, "w") as f:
            json.dump(system_json("kane-mu", M, normals, fr), f)
        p = run(["derive", "newton", "--system", sysfile, "--restitution", "1/2", "--json", "-o",
                 os.path.join(tmp, "kane-mu-law.json")], expect)
        if expect == 0:
            continue
        w = json.loads(p.stdout)
        if w["verdict"] != "two-solutions":
            fail(f"kane mu = {mu}: verdict {w['verdict']}")
            continue
        gm = [F(x) for x in w["gamma_minus"]]
        # u- = W^-T gamma- (n = d = 2)
        S = System(M, normals, fr)
        Wt = [S.columns[0], S.columns[1]]
        u = solve(Wt, gm)
        found = [S.velocities(s) for s in S.solutions(u, [F(1, 2)])]
        claimed = [[F(x) for x in g] for g in w["gamma_plus"]]
        if claimed[0] == claimed[1] or any(c not in found for c in claimed):
            fail(f"kane mu = {mu}: the witness's solutions {claimed} are not the oracle's {found}")
        else:
            print(f"kane mu = {mu}: not a function, gamma- = {w['gamma_minus']}: both solutions recomputed")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("ok")
