#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Detection power (issue 44): the bugs people make are found, correct solvers are not flagged.

Law mode, the newcomer's case (tests/impls/newton4_impl.py, the 4-ball law):
  - a plain solver with an absolute threshold (a contact approaches only if gamma < -1e-6) fails
    the CI line of docs/fuzzing.md; the same solver without the threshold passes it (its sums
    overflow near 1e308: those are `extreme` violations, which that line allows), and fails the
    strict default (no --allow extreme), which the text says why;
  - with --range 1e-150..1e150 the threshold is found within 2,000 samples (it passed a million
    when every sample was pushed to the top of the range), and every reported witness is
    recomputed here in Python fractions: the exact law (a sort of the ball velocities) differs
    from the answer by more than the tolerance;
  - the coverage: every piece and facet of the law, in the text, the JSON and the JUnit report;
    what a narrow range leaves untested is said.
Consistency mode (tests/impls/chain_engine.py, an engine-like sequential-impulse solver):
  - Box2D's velocity threshold (restitution off below 1) is consistent, but a `reference` finding
    against --reference approaching; the worst one is recomputed here: the reported y* satisfies
    the Newton law's complementarity conditions exactly (so it is the law's answer), and the
    answer is farther from it than the tolerance; its replay exits 1 and names the property;
  - the converged correct solver has no reference finding (negative control);
  - a solver that crashes on the input at rest: exit 1, the finding at-rest with a replay (it was
    exit 2, "the command ended without answering").
Usage: detection_test.py BINDIR SOURCE_DIR [--light]"""
import json
import math
import os
import subprocess
import sys
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import testkit  # noqa: E402

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
LIGHT = "--light" in sys.argv[3:]
CLI = os.path.join(BIN, "impactcert")
LAW = os.path.join(SRC, "proofs", "newton4", "law.json")
SOLVER = "python3 " + os.path.join(SRC, "tests", "impls", "newton4_impl.py")
ENGINE = "python3 " + os.path.join(SRC, "tests", "impls", "chain_engine.py")
failures = []


def fail(msg):
    failures.append(msg)


def run(args):
    return subprocess.run([CLI] + args, capture_output=True, text=True, cwd=SRC)


def fuzz_law(mode, extra):
    return run(["fuzz", "--law", LAW, "--impl-cmd", SOLVER + " " + mode, "--max-rel-error", "1e-12"] + extra)


# The CI line of docs/fuzzing.md, with a sample count instead of --seconds (reproducible).
CI = ["--allow", "extreme", "--samples", "4000" if LIGHT else "20000"]
for mode, want in [("threshold", 1), ("tolerance", 1), ("plain", 0), ("sorted", 0)]:
    r = fuzz_law(mode, CI)
    if r.returncode != want:
        fail(f"CI line, {mode}: exit {r.returncode}, expected {want}\n{r.stdout[-2000:]}{r.stderr}")
# The plain solver overflows near 1e308: strict by default, and the text says where.
r = fuzz_law("plain", ["--samples", "4000"])
if r.returncode != 1 or "at extreme magnitudes (fail the run; --allow extreme accepts them)" not in r.stdout:
    fail(f"plain solver without --allow extreme: exit {r.returncode}\n{r.stdout[-2000:]}")
if "samples with violations        0 within 2^-500..2^500" not in r.stdout:
    fail("plain solver: violations within the physical range?\n" + r.stdout[-2000:])


exact_law = testkit.newton4_exact
h_norm2 = testkit.newton4_h_norm2


r = fuzz_law("threshold", ["--range", "1e-150..1e150", "--samples", "2000", "--json", "--keep", "20"])
try:
    j = json.loads(r.stdout)
except json.JSONDecodeError:
    j = None
    fail(f"--range 1e-150..1e150 --json: not JSON (exit {r.returncode})\n{r.stdout[:500]}{r.stderr}")
if j is not None:
    if r.returncode != 1 or j["verdict"] != "violations":
        fail(f"the threshold solver passed 2,000 samples of --range 1e-150..1e150 (exit {r.returncode})")
    checked = 0
    for e in j["examples"]:
        if "input_b" in e:
            continue
        x = [F.from_float(float.fromhex(t)) for t in e["input"]]
        y = [F.from_float(float.fromhex(t)) for t in e["output"]]
        exact = exact_law(x)
        d = [a - b for a, b in zip(y, exact)]
        # outside --max-rel-error 1e-12: |y - S(x)| > R |x|, squared, in the law's metric
        if not h_norm2(d) > F(1e-12) ** 2 * h_norm2(x):
            fail(f"witness {e['input']} -> {e['output']} is within the tolerance of the exact law {exact}")
        checked += 1
    if checked == 0:
        fail("no single-point witness to recompute")
    cov = j["coverage"]
    if cov["pieces_hit"] != cov["pieces"] or cov["pieces"] != 24 or cov["facets_probed"] != cov["facets"]:
        fail(f"coverage: {cov}")
    if cov["decade_lo"] > -149 or cov["decade_hi"] < 148:
        fail(f"coverage: the range's decades not reached: {cov}")
    if not any("overflow there is unseen" in t for t in cov["not_tested"]):
        fail(f"coverage: the range's top not said untested: {cov['not_tested']}")

# A narrow range says what it leaves out, in the text and the JUnit report.
junit = os.path.join("/tmp", f"impactcert-detection-{os.getpid()}.xml")
r = fuzz_law("plain", ["--range", "1e-3..1e3", "--samples", "3000", "--junit", junit])
if r.returncode != 0 or "not tested                     no magnitude below 0.001: thresholds and tolerances there are unseen" not in r.stdout:
    fail(f"--range 1e-3..1e3: exit {r.returncode}, untested magnitudes not said\n{r.stdout}")
if "coverage                       pieces 24/24 hit, facets 72/72 probed, scales 1e-3..1e2 (6 decades)" not in r.stdout:
    fail("--range 1e-3..1e3: coverage line\n" + r.stdout)
try:
    with open(junit) as f:
        xml = f.read()
    os.unlink(junit)
    if "<failure" in xml:
        fail("JUnit: a failure in a passing run\n" + xml)
    if 'name="coverage"' not in xml or "<system-out>pieces 24/24 hit" not in xml or "not tested: no magnitude below" not in xml:
        fail("JUnit: no coverage case\n" + xml)
except OSError as e:
    fail(f"JUnit not written: {e}")

# With --allow extreme, the JUnit report of a failing run does not fail the allowed class.
r = fuzz_law("threshold", ["--allow", "extreme", "--samples", "1000", "--junit", junit])
try:
    with open(junit) as f:
        xml = f.read()
    os.unlink(junit)
    case = xml[xml.index('name="extreme magnitudes"'):]
    case = case[:case.index("</testcase>")]
    if r.returncode != 1 or "<failure" in case or "allowed: --allow extreme" not in case:
        fail(f"JUnit, --allow extreme: the allowed class failed or unexplained (exit {r.returncode})\n{case}")
except (OSError, ValueError) as e:
    fail(f"JUnit with --allow extreme: {e}")

# --allow takes one value.
r = fuzz_law("plain", ["--allow", "everything", "--samples", "10"])
if r.returncode != 2 or r.stderr.count("\n") != 1 or "--allow" not in r.stderr:
    fail(f"--allow everything: exit {r.returncode}: {r.stderr}")

# Consistency mode.
def fuzz_engine(mode, extra):
    return run(["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd", ENGINE + " " + mode, "--max-rel-error", "1e-9",
                "--restitution", "1", "--reference", "approaching", "--samples", "700" if LIGHT else "2000"] + extra)


r = fuzz_engine("threshold", ["--json"])
j = json.loads(r.stdout) if r.stdout.startswith("{") else None
if j is None or r.returncode != 1:
    fail(f"threshold engine: exit {r.returncode}\n{r.stdout[:1000]}{r.stderr}")
else:
    if not j["checked_properties"].get("reference") or j["violations"]["reference"] == 0:
        fail(f"threshold engine: no reference finding: {j['violations']}")
    # Box2D's threshold breaks restitution (a slow contact alone approaching keeps no bounce)
    # and nothing a consistent map must keep.
    for what in ("kinematic", "kinetic", "momentum"):
        if j["violations"][what]:
            fail(f"threshold engine: {what} violated? it is consistent: {j['violations']}")
    w = j["worst"]["reference"]
    x = [F.from_float(float.fromhex(t)) for t in w["input"]]
    y = [F.from_float(float.fromhex(t)) for t in w["output"]]
    ystar = [F(w["exact"][f"y*_{i + 1}"]) for i in range(3)]
    # y* is the Newton law with restitution 1 on approaching contacts: momentum kept, and per
    # contact gamma+ >= target, impulse >= 0, complementary (chain of unit masses).
    if sum(ystar) != sum(x):
        fail(f"y* {ystar} does not keep momentum of {x}")
    lam1 = x[0] - ystar[0]
    lam2 = ystar[2] - x[2]
    for k, lam in enumerate((lam1, lam2)):
        gm = x[k + 1] - x[k]
        gp = ystar[k + 1] - ystar[k]
        target = -gm if gm < 0 else F(0)
        if gp < target or lam < 0 or (gp - target) * lam != 0:
            fail(f"y* {ystar} breaks the Newton law at contact {k + 1} (input {x})")
    off2 = sum((a - b) ** 2 for a, b in zip(y, ystar))
    if not off2 > F(1e-9) ** 2 * sum(v * v for v in x):
        fail(f"reference finding within the tolerance: {w}")
    rr = testkit.run_replay(w["replay"], CLI)
    if rr.returncode != 1 or "(reference)" not in rr.stdout:
        fail(f"reference replay: exit {rr.returncode}\n{rr.stdout}{rr.stderr}")

# Effort (issue 44, item 4): the same engine at several iteration counts. Box2D's threshold does not
# come closer to the law with more iterations (model-level); the unconverged correct solver does
# (solver-level); the converged one is within the tolerance at its largest effort.
def effort_run(mode, efforts):
    return run(["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd", ENGINE + " " + mode + " --iterations {iterations}",
                "--efforts", efforts, "--max-rel-error", "1e-9", "--restitution", "1", "--reference", "approaching",
                "--samples", "300" if LIGHT else "1000", "--json"])


for mode, efforts, want in [("threshold", "1,4,64", "model-level"), ("correct", "1,4", "solver-level"),
                            ("correct", "1,64", "converged")]:
    r = effort_run(mode, efforts)
    try:
        e = json.loads(r.stdout)["effort"]
    except (json.JSONDecodeError, KeyError):
        fail(f"--efforts {efforts}, {mode}: no effort report (exit {r.returncode})\n{r.stdout[:800]}{r.stderr}")
        continue
    if e["diagnosis"] != want or [x["effort"] for x in e["runs"]] != [int(v) for v in efforts.split(",")]:
        fail(f"--efforts {efforts}, {mode}: {e}, expected {want}")
    if want == "model-level" and not (e["runs"][-1]["worst_distance"] > e["runs"][0]["worst_distance"] / 2 > 0):
        fail(f"model-level without a distance that stays: {e}")
    if want == "model-level":
        t = run(["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd", ENGINE + " threshold --iterations {iterations}",
                 "--efforts", efforts, "--max-rel-error", "1e-9", "--restitution", "1", "--reference", "approaching",
                 "--samples", "300"])
        if "model-level worst (sample" not in t.stdout or "--iterations 64' " not in t.stdout:
            fail("model-level: the text does not label the findings, or the replay is not at the largest effort\n" + t.stdout)
for args, words in [(["--impl-cmd", ENGINE + " correct", "--efforts", "1,4", "--reference", "approaching"], "{iterations}"),
                    (["--impl-cmd", ENGINE + " correct --iterations {iterations}"], "--reference"),
                    (["--impl-cmd", ENGINE + " correct --iterations {iterations}", "--efforts", "4,1", "--reference",
                      "approaching"], "ascending"),
                    (["--impl-cmd", ENGINE + " correct --iterations {iterations}", "--efforts", "4", "--reference",
                      "approaching"], "2 to 8"),
                    (["--impl-cmd", ENGINE + " correct --iterations {iterations}", "--efforts", "0,4", "--reference",
                      "approaching"], "1..10^9")]:
    b = run(["fuzz", "--masses", "1,1,1", "--velocities", "--restitution", "1", "--samples", "10"] + args)
    if b.returncode != 2 or words not in b.stderr or len(b.stderr.strip().splitlines()) != 1:
        fail(f"{args}: exit {b.returncode}, {b.stderr!r}")

# Where momentum fails, the kinetic findings are projections of a change not made of contact
# impulses, and say so (issue 44, item 4); a consistent engine has none marked.
SHOVE = "python3 " + os.path.join(SRC, "tests", "impls", "shove.py")
r = run(["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd", SHOVE, "--samples", "300", "--json"])
try:
    j = json.loads(r.stdout)
    v, pr = j["violations"], j.get("projections", {})
    if not (v["momentum"] > 0 and v["kinetic"] > 0 and pr.get("kinetic") == v["kinetic"] and
            j["worst"]["kinetic"].get("projection") is True and "Lambda projected" in j["worst"]["kinetic"]["detail"]):
        fail(f"shove: kinetic findings not marked as projections: {v}, {pr}, {j['worst'].get('kinetic')}")
except (json.JSONDecodeError, KeyError) as err:
    fail(f"shove --json: {err}\n{r.stdout[:500]}{r.stderr}")
r = fuzz_engine("threshold", ["--json"])
if r.stdout.startswith("{") and "projections" in json.loads(r.stdout):
    fail("the threshold engine (momentum kept) has findings marked as projections")

# The reference by name with friction (issue 44, item 3): derived on the fly, as derive newton
# --system would; the exact solver (tests/oracles, rounded) is never off it, one with its
# tangential impulses reversed is; Poisson with friction is a one-line refusal (--restitution with
# friction is Newton's restitution property: tests/diagnosis_test.py).
scene = os.path.join(SRC, "examples", "scenes", "two-disks.json")
scene_law = os.path.join("/tmp", f"impactcert-detection-{os.getpid()}-law.json")
run(["derive", "newton", "--system", scene, "-o", scene_law])
FRICTION = "python3 " + os.path.join(SRC, "tests", "impls", "friction_impls.py") + " " + scene_law
for mode, off in [("exact", False), ("reversed", True)]:
    r = run(["fuzz", "--system", scene, "--velocities", "--range", "0.01..10", "--max-rel-error", "1e-9", "--samples",
             "60" if LIGHT else "150", "--impl-cmd", FRICTION + " " + mode + " 1/2", "--reference", "newton", "--json"])
    try:
        j = json.loads(r.stdout)
        if "with Coulomb friction" not in j["reference"] or (j["violations"]["reference"] > 0) != off:
            fail(f"--reference newton with friction, {mode}: {j['reference']}, {j['violations']['reference']} off")
    except (json.JSONDecodeError, KeyError) as err:
        fail(f"--reference newton with friction, {mode}: {err}\n{r.stdout[:300]}{r.stderr}")
for args, words in [(["--reference", "poisson"], "not offered"),
                    (["--reference", scene_law, "--restitution", "1/2"], "Newton's")]:
    b = run(["fuzz", "--system", scene, "--velocities", "--impl-cmd", "cat", "--samples", "5"] + args)
    if b.returncode != 2 or words not in b.stderr or len(b.stderr.strip().splitlines()) != 1:
        fail(f"friction {args}: exit {b.returncode} {b.stderr!r}")
os.unlink(scene_law)

r = fuzz_engine("correct", ["--json"])
j = json.loads(r.stdout) if r.stdout.startswith("{") else None
if j is None or j["violations"]["reference"] != 0:
    fail(f"the converged correct engine has reference findings: {r.stdout[:1500]}")

r = fuzz_engine("restcrash", ["--json"])
j = json.loads(r.stdout) if r.stdout.startswith("{") else None
if j is None or r.returncode != 1 or j["violations"]["at-rest"] != 1:
    fail(f"crash at rest: exit {r.returncode} (expected 1 and the finding at-rest)\n{r.stdout[:800]}{r.stderr}")
elif "crashed" not in j["worst"]["at-rest"]["detail"] or "replay" not in j["worst"]["at-rest"]:
    fail(f"crash at rest: {j['worst']['at-rest']}")

# Consistency mode's coverage (issue 44, item 1): the JSON and text say which patterns of
# approaching contacts, decades and reference pieces the checked inputs reached, and what they did
# not (a run of 3 samples misses patterns: the negative control); the sampler's near-ties are
# there, read back from the inputs the implementation was sent.
inputs_log = os.path.join("/tmp", f"impactcert-detection-{os.getpid()}-inputs.txt")
for samples, full in (("2000", True), ("3", False)):
    r = run(["fuzz", "--masses", "1,1,1,1", "--velocities", "--impl-cmd", "tee -a " + inputs_log, "--samples", samples,
             "--restitution", "1", "--reference", "approaching", "--json"])
    try:
        cov = json.loads(r.stdout)["coverage"]
    except (json.JSONDecodeError, KeyError) as err:
        fail(f"consistency coverage ({samples} samples): {err}: {r.stdout[:300]}{r.stderr}")
        continue
    complete = cov["patterns_hit"] == cov["patterns"] == 7 and cov["reference_pieces_hit"] == cov["reference_pieces"] > 0
    if complete != full or (not full and not cov["not_tested"]) or (full and cov["decades"] < 5):
        fail(f"consistency coverage ({samples} samples): {cov}")
    else:
        print(f"consistency coverage, {samples} samples: {cov['text']}" + (f"; not tested: {cov['not_tested'][0]}" if cov["not_tested"] else ""))
near = 0
for line in open(inputs_log):
    xs = [float.fromhex(t) if "0x" in t else float(t) for t in line.split()]
    for a, b in zip(xs, xs[1:]):
        if a != 0 and a != b and (a > 0) == (b > 0):
            ulps = abs(a - b) / math.ulp(a)
            near += 1 <= ulps <= 2 ** 20 + 1
os.unlink(inputs_log)
if near == 0:
    fail("consistency sampler: no near-tie (components 1 to 2^20 ulps apart) among the inputs sent")
else:
    print(f"consistency sampler: {near} near-ties among the inputs sent")

testkit.finish(failures)
