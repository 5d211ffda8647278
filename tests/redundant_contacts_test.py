#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Redundant contacts (issue 43): scenes whose columns of W are linearly dependent, checked by an
independent oracle.

For each scene below, M and the columns of W are written here by hand (tests/oracles/
scene_columns.py) and must be the law's. The basis of the law's coordinates is recomputed here
(each column kept when independent of those kept before it, by rank), and the Newton law derived
by impactcert (restitution on all contacts and on approaching ones) must give, at random rational
u-, gamma_B+ = W_B^T u+ of the only solution the oracle finds by enumerating contact modes in body
velocities, singular modes included (tests/oracles/friction_lcp.py, dependent=True: M, W and the
Coulomb conditions, no G); the oracle must also find that no mode's feasible set holds two u+.
At each input the piece's declared impulse Lambda = L gamma_B is checked in body velocities:
M (u+ - u-) = W Lambda exactly, Lambda in the friction cone, and Coulomb's slip signs.
Witnesses: a ball in a corner with mu = 1 (an input with no solution) and mu = 2 (two
different u+), a particle jammed between two walls with restitutions 1/2 and 1/4 (no solution):
each recomputed by the oracle. Negative controls: a changed entry of Q and of an impulse; bad
law files (impulses missing, of the wrong size, on independent columns; symmetries), and the
commands that do not read dependent columns, one line each, exit 2.
Usage: redundant_contacts_test.py IMPACTCERT IMPACTCERT_CHECK SOURCE_DIR SAMPLES_PER_LAW [--light | --sanitizer]
(--light, CI's run: the rough box on an edge in space with restitution on all contacts only, and
not certified: its law with restitution on approaching contacts takes a minute to derive, prove,
certify and check. --sanitizer, the sanitizer build's: the box flat on rough ground and the box
flat on a plane only (the latter with restitution on all contacts, not certified), plus 200 samples of the box's float law fuzzed for consistency, so that
every new code path runs under the sanitizers at a tenth of the cost.)
"""
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
from fractions import Fraction as F

CLI, CHECK, SRC = sys.argv[1], sys.argv[2], sys.argv[3]
SAMPLES = int(sys.argv[4]) if len(sys.argv) > 4 else 1500
SANITIZER = "--sanitizer" in sys.argv[5:]
LIGHT = "--light" in sys.argv[5:] or SANITIZER
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
from friction_lcp import System, affine_solve  # noqa: E402
from scene_columns import hand_system, hand_system3, law_columns, locate, pieces_of  # noqa: E402
from testkit import finish  # noqa: E402

rng = random.Random(43)
failures = []
SCENES = os.path.join(SRC, "examples", "scenes")
H = F(1, 2)


def fail(msg):
    failures.append(msg)


def run(args, expect=0):
    p = subprocess.run(args, capture_output=True, text=True)
    if expect is not None and p.returncode != expect:
        fail(f"{' '.join(args)}: exit {p.returncode}, expected {expect}: {p.stderr.strip()[:300]}")
    return p


RY = [[F(4, 5), 0, F(-3, 5)], [0, 1, 0], [F(3, 5), 0, F(4, 5)]]
BOX_I = (F(5, 48), F(17, 48), F(5, 12))
# name: (2 or 3, bodies, contacts) as in scene_columns.hand_system(3): contacts (body a or None,
# body b, point, unit normal from a to b, mu).
CASES = {
    "box-flat-on-rough-ground": (2, [(1, F(5, 12), (0, H))],
                                 [(None, 0, (-1, 0), (0, 1), H), (None, 0, (1, 0), (0, 1), H)]),
    "ball-in-a-rough-corner": (2, [(1, F(2, 5), (1, 1))],
                               [(None, 0, (1, 0), (0, 1), F(1, 4)), (None, 0, (0, 1), (1, 0), F(1, 4))]),
    "rough-ladder": (2, [(1, F(25, 12), (F(3, 2), 2))],
                     [(None, 0, (3, 0), (0, 1), H), (None, 0, (0, 4), (1, 0), F(1, 3))]),
    # a 1 x 1/2 box on a 2 x 1 box; the upper pair rough (1/2): its two tangents are one column
    "rough-box-on-a-box": (2, [(2, F(5, 6), (0, H)), (1, F(5, 48), (H, F(5, 4)))],
                           [(None, 0, (-1, 0), (0, 1), 0), (None, 0, (1, 0), (0, 1), 0),
                            (0, 1, (1, 1), (0, 1), H), (0, 1, (0, 1), (0, 1), H)]),
    # four corners on a plane: rank 3
    "3d-box-flat-on-a-plane": (3, [(1, BOX_I, (0, 0, F(1, 4)), None)],
                               [(None, 0, (x, y, 0), (0, 0, 1), 0) for x in (-1, 1) for y in (-H, H)]),
    "3d-rough-box-on-an-edge": (3, [(1, BOX_I, (0, 0, F(4, 5)), RY)],
                                [(None, 0, (F(-13, 20), -H, 0), (0, 0, 1), F(1, 4)),
                                 (None, 0, (F(-13, 20), H, 0), (0, 0, 1), F(1, 4))]),
}
CORNER = CASES["ball-in-a-rough-corner"]  # the witnesses' scene
if SANITIZER:
    CASES = {k: v for k, v in CASES.items() if k in ("box-flat-on-rough-ground", "3d-box-flat-on-a-plane")}
# Restitution on approaching contacts: 1024 modes for the box on a box (beyond --max-modes 400).
# Under the sanitizers the box flat on a plane with restitution on all contacts only, not certified.
ONS = {name: ("all",) if name == "rough-box-on-a-box" or (LIGHT and name == "3d-rough-box-on-an-edge")
       or (SANITIZER and name == "3d-box-flat-on-a-plane") else ("all", "approaching") for name in CASES}
CERTIFY = {name for name in CASES if not (LIGHT and name == "3d-rough-box-on-an-edge")
           and not (SANITIZER and name == "3d-box-flat-on-a-plane")}
INLINE = {
    "rough-box-on-a-box": {
        "format": "impactcert-scene/1", "name": "rough-box-on-a-box",
        "bodies": [{"name": "base", "mass": "2", "inertia": "5/6", "position": ["0", "1/2"],
                    "shapes": [{"polygon": [["-1", "-1/2"], ["1", "-1/2"], ["1", "1/2"], ["-1", "1/2"]]}]},
                   {"name": "top", "mass": "1", "inertia": "5/48", "position": ["1/2", "5/4"],
                    "shapes": [{"polygon": [["-1/2", "-1/4"], ["1/2", "-1/4"], ["1/2", "1/4"], ["-1/2", "1/4"]]}]}],
        "boundaries": [{"name": "ground", "point": ["0", "0"], "normal": ["0", "1"]}],
        "pairs": [{"bodies": ["base", "top"], "mu": "1/2"}], "restitution": "1/2"},
}


def basis_of(columns):
    """The columns kept in order, each independent of those kept before it (by rank)."""
    kept = []
    for k, c in enumerate(columns):
        trial = [columns[j] for j in kept] + [c]
        # independent exactly when the only solution of sum x_j col_j = 0 is x = 0
        A = [[col[i] for col in trial] for i in range(len(c))]
        if not affine_solve(A, [F(0)] * len(c))[1]:
            kept.append(k)
    return kept


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


tmp = tempfile.mkdtemp(prefix="impactcert-redundant-")
try:
    compared = 0
    for name, (dim, bodies, contacts) in CASES.items():
        M, normals, friction = (hand_system if dim == 2 else hand_system3)(bodies, contacts)
        scene = os.path.join(SCENES, name + ".json")
        if name in INLINE:
            scene = os.path.join(tmp, name + ".scene.json")
            with open(scene, "w") as f:
                json.dump(INLINE[name], f)
        S = System(M, normals, friction)
        B = basis_of(S.columns)
        if len(B) == S.d:
            fail(f"{name}: the hand-written columns are independent: not a redundant scene")
            continue
        WB = [S.columns[k] for k in B]
        e = [H] * len(normals)
        samples = SAMPLES if dim == 2 else max(1, SAMPLES // 6)
        for on in ONS[name]:
            lawfile = os.path.join(tmp, f"{name}-{on}.json")
            if run([CLI, "derive", "newton", "--system", scene, "--restitution", "1/2", "--restitution-on", on,
                    "-o", lawfile]).returncode != 0:
                continue
            law = json.load(open(lawfile))
            cols, tangents, law_M = law_columns(law)
            if cols + tangents != S.columns or law_M != S.M:
                fail(f"{name}: the law's M and columns are not the hand-computed ones")
                break
            pieces = pieces_of(law)
            impulses = [[[F(x) for x in row] for row in p["impulses"]] for p in law["pieces"]]
            if any(len(L) != S.d or len(L[0]) != len(B) for L in impulses):
                fail(f"{name}/{on}: impulses are not {S.d} x {len(B)}")
                break
            for _ in range(samples):
                u = [F(rng.randint(-60, 60), rng.randint(1, 12)) for _ in range(S.n)]
                sols = S.solutions(u, e, approaching=(on == "approaching"), dependent=True)
                if len(sols) != 1 or S.spread:
                    fail(f"{name}/{on}: u- = {u}: the oracle finds {len(sols)} solutions (spread {S.spread})")
                    continue
                y = [dot(w, u) for w in WB]
                expected = [dot(w, sols[0]) for w in WB]
                got = locate(pieces, y)
                if got != [expected]:
                    fail(f"{name}/{on}: u- = {u}: law {got}, oracle {expected}")
                    break
                # The declared impulse of a piece containing y, in body velocities.
                k = next(i for i, (Rinv, _) in enumerate(pieces)
                         if all(dot(r, y) >= 0 for r in Rinv))
                lam = [dot(row, y) for row in impulses[k]]
                du = [a - b for a, b in zip(sols[0], u)]
                Mdu = [dot(S.M[i], du) for i in range(S.n)]
                Wl = [sum(S.columns[c][i] * lam[c] for c in range(S.d)) for i in range(S.n)]
                N = len(normals)
                gm, gp = S.velocities(u), S.velocities(sols[0])
                ok = Mdu == Wl and all(lam[c] >= 0 for c in range(N))
                for j, (c, mu, eT, _) in enumerate(S.tangents):
                    lt, bound, xi = lam[N + j], mu * lam[c], gp[N + j] + eT * gm[N + j]
                    ok = ok and abs(lt) <= bound and not (xi > 0 and lt != -bound) and not (xi < 0 and lt != bound)
                if not ok:
                    fail(f"{name}/{on}: u- = {u}: the impulse {lam} of piece {law['pieces'][k]['name']} "
                         "does not give u+ in the friction cone with Coulomb's signs")
                    break
                compared += 1
            # Negative controls: a changed Q entry no longer agrees; a changed impulse is refuted.
            j = next(j for j in range(len(y)) if y[j] != 0)
            bad = json.loads(json.dumps(law))
            bad["pieces"][k]["Q"][0][j] = str(F(bad["pieces"][k]["Q"][0][j]) + 1)
            if locate(pieces_of(bad), y) == [expected]:
                fail(f"{name}/{on}: a changed Q still agrees with the oracle")
            p = run([CLI, "verify", "--law", lawfile], None)
            verdict = {ln.split()[0]: ln.split()[2] for ln in p.stdout.splitlines()[2:] if len(ln.split()) > 2}
            if any(verdict.get(ob) != "proved" for ob in ("fan", "P1", "kinetic", "energetic")) or \
                    (on == "approaching" and verdict.get("kinematic") != "proved") or \
                    (friction and verdict.get("coulomb") != "proved"):
                fail(f"{name}/{on}: verify: {verdict}")
            # (--light: not on the rough box on an edge, whose verify takes the longest; the other
            # scenes' laws have the same check)
            if not (LIGHT and name == "3d-rough-box-on-an-edge"):
                bad = json.loads(json.dumps(law))
                bad["pieces"][k]["impulses"][0][0] = str(F(bad["pieces"][k]["impulses"][0][0]) + 1)
                badfile = os.path.join(tmp, "bad-impulse.json")
                with open(badfile, "w") as f:
                    json.dump(bad, f)
                p = run([CLI, "verify", "--law", badfile], 1)
                if "kinetic" not in p.stdout or " refuted " not in [ln for ln in p.stdout.splitlines() if "kinetic" in ln][0]:
                    fail(f"{name}/{on}: a changed impulse is not refuted by kinetic: {p.stdout[:300]}")
            if name in CERTIFY:
                cert = os.path.join(tmp, f"{name}-{on}.cert.json")
                run([CLI, "certify", "--law", lawfile, "-o", cert], None)
                run([CHECK, cert])
        if compared == 0:
            break
    want = sum(len(ONS[n]) * (SAMPLES if d == 2 else max(1, SAMPLES // 6)) for n, (d, _, _) in CASES.items())
    if compared < want:
        fail(f"only {compared} of {want} inputs compared")
    print(f"compared {compared} random rational inputs over {len(CASES)} redundant scenes with the oracle")

    if SANITIZER:  # the consistency fuzzer's linear programs on dependent columns, under the sanitizers
        scene = os.path.join(SCENES, "box-flat-on-rough-ground.json")
        law = os.path.join(tmp, "box-flat-on-rough-ground-approaching.json")
        p = run([CLI, "fuzz", "--system", scene, "--velocities", "--float-law", law, "--samples", "200",
                 "--reference", "approaching", "--restitution", "1/2"])
        if "verdict: no violation" not in p.stdout:
            fail(f"the box's float law in ball velocities: {p.stdout[-300:]}")
    # Witnesses, recomputed by the oracle in body velocities.
    corner = json.load(open(os.path.join(SCENES, "ball-in-a-rough-corner.json")))
    for mu, verdict in (("1", "no-solution"), ("2", "two-solutions")):
        corner["friction"] = mu
        scene = os.path.join(tmp, f"corner-{mu}.json")
        with open(scene, "w") as f:
            json.dump(corner, f)
        p = run([CLI, "derive", "newton", "--system", scene, "--json", "-o", os.path.join(tmp, "x.json")], 1)
        if os.path.exists(os.path.join(tmp, "x.json")):
            fail(f"corner mu = {mu}: a law was written")
        try:
            w = json.loads(p.stdout)
        except ValueError:
            fail(f"corner mu = {mu}: no JSON witness: {p.stdout[:200]} {p.stderr[:200]}")
            continue
        if w["verdict"] != verdict:
            fail(f"corner mu = {mu}: {w['verdict']}, expected {verdict}")
            continue
        _, bodies, contacts = CORNER
        S = System(*hand_system(bodies, [(a, b, pt, nrm, F(mu)) for (a, b, pt, nrm, _) in contacts]))
        u = [F(x) for x in w["u_minus"]]
        if S.velocities(u) != [F(x) for x in w["gamma_minus"]]:
            fail(f"corner mu = {mu}: W^T u- is not gamma-")
        sols = S.solutions(u, [H, H], dependent=True)
        if verdict == "no-solution" and sols:
            fail(f"corner mu = {mu}: the oracle finds {sols} at u- = {u}")
        if verdict == "two-solutions":
            ups = [[F(x) for x in v] for v in w["u_plus"]]
            if ups[0] == ups[1] or any(v not in sols for v in ups):
                fail(f"corner mu = {mu}: u+ {ups} are not two of the oracle's solutions {sols}")
        print(f"ball in a corner, mu = {mu}: {verdict} at u- = {[str(x) for x in u]}, recomputed")
    jam = os.path.join(tmp, "jam.json")
    with open(jam, "w") as f:
        json.dump({"format": "impactcert-system/1", "name": "jammed", "masses": ["1"],
                   "contacts": {"W": [["1", "-1"]]}}, f)
    p = run([CLI, "derive", "newton", "--system", jam, "--restitution", "1/2,1/4", "--json", "-o", "-"], 1)
    w = json.loads(p.stdout or "{}")
    S = System([[1]], [[1], [-1]], [])
    if w.get("verdict") != "no-solution" or S.solutions([F(x) for x in w["u_minus"]], [H, F(1, 4)], dependent=True):
        fail(f"jammed particle: {w}")
    run([CLI, "derive", "newton", "--system", jam, "--restitution", "1/2", "-o", os.path.join(tmp, "jam-law.json")])

    # Bad inputs: one line, exit 2, naming the place.
    law = json.load(open(os.path.join(tmp, "box-flat-on-rough-ground-all.json")))

    def bad_law(mutate, where):
        doc = json.loads(json.dumps(law))
        mutate(doc)
        path = os.path.join(tmp, "bad.json")
        with open(path, "w") as f:
            json.dump(doc, f)
        p = run([CLI, "verify", "--law", path], 2)
        if where not in p.stderr or len(p.stderr.strip().splitlines()) != 1:
            fail(f"{where}: {p.stderr.strip()[:300]}")
    bad_law(lambda d: d["pieces"][0].pop("impulses"), "$.pieces[0]")
    bad_law(lambda d: d.update(claims=["fan", "P3"]), "$.claims[1]")
    bad_law(lambda d: d["pieces"][1]["impulses"].pop(), "$.pieces[1].impulses")
    bad_law(lambda d: d.update(symmetries=[{"name": "s", "P": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]],
                                            "P_prime": [["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]]}]),
            "$.symmetries")
    full = os.path.join(tmp, "three-balls.json")
    run([CLI, "derive", "newton", "--masses", "1,1,1", "-o", full])
    law = json.load(open(full))
    bad_law(lambda d: d["pieces"][0].update(impulses=[["0", "0"], ["0", "0"]]), "$.pieces[0].impulses")
    lawfile = os.path.join(tmp, "box-flat-on-rough-ground-all.json")
    for args in ([CLI, "fuzz", "--law", lawfile, "--samples", "10"], [CLI, "verify", "--law", lawfile, "--shard", "1/2"],
                 [CLI, "smt", "--law", lawfile, "-o", os.path.join(tmp, "smt")]):
        p = run(args, 2)
        if "dependent contact columns (rank 3 of 4)" not in p.stderr or len(p.stderr.strip().splitlines()) != 1:
            fail(f"{' '.join(args[1:3])}: {p.stderr.strip()[:300]}")
    zero = os.path.join(tmp, "zero.json")
    with open(zero, "w") as f:
        json.dump({"format": "impactcert-system/1", "name": "zero", "masses": ["1"], "contacts": {"W": [["0"]]}}, f)
    p = run([CLI, "derive", "newton", "--system", zero], 2)
    if "rank 0" not in p.stderr or len(p.stderr.strip().splitlines()) != 1:
        fail(f"a zero W: {p.stderr.strip()[:300]}")

    # The checker is as strict as the prover: a kinematic refutation passed off as undecided (the fan's
    # limit) is rejected. W: N1 = e1, N2 = -e1 (dependent), N3 = e2 with a tangent e3; identity-like
    # pieces on the orthants and one repeated, so that the fan needs chambers.
    pieces = []
    for s in [(a, b, c) for a in (1, -1) for b in (1, -1) for c in (1, -1)]:
        pieces.append({"name": "p" + "".join("+" if x > 0 else "-" for x in s),
                       "Q": [[str(s[i]) if i == j else "0" for j in range(3)] for i in range(3)],
                       "rays": [[str(s[i]) if i == j else "0" for j in range(3)] for i in range(3)],
                       "impulses": [["0"] * 3 for _ in range(4)]})
    pieces.append(dict(pieces[0], name="again"))
    forge = os.path.join(tmp, "forge.json")
    with open(forge, "w") as f:
        json.dump({"format": "impactcert-law/1", "name": "forge", "masses": ["1", "1", "1"],
                   "contacts": {"W": [["1", "-1", "0"], ["0", "0", "1"], ["0", "0", "0"]],
                                "friction": [{"contact": 3, "mu": "1/2", "tangents": [["0", "0", "1"]]}]},
                   "pieces": pieces}, f)
    cert = os.path.join(tmp, "forge.cert.json")
    run([CLI, "certify", "--law", forge, "--max-chambers", "1", "-o", cert], 1)
    doc = json.load(open(cert))
    ob = next(o for o in doc["obligations"] if o["id"] == "kinematic")
    if ob["verdict"] != "refuted":
        fail(f"forged law: kinematic is {ob['verdict']}, expected refuted")
    ob.update(verdict="undecided", checks=0, method="exact decision beyond a limit",
              limit="the facet arrangement needs more than 1 chamber-enumeration steps (raise it with --max-chambers)")
    ob.pop("counterexample", None)
    ob["data"] = {}
    doc["verdict"] = "undecided"
    with open(cert, "w") as f:
        json.dump(doc, f)
    p = run([CHECK, cert], None)
    if p.returncode == 0 or "refutes kinematic" not in p.stdout + p.stderr:
        fail(f"a kinematic refutation passed off as undecided: checker exit {p.returncode}: {(p.stdout + p.stderr)[-300:]}")

    scene = os.path.join(SCENES, "box-flat-on-rough-ground.json")
    for args, where in (([CLI, "derive", "sequential", "--system", scene], "$.contacts"),
                        ([CLI, "derive", "poisson", "--system", scene], "$.contacts"),
                        ([CLI, "fuzz", "--system", scene, "--impl-cmd", "true", "--samples", "1"], "--velocities")):
        p = run(args, 2)
        if where not in p.stderr or "rank 3" not in p.stderr or len(p.stderr.strip().splitlines()) != 1:
            fail(f"{' '.join(args[1:3])}: {p.stderr.strip()[:300]}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish(failures)
