#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Siconos's two-dimensional frictional contact solvers (examples/engines/siconos_fc2d.py, Debian's
python3-siconos), fuzzed on two disks on rough ground (examples/scenes/two-disks.json).

- NSGS (tolerance 1e-12, up to 1000 sweeps) with restitution on approaching contacts: no
  violation, and no answer off the exact Newton law with friction (`--reference approaching`).
- Lemke (fc2d_lexicolemke), which reports success on every one of these problems: friction that
  does not oppose the slip and answers off the exact law. The worst Coulomb case is replayed
  (`eval --float`: exit 1) and recomputed here in fractions from M and W (Lambda = G^-1 (gamma+ -
  gamma-)): a slipping tangent whose impulse is not -mu Lambda_N times the slip's sign.
Usage: siconos_fc2d_test.py BUILD_DIR SOURCE_DIR PYTHON
"""
import json
import os
import shlex
import subprocess
import sys
import tempfile
from fractions import Fraction as F

BUILD, SRC, PYTHON = sys.argv[1], sys.argv[2], sys.argv[3]
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
import testkit  # noqa: E402
from friction_lcp import System, breaks  # noqa: E402

CLI = os.path.join(BUILD, "impactcert")
DRIVER = os.path.join(SRC, "examples", "engines", "siconos_fc2d.py")
SCENE = os.path.join(SRC, "examples", "scenes", "two-disks.json")
failures = []

tmp = tempfile.mkdtemp(prefix="impactcert-siconos-")
law = os.path.join(tmp, "two-disks.json")
subprocess.run([CLI, "derive", "newton", "--system", SCENE, "-o", law], check=True, capture_output=True)
head = json.load(open(law))
W = head["contacts"]["W"]
n = len(W)
M = [[F(head["masses"][i]) if i == j else F(0) for j in range(n)] for i in range(n)]
S = System(M, [[F(W[i][k]) for i in range(n)] for k in range(len(W[0]))],
           [(f["contact"] - 1, F(f["mu"]), F(0), f["tangents"]) for f in head["contacts"]["friction"]])


def fuzz(solver):
    impl = shlex.join([PYTHON, DRIVER, "--system", law, "--restitution", "1/2", "--restitution-on", "approaching",
                       "--solver", solver])
    p = subprocess.run([CLI, "fuzz", "--system", SCENE, "--velocities", "--impl-cmd", impl, "--range", "0.01..10",
                        "--max-rel-error", "1e-9", "--samples", "1000", "--reference", "approaching", "--json"],
                       capture_output=True, text=True)
    return p.returncode, json.loads(p.stdout)


status, j = fuzz("nsgs")
bad = {k: v for k, v in j["violations"].items() if v}
if status != 0 or bad:
    failures.append(f"nsgs: exit {status}, {bad}")
else:
    print(f"nsgs: {j['samples']} samples, no violation, every answer on the exact law")

status, j = fuzz("lemke")
if status != 1 or not j["violations"]["coulomb"] or not j["violations"]["reference"]:
    failures.append(f"lemke: exit {status}, {j['violations']}")
else:
    w = j["worst"]["coulomb"]
    real = breaks(S, [F(float.fromhex(t)) for t in w["input"]], [F(float.fromhex(t)) for t in w["output"]], "coulomb")
    if not real:
        failures.append(f"lemke: the worst Coulomb case does not recompute as a violation: {w}")
    r = testkit.run_replay(w["replay"], CLI)
    if r.returncode != 1 or "(coulomb)" not in r.stdout:
        failures.append(f"lemke: replay: exit {r.returncode}: {r.stdout[-300:]}")
    print(f"lemke: coulomb {j['violations']['coulomb']}, reference {j['violations']['reference']}: "
          "the worst case replayed and recomputed")

# A system with a contact without friction is refused in one line.
p = subprocess.run([PYTHON, DRIVER, "--system", os.path.join(SRC, "proofs", "newton3", "law.json")], input="",
                   capture_output=True, text=True)
if p.returncode != 2 or p.stderr.count("\n") != 1:
    failures.append(f"a frictionless system: exit {p.returncode}: {p.stderr!r}")
testkit.finish(failures)
