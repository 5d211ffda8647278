#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Scenes with polygons, capsules and skins (issue 43): contacts found exactly, laws checked by
an independent oracle.

For each scene of examples/scenes/ below, the contacts are written here by hand (point, normal,
bodies); their columns of W are computed in fractions from the lever arms (and the tangent
(n_y, -n_x) where the contact is rough) and must be the law's columns. The Newton law derived
from the scene (restitution on all contacts and on approaching ones) must then give, at random
rational u-, the gamma+ of the only solution the oracle finds by enumerating contact modes in
body velocities (tests/oracles/friction_lcp.py: M, W and the Coulomb conditions, no G).
Negative controls: a changed entry of Q is caught; a scene made of four segments landing on a
corner has one contact (a shared vertex counted once); overlapping, non-convex, irrational and
ill-defined geometry is one line naming the shape, exit 2.
Usage: scene_shapes_test.py IMPACTCERT SOURCE_DIR SAMPLES_PER_LAW [--light]
(--light, the sanitizer build's run: restitution on all contacts only, without the ball on a ball.)
"""
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
from fractions import Fraction as F

CLI, SRC = sys.argv[1], sys.argv[2]
SAMPLES = int(sys.argv[3]) if len(sys.argv) > 3 else 630
LIGHT = "--light" in sys.argv[4:]
SAMPLES3 = max(1, SAMPLES // 8)  # scenes in space: the oracle enumerates 10 modes per rough contact
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
from friction_lcp import System  # noqa: E402
from scene_columns import hand_system, hand_system3, law_columns, locate, pieces_of  # noqa: E402
from testkit import finish  # noqa: E402

rng = random.Random(20261128)
failures = []
SCENES = os.path.join(SRC, "examples", "scenes")


def fail(msg):
    failures.append(msg)


def run(args, expect=0):
    p = subprocess.run([CLI] + args, capture_output=True, text=True)
    if expect is not None and p.returncode != expect:
        fail(f"{' '.join(args)}: exit {p.returncode}, expected {expect}: {p.stderr.strip()[:300]}")
    return p


# Each scene by hand: bodies (mass, inertia, centre) in order, and contacts (body a or None for a
# boundary, body b, point, unit normal from a to b, mu).
H = F(1, 2)
HAND = {
    # a 2 x 1 box flat on the ground: its two bottom corners
    "box-landing-flat": ([(1, F(5, 12), (0, H))],
                         [(None, 0, (-1, 0), (0, 1), 0), (None, 0, (1, 0), (0, 1), 0)]),
    # a unit disk at (1, 1) in the corner of a floor and a wall
    "ball-in-a-corner": ([(1, F(2, 5), (1, 1))],
                         [(None, 0, (1, 0), (0, 1), 0), (None, 0, (0, 1), (1, 0), 0)]),
    # a ladder from (3, 0) on a rough floor (mu 1/2) to (0, 4) on a smooth wall
    "ladder": ([(1, F(25, 12), (F(3, 2), 2))],
               [(None, 0, (3, 0), (0, 1), H), (None, 0, (0, 4), (1, 0), 0)]),
    # a capsule (segment from -1 to 1, radius 1/4) lying on its side: the two ends of its flat
    "capsule-on-its-side": ([(1, H, (0, F(1, 4)))],
                            [(None, 0, (-1, 0), (0, 1), 0), (None, 0, (1, 0), (0, 1), 0)]),
    # a 2 x 1 box tilted by (4/5, 3/5) with a skin of 1/10, on its lowest rounded corner, rough (1/4)
    "rounded-box-on-a-corner": ([(1, F(5, 12), (0, F(11, 10)))],
                                [(None, 0, (-H, 0), (0, 1), F(1, 4))]),
    # a 1 x 1/2 box on a 2 x 1 box whose right edges line up: the upper box's bottom corners
    "box-on-a-box": ([(2, F(5, 6), (0, H)), (1, F(5, 48), (H, F(5, 4)))],
                     [(None, 0, (-1, 0), (0, 1), 0), (None, 0, (1, 0), (0, 1), 0),
                      (0, 1, (1, 1), (0, 1), 0), (0, 1, (0, 1), (0, 1), 0)]),
    # a capsule (core from (-1/4, 5/4) to (3/4, 5/4), radius 1/4) lying on that box: skin to edge
    "capsule-on-a-box": ([(2, F(5, 6), (0, H)), (1, F(1, 8), (F(1, 4), F(5, 4)))],
                         [(None, 0, (-1, 0), (0, 1), 0), (None, 0, (1, 0), (0, 1), 0),
                          (0, 1, (F(-1, 4), 1), (0, 1), 0), (0, 1, (F(3, 4), 1), (0, 1), 0)]),
    # the block of docs/sweep.md, landing on a listed corner (rough, 1/2)
    "block-on-a-corner": ([(1, F(5, 12), (0, 1))], [(None, 0, (-H, 0), (0, 1), H)]),
}


# Scenes in space by hand: bodies (mass, principal moments, centre, rotation rows or None) and
# contacts (body a or None, body b, point, unit normal from a to b, mu). A rough contact has the
# tangents H e1, H e2 of the reflection H = I - 2 v v^T / v.v, v = n - e3 (docs/formats.md).
R7 = [[F(3, 7), F(-2, 7), F(6, 7)], [F(6, 7), F(3, 7), F(-2, 7)], [F(-2, 7), F(6, 7), F(3, 7)]]
RY = [[F(4, 5), 0, F(-3, 5)], [0, 1, 0], [F(3, 5), 0, F(4, 5)]]
BOX_I = (F(5, 48), F(17, 48), F(5, 12))
HAND3 = {
    "3d-spinning-ball": ([(1, (F(2, 5),) * 3, (0, 0, 1), None)], [(None, 0, (0, 0, 0), (0, 0, 1), H)]),
    # the lowest corner of the box (half extents 1, 1/2, 1/4) turned by R7: R7 (1, -1/2, -1/4) + (0, 0, 23/28)
    "3d-box-on-a-corner": ([(1, BOX_I, (0, 0, F(23, 28)), R7)],
                           [(None, 0, (F(5, 14), F(5, 7), 0), (0, 0, 1), F(1, 4))]),
    # turned about y: the edge of the corners RY (-1, -+1/2, -1/4) + (0, 0, 4/5)
    "3d-box-on-an-edge": ([(1, BOX_I, (0, 0, F(4, 5)), RY)],
                          [(None, 0, (F(-13, 20), -H, 0), (0, 0, 1), 0), (None, 0, (F(-13, 20), H, 0), (0, 0, 1), 0)]),
    "3d-ball-on-a-ball": ([(2, (F(4, 5),) * 3, (0, 0, 1), None), (1, (F(1, 10),) * 3, (1, 1, F(3, 2)), None)],
                          [(None, 0, (0, 0, 0), (0, 0, 1), H), (0, 1, (F(2, 3), F(2, 3), F(4, 3)), (F(2, 3), F(2, 3), F(1, 3)), H)]),
    "3d-ball-in-a-corner": ([(1, (F(2, 5),) * 3, (1, 0, 1), None)],
                            [(None, 0, (1, 0, 0), (0, 0, 1), H), (None, 0, (0, 0, 1), (1, 0, 0), 0)]),
    # inline (INLINE below): a box turned by RY with a full inertia matrix; a ball whose sphere is
    # off its centre touches the box's face +x at RY (1, 0, 0), and a rough tilted plane behind it
    "inline-ball-on-a-box-face": ([(2, [[H, F(1, 10), 0], [F(1, 10), F(1, 3), 0], [0, 0, F(1, 4)]], (0, 0, 0), RY),
                                   (1, (F(1, 10),) * 3, (F(6, 5), 0, F(19, 10)), None)],
                                  [(0, 1, (F(4, 5), 0, F(3, 5)), (F(4, 5), 0, F(3, 5)), 0),
                                   (None, 1, (F(8, 5), 0, F(6, 5)), (F(-4, 5), 0, F(-3, 5)), H)]),
}
INLINE = {
    "inline-ball-on-a-box-face": {
        "format": "impactcert-scene/1", "name": "ball-on-a-box-face", "dimension": 3,
        "bodies": [{"name": "box", "mass": "2", "inertia": [["1/2", "1/10", "0"], ["1/10", "1/3", "0"], ["0", "0", "1/4"]],
                    "position": ["0", "0", "0"], "rotation": [["4/5", "0", "-3/5"], ["0", "1", "0"], ["3/5", "0", "4/5"]],
                    "shapes": [{"box": ["1", "1/2", "1/4"]}]},
                   {"name": "ball", "mass": "1", "inertia": ["1/10", "1/10", "1/10"], "position": ["6/5", "0", "19/10"],
                    "shapes": [{"sphere": "1/2", "center": ["0", "0", "-1"]}]}],
        "boundaries": [{"name": "backstop", "point": ["8/5", "0", "6/5"], "normal": ["-4/5", "0", "-3/5"]}],
        "pairs": [{"bodies": ["ball", "backstop"], "mu": "1/2"}], "restitution": "1/2"},
}


tmp = tempfile.mkdtemp(prefix="impactcert-shapes-")
try:
    compared = 0
    both = ("all",) if LIGHT else ("all", "approaching")
    cases = [(name, hand_system(*spec), SAMPLES, both) for name, spec in HAND.items()]
    # The ball on a ball with restitution on approaching contacts has 400 modes (24 s to derive): all only.
    # Its oracle enumerates 100 modes per input (0.14 s): fewer inputs there.
    cases += [(name, hand_system3(*spec), max(1, SAMPLES // 30) if name == "3d-ball-on-a-ball" else SAMPLES3,
               ("all",) if name == "3d-ball-on-a-ball" else both) for name, spec in HAND3.items()
              if not (LIGHT and name == "3d-ball-on-a-ball")]
    for name, (M, normals, friction), samples, ons in cases:
        scene = os.path.join(SCENES, name + ".json")
        if name in INLINE:
            scene = os.path.join(tmp, name + ".scene.json")
            with open(scene, "w") as f:
                json.dump(INLINE[name], f)
        e = [F(1, 2)] * len(normals)
        for on in ons:
            lawfile = os.path.join(tmp, f"{name}-{on}.json")
            if run(["derive", "newton", "--system", scene, "--restitution", "1/2", "--restitution-on", on,
                    "-o", lawfile]).returncode != 0:
                continue
            law = json.load(open(lawfile))
            cols, tangents, law_M = law_columns(law)
            hand_tangents = [c for (_, _, _, cs) in friction for c in cs]
            if cols != normals or tangents != hand_tangents or law_M != M:
                fail(f"{name}: the law's M and columns {law_M} / {cols} / {tangents} are not the hand-computed "
                     f"{M} / {normals} / {hand_tangents}")
                break
            S = System(M, normals, friction)
            pieces = pieces_of(law)
            for _ in range(samples):
                u = [F(rng.randint(-60, 60), rng.randint(1, 12)) for _ in range(S.n)]
                sols = S.solutions(u, e, approaching=(on == "approaching"))
                if len(sols) != 1:
                    fail(f"{name}/{on}: u- = {u}: the oracle finds {len(sols)} solutions")
                    continue
                gm, expected = S.velocities(u), S.velocities(sols[0])
                got = locate(pieces, gm)
                if got != [expected]:
                    fail(f"{name}/{on}: u- = {u}: law {got}, oracle {expected}")
                    break
                compared += 1
            # Negative control: one entry of Q changed in the piece of the last gamma- is caught.
            k = next(i for i, (Rinv, _) in enumerate(pieces)
                     if all(sum(r[j] * gm[j] for j in range(len(gm))) >= 0 for r in Rinv))
            j = next(j for j in range(len(gm)) if gm[j] != 0)
            bad = json.loads(json.dumps(law))
            bad["pieces"][k]["Q"][0][j] = str(F(bad["pieces"][k]["Q"][0][j]) + 1)
            if locate(pieces_of(bad), gm) == [expected]:
                fail(f"{name}/{on}: a changed Q still agrees with the oracle")
        p = run(["verify", "--law", os.path.join(tmp, f"{name}-all.json")], None)
        if p.returncode not in (0, 1):
            fail(f"{name}: verify exit {p.returncode}: {p.stderr.strip()[:200]}")
    if compared < sum(samples * len(ons) for (_, _, samples, ons) in cases):
        fail(f"only {compared} inputs compared")
    print(f"compared {compared} random rational inputs over {len(cases)} scenes with the oracle")

    # A box drawn as four segments, landing on a corner: the corner is on two segments, one contact.
    outline = {"format": "impactcert-scene/1", "name": "outline",
               "bodies": [{"name": "box", "mass": "1", "inertia": "5/12", "position": ["0", "1"], "shapes": [
                   {"segment": [["-1/2", "-1"], ["11/10", "1/5"]]}, {"segment": [["11/10", "1/5"], ["1/2", "1"]]},
                   {"segment": [["1/2", "1"], ["-11/10", "-1/5"]]}, {"segment": [["-11/10", "-1/5"], ["-1/2", "-1"]]}]}],
               "boundaries": [{"name": "ground", "point": ["0", "0"], "normal": ["0", "1"]}], "friction": "1/2",
               "restitution": "1/2"}

    def scene_file(doc, tag):
        path = os.path.join(tmp, tag + ".json")
        with open(path, "w") as f:
            json.dump(doc, f)
        return path

    p = run(["derive", "newton", "--system", scene_file(outline, "outline"), "-o", os.path.join(tmp, "outline-law.json")])
    if p.returncode == 0 and len(json.load(open(os.path.join(tmp, "outline-law.json")))["contacts"]["W"][0]) != 1:
        fail("outline: a shared vertex gave more than one contact")

    # Bad geometry: one line naming the place, exit 2.
    def box(position, polygon=None, radius=None, name="box"):
        shape = {"polygon": polygon or [["-1", "-1/2"], ["1", "-1/2"], ["1", "1/2"], ["-1", "1/2"]]}
        if radius is not None:
            shape["radius"] = radius
        return {"name": name, "mass": "1", "inertia": "1", "position": position, "shapes": [shape]}

    ground = [{"name": "ground", "point": ["0", "0"], "normal": ["0", "1"]}]
    BAD = [
        ("sunk", {"bodies": [box(["0", "1/4"])], "boundaries": ground}, "$.bodies[0].shapes[0]", "beyond the boundary"),
        ("skin sunk", {"bodies": [box(["0", "1/2"], radius="1/10")], "boundaries": ground}, "$.bodies[0].shapes[0]",
         "beyond the boundary"),
        ("overlap", {"bodies": [box(["0", "1/2"]), box(["1", "3/4"], name="b")], "boundaries": ground},
         "$.bodies[0].shapes[0] and $.bodies[1].shapes[0]", "overlap"),
        ("non-convex", {"bodies": [box(["0", "1"], polygon=[["-1", "-1"], ["0", "0"], ["1", "-1"], ["0", "1"]])],
                        "boundaries": ground}, "$.bodies[0].shapes[0]", "convex"),
        ("collinear", {"bodies": [box(["0", "1"], polygon=[["-1", "-1"], ["0", "-1"], ["1", "-1"], ["0", "1"]])],
                       "boundaries": ground}, "$.bodies[0].shapes[0].polygon", "on a line"),
        ("two vertices", {"bodies": [box(["0", "1"], polygon=[["-1", "-1"], ["1", "-1"]])], "boundaries": ground},
         "$.bodies[0].shapes[0].polygon", "3 to 64"),
        ("negative skin", {"bodies": [box(["0", "1/2"], radius="-1/10")], "boundaries": ground},
         "$.bodies[0].shapes[0].radius", ">= 0"),
        # two squares touching corner to corner: both edge lines through the corner separate them
        ("corners", {"bodies": [box(["0", "0"], polygon=[["-1", "-1"], ["0", "-1"], ["0", "0"], ["-1", "0"]]),
                                box(["0", "0"], polygon=[["0", "0"], ["1", "0"], ["1", "1"], ["0", "1"]], name="b")]},
         "$.bodies[0].shapes[0] and $.bodies[1].shapes[0]", "normal is not defined"),
        # two segments end to end in a line: no normal (a perpendicular one would be wrong)
        ("end to end", {"bodies": [{"name": "a", "mass": "1", "inertia": "1", "position": ["1/2", "1"],
                                    "shapes": [{"segment": [["-1/2", "-1"], ["1/2", "-1"]]}]},
                                   {"name": "b", "mass": "1", "inertia": "1", "position": ["3/2", "-1"],
                                    "shapes": [{"segment": [["-1/2", "1"], ["1/2", "1"]]}]}]},
         "$.bodies[0].shapes[0] and $.bodies[1].shapes[0]", "normal is not defined"),
        # a vertex on an edge of irrational length (from (0, -1) to (1, 1)): its unit normal is irrational
        ("irrational", {"bodies": [box(["0", "0"], polygon=[["-1", "-1"], ["0", "-1"], ["1", "1"], ["-1", "1"]]),
                                   box(["2", "0"], polygon=[["-3/2", "0"], ["1", "-2"], ["1", "0"]], name="b")]},
         "$.bodies[0].shapes[0]", "not rational"),
    ]
    def body3(name, position, shapes, rotation=None, inertia=("1", "1", "1")):
        b = {"name": name, "mass": "1", "inertia": list(inertia), "position": position, "shapes": shapes}
        if rotation:
            b["rotation"] = rotation
        return b

    plane3 = [{"name": "ground", "point": ["0", "0", "0"], "normal": ["0", "0", "1"]}]
    ball = [{"sphere": "1"}]
    BAD += [(tag, dict({"dimension": 3}, **doc), where, needle) for tag, doc, where, needle in [
        ("3d not a rotation", {"bodies": [body3("b", ["0", "0", "1"], ball, [["1", "0", "0"], ["0", "1", "1"], ["0", "0", "1"]])],
                               "boundaries": plane3}, "$.bodies[0].rotation", "orthonormal"),
        ("3d reflection", {"bodies": [body3("b", ["0", "0", "1"], ball, [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "-1"]])],
                           "boundaries": plane3}, "$.bodies[0].rotation", "determinant"),
        ("3d inertia", {"bodies": [body3("b", ["0", "0", "1"], ball, None, (["1", "2", "0"], ["2", "1", "0"], ["0", "0", "1"]))],
                        "boundaries": plane3}, "$.bodies[0].inertia", "positive definite"),
        ("3d flat point", {"bodies": [body3("b", ["0", "1"], ball)], "boundaries": plane3}, "$.bodies[0].position", "[x, y, z]"),
        ("3d sphere in a box", {"bodies": [body3("a", ["0", "0", "2"], [{"box": ["1", "1", "1"]}]),
                                           body3("b", ["0", "0", "2"], [{"sphere": "1/4"}])], "boundaries": plane3},
         "$.bodies[0].shapes[0] and $.bodies[1].shapes[0]", "overlap"),
        ("3d two boxes", {"bodies": [body3("a", ["0", "0", "1"], [{"box": ["1", "1", "1"]}]),
                                     body3("b", ["0", "0", "3"], [{"box": ["1", "1", "1"]}])], "boundaries": plane3},
         "$.bodies[0].shapes[0] and $.bodies[1].shapes[0]", "list them"),
        # two spheres of one body touching a box's edge at one point, with two normals
        ("3d two normals", {"bodies": [body3("a", ["0", "0", "1"], [{"box": ["1", "1", "1"]}]),
                                       body3("b", ["0", "0", "0"], [{"sphere": "1", "center": ["2", "1", "1"]},
                                                                    {"sphere": "1", "center": ["1", "2", "1"]}])]},
         "$.bodies[0].shapes[0] and $.bodies[1].shapes[1]", "normal is not defined"),
        ("3d listed off the ball", {"bodies": [body3("b", ["0", "0", "1"], ball)], "boundaries": plane3,
                                    "contacts": [{"bodies": ["ground", "b"], "point": ["5", "0", "0"], "normal": ["0", "0", "1"]}]},
         "$.contacts[0].point", "not on a shape"),
        ("3d contacts word", {"bodies": [body3("b", ["0", "0", "1"], ball)], "boundaries": plane3, "contacts": "auto"},
         "$.contacts", "\"find\""),
    ]]
    for tag, doc, where, needle in BAD:
        doc = dict({"format": "impactcert-scene/1", "name": tag.replace(" ", "-")}, **doc)
        p = run(["derive", "newton", "--system", scene_file(doc, tag.replace(" ", "-"))], 2)
        if where not in p.stderr or needle not in p.stderr or p.stderr.count("\n") != 1:
            fail(f"bad scene {tag}: {p.stderr!r}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish(failures)
