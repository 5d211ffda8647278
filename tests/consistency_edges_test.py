#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Consistency fuzzing at the edges (reliability round four, items 2 and 3).

2. A correctly rounded consistent answer is never reported, on the whole accepted --range, the
   subnormals included: the exact plastic law (Newton, e = 0) and the Newton law with
   restitution on approaching contacts (e = 1/2) of masses 1, 2, 3, rounded to doubles by the
   independent oracle, fuzzed with pairs over ranges from 1e-320 to 1e150: no violation. A
   negative control: the same law at e = 1/2 on every contact (the classical law, not kinematic)
   is reported at every range.
3. A NaN answered for the second point of a pair is reported: every NaN the implementation
   answers (it logs them) is a non-finite finding.
Usage: consistency_edges_test.py IMPACTCERT SOURCE_DIR
"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import testkit  # noqa: E402
import tempfile

CLI, SRC = sys.argv[1], sys.argv[2]
IMPLS = os.path.join(SRC, "tests", "impls")
failures = []
tmp = tempfile.mkdtemp(prefix="impactcert-edges-")


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


system = os.path.join(tmp, "chain.json")
json.dump({"format": "impactcert-system/1", "name": "chain-1-2-3", "masses": ["1", "2", "3"],
           "contacts": {"W": [["-1", "0"], ["1", "-1"], ["0", "1"]]}}, open(system, "w"))
oracle_impl = os.path.join(IMPLS, "friction_impls.py")
try:
    for rng in ("1e-320..1e-316", "1e-320..1e-300", "1e-300..1e-250", "1e-3..1e3", "1e100..1e150"):
        for e, on, expect_clean in (("0", "all", True), ("1/2", "approaching", True), ("1/2", "all", False)):
            impl = f"python3 {oracle_impl} {system} exact {e}" + (" approaching" if on == "approaching" else "")
            p = subprocess.run([CLI, "fuzz", "--system", system, "--velocities", "--impl-cmd", impl, "--range", rng,
                                "--samples", "300", "--require", "nonexpansive,continuity", "--json"],
                               capture_output=True, text=True)
            try:
                j = json.loads(p.stdout)
            except json.JSONDecodeError:
                fail(f"{rng} e={e} {on}: no JSON (exit {p.returncode}): {p.stderr[:200]}")
                continue
            found = {k: v for k, v in j["violations"].items() if v}
            if expect_clean and (p.returncode != 0 or found):
                fail(f"{rng}, e = {e} on {on}: a correctly rounded consistent law reported: {found}")
            if not expect_clean and not found.get("kinematic"):
                fail(f"{rng}, e = {e} on {on}: the classical law's negative contact velocities not reported ({found})")
        print(f"--range {rng}: the exact laws rounded to doubles raise no alarm; the classical law is reported")

    log = os.path.join(tmp, "nans.log")
    p = subprocess.run([CLI, "fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
                        f"python3 {os.path.join(IMPLS, 'nan_second.py')} {log}", "--samples", "400",
                        "--require", "nonexpansive", "--json"], capture_output=True, text=True)
    j = json.loads(p.stdout)
    nans = sum(1 for _ in open(log)) if os.path.exists(log) else 0
    if nans == 0 or j["violations"]["non_finite"] != nans or p.returncode != 1:
        fail(f"{nans} NaN answers, {j['violations']['non_finite']} reported (exit {p.returncode})")
    else:
        print(f"{nans} NaN answers (first and second points of pairs), all {nans} reported")
    # 5. --samples 2^64 - 1: the block count must not wrap (it gave exit 3 at once, 0 samples,
    # blaming --seconds): the run goes on until --seconds stops it, with samples checked.
    sort_impl = f"python3 {os.path.join(IMPLS, 'cradle_controls.py')} sort"
    p = subprocess.run([CLI, "fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd", sort_impl,
                        "--samples", "18446744073709551615", "--seconds", "8", "--json"], capture_output=True, text=True)
    j = json.loads(p.stdout) if p.stdout.strip().startswith("{") else {}
    if p.returncode != 0 or j.get("samples", 0) == 0:
        fail(f"--samples 2^64 - 1: exit {p.returncode}, {j.get('samples')} samples: {p.stderr.strip()}")
    else:
        print(f"--samples 2^64 - 1 --seconds 8: {j['samples']} samples checked, exit 0")
    # 4. One malformed answer (one number too many, or a NUL inside the line) to the first input of
    # a batch is that input's failure only: the other answers are checked, and a NUL-cut line is
    # never read as numbers.
    for mode in ("extra", "nul"):
        p = subprocess.run([CLI, "fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
                            f"python3 {os.path.join(IMPLS, 'one_bad_answer.py')} {mode}", "--samples", "1000",
                            "--jobs", "2", "--json"], capture_output=True, text=True)
        j = json.loads(p.stdout)
        v = j["violations"]
        others = {k: x for k, x in v.items() if x and k != "malformed"}
        # One bad input per process (two jobs), answered badly each time it comes: the structured
        # inputs meet a few vectors twice (a unit vector is also a small-integer vector), so up to
        # two more.
        if not (1 <= v["malformed"] <= 4) or others or j["samples"] != 1000:
            fail(f"one bad answer ({mode}): malformed {v['malformed']}, others {others}, samples {j['samples']}")
        else:
            print(f"one bad answer ({mode}): {v['malformed']} malformed (one per process), the rest checked")
    # Issue 31, 4: the probe's answer is checked. A map that moves balls at rest is reported as
    # at-rest (its replay names it); the exact sort raises nothing there.
    for mode, expect in (("restless", 1), ("sort", 0)):
        p = subprocess.run([CLI, "fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
                            f"python3 {os.path.join(IMPLS, 'cradle_controls.py')} {mode}", "--samples", "200", "--json"],
                           capture_output=True, text=True)
        j = json.loads(p.stdout)
        if j["violations"]["at-rest"] != expect or p.returncode != expect:
            fail(f"at-rest ({mode}): {j['violations']['at-rest']} findings, exit {p.returncode}")
        elif expect:
            r = testkit.run_replay(j["worst"]["at-rest"]["replay"], CLI)
            if r.returncode != 1 or "(at-rest)" not in r.stdout:
                fail(f"at-rest replay: exit {r.returncode}: {r.stdout[-200:]}")
            else:
                print("at-rest: a map that moves balls at rest is reported, and its replay says so")
    # 7. --shard "" (an unset $SHARD): refused in one line, never the whole run.
    for cmd in (["verify", "--shard", ""], ["certify", "--shard", "", "-o", os.path.join(tmp, "part.json")]):
        p = subprocess.run([CLI] + cmd, capture_output=True, text=True)
        if p.returncode != 2 or "--shard" not in p.stderr or len(p.stderr.strip().splitlines()) != 1:
            fail(f"{cmd}: exit {p.returncode}: {p.stderr.strip()!r}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
if failures:
    print(f"{len(failures)} failure(s)")
    sys.exit(1)
print("ok")
