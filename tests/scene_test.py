#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Planar scenes (impactcert-scene/1, SPEC section 9): contacts found exactly, columns from lever
arms, and bad scenes refused in one line naming the place.

Each scene's W (normals, then the friction tangents) as `derive newton` writes it must equal the
columns computed here by hand from the geometry: for a contact at p with unit normal n from body i
to body j, the column holds (n_x, n_y, (p - c_j) x n) at j and minus that at i; the tangent
t = (n_y, -n_x) the same way.
Usage: scene_test.py IMPACTCERT
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
from fractions import Fraction as F

CLI = sys.argv[1]
failures = []
tmp = tempfile.mkdtemp(prefix="impactcert-scene-")


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def column(nbodies, contact, direction):
    col = [F(0)] * (3 * nbodies)
    (i, ci), (j, cj), p = contact["i"], contact["j"], contact["p"]
    for b, c, s in ((i, ci, -1), (j, cj, 1)):
        if b is None:
            continue
        r = (p[0] - c[0], p[1] - c[1])
        col[3 * b] += s * direction[0]
        col[3 * b + 1] += s * direction[1]
        col[3 * b + 2] += s * (r[0] * direction[1] - r[1] * direction[0])
    return col


def law_of(scene, args=()):
    path = os.path.join(tmp, "scene.json")
    json.dump(scene, open(path, "w"))
    out = os.path.join(tmp, "law.json")
    p = subprocess.run([CLI, "derive", "newton", "--system", path, "-o", out] + list(args), capture_output=True, text=True)
    return p, (json.load(open(out)) if p.returncode == 0 else None)


def body(name, m, J, c, shapes):
    return {"name": name, "mass": str(m), "inertia": str(J), "position": [str(c[0]), str(c[1])], "shapes": shapes}


GROUND = [{"name": "ground", "point": ["0", "0"], "normal": ["0", "1"]}]
c1, c2 = (F(0), F(2)), (F(3), F(6))
CASES = [
    # name, scene, expected contacts [(i, centre_i), (j, centre_j), point, normal, mu]
    ("disk on rough ground",
     {"format": "impactcert-scene/1", "name": "disk", "bodies": [body("disk", 1, F(1, 2), (0, 1), [{"disk": "1"}])],
      "boundaries": GROUND, "friction": "1/2"},
     1, [dict(i=(None, None), j=(0, (0, 1)), p=(0, 0), n=(0, 1), mu=F(1, 2))]),
    ("two disks at a 3-4-5 angle on the ground, smooth between them",
     {"format": "impactcert-scene/1", "name": "pair",
      "bodies": [body("a", 2, 4, c1, [{"disk": "2"}]), body("b", 3, 27, c2, [{"disk": "3"}])],
      "boundaries": GROUND, "friction": "1/3", "pairs": [{"bodies": ["a", "b"], "mu": "0"}]},
     2, [dict(i=(None, None), j=(0, c1), p=(0, 0), n=(0, 1), mu=F(1, 3)),
         dict(i=(0, c1), j=(1, c2), p=(F(6, 5), F(2) + F(8, 5)), n=(F(3, 5), F(4, 5)), mu=F(0))]),
    ("a rod's end on the ground",
     {"format": "impactcert-scene/1", "name": "rod",
      "bodies": [body("rod", 1, F(1, 3), (F(3, 5), F(4, 5)), [{"segment": [["-3/5", "-4/5"], ["3/5", "4/5"]]}])],
      "boundaries": GROUND, "friction": "1/2"},
     1, [dict(i=(None, None), j=(0, (F(3, 5), F(4, 5))), p=(0, 0), n=(0, 1), mu=F(1, 2))]),
    ("a disk on a plank (a segment of another body), off its centre",
     {"format": "impactcert-scene/1", "name": "plank",
      "bodies": [body("plank", 4, 3, (0, 0), [{"segment": [["-3", "0"], ["3", "0"]]}]),
                 body("disk", 1, F(1, 2), (2, 1), [{"disk": "1"}])], "friction": "1/4"},
     2, [dict(i=(0, (0, 0)), j=(1, (2, 1)), p=(2, 0), n=(0, 1), mu=F(1, 4))]),
    ("a stick's end on a tilted board (3-4-5 length, rational normal)",
     {"format": "impactcert-scene/1", "name": "board",
      "bodies": [body("board", 5, 10, (0, 0), [{"segment": [["-4", "-3"], ["4", "3"]]}]),
                 body("stick", 1, 1, (F(-11, 5), F(-2, 5)), [{"segment": [["3/5", "-4/5"], ["-3/5", "4/5"]]}])]},
     2, None),
    ("a listed contact",
     {"format": "impactcert-scene/1", "name": "listed", "bodies": [body("disk", 1, F(1, 2), (0, 1), [{"disk": "1"}])],
      "boundaries": GROUND,
      "contacts": [{"bodies": ["ground", "disk"], "point": ["0", "0"], "normal": ["0", "1"], "mu": "1/5", "restitution": "1/2"}]},
     1, [dict(i=(None, None), j=(0, (0, 1)), p=(0, 0), n=(0, 1), mu=F(1, 5))]),
]
try:
    for name, scene, nbodies, expected, in CASES:
        p, law = law_of(scene)
        if law is None:
            fail(f"{name}: exit {p.returncode}: {p.stderr.strip()}")
            continue
        W = [[F(x) for x in row] for row in law["contacts"]["W"]]
        got_normals = [[W[r][k] for r in range(len(W))] for k in range(len(W[0]))]
        got_tangents = {f["contact"] - 1: ([F(x) for x in f["tangents"][0]], F(f["mu"]))
                        for f in law["contacts"].get("friction", [])}
        if expected is None:
            # the stick's lower end e = (-8/5, -6/5) lies on the board (y = 3/4 x); the normal is the
            # board's unit normal towards the stick, (-3/5, 4/5)
            if len(got_normals) != 1:
                fail(f"{name}: {len(got_normals)} contacts")
            else:
                n = (F(-3, 5), F(4, 5))
                cj, e = (F(-11, 5), F(-2, 5)), (F(-8, 5), F(-6, 5))
                want = column(nbodies, dict(i=(0, (0, 0)), j=(1, cj), p=e), n)
                if got_normals[0] != want:
                    fail(f"{name}: normal column {got_normals[0]}, expected {want}")
            continue
        if len(got_normals) != len(expected):
            fail(f"{name}: {len(got_normals)} contacts, expected {len(expected)}")
            continue
        for k, ct in enumerate(expected):
            c = dict(i=ct["i"], j=ct["j"], p=tuple(F(x) for x in ct["p"]))
            c["i"] = (c["i"][0], tuple(F(x) for x in c["i"][1]) if c["i"][1] is not None else None)
            c["j"] = (c["j"][0], tuple(F(x) for x in c["j"][1]))
            n = tuple(F(x) for x in ct["n"])
            want = column(nbodies, c, n)
            if got_normals[k] != want:
                fail(f"{name}: contact {k + 1}: normal column {got_normals[k]}, expected {want}")
            if ct["mu"]:
                t = (n[1], -n[0])
                want_t = column(nbodies, c, t)
                if k not in got_tangents or got_tangents[k] != (want_t, ct["mu"]):
                    fail(f"{name}: contact {k + 1}: tangent {got_tangents.get(k)}, expected {(want_t, ct['mu'])}")
            elif k in got_tangents:
                fail(f"{name}: contact {k + 1}: mu = 0 has a tangent")
        print(f"{name}: {len(expected)} contact(s), columns as computed by hand")

    # Bad scenes: exit 2, one line, the place named.
    disk = body("disk", 1, F(1, 2), (0, 1), [{"disk": "1"}])
    BAD = [
        ("a listed point 0.005 inside the disk (an engine's skin)",
         {"format": "impactcert-scene/1", "name": "x", "bodies": [disk], "boundaries": GROUND,
          "contacts": [{"bodies": ["ground", "disk"], "point": ["0", "0.005"], "normal": ["0", "1"]}]},
         "$.contacts[0].point"),
        ("a normal that is not a unit vector", {"format": "impactcert-scene/1", "name": "x", "bodies": [disk],
                                                "boundaries": [{"name": "g", "point": ["0", "0"], "normal": ["1", "1"]}]},
         "$.boundaries[0].normal"),
        ("an edge of irrational length",
         {"format": "impactcert-scene/1", "name": "x",
          "bodies": [body("a", 1, 1, (0, 0), [{"segment": [["-1", "-1"], ["1", "1"]]}]),
                     body("b", 1, 1, (-1, 2), [{"segment": [["0", "0"], ["1", "-2"]]}])]},
         "$.bodies[0].shapes[0]"),
        ("a negative friction coefficient", {"format": "impactcert-scene/1", "name": "x", "bodies": [disk],
                                             "boundaries": GROUND, "friction": "-1/2"}, "$.friction"),
        ("no contact", {"format": "impactcert-scene/1", "name": "x", "bodies": [body("d", 1, 1, (0, 5), [{"disk": "1"}])],
                        "boundaries": GROUND}, "$.contacts"),
        ("a restitution for one contact only",
         {"format": "impactcert-scene/1", "name": "x",
          "bodies": [body("a", 1, 1, (0, 1), [{"disk": "1"}]), body("b", 1, 1, (2, 1), [{"disk": "1"}])],
          "boundaries": GROUND, "pairs": [{"bodies": ["a", "b"], "restitution": "1/2"}]}, "contact 1 (ground/a) has no restitution"),
        ("an unknown key", {"format": "impactcert-scene/1", "name": "x", "bodies": [disk], "boundaries": GROUND,
                            "gravity": "9.81"}, "$.gravity"),
        ("a zero mass", {"format": "impactcert-scene/1", "name": "x", "bodies": [body("d", 0, 1, (0, 1), [{"disk": "1"}])],
                         "boundaries": GROUND}, "$.bodies[0].mass"),
    ]
    for name, scene, place in BAD:
        p, law = law_of(scene)
        lines = p.stderr.strip().splitlines()
        # (never a path of a system file that the scene does not have: issue 43)
        if p.returncode != 2 or len(lines) != 1 or place not in lines[0] or "$.contacts.friction" in lines[0]:
            fail(f"{name}: exit {p.returncode}, stderr {p.stderr.strip()!r} (expected exit 2 naming {place})")
        else:
            print(f"refused: {name}: {lines[0]}")

    # Names (issue 40, item 6): a scene's derived law names its velocities and contacts
    # ("coordinates"), verify and report speak of its bodies and contacts by name, the certificate
    # carries them and impactcert-check verifies it; a wrong number of names is refused by the
    # prover (exit 2) and rejected by the checker (exit 1, as any law the prover would refuse),
    # each in one line naming the place.
    SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    CHECK = os.path.join(os.path.dirname(CLI), "impactcert-check")
    two = json.load(open(os.path.join(SRC, "examples", "scenes", "two-disks.json")))
    p, law = law_of(two)
    names = law and law.get("coordinates")
    want = {"velocities": ["lower.vx", "lower.vy", "lower.omega", "upper.vx", "upper.vy", "upper.omega"],
            "contacts": ["ground/lower", "lower/upper"]}
    if names != want:
        fail(f"two disks: coordinates {names}, expected {want}")
    law_path = os.path.join(tmp, "named.json")
    json.dump(law, open(law_path, "w"))
    v = subprocess.run([CLI, "verify", "--law", law_path], capture_output=True, text=True)
    head = v.stdout.splitlines()[0] if v.stdout else ""
    if "2 bodies (lower, upper), 6 velocities, 2 contacts (ground/lower, lower/upper) with 2 friction tangents" not in head:
        fail(f"verify names the scene's bodies and contacts: {head!r}")
    cert = os.path.join(tmp, "named.cert.json")
    subprocess.run([CLI, "certify", "--law", law_path, "-o", cert], capture_output=True, text=True)
    k = subprocess.run([CHECK, cert], capture_output=True, text=True)
    if k.returncode not in (0, 1) or "verified" not in k.stdout:
        fail(f"impactcert-check on a law with names: exit {k.returncode}: {k.stdout}{k.stderr}")
    bad = dict(law)
    bad["coordinates"] = {"velocities": want["velocities"][:5], "contacts": want["contacts"]}
    json.dump(bad, open(law_path, "w"))
    v = subprocess.run([CLI, "verify", "--law", law_path], capture_output=True, text=True)
    if v.returncode != 2 or "$.coordinates.velocities" not in v.stderr:
        fail(f"five names for six velocities: verify exit {v.returncode}: {v.stderr.strip()}")
    doc = json.load(open(cert))
    doc["law"]["coordinates"]["contacts"] = ["ground/lower"]
    import hashlib
    doc["law_sha256"] = hashlib.sha256(json.dumps(doc["law"], separators=(",", ":"),
                                                  ensure_ascii=False).encode()).hexdigest()
    json.dump(doc, open(cert, "w"))
    k = subprocess.run([CHECK, cert], capture_output=True, text=True)
    if k.returncode != 1 or "rejected: $.law.coordinates.contacts" not in k.stdout + k.stderr:
        fail(f"impactcert-check, one name for two contacts: exit {k.returncode}: {(k.stdout + k.stderr).strip()}")
    # A system file may name its coordinates too; derive carries them into the law, and a wrong
    # count is one line naming the place.
    system = {"format": "impactcert-system/1", "name": "wall-and-ball", "masses": ["1", "2"],
              "contacts": {"W": [["-1", "1"], ["1", "0"]]},
              "coordinates": {"velocities": ["left", "right"], "contacts": ["between", "wall"]}}
    for names, ok in ((["between", "wall"], True), (["between"], False)):
        system["coordinates"]["contacts"] = names
        sys_path = os.path.join(tmp, "named-system.json")
        json.dump(system, open(sys_path, "w"))
        out = os.path.join(tmp, "named-system-law.json")
        d = subprocess.run([CLI, "derive", "newton", "--system", sys_path, "--restitution", "1", "-o", out],
                           capture_output=True, text=True)
        if ok and (d.returncode != 0 or json.load(open(out)).get("coordinates") != system["coordinates"]):
            fail(f"a system's names are not carried into its law: exit {d.returncode}: {d.stderr.strip()}")
        if not ok and (d.returncode != 2 or "$.coordinates.contacts: expected 2 names" not in d.stderr
                       or len(d.stderr.strip().splitlines()) != 1):
            fail(f"one name for two contacts in a system file: exit {d.returncode}: {d.stderr.strip()}")
    # Names are the file's text: report.md and report.html escape them (a contact named like a
    # script, a table cell's end and emphasis), and a long name is cut.
    odd = dict(law)
    odd["coordinates"] = {"velocities": want["velocities"],
                          "contacts": ["<script>alert(1)</script>", "a | b *x* `y` " + "L" * 100]}
    json.dump(odd, open(law_path, "w"))
    out_dir = os.path.join(tmp, "odd-report")
    r = subprocess.run([CLI, "report", "--law", law_path, "-o", out_dir], capture_output=True, text=True)
    html = open(os.path.join(out_dir, "report.html")).read() if r.returncode == 0 else ""
    md = open(os.path.join(out_dir, "report.md")).read() if r.returncode == 0 else ""
    if r.returncode != 0 or "<script>alert" in html or "&lt;script&gt;alert(1)&lt;/script&gt;" not in html:
        fail(f"report.html does not escape a contact's name (exit {r.returncode})")
    elif "a | b" in md or "a \\| b \\*x\\*" not in md or "L" * 60 in md:
        fail("report.md does not escape or cut a contact's name: " +
             next((line for line in md.splitlines() if "contacts (" in line), "")[:300])
    if not failures:
        print("names: the law names the scene's velocities and contacts; verify and the checker use and check them; "
              "reports escape them")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("ok")
