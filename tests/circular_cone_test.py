#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""`fuzz --cone circular` (issue 43): consistency fuzzing against Coulomb's law with the circular
cone, decided exactly on the answers' doubles (proofs/README.md, "Consistency with a circular
friction cone").

- The law in closed form for a ball on a plane (tests/impls/circular_ball.py, fractions rounded to
  doubles): no alarm, nor with its friction turned by 1e-12 rad; planted errors are found: the
  friction box (friction_cone, and coulomb: its friction is not along a slip off the diagonal),
  the friction turned by 3/5, 4/5 and by 1e-8 rad (coulomb), mu doubled (friction_cone).
- Siconos's fc3d solvers (examples/engines/siconos_fc3d.py, Debian's python3-siconos), NSGS and
  the semismooth Newton on Alart-Curnier's function: no alarm on a spinning ball and on a ball
  resting on a ball (two rough contacts). Judged by the box, Siconos's answers break the box's
  Coulomb law (the two models differ); the ODE's box judged by the circle breaks the cone.
- Every property's worst finding is replayed (`eval --float`, exit 1) and recomputed here by a
  second route: Lambda = G^-1 (gamma+ - gamma-) in fractions (tests/oracles/friction_lcp.py), the
  violation beyond the tolerance with square roots bounded by integer square roots.
- Bad input: no friction, dependent columns, a reference law, an unknown cone, --cone with a law.
Usage: circular_cone_test.py BUILD_DIR SOURCE_DIR PYTHON ODE_SCENE|- [--light]
(--light: 200 samples, and one run of each kind; "-": no ODE example, as in the sanitizer build.)
"""
import json
import math
import os
import re
import shlex
import subprocess
import sys
import tempfile
from fractions import Fraction as F

BUILD, SRC, PYTHON, ODE = sys.argv[1:5]
LIGHT = "--light" in sys.argv[5:]
sys.path.insert(0, os.path.join(SRC, "tests"))
sys.path.insert(0, os.path.join(SRC, "tests", "oracles"))
import testkit  # noqa: E402
from friction_lcp import System  # noqa: E402

CLI = os.path.join(BUILD, "impactcert")
SCENES = os.path.join(SRC, "examples", "scenes")
BALL = os.path.join(SRC, "tests", "impls", "circular_ball.py")
DRIVER = os.path.join(SRC, "examples", "engines", "siconos_fc3d.py")
SAMPLES = "200" if LIGHT else "2000"
failures = []
fail = failures.append
tmp = tempfile.mkdtemp(prefix="impactcert-circular-")


def law_of(name):
    path = os.path.join(tmp, name + ".json")
    subprocess.run([CLI, "derive", "newton", "--system", os.path.join(SCENES, name + ".json"), "-o", path],
                   check=True, capture_output=True)
    head = json.load(open(path))
    W = head["contacts"]["W"]
    n = len(W)
    M = [[F(head["masses"][i]) if i == j else F(0) for j in range(n)] for i in range(n)]
    S = System(M, [[F(W[i][k]) for i in range(n)] for k in range(len(W[0]))],
               [(f["contact"] - 1, F(f["mu"]), F(0), f["tangents"]) for f in head["contacts"]["friction"]])
    return path, S


def sqrt_bounds(x):
    """Rationals lo <= sqrt(x) <= hi (x >= 0), by integer square roots at 2^-200."""
    if x == 0:
        return F(0), F(0)
    scale = 1 << 400
    r = math.isqrt(x.numerator * scale // x.denominator)
    return F(r, 1 << 200), F(r + 1, 1 << 200)


def certainly_positive(P, Q, S):
    """P + Q sqrt(S) > 0, shown with sqrt(S) bounded on the unfavourable side."""
    lo, hi = sqrt_bounds(S)
    return P + Q * (lo if Q >= 0 else hi) > 0


def recheck(S, finding, tol_rel, prop):
    """The finding by the second route: exact impulses from M and W, the violation beyond the
    tolerance t = R |u-|_M + A of proofs/README.md's lemma (A, the underflow allowance, bounded
    above by 2^-1000)."""
    u = [F(float.fromhex(x)) for x in finding["input"]]
    y = [F(float.fromhex(x)) for x in finding["output"]]
    gm, gp, lam = S.impulses(u, y)
    k = int(re.search(r"\(contact (\d+),", finding["detail"]).group(1)) - 1
    T = [len(S.normals) + j for j, t in enumerate(S.tangents) if t[0] == k]
    mu = S.tangents[T[0] - len(S.normals)][1]
    Minv_cols = [testkit_solve(S.M, c) for c in S.columns]
    G = [[sum(a[i] * mc[i] for i in range(S.n)) for mc in Minv_cols] for a in S.columns]
    H = invert(G)
    t = F(tol_rel) * sqrt_bounds(S.energy2(u))[1] + F(1, 2 ** 1000)
    lt, xi, ln = [lam[j] for j in T], [gp[j] for j in T], lam[k]
    lt2, xi2, dot = sum(x * x for x in lt), sum(x * x for x in xi), sum(a * b for a, b in zip(lt, xi))
    hT = sqrt_bounds(sum(H[j][j] for j in T))[1]
    gT = sqrt_bounds(sum(G[j][j] for j in T))[1]
    hN = sqrt_bounds(H[k][k])[1]
    got = finding.get("exact", {})
    if prop == "friction_cone":
        if F(got.get("|Lambda_T|^2", "-1")) != lt2 or F(got.get("mu Lambda_N", "-1")) != mu * ln:
            return f"the figures {got} are not |Lambda_T|^2 = {lt2}, mu Lambda_N = {mu * ln}"
        bound = mu * ln + t * (hT + mu * hN)
        return None if bound < 0 or lt2 > bound * bound else "within the tolerance of the cone"
    L = max(ln + t * hN, F(0))
    if F(got.get("Lambda_T . xi_T", "x0")) != dot or F(got.get("|xi_T|^2", "-1")) != xi2:
        return f"the figures {got} are not Lambda_T . xi_T = {dot}, |xi_T|^2 = {xi2}"
    too_little = certainly_positive(dot - 2 * mu * L * t * gT, mu * ln - t * (hT + mu * hN), xi2)
    a, b = t * hT, mu * L * t * gT
    aside = certainly_positive(lt2 * xi2 - dot * dot - a * a * xi2 - b * b, -2 * a * b, xi2)
    return None if too_little or aside else "within the tolerance of Coulomb's law"


def testkit_solve(A, b):
    from friction_lcp import solve
    return solve(A, b)


def invert(A):
    n = len(A)
    cols = [testkit_solve(A, [F(int(i == j)) for i in range(n)]) for j in range(n)]
    return [[cols[j][i] for j in range(n)] for i in range(n)]


def fuzz(scene, impl, extra=(), rel="1e-9", samples=SAMPLES):
    p = subprocess.run([CLI, "fuzz", "--system", os.path.join(SCENES, scene + ".json"), "--velocities", "--impl-cmd", impl,
                        "--range", "0.01..10", "--max-rel-error", rel, "--samples", samples, "--restitution", "1/2",
                        "--json"] + list(extra), capture_output=True, text=True)
    try:
        return p.returncode, json.loads(p.stdout)
    except json.JSONDecodeError:
        fail(f"{scene} {impl}: not JSON (exit {p.returncode}): {p.stdout[:300]}{p.stderr[:300]}")
        return p.returncode, None


def expect(label, scene, S, impl, found, extra=("--cone", "circular"), rel="1e-9"):
    status, j = fuzz(scene, impl, extra, rel)
    if j is None:
        return
    seen = {k for k, v in j["violations"].items() if v}
    if seen != set(found) or status != (1 if found else 0):
        fail(f"{label}: exit {status}, violations {j['violations']}, expected {sorted(found)}")
        return
    if j.get("cone") != ("circular" if "circular" in extra else "box"):
        fail(f"{label}: the report's cone is {j.get('cone')!r}")
    for prop in found:
        w = j["worst"][prop]
        why = recheck(S, w, rel, prop) if "circular" in extra else None
        if why:
            fail(f"{label}: the worst {prop} finding, recomputed: {why}\n{w}")
        if "circular" in extra and recheck(S, w, "1e3", prop) is None:  # the recheck's own control
            fail(f"{label}: the recheck passes the {prop} finding at a tolerance of 1e3 too")
        rr = testkit.run_replay(w["replay"], CLI)
        if rr.returncode != 1 or ("--cone circular" in w["replay"]) != ("circular" in extra):
            fail(f"{label}: replay exit {rr.returncode}: {w['replay']}")
    print(f"{label}: {j['samples']} samples, " + (", ".join(f"{p} {j['violations'][p]}" for p in found) or "no violation"))


ball_law, BALL_S = law_of("3d-spinning-ball")
two_law, TWO_S = law_of("3d-ball-on-a-ball") if not LIGHT else (None, None)  # 5050 mode pairs to derive


def ball(mode):
    return shlex.join(["python3", BALL, ball_law, mode, "1/2"])


def siconos(law, solver):
    return shlex.join([PYTHON, DRIVER, "--system", law, "--restitution", "1/2", "--restitution-on", "approaching",
                       "--solver", solver])


# The law in closed form, and planted errors.
# (--light, the sanitizer build's run: the checker's code on one run of each kind.)
expect("ball, exact", "3d-spinning-ball", BALL_S, ball("exact"), [])
if not LIGHT:
    expect("ball, exact, judged at 1e-15", "3d-spinning-ball", BALL_S, ball("exact"), [], rel="1e-15")
    expect("ball, turned by 1e-12 rad", "3d-spinning-ball", BALL_S, ball("tilt:1e-12"), [])
    expect("ball, the box", "3d-spinning-ball", BALL_S, ball("box"), ["friction_cone", "coulomb"])
    expect("ball, turned by 3/5, 4/5", "3d-spinning-ball", BALL_S, ball("rotated"), ["coulomb"])
expect("ball, turned by 1e-8 rad", "3d-spinning-ball", BALL_S, ball("tilt:1e-8"), ["coulomb"])
expect("ball, mu doubled", "3d-spinning-ball", BALL_S, ball("mu2"), ["friction_cone"])
# Siconos: the circle.
for solver in ("nsgs",) if LIGHT else ("nsgs", "nsn-ac"):
    expect(f"siconos {solver}, spinning ball", "3d-spinning-ball", BALL_S, siconos(ball_law, solver), [])
    if not LIGHT:
        expect(f"siconos {solver}, ball on a ball", "3d-ball-on-a-ball", TWO_S, siconos(two_law, solver), [])
# The two models judged by each other.
if not LIGHT:
    expect("siconos nsgs judged by the box", "3d-spinning-ball", BALL_S, siconos(ball_law, "nsgs"), ["coulomb"], extra=())
if ODE != "-":
    ode = shlex.join([ODE, "--scene", os.path.join(SCENES, "3d-spinning-ball.json")])
    expect("ODE's box judged by the circle", "3d-spinning-ball", BALL_S, ode, ["friction_cone", "coulomb"], rel="1e-6")
else:
    print("ODE's box judged by the circle: not run (no ODE example in this build)")

# Bad input: one line, exit 2.
for args, words in [
        (["--system", os.path.join(SCENES, "3d-box-on-an-edge.json"), "--cone", "circular"], "has no friction"),
        (["--system", os.path.join(SCENES, "3d-rough-box-on-an-edge.json"), "--cone", "circular"], "rank 5 of 6"),
        (["--system", os.path.join(SCENES, "3d-spinning-ball.json"), "--cone", "circular", "--reference", "approaching"],
         "no reference law"),
        (["--system", os.path.join(SCENES, "3d-spinning-ball.json"), "--cone", "square"], "expected box or circular"),
        (["--law", os.path.join(SRC, "proofs", "newton4", "law.json"), "--cone", "circular"], "consistency fuzzing only")]:
    p = subprocess.run([CLI, "fuzz", "--velocities", "--impl-cmd", "cat", "--restitution", "1/2"] + args,
                       capture_output=True, text=True)
    if args[0] == "--law":
        p = subprocess.run([CLI, "fuzz", "--impl-cmd", "cat"] + args, capture_output=True, text=True)
    if p.returncode != 2 or words not in p.stderr or p.stderr.count("\n") != 1:
        fail(f"{args}: exit {p.returncode}, stderr {p.stderr!r}")
p = subprocess.run([CLI, "eval", "--float", "--law", os.path.join(SRC, "proofs", "newton4", "law.json"), "--impl-cmd", "cat",
                    "--cone", "circular", "--", "1", "-1", "0"], capture_output=True, text=True)
if p.returncode != 2 or "--cone: consistency replays only" not in p.stderr:
    fail(f"eval --law --cone: exit {p.returncode}, {p.stderr!r}")

if failures:
    print("FAILED:\n" + "\n".join(failures))
    sys.exit(1)
print("circular cone: every finding recomputed and replayed, no false alarm")
