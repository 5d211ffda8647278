#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Friction polygons (issue 43: MuJoCo's pyramidal cone and any rational polygon; proofs/README.md,
"Polygonal friction cones").

- Laws: `derive newton` on scenes in space with "friction_cone": "pyramid", a hexagon and a
  triangle (anisotropic), one and two rough contacts, and on dependent columns (a rough box on an
  edge with the pyramid); each verified (kinetic and coulomb proved, coulomb by its polygon
  forms), certified and checked by impactcert-check; and (independent columns) compared with an
  independent oracle in body velocities (tests/oracles/polygon_lcp.py: every combination of stick,
  vertex and edge states solved by elimination, Coulomb's law checked on the solution) at random
  rational inputs: exactly one u+, the law's.
- Mutants: the law's mu raised in its head (its friction then dissipates too little): coulomb
  refuted by a polygon form, the refutation certified and checked; the witness moved, the verdict
  forged as proved and a polygon form's matrix changed are each rejected by the checker.
- Fuzzing: the law in doubles raises no alarm; the law of mu halved (coulomb) and the box law
  (friction_cone) are found, replayed and recomputed here in fractions.
- Bad polygons and bad uses: one line, exit 2.
Usage: polygon_friction_test.py BINDIR SOURCE_DIR SAMPLES [--light]
"""
import json
import os
import random
import subprocess
import sys
import tempfile
from fractions import Fraction as F

BIN, SRC, SAMPLES = sys.argv[1], sys.argv[2], int(sys.argv[3])
LIGHT = "--light" in sys.argv[4:]
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
import testkit  # noqa: E402
from friction_lcp import solve, System  # noqa: E402
from polygon_lcp import PolygonSystem, vertices  # noqa: E402
from scene_columns import law_columns, pieces_of, locate  # noqa: E402

CLI, CHECK = os.path.join(BIN, "impactcert"), os.path.join(BIN, "impactcert-check")
SCENES = os.path.join(SRC, "examples", "scenes")
failures = []
fail = failures.append
tmp = tempfile.mkdtemp(prefix="impactcert-polygon-")
HEXAGON = [["2", "0"], ["1", "2"], ["-1", "2"], ["-2", "0"], ["-1", "-2"], ["1", "-2"]]
TRIANGLE = [["1", "0"], ["-1", "1"], ["-1", "-1"]]


def run(args, want=None):
    p = subprocess.run(args, capture_output=True, text=True)
    if want is not None and p.returncode != want:
        fail(f"{' '.join(args[:4])}...: exit {p.returncode}, expected {want}\n{p.stdout[-600:]}{p.stderr[-600:]}")
    return p


def scene(base, name, cone, friction=None):
    doc = json.load(open(os.path.join(SCENES, base + ".json")))
    doc["name"], doc["friction_cone"] = name, cone
    if friction:
        doc["friction"] = friction
    path = os.path.join(tmp, name + ".json")
    json.dump(doc, open(path, "w"))
    return path


CASES = [("3d-spinning-ball", "ball-pyramid", "pyramid", None),
         ("3d-spinning-ball", "ball-triangle", {"facets": TRIANGLE}, None),
         ("3d-box-on-a-corner", "corner-hexagon", {"facets": HEXAGON}, None)]
if not LIGHT:
    CASES.append(("3d-ball-on-a-ball", "two-balls-pyramid", "pyramid", None))


def oracle_of(law):
    cols, _, M = law_columns(law)
    contacts = [None] * len(cols)
    for f in law["contacts"].get("friction", []):
        facets = [tuple(F(x) for x in a) for a in f.get("facets", [])]
        if not facets:
            fail("a polygon law without facets in its head")
        contacts[f["contact"] - 1] = (F(f["mu"]), tuple([F(x) for x in t] for t in f["tangents"]), facets)
    return PolygonSystem(M, cols, contacts)


def law_u_plus(S, pieces, gm):
    """u- with W^T u- = gamma- (least squares in the identity metric), and u+ from each value of the
    law: u+ = u- + M^-1 W H (gamma+ - gamma-), with H by solving G in fractions."""
    d, n = S.d, S.n
    WtW = [[sum(S.cols[a][i] * S.cols[b][i] for i in range(n)) for b in range(d)] for a in range(d)]
    y = solve(WtW, gm)
    u = [sum(S.cols[a][i] * y[a] for a in range(d)) for i in range(n)]
    Minv_cols = [solve(S.M, c) for c in S.cols]
    G = [[sum(a[i] * mc[i] for i in range(n)) for mc in Minv_cols] for a in S.cols]
    outs = []
    for gp in locate(pieces, gm):
        lam = solve(G, [p - m for p, m in zip(gp, gm)])
        outs.append([u[i] + sum(Minv_cols[q][i] * lam[q] for q in range(d)) for i in range(n)])
    return u, outs


rng = random.Random(43)
laws = {}
for base, name, cone, friction in CASES:
    sc = scene(base, name, cone, friction)
    law = os.path.join(tmp, name + "-law.json")
    run([CLI, "derive", "newton", "--system", sc, "-o", law], 0)
    if not os.path.exists(law):
        continue
    laws[name] = (sc, law)
    cert = os.path.join(tmp, name + "-cert.json")
    run([CLI, "certify", "--law", law, "-o", cert])  # the verdicts of verify, with their evidence
    try:
        verdicts = {o["id"]: o["verdict"] for o in json.load(open(cert))["obligations"]}
    except (OSError, ValueError, KeyError):
        fail(f"{name}: no certificate")
        continue
    # (kinematic fails for two balls, as for their box law: restitution on every contact lets a
    # separating contact's gamma_N+ go down to -e gamma_N-.)
    for ob in ("fan", "kinetic", "coulomb") + (("kinematic",) if name != "two-balls-pyramid" else ()):
        if verdicts.get(ob) != "proved":
            fail(f"{name}: {ob} {verdicts.get(ob)}")
    c = run([CHECK, cert], None)
    if "verified" not in c.stdout:
        fail(f"{name}: impactcert-check: {c.stdout}{c.stderr}")
    doc = json.load(open(law))
    forms = [o for o in json.load(open(cert))["obligations"] if o["id"] == "coulomb"][0]["data"]["polygon_forms"]
    K = sum(len(f["facets"]) for f in doc["contacts"]["friction"])
    if len(forms) != K * len(doc["pieces"]):
        fail(f"{name}: {len(forms)} polygon forms, expected {K} vertices x {len(doc['pieces'])} pieces")
    S, pieces = oracle_of(doc), pieces_of(doc)
    e = F(json.load(open(sc))["restitution"])
    compared = 0
    for _ in range(SAMPLES):
        gm = [F(rng.randint(-40, 40), rng.randint(1, 9)) for _ in range(S.d)]
        if all(gm[k] >= 0 for k in range(len(S.normals))):
            gm[0] = -abs(gm[0]) - 1
        u, outs = law_u_plus(S, pieces, gm)
        sols = S.solutions(u, e)
        if len(sols) != 1 or any(o != sols[0] for o in outs) or not outs:
            fail(f"{name}: gamma- = {gm}: the oracle finds {len(sols)} u+, the law {len(outs)} values; differ")
            break
        compared += 1
    print(f"{name}: {len(doc['pieces'])} pieces, coulomb by {len(forms)} polygon forms, {compared} inputs agree with the oracle")

# Dependent columns (a rough box on an edge: six columns of rank 5) with the pyramid: the pieces
# declare their impulses, and kinetic and coulomb are proved on them and checked.
if not LIGHT:
    sc = scene("3d-rough-box-on-an-edge", "edge-pyramid", "pyramid")
    law = os.path.join(tmp, "edge-pyramid-law.json")
    run([CLI, "derive", "newton", "--system", sc, "-o", law], 0)
    cert = os.path.join(tmp, "edge-pyramid-cert.json")
    run([CLI, "certify", "--law", law, "-o", cert])
    verdicts = {o["id"]: o["verdict"] for o in json.load(open(cert))["obligations"]}
    if verdicts.get("kinetic") != "proved" or verdicts.get("coulomb") != "proved" or \
            "verified" not in run([CHECK, cert]).stdout:
        fail(f"rough box on an edge with the pyramid: {verdicts}")
    else:
        print(f"rough box on an edge, pyramid: {len(json.load(open(law))['pieces'])} pieces on 5 of 6 columns, "
              "kinetic and coulomb proved and checked")

# Mutants: mu raised in the head of the pyramid ball's law.
if "ball-pyramid" in laws:
    doc = json.load(open(laws["ball-pyramid"][1]))
    quarter = scene("3d-spinning-ball", "ball-pyramid-quarter", "pyramid", "1/4")
    qlaw = os.path.join(tmp, "quarter-law.json")
    run([CLI, "derive", "newton", "--system", quarter, "-o", qlaw], 0)
    bad = json.load(open(qlaw))
    bad["contacts"]["friction"][0]["mu"] = "1/2"
    bad["name"] = "mu-raised"
    badf = os.path.join(tmp, "mu-raised.json")
    json.dump(bad, open(badf, "w"))
    v = run([CLI, "verify", "--law", badf, "--json"], 1)
    ob = [o for o in json.loads(v.stdout)["obligations"] if o["id"] == "coulomb"][0]
    w = ob.get("counterexample", {})
    if ob["verdict"] != "refuted" or "vertex" not in w:
        fail(f"mu raised: coulomb {ob['verdict']}, {w}")
    else:
        # Recomputed: at gamma, (Lambda_T - mu Lambda_N v) . xi_T > 0 with the raised mu, and
        # gamma+ = Q gamma of the piece named.
        gamma = [F(x) for x in w["gamma"]]
        lam, xi = [F(x) for x in w["impulse"]], [F(x) for x in w["xi_T"]]
        v_ = vertices([tuple(F(x) for x in a) for a in bad["contacts"]["friction"][0]["facets"]])[w["vertex"] - 1]
        q = (lam[1] - F(1, 2) * lam[0] * v_[0]) * xi[0] + (lam[2] - F(1, 2) * lam[0] * v_[1]) * xi[1]
        S, pieces = oracle_of(bad), pieces_of(bad)
        if q <= 0 or [F(x) for x in w["gamma_plus"]] not in locate(pieces, gamma):
            fail(f"mu raised: the witness does not show the failure: q = {q}, {w}")
    cert = os.path.join(tmp, "mu-raised-cert.json")
    run([CLI, "certify", "--law", badf, "-o", cert])
    if "verified (mu-raised: refuted)" not in run([CHECK, cert]).stdout:
        fail("mu raised: the refutation's certificate is not verified")
    original = json.load(open(cert))

    def tampered(change, label):
        c = json.loads(json.dumps(original))
        change([o for o in c["obligations"] if o["id"] == "coulomb"][0])
        path = os.path.join(tmp, "tampered.json")
        json.dump(c, open(path, "w"))
        p = run([CHECK, path])
        if p.returncode == 0 or "rejected" not in p.stdout + p.stderr:
            fail(f"tampered certificate ({label}) accepted: exit {p.returncode} {p.stdout}{p.stderr}")

    def moved(o):
        o["counterexample"]["gamma"][0] = str(F(o["counterexample"]["gamma"][0]) - 1)

    def forged(o):
        o["verdict"] = "proved"
        del o["counterexample"]

    def matrix(o):
        o["data"]["polygon_forms"][0]["A"][0][0] = str(F(o["data"]["polygon_forms"][0]["A"][0][0]) + 1)

    tampered(moved, "witness moved")
    tampered(forged, "refuted passed off as proved")
    tampered(matrix, "a polygon form's matrix changed")

    # The law of mu = 1/2 declared with mu = 1/4: impulses outside the polygon, so coulomb is refuted
    # before any polygon form; passed off as undecided at --max-faces, it is rejected.
    low = json.load(open(laws["ball-pyramid"][1]))
    low["contacts"]["friction"][0]["mu"] = "1/4"
    low["name"] = "mu-lowered"
    lowf = os.path.join(tmp, "mu-lowered.json")
    json.dump(low, open(lowf, "w"))
    cert = os.path.join(tmp, "mu-lowered-cert.json")
    run([CLI, "certify", "--law", lowf, "-o", cert], 1)
    original = json.load(open(cert))

    def hidden(o):
        if o["verdict"] != "refuted" or o["data"]:
            fail(f"mu lowered: coulomb {o['verdict']} with data {list(o['data'])}, expected refuted before the forms")
        o["verdict"] = "undecided"
        del o["counterexample"]
        o["limit"] = "a KKT enumeration needs more than 10 faces (raise it with --max-faces)"

    tampered(hidden, "a refutation by the friction cone passed off as undecided at --max-faces")

# Fuzzing against the polygon: the law in doubles, the law of mu halved, the box law.
if "ball-pyramid" in laws:
    sc, law = laws["ball-pyramid"]
    box = os.path.join(tmp, "box-law.json")
    run([CLI, "derive", "newton", "--system", os.path.join(SCENES, "3d-spinning-ball.json"), "-o", box], 0)
    n_samples = "300" if LIGHT else "3000"
    for label, fl, found in (("the law", law, set()), ("mu halved", qlaw, {"coulomb"}), ("the box", box, {"friction_cone"})):
        p = run([CLI, "fuzz", "--system", sc, "--float-law", fl, "--samples", n_samples, "--max-rel-error", "1e-12",
                 "--restitution", "1/2", "--json"])
        try:
            j = json.loads(p.stdout)
        except ValueError:
            fail(f"fuzz {label}: {p.stdout[:300]}{p.stderr[:300]}")
            continue
        seen = {k for k, v in j["violations"].items() if v}
        if seen != found:
            fail(f"fuzz {label}: {j['violations']}")
            continue
        for prop in found:
            f = j["worst"][prop]
            if testkit.run_replay(f["replay"], CLI).returncode != 1:
                fail(f"fuzz {label}: the replay of {prop} does not exit 1")
            # Second route: Lambda = G^-1 (gamma+ - gamma-) in fractions, the polygon's figure.
            x = [F(float.fromhex(t)) for t in f["input"]]
            y = [F(float.fromhex(t)) for t in f["output"]]
            doc = json.load(open(law))
            cols, tans, M = law_columns(doc)
            Sx = System(M, cols, [(0, F(1, 2), F(0), doc["contacts"]["friction"][0]["tangents"])])
            Minv = [solve(M, c) for c in Sx.columns]
            G = [[sum(a[i] * mc[i] for i in range(Sx.n)) for mc in Minv] for a in Sx.columns]
            lam = solve(G, [b - a for a, b in zip(x, y)])
            facets = [tuple(F(t) for t in a) for a in doc["contacts"]["friction"][0]["facets"]]
            if prop == "friction_cone":
                value = max(a[0] * lam[1] + a[1] * lam[2] for a in facets) - F(1, 2) * lam[0]
                if F(f["exact"]["a . Lambda_T"]) - F(f["exact"]["mu Lambda_N"]) > value or value <= 0:
                    fail(f"fuzz {label}: friction_cone not recomputed: {value}, {f['exact']}")
            else:
                xi = y[1:3]
                qs = [(lam[1] - F(1, 2) * lam[0] * v[0]) * xi[0] + (lam[2] - F(1, 2) * lam[0] * v[1]) * xi[1]
                      for v in vertices(facets)]
                if F(f["exact"]["(Lambda_T - mu Lambda_N v) . xi_T"]) not in qs or \
                        F(f["exact"]["(Lambda_T - mu Lambda_N v) . xi_T"]) <= F(f["exact"]["bound"]):
                    fail(f"fuzz {label}: coulomb not recomputed: {qs}, {f['exact']}")
        print(f"fuzz {label}: {j['samples']} samples, " + (", ".join(f"{k} {j['violations'][k]}" for k in found) or "no violation"))

# Bad polygons and bad uses: one line, exit 2.
for cone, words in [({"facets": [["1", "0"], ["0", "1"]]}, "at least three facets"),
                    ({"facets": []}, "at least three facets"),
                    ({"facets": [["1", "0"], ["0", "0"], ["-1", "1"]]}, "must not be zero"),
                    ({"facets": [["1", "0"], ["-1", "-1"], ["-1", "1"]]}, "counterclockwise"),
                    ({"facets": [["1", "0"], ["-1", "1"], ["-1", "-1"], ["1", "0"], ["-1", "1"], ["-1", "-1"]]},
                     "once around"),
                    ({"facets": [["1", "0"], ["1", "1"], ["-1", "1"], ["-1", "-1"], ["1", "-1"]]}, "not an edge"),
                    ({"facets": [["1", "0"], ["-1", "x"], ["-1", "-1"]]}, "facets[1]"),
                    ("cone", "expected \"box\", \"pyramid\"")]:
    sc = scene("3d-spinning-ball", "bad", cone)
    p = run([CLI, "derive", "newton", "--system", sc], 2)
    if words not in p.stderr or "$.friction_cone" not in p.stderr or p.stderr.count("\n") != 1:
        fail(f"friction_cone {cone}: {p.stderr!r}")
# Many facets: beyond the format's 1,024 refused; 300 (a polygon around the unit circle, tangent
# at rational points) give 602 states, beyond --max-modes 400, refused at once (exit 3) before
# any mode is built.
def circle_facets(k):
    ts = [F(i - k // 2, 20) for i in range(k)]
    return [[str((1 - t * t) / (1 + t * t)), str(2 * t / (1 + t * t))] for t in ts]


p = run([CLI, "derive", "newton", "--system", scene("3d-spinning-ball", "many", {"facets": circle_facets(1025)})], 2)
if "at most 1024 facets" not in p.stderr:
    fail(f"1025 facets: {p.stderr!r}")
p = subprocess.run([CLI, "derive", "newton", "--system", scene("3d-spinning-ball", "many", {"facets": circle_facets(300)})],
                   capture_output=True, text=True, timeout=60)
if p.returncode != 3 or "has 602 contact modes, more than 400" not in p.stderr or "--max-modes" not in p.stderr:
    fail(f"300 facets: exit {p.returncode}, {p.stderr!r}")

if "ball-pyramid" in laws:
    sc, law = laws["ball-pyramid"]
    for args, words in [(["derive", "sequential", "--system", sc], "friction polygons are not offered"),
                        (["fuzz", "--system", sc, "--cone", "circular", "--impl-cmd", "cat"], "declares friction polygons")]:
        p = run([CLI] + args, 2)
        if words not in p.stderr:
            fail(f"{args[:2]}: {p.stderr!r}")
    planar = json.load(open(law))
    planar["contacts"]["friction"][0]["tangents"] = planar["contacts"]["friction"][0]["tangents"][:1]
    path = os.path.join(tmp, "one-tangent.json")
    json.dump(planar, open(path, "w"))
    p = run([CLI, "verify", "--law", path], 2)
    if "facets" not in p.stderr or "two tangents" not in p.stderr:
        fail(f"facets with one tangent: {p.stderr!r}")

if failures:
    print("FAILED:\n" + "\n".join(failures))
    sys.exit(1)
print("friction polygons: laws agree with the oracle, mutants refuted and checked, fuzzing finds the planted errors")
