#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Box2D with friction and rotation (examples/engines/box2d_friction.cpp), fuzzed for consistency
on the scenes of examples/scenes/: a spinning disk on rough ground, two disks (one resting on
the other) on the ground, a box landing flat and a box on a box (polygons, two contacts each).

- Converged (200 iterations) and without Box2D's edge skin, the engine computes the Newton law
  with friction (restitution on approaching contacts, e_T = 0): its answers agree with the
  independent oracle to float accuracy, and the fuzzer reports no violation of any kind.
- At Box2D's default 8 iterations the two-disk scene is not converged: kinematic, friction-cone
  and Coulomb violations are reported (the box on a box: kinematic); with the default skin (the contact point 0.005 m off the
  scene's) momentum and Coulomb violations. Each worst case is replayed (`eval --float`: exit 1,
  the property named) and recomputed here in fractions from M and W (Lambda = H (gamma+ - gamma-)).
- A box flat on rough ground (two rough contacts, dependent columns): converged and without the
  skin, no violation, and the answers are the oracle's (singular modes included); with the skin,
  kinetic findings (the contact points 0.005 m below the scene's: only a pulling normal impulse at
  the scene's points gives Box2D's change of velocity), the worst one replayed and
  recomputed exactly (tests/oracles/dependent_lp.py: infeasible at the tolerance, feasible just
  above the fuzzer's least distance).
Usage: box2d_friction_test.py BUILD_DIR SOURCE_DIR DRIVER [--light]
(--light, the sanitizer build's run: without the box flat on rough ground, whose findings are
linear programs; tests/redundant_contacts_test.py runs those under the sanitizers.)
"""
import json
import os
import random
import shlex
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import testkit  # noqa: E402
from fractions import Fraction as F

BUILD, SRC, DRIVER = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
from friction_lcp import System, breaks  # noqa: E402
from dependent_lp import box_feasible, finding, widths  # noqa: E402

CLI = os.path.join(BUILD, "impactcert")
SCENES = os.path.join(SRC, "examples", "scenes")
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def mechanics(scene_path):
    """M, the columns (normals then tangents), mu per tangent's contact, from the law impactcert derives."""
    law = "/tmp/impactcert-box2d-test-%d.json" % os.getpid()
    subprocess.run([CLI, "derive", "newton", "--system", scene_path, "--restitution-on", "approaching", "-o", law],
                   check=True, capture_output=True)
    head = json.load(open(law))
    os.unlink(law)
    m = [F(x) for x in head["masses"]]
    n = len(m)
    M = [[m[i] if i == j else F(0) for j in range(n)] for i in range(n)]
    W = head["contacts"]["W"]
    normals = [[F(W[i][k]) for i in range(n)] for k in range(len(W[0]))]
    fr = [(f["contact"] - 1, F(f["mu"]), F(0), f["tangents"]) for f in head["contacts"].get("friction", [])]
    return System(M, normals, fr), [F(x) for x in head["masses"]]


def box2d(scene_path, args, inputs):
    p = subprocess.run([DRIVER, "--scene", scene_path] + args, input="".join(" ".join(repr(x) for x in u) + "\n" for u in inputs),
                       capture_output=True, text=True, check=True)
    return [[float(t) for t in line.split()] for line in p.stdout.splitlines()]


def fuzz(scene_path, args, samples=2000):
    impl = shlex.join([DRIVER, "--scene", scene_path] + args)
    p = subprocess.run([CLI, "fuzz", "--system", scene_path, "--velocities", "--impl-cmd", impl, "--range", "0.01..10",
                        "--max-rel-error", "1e-5", "--samples", str(samples), "--json"], capture_output=True, text=True)
    return p.returncode, json.loads(p.stdout)


def recompute(S, w, prop):
    """The worst case of `prop`, recomputed in contact space from M and W (the oracle's breaks)."""
    return breaks(S, [F(float.fromhex(t)) for t in w["input"]], [F(float.fromhex(t)) for t in w["output"]], prop)


TITLES = {"kinematic": "(kinematic)", "friction_cone": "(friction cone)", "coulomb": "(coulomb)", "momentum": "(momentum)"}
rng = random.Random(7)
LIGHT = "--light" in sys.argv[4:]
for scene in ("spinning-disk", "two-disks", "box-landing-flat", "box-on-a-box") + (() if LIGHT else ("box-flat-on-rough-ground",)):
    path = os.path.join(SCENES, scene + ".json")
    S, _ = mechanics(path)
    # Converged and without the skin: the engine's answers are the law's (the oracle's), to float accuracy.
    inputs = [[round(rng.uniform(-5, 5), 3) for _ in range(S.n)] for _ in range(40)]
    inputs = [u for u in inputs if any(g < 0 for g in S.velocities([F(x) for x in u])[:len(S.normals)])]
    outs = box2d(path, ["--iterations", "200", "--edge-radius", "0"], inputs)
    worst = 0.0
    for u, v in zip(inputs, outs):
        sols = S.solutions([F(x) for x in u], [F(1, 2)] * len(S.normals), approaching=True,
                           dependent=scene == "box-flat-on-rough-ground")
        if len(sols) != 1:
            fail(f"{scene}: the oracle finds {len(sols)} solutions at {u}")
            continue
        exact = [float(x) for x in sols[0]]
        err = max(abs(a - b) for a, b in zip(exact, v)) / max(1.0, max(abs(x) for x in u))
        worst = max(worst, err)
    if worst > 1e-5:
        fail(f"{scene}: Box2D (200 iterations, no skin) differs from the Newton law with friction by {worst:.3g}")
    # dependent columns: linear programs per sample, a quarter of the samples
    status, j = fuzz(path, ["--iterations", "200", "--edge-radius", "0"], 500 if scene == "box-flat-on-rough-ground" else 2000)
    bad = {k: v for k, v in j["violations"].items() if v}
    if status != 0 or bad:
        fail(f"{scene}: converged Box2D without skin: exit {status}, {bad}")
    else:
        print(f"{scene}: converged, no skin: {j['samples']} samples, no violation; "
              f"largest deviation from the exact law {worst:.2g}")

    for args, expected in ((["--iterations", "8", "--edge-radius", "0"], {"two-disks": ["kinematic", "friction_cone", "coulomb"],
                                                                            "box-on-a-box": ["kinematic"]}),
                           (["--iterations", "200"], {"spinning-disk": ["momentum", "coulomb"]})):
        status, j = fuzz(path, args)
        v = j["violations"]
        for prop in expected.get(scene, []):
            if not v[prop]:
                fail(f"{scene} {args}: no {prop} violation reported ({v})")
                continue
            w = j["worst"][prop]
            if not recompute(S, w, prop):
                fail(f"{scene} {args}: the worst {prop} case does not recompute as a violation: {w}")
            r = testkit.run_replay(w["replay"], CLI)
            if r.returncode != 1 or TITLES[prop] not in r.stdout:
                fail(f"{scene} {args}: replay of {prop}: exit {r.returncode}: {r.stdout[-300:]}")
        if expected.get(scene):
            print(f"{scene} {' '.join(args)}: " + ", ".join(f"{k} {v[k]}" for k in expected[scene]) +
                  ": worst cases replayed and recomputed")
    if scene == "box-flat-on-rough-ground":  # dependent columns: the friction cone by a linear program
        status, j = fuzz(path, ["--iterations", "200"], 500)
        w = j["worst"].get("kinetic")
        if status != 1 or not w:
            fail(f"{scene} with the skin: no kinetic finding ({j['violations']})")
        else:
            du, t, tol = finding(w)
            ws = widths(S)
            if box_feasible(S, du, tol, ws, "kinetic") or not box_feasible(S, du, t * F(101, 100), ws, "kinetic"):
                fail(f"{scene} with the skin: the worst kinetic case does not recompute (t = {float(t)})")
            r = testkit.run_replay(w["replay"], CLI)
            if r.returncode != 1 or "(kinetic)" not in r.stdout:
                fail(f"{scene} with the skin: replay exit {r.returncode}")
            print(f"{scene} with the skin: kinetic {j['violations']['kinetic']}, worst {float(t):.3g} "
                  f"against a tolerance of {float(tol):.3g}: recomputed exactly, replayed")
# Segments and capsules are refused by the driver (Box2D 2.4 collides no edge with an edge).
p = subprocess.run([DRIVER, "--scene", os.path.join(SCENES, "ladder.json")], input="0 0 0\n", capture_output=True, text=True)
if p.returncode != 2 or "not driven" not in p.stderr or p.stderr.count("\n") != 1:
    fail(f"the ladder (a segment) is not refused in one line: exit {p.returncode}: {p.stderr!r}")
if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("ok")
