#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Scenes with dependent contact columns against their baselines, in one run (scripts/bench):
derive newton (restitution on approaching contacts) and verify, wall time and pieces, for a box
landing flat (frictionless: independent columns) and on rough ground (four columns, rank 3), a box
on an edge in space without and with friction (six columns, rank 5), and a box flat on a plane in
space (four corners, rank 3).

Usage: scene_bench.py IMPACTCERT SOURCE_DIR"""

import os
import re
import subprocess
import sys
import tempfile
import time

cli, src = sys.argv[1], sys.argv[2]
scenes = [("box-landing-flat", "planar baseline: frictionless, independent"),
          ("box-flat-on-rough-ground", "planar, rough: 4 columns, rank 3"),
          ("3d-box-on-an-edge", "space baseline: frictionless, independent"),
          ("3d-rough-box-on-an-edge", "space, rough: 6 columns, rank 5"),
          ("3d-box-flat-on-a-plane", "space, frictionless: 4 columns, rank 3")]
rows = []
with tempfile.TemporaryDirectory() as tmp:
    for name, what in scenes:
        law = os.path.join(tmp, name + ".json")
        t0 = time.monotonic()
        d = subprocess.run([cli, "derive", "newton", "--system", os.path.join(src, "examples", "scenes", name + ".json"),
                            "--restitution-on", "approaching", "-o", law], capture_output=True, text=True)
        t1 = time.monotonic()
        v = subprocess.run([cli, "verify", "--law", law], capture_output=True, text=True)
        t2 = time.monotonic()
        pieces = re.search(r"\(([0-9]+) pieces", d.stderr)
        verdict = v.stdout.strip().splitlines()[-1].split(" (")[0] if v.stdout.strip() else "-"
        rows.append((name, what, d.returncode, t1 - t0, pieces.group(1) if pieces else "-", t2 - t1, verdict))
print("derive newton and verify, scenes with dependent contact columns and their baselines (this run)")
print(f"  {'scene':<26}{'exit':>5}{'derive s':>10}{'pieces':>8}{'verify s':>10}  verdict; what")
for name, what, rc, dt, pieces, vt, verdict in rows:
    print(f"  {name:<26}{rc:>5}{dt:>10.2f}{pieces:>8}{vt:>10.2f}  {verdict}; {what}")
