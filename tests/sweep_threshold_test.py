#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""sweep --system/--scene and --thresholds, checked by a second route.

- Kane's double pendulum (proofs/kane), the Newton law with friction over mu: the energetic
  threshold's polynomial must be the slip boundary's F_f(mu) of proofs/README.md, computed here
  from M and W in fractions (G = W^T M^-1 W); mu* = (39777 - sqrt 349926813)/133704 must lie in
  the enclosure (squares compared exactly); the laws derived by `derive newton` at both ends must
  verify energetic proved and refuted, and the gain at the upper end is recomputed in body
  velocities by the oracle (tests/oracles/friction_lcp.py, no G). The law stops being a function
  at G_NN / G_NT, which the derive column's enclosure must hold.
- The block on a corner (examples/scenes/block-on-a-corner.json) at e = 9/10 over mu: the
  polynomial 323 mu^2 - 120 mu + 8 with mu* = (60 - 2 sqrt 254)/323 in the enclosure, the laws
  at both ends verified and the gain at the upper end recomputed by the oracle.
- Three equal balls, the Newton law with restitution on approaching contacts, over e: the
  threshold must be sqrt(3)/2 (polynomial 4 e^2 - 3), with the laws at both ends verified and the
  gain at the upper end recomputed by the oracle in ball velocities.
- Controls: a range with no change gives no threshold; bad inputs are one line and exit 2; a
  sharded system sweep merged equals the single run.
Usage: sweep_threshold_test.py BINDIR SOURCE_DIR [--light]
(--light, the sanitizer build's run: Kane over mu, the controls and the bad input only.)
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
from fractions import Fraction as F

BIN, SRC = sys.argv[1], sys.argv[2]
LIGHT = "--light" in sys.argv[3:]
CLI = os.path.join(BIN, "impactcert")
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
from friction_lcp import System, solve  # noqa: E402
from testkit import finish  # noqa: E402

failures = []
tmp = tempfile.mkdtemp(prefix="impactcert-threshold-")
KANE = os.path.join(SRC, "proofs", "kane", "gains", "system.json")


def fail(msg):
    failures.append(msg)


def run(args, expect=0, what=""):
    p = subprocess.run([CLI] + args, capture_output=True, text=True)
    if p.returncode != expect:
        fail(f"{what or ' '.join(args)}: exit {p.returncode}, expected {expect}: {p.stderr.strip()[:300]}")
    return p


def load(path):
    with open(path) as f:
        return json.load(f)


def poly_value(text, var, x):
    """An integer polynomial as sweep writes it ("267408 mu^2 - 159108 mu + 18433") at x."""
    total = F(0)
    for term in text.replace(" - ", " + -").split(" + "):
        sign = -1 if term.startswith("-") else 1
        term = term.lstrip("-")
        if var in term:
            coef, _, power = term.partition(var)
            value = (F(coef.strip()) if coef.strip() else F(1)) * x ** (int(power[1:]) if power else 1)
        else:
            value = F(term)
        total += sign * value
    return total


def thresholds(out_dir):
    return {t["column"]: t for t in load(os.path.join(out_dir, "sweep.json"))["thresholds"]}


def system_with_mu(mu):
    doc = load(KANE)
    doc["contacts"]["friction"][0]["mu"] = str(mu)
    path = os.path.join(tmp, f"kane-{str(mu).replace('/', '_')}.json")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def energetic_at(system_path, restitution, extra=()):
    law = system_path + ".law.json"
    run(["derive", "newton", "--system", system_path, "--restitution", restitution, *extra, "-o", law], 0, "derive")
    p = subprocess.run([CLI, "verify", "--law", law, "--json"], capture_output=True, text=True)
    return {o["id"]: o for o in json.loads(p.stdout)["obligations"]}["energetic"]


try:
    # ---- Kane over mu.
    doc = load(KANE)
    M = [[F(x) for x in row] for row in doc["M"]]
    WN = [F(r[0]) for r in doc["contacts"]["W"]]
    WT = [F(x) for x in doc["contacts"]["friction"][0]["tangents"][0]]
    det = M[0][0] * M[1][1] - M[0][1] * M[1][0]
    Mi = [[M[1][1] / det, -M[0][1] / det], [-M[1][0] / det, M[0][0] / det]]

    def g(a, b):
        return sum(a[i] * Mi[i][j] * b[j] for i in range(2) for j in range(2))

    GNN, GNT, GTT = g(WN, WN), g(WN, WT), g(WT, WT)
    e = F(1, 2)

    def F_f(mu, e=e):  # proofs/README.md, Kane's example: the slip-forward boundary's energy balance
        return GNN * (e - 1) / (1 + e) + 2 * mu * GNT / (1 + e) - mu * mu * GTT

    def proportional(poly, e):
        return len({F_f(x, e) / poly_value(poly, "mu", x) for x in (F(0), F(1, 3), F(2, 7))}) == 1

    out = os.path.join(tmp, "kane")
    run(["sweep", "--system", KANE, "--law", "newton", "--restitution", "1/2", "--vary", "mu=0..1/2:11",
         "--thresholds", "-o", out], 0, "kane sweep")
    th = thresholds(out)
    en = th.get("energetic")
    if not en:
        fail("kane: no energetic threshold")
    else:
        lo, hi = F(en["in"][0]), F(en["in"][1])
        if not (en["below"], en["above"]) == ("proved", "refuted") or not 0 < hi - lo <= F(1, 10**10):
            fail(f"kane: energetic enclosure {en['in']} ({en['below']} -> {en['above']})")
        poly = en.get("boundary", {}).get("polynomial")
        if poly != "267408 mu^2 - 159108 mu + 18433":
            fail(f"kane: energetic polynomial {poly!r}, boundary {en.get('boundary')}")
        else:
            # Second route: F_f from G, proportional to the polynomial (three points fix a quadratic).
            if not proportional(poly, e):
                fail("kane: the polynomial is not proportional to F_f")
            if not poly_value(poly, "mu", lo) * poly_value(poly, "mu", hi) < 0:
                fail("kane: the polynomial does not change sign across the enclosure")
        # mu* = (39777 - sqrt(349926813)) / 133704 in [lo, hi]: 39777 - 133704 x = sqrt(D) at x = mu*.
        a_lo, a_hi = 39777 - 133704 * lo, 39777 - 133704 * hi
        if not (a_hi > 0 and a_hi * a_hi <= 349926813 <= a_lo * a_lo):
            fail(f"kane: mu* is not in [{lo}, {hi}]")
        # The laws at both ends, by derive and verify; the gain above recomputed in body velocities.
        below, above = energetic_at(system_with_mu(lo), "1/2"), energetic_at(system_with_mu(hi), "1/2")
        if below["verdict"] != "proved" or above["verdict"] != "refuted":
            fail(f"kane: energetic at the ends {below['verdict']} / {above['verdict']}")
        else:
            S = System(M, [WN], [(0, hi, F(0), [WT])])
            gm = [F(x) for x in above["counterexample"]["gamma"]]
            u = solve([S.columns[0], S.columns[1]], gm)
            sols = S.solutions(u, [e])
            if len(sols) != 1 or not S.energy2(sols[0]) > S.energy2(u):
                fail("kane: the oracle does not find the energy gain at the upper end")
    fn = th.get("derive")
    if not fn or (fn["below"], fn["above"]) != ("law", "not-a-function") or not (
            F(fn["in"][0]) <= GNN / GNT <= F(fn["in"][1])):
        fail(f"kane: the function's threshold G_NN/G_NT = {GNN / GNT} is not enclosed: {fn}")

    if not LIGHT:  # the sanitizer build leaves these sweeps to the Release run
        # A grid that runs downwards gives the same enclosures, from the smaller end.
        out_down = os.path.join(tmp, "kane-down")
        run(["sweep", "--system", KANE, "--law", "newton", "--restitution", "1/2", "--vary", "mu=1/2..0:11",
             "--thresholds", "-o", out_down], 0, "kane sweep downwards")
        down = thresholds(out_down)
        for column in ("energetic", "derive"):
            if column in th and column in down and (down[column]["in"], down[column]["below"], down[column]["above"]) != (
                    th[column]["in"], th[column]["below"], th[column]["above"]):
                fail(f"kane downwards: {column} {down[column]} differs from upwards {th[column]}")
        if set(down) != set(th):
            fail(f"kane downwards: columns {sorted(down)} against {sorted(th)}")

        # Over e at mu = 1/4: a rational threshold, F_f's root in e, given exactly with its linear factor.
        out = os.path.join(tmp, "kane-e")
        run(["sweep", "--system", KANE, "--law", "newton", "--vary", "e=0..1:11", "--thresholds", "-o", out], 0, "kane e")
        en = thresholds(out).get("energetic", {})
        mu = F(1, 4)
        e_star = (GNN - 2 * mu * GNT + mu * mu * GTT) / (GNN - mu * mu * GTT)  # F_f(1/4, e) = 0
        b = en.get("boundary", {})
        if b.get("root") != f"{e_star.numerator}/{e_star.denominator}" or \
                b.get("polynomial") != f"{e_star.denominator} e - {e_star.numerator}" or \
                not F(en["in"][0]) <= e_star <= F(en["in"][1]):
            fail(f"kane over e: expected the exact root {e_star}, got {en}")

        # ---- The block on a corner at e = 9/10 over mu: mu* = (60 - 2 sqrt 254)/323, the root of
        # 323 mu^2 - 120 mu + 8 (docs/sweep.md); the laws at both ends, the gain above by the oracle.
        block = load(os.path.join(SRC, "examples", "scenes", "block-on-a-corner.json"))
        block["restitution"] = "9/10"

        def block_with_mu(mu):
            path = os.path.join(tmp, f"block-{str(mu).replace('/', '_')}.json")
            with open(path, "w") as f:
                json.dump(dict(block, friction=str(mu)), f)
            return path

        out = os.path.join(tmp, "block")
        run(["sweep", "--scene", block_with_mu(F(1, 2)), "--law", "newton", "--vary", "mu=0..1:11", "--thresholds",
             "-o", out], 0, "block sweep")
        en = thresholds(out).get("energetic")
        if not en or en.get("boundary", {}).get("polynomial") != "323 mu^2 - 120 mu + 8":
            fail(f"block: energetic threshold {en}")
        else:
            lo, hi = F(en["in"][0]), F(en["in"][1])
            # 60 - 323 x = 2 sqrt(254) at x = mu*: squares compared exactly.
            if not (60 - 323 * hi > 0 and (60 - 323 * hi) ** 2 <= 1016 <= (60 - 323 * lo) ** 2):
                fail(f"block: mu* is not in [{lo}, {hi}]")
            below, above = energetic_at(block_with_mu(lo), "9/10"), energetic_at(block_with_mu(hi), "9/10")
            if below["verdict"] != "proved" or above["verdict"] != "refuted":
                fail(f"block: energetic at the ends {below['verdict']} / {above['verdict']}")
            else:
                head = load(block_with_mu(hi) + ".law.json")
                n = len(head["contacts"]["W"])
                Mb = [[F(head["masses"][i]) if i == j else F(0) for j in range(n)] for i in range(n)]
                WNb = [F(r[0]) for r in head["contacts"]["W"]]
                WTb = [F(x) for x in head["contacts"]["friction"][0]["tangents"][0]]
                S = System(Mb, [WNb], [(0, hi, F(0), [WTb])])
                gm = [F(x) for x in above["counterexample"]["gamma"]]
                # u- = W (W^T W)^-1 gamma- (three velocities, two columns)
                WtW = [[sum(a[i] * b[i] for i in range(n)) for b in S.columns] for a in S.columns]
                y = solve(WtW, gm)
                u = [sum(S.columns[k][i] * y[k] for k in range(2)) for i in range(n)]
                sols = S.solutions(u, [F(9, 10)])
                if len(sols) != 1 or not S.energy2(sols[0]) > S.energy2(u):
                    fail("block: the oracle does not find the energy gain at the upper end")

        # ---- Three equal balls, Newton with restitution on approaching contacts, over e.
        out = os.path.join(tmp, "chain")
        run(["sweep", "--masses", "1,1,1", "--restitution", "e", "--law", "newton", "--restitution-on", "approaching",
             "--vary", "e=0..1:11", "--thresholds", "--threshold-digits", "12", "-o", out], 0, "chain sweep")
        en = thresholds(out).get("energetic")
        if not en or en.get("boundary", {}).get("polynomial") != "4 e^2 - 3":
            fail(f"chain: energetic threshold {en}")
        else:
            lo, hi = F(en["in"][0]), F(en["in"][1])
            if not (lo * lo * 4 < 3 < hi * hi * 4) or hi - lo > F(1, 10**12):
                fail(f"chain: sqrt(3)/2 not in [{lo}, {hi}]")
            chain = os.path.join(tmp, "chain3.json")
            with open(chain, "w") as f:
                json.dump({"format": "impactcert-system/1", "name": "chain3", "masses": ["1", "1", "1"]}, f)
            below = energetic_at(chain, str(lo), ["--restitution-on", "approaching"])
            above = energetic_at(chain, str(hi), ["--restitution-on", "approaching"])
            if below["verdict"] != "proved" or above["verdict"] != "refuted":
                fail(f"chain: energetic at the ends {below['verdict']} / {above['verdict']}")
            else:
                I3 = [[F(int(i == j)) for j in range(3)] for i in range(3)]
                S = System(I3, [[-1, 1, 0], [0, -1, 1]], [])
                gm = [F(x) for x in above["counterexample"]["gamma"]]
                u = [F(0), gm[0], gm[0] + gm[1]]
                sols = S.solutions(u, [hi, hi], approaching=True)
                if len(sols) != 1 or not S.energy2(sols[0]) > S.energy2(u):
                    fail("chain: the oracle does not find the energy gain at the upper end")

    # ---- Controls: no change, no threshold; at e = 1/4 another polynomial, F_f's at 1/4.
    out = os.path.join(tmp, "none")
    run(["sweep", "--system", KANE, "--law", "newton", "--restitution", "1/2", "--vary", "mu=0..3/20:4",
         "--thresholds", "-o", out], 0, "control sweep")
    if "energetic" in thresholds(out):
        fail("control: an energetic threshold where every law is consistent")
    out = os.path.join(tmp, "quarter")
    run(["sweep", "--system", KANE, "--law", "newton", "--restitution", "1/4", "--vary", "mu=0..1/2:6",
         "--thresholds", "-o", out], 0, "e = 1/4 sweep")
    poly = thresholds(out).get("energetic", {}).get("boundary", {}).get("polynomial")
    if not poly or poly == "267408 mu^2 - 159108 mu + 18433" or not proportional(poly, F(1, 4)) or proportional(poly, e):
        fail(f"control: the polynomial at e = 1/4 is {poly!r}")

    # ---- Bad input: one line, exit 2.
    scene = os.path.join(SRC, "examples", "scenes", "spinning-disk.json")
    for args, needle in (
            (["--system", KANE, "--vary", "x=0..1:3"], "--vary x"),
            (["--system", KANE, "--vary", "mu2=0..1:3"], "1 contacts"),
            (["--system", KANE, "--vary", "mu=-1..1:3"], "negative"),
            (["--system", KANE, "--vary", "e=0..2:3"], "outside [0, 1]"),
            (["--system", KANE, "--law", "poisson", "--vary", "mu=0..1:3"], "Poisson"),
            (["--system", KANE, "--vary", "mu=0..1:3", "--vary", "e=0..1:3", "--thresholds"], "--thresholds"),
            (["--masses", "1,1", "--system", KANE, "--vary", "mu=0..1:3"], "give one"),
            (["--scene", KANE, "--vary", "mu=0..1:3"], "not an impactcert-scene/1"),
            (["--system", scene, "--vary", "mu=0..1:3"], "a scene"),
            (["--system", KANE, "--restitution", "e", "--vary", "mu=0..1:3"], "not a --vary parameter"),
            (["--masses", "1,1,1", "--vary", "e=0..1:3", "--restitution", "e", "--law", "sideways"], "--law")):
        p = run(["sweep", *args, "-o", os.path.join(tmp, "bad")], 2, "bad input " + " ".join(args))
        if needle not in p.stderr or p.stderr.count("\n") != 1:
            fail(f"bad input {args}: {p.stderr!r}")

    # ---- Shards of a system sweep, merged, equal the single run.
    single = os.path.join(tmp, "single")
    args = ["sweep", "--scene", scene, "--law", "newton", "--vary", "mu=0..1:5", "--vary", "e=0..1:3"]
    run(args + ["-o", single], 0, "single scene sweep")
    parts = []
    for k in (1, 2):
        d = os.path.join(tmp, f"part{k}")
        p = run(args + ["--shard", f"{k}/2", "-o", d], 0, f"shard {k}")
        parts.append(p.stdout.strip())
    merged = os.path.join(tmp, "merged")
    run(["sweep", "--merge", *parts, "-o", merged], 0, "merge")
    if load(os.path.join(merged, "sweep.json")) != load(os.path.join(single, "sweep.json")):
        fail("shards: the merged scene sweep differs from the single run")
    csv = open(os.path.join(single, "sweep.csv")).read().splitlines()
    if "coulomb" not in csv[0].split(","):
        fail("scene sweep: no coulomb column")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

finish(failures)
