#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Consistency fuzzing with friction (SPEC section 9): no false alarm, real findings replayed.

Implementations (tests/impls/friction_impls.py) of the Newton law with friction, rounded to
doubles from the exact oracle: `exact` must raise no alarm but energy, and energy only where the
law itself gains (Kane's pendulum at mu = 1/4); `reversed` and `excess` must be reported as
coulomb and friction-cone violations, each worst case replayed with `eval --float` (exit 1, the
property named) and recomputed here in fractions from M and W (beyond a margin far above the
tolerance). Systems: a spinning disk on rough ground and a tilted rod (planar scenes), Kane's
pendulum (a law file's head).
Usage: friction_fuzz_test.py BUILD_DIR SOURCE_DIR SAMPLES
"""
import json
import os
import shutil
import shlex
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import testkit  # noqa: E402
import tempfile
from fractions import Fraction as F

BUILD, SRC = sys.argv[1], sys.argv[2]
SAMPLES = sys.argv[3] if len(sys.argv) > 3 else "200"
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
from friction_lcp import solve  # noqa: E402

CLI = os.path.join(BUILD, "impactcert")
IMPL = os.path.join(SRC, "tests", "impls", "friction_impls.py")
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def hexf(t):
    return F(float.fromhex(t))


tmp = tempfile.mkdtemp(prefix="impactcert-friction-fuzz-")
scenes = {
    "disk": {"format": "impactcert-scene/1", "name": "spinning-disk",
             "bodies": [{"name": "disk", "mass": "1", "inertia": "1/2", "position": ["0", "1"], "shapes": [{"disk": "1"}]}],
             "boundaries": [{"name": "ground", "point": ["0", "0"], "normal": ["0", "1"]}],
             "friction": "1/2", "restitution": "1/2"},
    "rod": {"format": "impactcert-scene/1", "name": "rod",
            "bodies": [{"name": "rod", "mass": "1", "inertia": "1/3", "position": ["3/5", "4/5"],
                        "shapes": [{"segment": [["-3/5", "-4/5"], ["3/5", "4/5"]]}]}],
            "boundaries": [{"name": "ground", "point": ["0", "0"], "normal": ["0", "1"]}],
            "friction": "1/2", "restitution": "1/2"},
}
try:
    systems = {}
    for name, scene in scenes.items():
        path = os.path.join(tmp, name + ".json")
        json.dump(scene, open(path, "w"))
        law = os.path.join(tmp, name + "-law.json")
        p = subprocess.run([CLI, "derive", "newton", "--system", path, "-o", law], capture_output=True, text=True)
        if p.returncode != 0:
            fail(f"derive {name}: {p.stderr}")
            continue
        systems[name] = (path, law, False)
    systems["kane"] = (os.path.join(SRC, "proofs", "kane", "gains", "law.json"),
                       os.path.join(SRC, "proofs", "kane", "gains", "law.json"), True)

    for name, (system, law, gains) in systems.items():
        head = json.load(open(law))
        if "M" in head:
            M = [[F(x) for x in r] for r in head["M"]]
        else:
            m = [F(x) for x in head["masses"]]
            M = [[m[i] if i == j else F(0) for j in range(len(m))] for i in range(len(m))]
        n = len(M)
        W = head["contacts"]["W"]
        cols = [[F(W[i][k]) for i in range(n)] for k in range(len(W[0]))]
        fr = head["contacts"]["friction"][0]
        cols.append([F(x) for x in fr["tangents"][0]])
        mu = F(fr["mu"])
        for mode in ("exact", "reversed", "excess"):
            cmd = [CLI, "fuzz", "--system", system, "--velocities", "--samples", SAMPLES, "--json",
                   "--impl-cmd", f"python3 {shlex.quote(IMPL)} {shlex.quote(law)} {mode} 1/2"]
            p = subprocess.run(cmd, capture_output=True, text=True)
            try:
                j = json.loads(p.stdout)
            except json.JSONDecodeError:
                fail(f"{name}/{mode}: no JSON (exit {p.returncode}): {p.stderr[:300]}")
                continue
            v = j["violations"]
            if not (j["checked_properties"]["friction_cone"] and j["checked_properties"]["coulomb"]):
                fail(f"{name}/{mode}: friction properties not checked")
            if any(v[k] for k in ("crashed", "hung", "malformed", "refused", "non_finite", "momentum", "kinetic")):
                fail(f"{name}/{mode}: unexpected failures {v}")
            if mode == "exact":
                others = {k: v[k] for k in ("kinematic", "friction_cone", "coulomb", "nonexpansive", "continuity") if v[k]}
                if others:
                    fail(f"{name}/exact: false alarm {others}")
                if gains != (v["energy"] > 0):
                    fail(f"{name}/exact: energy {v['energy']} (the law gains energy: {gains})")
                continue
            wanted = "coulomb" if mode == "reversed" else "friction_cone"
            if v[wanted] == 0:
                fail(f"{name}/{mode}: no {wanted} violation reported")
                continue
            w = j["worst"][wanted]
            # Independent recomputation: Lambda from M (u+ - u-) = W Lambda (W has full column rank).
            u = [hexf(t) for t in w["input"]]
            up = [hexf(t) for t in w["output"]]
            du = [a - b for a, b in zip(up, u)]
            Mdu = [sum(M[i][k] * du[k] for k in range(n)) for i in range(n)]
            Gram = [[sum(a[i] * b[i] for i in range(n)) for b in cols] for a in cols]
            lam = solve(Gram, [sum(a[i] * Mdu[i] for i in range(n)) for a in cols])
            scale = sum(abs(x) for x in lam) + 1
            if mode == "excess":
                if not abs(lam[-1]) - mu * lam[0] > F(1, 10**6) * scale:
                    fail(f"{name}/excess: the worst case is not outside the friction cone: Lambda = {lam}")
            else:
                gp_t = sum(cols[-1][i] * up[i] for i in range(n))  # e_T = 0
                slipping = abs(gp_t) > F(1, 10**6) * (sum(abs(x) for x in u) + 1)
                opposing = lam[-1] == -mu * lam[0] if gp_t > 0 else lam[-1] == mu * lam[0]
                if not slipping or opposing:
                    fail(f"{name}/reversed: the worst case obeys Coulomb: xi_T = {gp_t}, Lambda = {lam}")
            r = testkit.run_replay(w["replay"], CLI)
            title = "(coulomb)" if wanted == "coulomb" else "(friction cone)"
            if r.returncode != 1 or title not in r.stdout + r.stderr:
                fail(f"{name}/{mode}: replay exit {r.returncode}: {(r.stdout + r.stderr)[:300]}")
            print(f"{name}/{mode}: {wanted} {v[wanted]}, worst replayed and recomputed")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("ok")
