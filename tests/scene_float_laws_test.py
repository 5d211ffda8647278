#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Consistency fuzzing on the new scenes (issue 43): a correct exact law rounded to doubles raises
no alarm; a planted restitution or friction error is found and replayed.

For every scene of examples/scenes/ with polygons, capsules or skins and every scene in space,
the Newton law with restitution on approaching contacts is derived and fuzzed as impactcert's
float law (`fuzz --float-law`, against the same law derived on the fly with `--reference`): no
violation of any kind. Planted bugs, each required to be caught with a replay that exits 1:
  - restitution: the law derived with e + 1/10 at every contact, fuzzed with --restitution e;
  - friction (scenes with friction): the law derived with every mu doubled, against the reference
    law of the scene as it is.
Usage: scene_float_laws_test.py BINDIR SOURCE_DIR SAMPLES [--light]
(--light, the sanitizer build's run: four of the scenes, two planar and two in space.)
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

BIN, SRC = sys.argv[1], sys.argv[2]
SAMPLES = sys.argv[3] if len(sys.argv) > 3 else "2000"
CLI = os.path.join(BIN, "impactcert")
sys.path.insert(0, os.path.join(SRC, "tests"))
import testkit  # noqa: E402

SCENES = ["box-landing-flat", "ball-in-a-corner", "ladder", "capsule-on-its-side", "rounded-box-on-a-corner",
          "box-on-a-box", "capsule-on-a-box", "block-on-a-corner", "3d-spinning-ball", "3d-box-on-a-corner",
          "3d-box-on-an-edge", "3d-ball-in-a-corner"]
if "--light" in sys.argv[4:]:
    SCENES = ["box-landing-flat", "rounded-box-on-a-corner", "3d-spinning-ball", "3d-box-on-a-corner"]
failures = []
tmp = tempfile.mkdtemp(prefix="impactcert-scene-float-")


def run(args, expect=0):
    p = subprocess.run([CLI] + args, capture_output=True, text=True)
    if expect is not None and p.returncode != expect:
        failures.append(f"{' '.join(args)}: exit {p.returncode}, expected {expect}: {p.stderr.strip()[:300]}")
    return p


def fuzz(scene, law, extra):
    p = run(["fuzz", "--system", scene, "--float-law", law, "--range", "0.01..10", "--max-rel-error", "1e-12",
             "--samples", SAMPLES, "--json"] + extra, None)
    return p.returncode, json.loads(p.stdout) if p.stdout else {}


def scaled(doc, key, factor):
    """The scene with every value of `key` (friction or restitution) replaced by f(value)."""
    doc = json.loads(json.dumps(doc))

    def walk(x):
        if isinstance(x, dict):
            for k, v in list(x.items()):
                if k == key or (key == "friction" and k == "mu"):
                    x[k] = factor(v)
                else:
                    walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
    walk(doc)
    return doc


try:
    from fractions import Fraction as F
    for name in SCENES:
        scene = os.path.join(SRC, "examples", "scenes", name + ".json")
        doc = json.load(open(scene))
        e = F(doc.get("restitution", "1"))
        law = os.path.join(tmp, name + ".json")
        run(["derive", "newton", "--system", scene, "--restitution-on", "approaching", "-o", law])
        status, j = fuzz(scene, law, ["--reference", "approaching", "--restitution", str(e)])
        bad = {k: v for k, v in j.get("violations", {}).items() if v}
        if status != 0 or bad:
            failures.append(f"{name}: the exact law in doubles: exit {status}, {bad}")
        # Planted: restitution e + 1/10.
        wrong = os.path.join(tmp, name + "-e.json")
        run(["derive", "newton", "--system", scene, "--restitution-on", "approaching", "--restitution",
             str(min(e + F(1, 10), F(1)) if e < 1 else F(9, 10)), "-o", wrong])
        status, j = fuzz(scene, wrong, ["--restitution", str(e)])
        if status != 1 or not j["violations"].get("restitution"):
            failures.append(f"{name}: a planted restitution error is not found: exit {status}, {j.get('violations')}")
        else:
            r = testkit.run_replay(j["worst"]["restitution"]["replay"], CLI)
            if r.returncode != 1:
                failures.append(f"{name}: the restitution replay exits {r.returncode}")
        # Planted: every mu doubled (scenes with friction).
        if "friction" in json.dumps(json.load(open(law))["contacts"]):
            rough = os.path.join(tmp, name + "-mu.scene.json")
            with open(rough, "w") as f:
                json.dump(scaled(doc, "friction", lambda v: str(2 * F(v))), f)
            wrong = os.path.join(tmp, name + "-mu.json")
            run(["derive", "newton", "--system", rough, "--restitution-on", "approaching", "-o", wrong])
            status, j = fuzz(scene, wrong, ["--reference", "approaching"])
            if status != 1 or not j["violations"].get("reference"):
                failures.append(f"{name}: a planted friction error is not found: exit {status}, {j.get('violations')}")
            else:
                r = testkit.run_replay(j["worst"]["reference"]["replay"], CLI)
                if r.returncode != 1:
                    failures.append(f"{name}: the friction replay exits {r.returncode}")
        print(f"{name}: no alarm on the exact law; planted errors found and replayed")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
testkit.finish(failures)
