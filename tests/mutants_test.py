#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The gate's own strength (issue 44, item 5): `fuzz --mutants N` on the 4-ball law.

  - The CI line of docs/fuzzing.md (--max-rel-error 1e-12 --allow extreme) passes the control
    (the law's plain double evaluation) and kills every mutant it runs that has a witness of a
    difference; each kill's witness is recomputed here in Python fractions, independently of
    impactcert: the mutant's answer is farther from the exact law (a sort) than the tolerance,
    its replay (`eval --float --mutant ID --max-rel-error 1e-12`) exits 1 and the control's
    answer at the same input exits 0.
  - A narrow range (1e-3..1e3) lets the velocity thresholds survive, each with a witness below
    the range that is recomputed the same way; --min-kill-rate 1 then exits 1.
  - Equivalent mutants are only those whose program gives the control's doubles: a zero entry
    negated, integer constants "rounded" to 6 digits. Checked by evaluating both at 300 inputs; none is run or counted.
  - Bad input: --mutants with --impl-cmd, without a tolerance, in consistency mode; --mutant
    with an unknown operator, an index out of range, the last piece (the else branch); a
    --min-kill-rate outside 0..1. Each is exit 2 with one line.
Usage: mutants_test.py BINDIR SOURCE_DIR [--light]"""
import json
import os
import random
import subprocess
import sys
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import testkit  # noqa: E402

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
LIGHT = "--light" in sys.argv[3:]
CLI = os.path.join(BIN, "impactcert")
LAW = os.path.join(SRC, "proofs", "newton4", "law.json")
failures = []
fail = failures.append
R = F(1e-12)


def run(args, stdin=None):
    return subprocess.run([CLI] + args, capture_output=True, text=True, cwd=SRC, input=stdin)


def outside(x_hex, y_hex):
    x = [F.from_float(float.fromhex(t)) for t in x_hex]
    y = [F.from_float(float.fromhex(t)) for t in y_hex]
    d = [a - b for a, b in zip(y, testkit.newton4_exact(x))]
    return testkit.newton4_h_norm2(d) > R * R * testkit.newton4_h_norm2(x)


def mutants(extra):
    # --light (the sanitizer run): the first 80 mutants, taken one operator after another
    r = run(["fuzz", "--law", LAW, "--mutants", "80" if LIGHT else "400", "--max-rel-error", "1e-12", "--json"] + extra)
    try:
        return r, json.loads(r.stdout)
    except json.JSONDecodeError:
        fail(f"--mutants {extra}: not JSON (exit {r.returncode})\n{r.stdout[:400]}{r.stderr}")
        return r, None


def check_witness(m, label):
    w = m["witness"]
    if not outside(w["input"], w["output"]):
        fail(f"{label} {m['id']}: witness {w['input']} -> {w['output']} is within the tolerance of the exact law")
    rr = testkit.run_replay(w["replay"], CLI)
    if rr.returncode != 1:
        fail(f"{label} {m['id']}: replay exit {rr.returncode}\n{w['replay']}\n{rr.stdout}{rr.stderr}")
    rc = run(["eval", "--float", "--law", LAW, "--mutant", "none", "--max-rel-error", "1e-12", "--"] + w["input"])
    if rc.returncode != 0:
        fail(f"{label} {m['id']}: the control is off at the witness too (exit {rc.returncode})\n{rc.stdout}")


samples = "1000" if LIGHT else "20000"
r, j = mutants(["--allow", "extreme", "--samples", samples])
if j is not None:
    if r.returncode != 0 or j["verdict"] != "measured" or j["control"]["violations"]:
        fail(f"CI line: exit {r.returncode}, verdict {j['verdict']}, control {j['control']}")
    c = j["counts"]
    if c["killed"] < 40 or c["survived_with_witness"] != 0 or c["unconfirmed"] != 0 or j["kill_rate"] != 1:
        fail(f"CI line: counts {c}, kill rate {j['kill_rate']}")
    ops = {m["id"].split(":")[0] for m in j["mutants"] if m["result"] == "killed"}
    for op in ["dead-zone", "slow-contact", "facet-flip", "facet-drop", "sign", "formula", "separating", "float32"]:
        if op not in ops:
            fail(f"CI line: no {op} mutant killed ({sorted(ops)})")
    killed = [m for m in j["mutants"] if m["result"] == "killed"]
    for m in killed[: 12 if LIGHT else len(killed)]:
        check_witness(m, "CI line")
    # Equivalent: the program's doubles are the control's.
    rng = random.Random(7)
    def comp():
        k = rng.randint(0, 5)
        if k == 0:
            return rng.choice([0.0, -0.0, 5e-324, -5e-324, 2.0 ** -1070, 1.7e308, -1.7e308])
        return rng.choice([-1, 1]) * rng.random() * 10 ** rng.randint(-300, 300)
    pts = "\n".join(" ".join(float.hex(comp()) for _ in range(3)) for _ in range(300)) + "\n"
    base = run(["eval", "--float", "--law", LAW, "--mutant", "none"], pts)
    ctrl = [ln for ln in base.stdout.splitlines() if ln.startswith("impl ")]
    equivalent = [m for m in j["mutants"] if m["result"] == "equivalent"]
    if not equivalent:
        fail("no equivalent mutant recognised (the 4-ball law's Q have zero entries)")
    for m in equivalent[: 5 if LIGHT else len(equivalent)]:
        why = {"sign": "the entry is 0", "constant-digits": "already has at most 6 significant digits"}
        if "samples" in m or why.get(m["id"].split(":")[0], "?") not in m["why"]:
            fail(f"equivalent {m}")
        e = run(["eval", "--float", "--law", LAW, "--mutant", m["id"]], pts)
        got = [ln.replace("-0x0p+0", "0x0p+0") for ln in e.stdout.splitlines() if ln.startswith("impl ")]
        if got != [ln.replace("-0x0p+0", "0x0p+0") for ln in ctrl] or len(got) != 300:
            fail(f"equivalent mutant {m['id']} gives other doubles than the control")

# A narrow range: the thresholds below it survive, with witnesses there.
r, j = mutants(["--allow", "extreme", "--range", "1e-3..1e3", "--samples", "1500" if LIGHT else "3000", "--min-kill-rate", "1"])
if j is not None:
    if r.returncode != 1 or j["verdict"] != "failed":
        fail(f"--range 1e-3..1e3 --min-kill-rate 1: exit {r.returncode}, verdict {j['verdict']}")
    surv = {m["id"]: m for m in j["mutants"] if m["result"] == "survived"}
    for mid in ["dead-zone:1e-06", "dead-zone:0.001", "slow-contact:1e-09"]:
        if mid not in surv:
            fail(f"--range 1e-3..1e3: {mid} not a survivor with a witness ({sorted(surv)})")
        else:
            check_witness(surv[mid], "--range 1e-3..1e3")
    if j["kill_rate"] >= 1 or j["counts"]["killed"] < 30:
        fail(f"--range 1e-3..1e3: kill rate {j['kill_rate']}, counts {j['counts']}")
    # The text report of the same run (the Release build's only: under the sanitizers the run above
    # covers the same code but the report, and the run is the longest of this script).
    t = None if LIGHT else run(["fuzz", "--law", LAW, "--mutants", "400", "--max-rel-error", "1e-12", "--allow",
                                "extreme", "--range", "1e-3..1e3", "--samples", "3000"])
    if t is not None and (t.returncode != 0 or "kill rate      " not in t.stdout or
                          "  survivor       dead-zone:1e-06: contact velocities of magnitude below 1e-06" not in t.stdout):
        fail(f"text report: exit {t.returncode}\n{t.stdout[-3000:]}")

# A replay judges the run's tolerance (issue 40, item 8: law-mode replays dropped --max-rel-error
# and judged at 0 ulp): one ulp off, within 1e-12, exits 0 with it and 1 without it.
sorted_cmd = "python3 " + os.path.join(SRC, "tests", "impls", "newton4_impl.py") + " sorted"
pt = ["0.1", "-0.7", "0.3"]
for tol, want in [(["--max-rel-error", "1e-12"], 0), ([], 1), (["--max-rel-error", "0"], 1)]:
    e = run(["eval", "--float", "--law", LAW, "--impl-cmd", sorted_cmd] + tol + ["--"] + pt)
    if e.returncode != want or "error 0, 1, 0 ulp" not in e.stdout:
        fail(f"replay {tol}: exit {e.returncode}, expected {want}\n{e.stdout}{e.stderr}")
r = run(["fuzz", "--law", LAW, "--impl-cmd", "python3 " + os.path.join(SRC, "tests", "impls", "newton4_impl.py") +
         " threshold", "--max-rel-error", "1e-12", "--allow", "extreme", "--samples", "400", "--json"])
try:
    ex = [x for x in json.loads(r.stdout)["examples"] if not x["extreme"]]
    if not ex or " --max-rel-error 1e-12 " not in ex[0]["replay"] or testkit.run_replay(ex[0]["replay"], CLI).returncode != 1:
        fail(f"a law-mode replay without the run's tolerance, or not exiting 1: {ex[:1]}")
except (json.JSONDecodeError, KeyError) as err:
    fail(f"threshold solver --json: {err}\n{r.stdout[:300]}")

# A gate that fails the control runs no mutant and exits 1 (plain sums are not correctly rounded).
c = run(["fuzz", "--law", LAW, "--mutants", "30", "--max-ulps", "0", "--samples", "2000"])
if c.returncode != 1 or "no mutant was run" not in c.stdout or "  mutants        none run" not in c.stdout:
    fail(f"--max-ulps 0: exit {c.returncode}\n{c.stdout}")
# A mutant's ID names its parameter exactly (the replay runs the same mutant).
c = run(["fuzz", "--law", LAW, "--mutant", "dead-zone:0.0012345678", "--max-rel-error", "1e-12", "--allow", "extreme",
         "--samples", "2000"])
if c.returncode != 1 or "--mutant dead-zone:0.0012345678 --" not in c.stdout:
    fail(f"--mutant dead-zone:0.0012345678: exit {c.returncode}, the replay names another mutant\n{c.stdout[-1500:]}")

# Bad input: one line, exit 2.
bad = [
    (["fuzz", "--law", LAW, "--mutants", "5", "--max-rel-error", "1e-12", "--impl-cmd", "cat"], "--mutants"),
    (["fuzz", "--law", LAW, "--mutants", "5"], "tolerance"),
    (["fuzz", "--masses", "1,1,1", "--mutants", "5", "--impl-cmd", "cat"], "law mode only"),
    (["fuzz", "--law", LAW, "--mutant", "bogus", "--max-rel-error", "1e-12"], "unknown operator"),
    (["fuzz", "--law", LAW, "--mutant", "sign:24:0:0", "--max-rel-error", "1e-12"], "out of range"),
    (["fuzz", "--law", LAW, "--mutant", "facet-drop:23:0", "--max-rel-error", "1e-12"], "else branch"),
    (["fuzz", "--law", LAW, "--mutant", "dead-zone:-1", "--max-rel-error", "1e-12"], "> 0"),
    (["fuzz", "--law", LAW, "--mutants", "5", "--max-rel-error", "1e-12", "--min-kill-rate", "1.5"], "0..1"),
    (["fuzz", "--law", LAW, "--max-rel-error", "1e-12", "--min-kill-rate", "0.5"], "with --mutants only"),
    (["eval", "--law", LAW, "--mutant", "none", "1", "0", "0"], "need --float"),
    (["fuzz", "--law", LAW, "--mutant", "", "--max-rel-error", "1e-12"], "empty"),
    (["eval", "--float", "--law", LAW, "--mutant", "", "1", "0", "0"], "empty"),
    (["fuzz", "--law", LAW, "--mutant", "dead-zone: 1", "--max-rel-error", "1e-12"], "> 0"),
]
for args, words in bad:
    b = run(args)
    lines = b.stderr.strip().splitlines()
    if b.returncode != 2 or len(lines) != 1 or words not in b.stderr:
        fail(f"{' '.join(args[1:])}: exit {b.returncode}, stderr {b.stderr!r} (expected one line with {words!r})")

testkit.finish(failures)
