#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The Open Dynamics Engine on scenes in space (examples/engines/ode_scene.cpp), fuzzed for
consistency and against the exact law.

- A spinning ball on rough ground and a box landing on an edge: ODE's dWorldStep (its big-matrix
  LCP, friction as its box, restitution on approaching contacts) agrees with the independent
  oracle (tests/oracles/friction_lcp.py: body velocities, no G) to 1e-9, and the fuzzer with
  `--reference approaching` reports nothing.
- A ball on a ball on rough ground: ODE applies friction at the ground with no normal impulse
  there (its dContactApprox1 bounds friction by a normal force the LCP later drops): friction-cone
  and Coulomb findings, each worst case replayed (`eval --float`: exit 1) and recomputed here in
  fractions (Lambda = G^-1 (gamma+ - gamma-) from M and W).
- A box landing exactly on one corner: in doubles ODE finds no contact (the corner's depth rounds
  below zero), so every approaching sample keeps its velocity: kinematic on every sample.
- Dependent columns. A box flat on a plane (four corners, rank 3): ODE finds only some of the
  corners in doubles, and a missed corner keeps approaching (kinematic, recomputed from W). A rough
  box on an edge (six columns, rank 5): friction-cone findings, no impulse in ODE's box of friction
  gives its change of velocity; the worst one replayed and its least distance recomputed by a
  second route (scipy's HiGHS, tests/oracles/dependent_lp.py), far beyond the tolerance.
Usage: ode_scene_test.py BUILD_DIR SOURCE_DIR DRIVER
"""
import json
import os
import random
import shlex
import subprocess
import sys
from fractions import Fraction as F

BUILD, SRC, DRIVER = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
import testkit  # noqa: E402
from friction_lcp import System, breaks  # noqa: E402
from dependent_lp import finding, least_t_float, widths  # noqa: E402

CLI = os.path.join(BUILD, "impactcert")
SCENES = os.path.join(SRC, "examples", "scenes")
failures = []


def fail(msg):
    failures.append(msg)


def mechanics(scene):
    law = f"/tmp/impactcert-ode-test-{os.getpid()}.json"
    subprocess.run([CLI, "derive", "newton", "--system", scene, "-o", law],  # only its M and W are read
                   check=True, capture_output=True)
    head = json.load(open(law))
    os.unlink(law)
    W = head["contacts"]["W"]
    n = len(W)
    if "M" in head:
        M = [[F(x) for x in row] for row in head["M"]]
    else:
        M = [[F(head["masses"][i]) if i == j else F(0) for j in range(n)] for i in range(n)]
    normals = [[F(W[i][k]) for i in range(n)] for k in range(len(W[0]))]
    fr = [(f["contact"] - 1, F(f["mu"]), F(0), f["tangents"]) for f in head["contacts"].get("friction", [])]
    return System(M, normals, fr)


def ode(scene, inputs):
    p = subprocess.run([DRIVER, "--scene", scene], input="".join(" ".join(repr(x) for x in u) + "\n" for u in inputs),
                       capture_output=True, text=True, check=True)
    return [[float(t) for t in line.split()] for line in p.stdout.splitlines()]


def fuzz(scene, samples=1000, reference=True):
    impl = shlex.join([DRIVER, "--scene", scene])
    p = subprocess.run([CLI, "fuzz", "--system", scene, "--velocities", "--impl-cmd", impl, "--range", "0.01..10",
                        "--max-rel-error", "1e-6", "--samples", str(samples), "--json"] +
                       (["--reference", "approaching"] if reference else []), capture_output=True, text=True)
    return p.returncode, json.loads(p.stdout)


rng = random.Random(11)
for name in ("3d-spinning-ball", "3d-box-on-an-edge"):
    scene = os.path.join(SCENES, name + ".json")
    S = mechanics(scene)
    inputs = [[round(rng.uniform(-5, 5), 3) for _ in range(S.n)] for _ in range(60)]
    inputs = [u for u in inputs if any(g < 0 for g in S.velocities([F(x) for x in u])[:len(S.normals)])]
    worst = 0.0
    for u, v in zip(inputs, ode(scene, inputs)):
        sols = S.solutions([F(x) for x in u], [F(1, 2)] * len(S.normals), approaching=True)
        if len(sols) != 1:
            fail(f"{name}: the oracle finds {len(sols)} solutions at {u}")
            continue
        worst = max(worst, max(abs(float(a) - b) for a, b in zip(sols[0], v)) / max(1.0, max(abs(x) for x in u)))
    if not inputs or worst > 1e-9:
        fail(f"{name}: ODE differs from the Newton law with friction by {worst:.3g} ({len(inputs)} inputs)")
    status, j = fuzz(scene)
    bad = {k: v for k, v in j["violations"].items() if v}
    if status != 0 or bad:
        fail(f"{name}: exit {status}, {bad}")
    else:
        print(f"{name}: {j['samples']} samples, no violation; largest deviation from the oracle {worst:.2g}")

# A ball on a ball: friction without a normal impulse at the ground, replayed and recomputed.
scene = os.path.join(SCENES, "3d-ball-on-a-ball.json")
S = mechanics(scene)
status, j = fuzz(scene, 500, reference=False)  # its law with restitution on approaching contacts: 400 modes, 24 s
for prop in ("friction_cone", "coulomb"):
    if not j["violations"][prop]:
        fail(f"ball on a ball: no {prop} finding ({j['violations']})")
        continue
    w = j["worst"][prop]
    real = breaks(S, [F(float.fromhex(t)) for t in w["input"]], [F(float.fromhex(t)) for t in w["output"]], prop)
    if not real:
        fail(f"ball on a ball: the worst {prop} case does not recompute as a violation: {w}")
    r = testkit.run_replay(w["replay"], CLI)
    if r.returncode != 1:
        fail(f"ball on a ball: replay of {prop}: exit {r.returncode}: {r.stdout[-300:]}")
print(f"3d-ball-on-a-ball: friction_cone {j['violations']['friction_cone']}, coulomb {j['violations']['coulomb']}: "
      "worst cases replayed and recomputed")

# A box exactly on one corner: ODE finds no contact in doubles.
scene = os.path.join(SCENES, "3d-box-on-a-corner.json")
status, j = fuzz(scene, 300)
if j["violations"]["kinematic"] < 250 or status != 1:
    fail(f"box on a corner: expected kinematic on the approaching samples, got exit {status}, {j['violations']}")

# Dependent columns: a box flat on a plane (corners missed) and a rough box on an edge (friction).
scene = os.path.join(SCENES, "3d-box-flat-on-a-plane.json")
S = mechanics(scene)
status, j = fuzz(scene, 200)
w = j["worst"].get("kinematic")
if status != 1 or not w or not breaks(S, [F(float.fromhex(t)) for t in w["input"]],
                                      [F(float.fromhex(t)) for t in w["output"]], "kinematic"):
    fail(f"box flat on a plane: no kinematic finding that recomputes ({j['violations']})")
else:
    print(f"3d-box-flat-on-a-plane: kinematic {j['violations']['kinematic']} (corners ODE does not find), recomputed")
scene = os.path.join(SCENES, "3d-rough-box-on-an-edge.json")
S = mechanics(scene)
status, j = fuzz(scene, 100, reference=False)  # its law with restitution on approaching contacts: 24 s to derive
w = j["worst"].get("friction_cone")
if status != 1 or not w:
    fail(f"rough box on an edge: no friction-cone finding ({j['violations']})")
else:
    du, t, tol = finding(w)
    t, tol = float(t), float(tol)
    second = least_t_float(S, du, widths(S))
    if second is None or abs(second - t) > 1e-6 * t or not t > 100 * tol:
        fail(f"rough box on an edge: least distance {t}, by scipy {second}, tolerance {tol}")
    r = testkit.run_replay(w["replay"], CLI)
    if r.returncode != 1 or "(friction cone)" not in r.stdout:
        fail(f"rough box on an edge: replay exit {r.returncode}")
    print(f"3d-rough-box-on-an-edge: friction_cone {j['violations']['friction_cone']}, worst {t:.3g} (scipy {second:.3g}) "
          f"against a tolerance of {tol:.3g}: replayed")

# Scenes in the plane and listed contacts are refused in one line.
for bad in ("two-disks.json", "block-on-a-corner.json"):
    p = subprocess.run([DRIVER, "--scene", os.path.join(SCENES, bad)], input="", capture_output=True, text=True)
    if p.returncode != 2 or p.stderr.count("\n") != 1:
        fail(f"{bad}: exit {p.returncode}: {p.stderr!r}")
testkit.finish(failures)
