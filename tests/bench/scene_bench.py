#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Scenes with dependent contact columns against their baselines, in one run (scripts/bench):
derive newton (restitution on approaching contacts) and verify, wall time and pieces, for a box
landing flat (frictionless: independent columns) and on rough ground (four columns, rank 3), a box
on an edge in space without and with friction (six columns, rank 5), and a box flat on a plane in
space (four corners, rank 3); and a spinning ball in space with the friction box, the pyramid and
a hexagon of friction (the polygon's coulomb by copositive forms, one per piece and vertex).

Usage: scene_bench.py IMPACTCERT SOURCE_DIR"""

import json
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
          ("3d-box-flat-on-a-plane", "space, frictionless: 4 columns, rank 3"),
          ("3d-spinning-ball", "space, the friction box: baseline"),
          ("3d-spinning-ball-pyramid", "space, MuJoCo's pyramid"),
          ("3d-spinning-ball-hexagon", "space, a hexagon of friction (written here)")]
rows = []
with tempfile.TemporaryDirectory() as tmp:
    hexagon = json.load(open(os.path.join(src, "examples", "scenes", "3d-spinning-ball.json")))
    hexagon["name"] = "3d-spinning-ball-hexagon"
    hexagon["friction_cone"] = {"facets": [["2", "0"], ["1", "2"], ["-1", "2"], ["-2", "0"], ["-1", "-2"], ["1", "-2"]]}
    json.dump(hexagon, open(os.path.join(tmp, "3d-spinning-ball-hexagon.json"), "w"))
    for name, what in scenes:
        law = os.path.join(tmp, name + ".json")
        scene = os.path.join(src, "examples", "scenes", name + ".json")
        if not os.path.exists(scene):
            scene = os.path.join(tmp, name + ".json")
            law = os.path.join(tmp, name + "-law.json")
        t0 = time.monotonic()
        d = subprocess.run([cli, "derive", "newton", "--system", scene,
                            "--restitution-on", "approaching", "-o", law], capture_output=True, text=True)
        t1 = time.monotonic()
        v = subprocess.run([cli, "verify", "--law", law], capture_output=True, text=True)
        t2 = time.monotonic()
        pieces = re.search(r"\(([0-9]+) pieces", d.stderr)
        verdict = v.stdout.strip().splitlines()[-1].split(" (")[0] if v.stdout.strip() else "-"
        rows.append((name, what, d.returncode, t1 - t0, pieces.group(1) if pieces else "-", t2 - t1, verdict))
print("derive newton and verify, scenes with dependent contact columns, friction polygons and their baselines (this run)")
print(f"  {'scene':<26}{'exit':>5}{'derive s':>10}{'pieces':>8}{'verify s':>10}  verdict; what")
for name, what, rc, dt, pieces, vt, verdict in rows:
    print(f"  {name:<26}{rc:>5}{dt:>10.2f}{pieces:>8}{vt:>10.2f}  {verdict}; {what}")
