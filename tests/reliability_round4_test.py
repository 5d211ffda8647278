#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reliability round four (issue 33), items 7, 9 and 10e, as a user meets them:
  - 9: derive holds its regions and pieces within --max-memory: the 7-ball cradle at e = 9/10
    ends undecided (exit 3, one line naming --max-memory) in bounded time and memory; a law that
    fits is the same law whatever the budget; sweep's --max-memory bounds each derivation too.
  - 7: a sweep part whose verdict is any string (its hash recomputed, as anyone can) is refused
    naming the place; sweep's outputs and parts are whole or absent: a run killed in the middle
    of writing them (SIGXFSZ from `ulimit -f`, which is certain to strike mid-write) leaves the
    previous file or none.
Usage: reliability_round4_test.py BINDIR [--sanitized]
(--sanitized: the ASan build, whose shadow memory and quarantine add about a gigabyte to a
process's resident size; the bound on the 7-ball run is raised accordingly.)"""
import hashlib
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time

BIN = sys.argv[1]
SANITIZED = "--sanitized" in sys.argv[2:]
CLI = os.path.join(BIN, "impactcert")
tmp = tempfile.mkdtemp(prefix="impactcert-round4-")
failures = []


def fail(msg):
    failures.append(msg)
    print("FAIL:", msg)


def run(args, **kw):
    return subprocess.run([CLI] + args, capture_output=True, text=True, **kw)


def one_line(p, label):
    lines = p.stderr.strip().splitlines()
    if len(lines) != 1:
        fail(f"{label}: expected one line on stderr, got {len(lines)}: {p.stderr[:300]!r}")
    return lines[0] if lines else ""


try:
    # ---- 9: derive --max-memory
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    t0 = time.time()
    # (Under the sanitizers 8 MB: the same stop, a quarter of the time.)
    budget = "8" if SANITIZED else "32"
    p = run(["derive", "sequential", "--masses", "1,1,1,1,1,1,1", "--restitution", "9/10", "--max-memory", budget,
             "-o", os.path.join(tmp, "d7.json")], timeout=600)
    elapsed = time.time() - t0
    peak_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    line = one_line(p, "7 balls")
    if p.returncode != 3 or "--max-memory" not in line or "undecided" not in line:
        fail(f"7 balls at --max-memory {budget}: exit {p.returncode}: {line}")
    elif os.path.exists(os.path.join(tmp, "d7.json")):
        fail("7 balls: a law file was written although the derivation stopped")
    else:
        print(f"7 balls, --max-memory {budget}: exit 3 after {elapsed:.1f} s: {line}")
    bound_mb = 1600 if SANITIZED else 300
    if peak_kb > max(before, bound_mb * 1024):
        fail(f"7 balls at --max-memory {budget}: the process grew to {peak_kb // 1024} MB (bound {bound_mb} MB)")
    # A law that fits is the same law with any budget that holds it; one below it is undecided.
    laws = {}
    for mb in ("3", "2048"):
        out = os.path.join(tmp, f"d5-{mb}.json")
        p = run(["derive", "sequential", "--masses", "1,1,1,1,1", "--restitution", "9/10", "--max-memory", mb, "-o", out])
        laws[mb] = (p.returncode, open(out).read() if os.path.exists(out) else None, p.stderr.strip())
    if laws["2048"][0] != 0 or laws["2048"][1] is None:
        fail(f"5 balls at 2048 MB: {laws['2048']}")
    if laws["3"][0] != 3 or "--max-memory" not in laws["3"][2] or laws["3"][1] is not None:
        fail(f"5 balls at 3 MB: expected undecided naming --max-memory, got {laws['3'][0]}: {laws['3'][2]}")
    p = run(["derive", "sequential", "--masses", "1,1,1,1,1", "--restitution", "9/10", "--max-memory", "100",
             "-o", os.path.join(tmp, "d5-100.json")])
    if p.returncode != 0 or open(os.path.join(tmp, "d5-100.json")).read() != laws["2048"][1]:
        fail("5 balls: the law at 100 MB differs from the law at 2048 MB")
    for kind in ("newton", "poisson"):
        p = run(["derive", kind, "--masses", "1,1,1,1", "--max-memory", "0"])
        if p.returncode != 3 or "--max-memory" not in p.stderr:
            fail(f"derive {kind} --max-memory 0: exit {p.returncode}: {p.stderr.strip()}")
    # sweep: the budget reaches each derivation (undecided points, not a crash or a stall).
    sw = os.path.join(tmp, "sweep-mem")
    p = run(["sweep", "--masses", "1,m,1,1,1", "--restitution", "9/10", "--vary", "m=1/2..2:2", "--jobs", "1",
             "--max-memory", "1", "-o", sw])
    rows = open(os.path.join(sw, "sweep.csv")).read().splitlines()[1:] if p.returncode == 0 else []
    if p.returncode != 0 or len(rows) != 2 or not all(r.endswith(",undecided") for r in rows):
        fail(f"sweep --max-memory 1: exit {p.returncode}, rows {rows}: {p.stderr.strip()}")

    # ---- 7: a sweep part's verdict must be a verdict
    parts = []
    for k in (1, 2):
        d = os.path.join(tmp, f"s{k}")
        p = run(["sweep", "--masses", "1,m,1", "--restitution", "1/2", "--vary", "m=1/2..2:3", "--jobs", "1",
                 "--shard", f"{k}/2", "-o", d])
        if p.returncode != 0:
            fail(f"sweep --shard {k}/2: exit {p.returncode}: {p.stderr.strip()}")
        parts.append(os.path.join(d, f"sweep.part-{k}-of-2.json"))
    merged = os.path.join(tmp, "merged")
    p = run(["sweep", "--merge"] + parts + ["-o", merged])
    if p.returncode != 0:
        fail(f"sweep --merge of good parts: exit {p.returncode}: {p.stderr.strip()}")
    for forged_verdict in ("proved\nm,evil", "certainly", ""):
        doc = json.load(open(parts[0]))
        doc["points"][0]["obligations"]["P1"]["verdict"] = forged_verdict
        del doc["sha256"]
        # The digest as the part defines it: SHA-256 of the compact text without "sha256", keys
        # in the order written.
        doc["sha256"] = hashlib.sha256(json.dumps(doc, separators=(",", ":"), ensure_ascii=False).encode()).hexdigest()
        forged = os.path.join(tmp, "forged.json")
        with open(forged, "w") as f:
            json.dump(doc, f)
        out = os.path.join(tmp, "merged-forged")
        p = run(["sweep", "--merge", forged, parts[1], "-o", out])
        line = one_line(p, f"forged verdict {forged_verdict!r}")
        if p.returncode != 2 or "P1.verdict" not in line:
            fail(f"a part with the verdict {forged_verdict!r} (hash recomputed): exit {p.returncode}: {line}")
        elif os.path.exists(os.path.join(out, "sweep.csv")):
            fail("a refused merge wrote sweep.csv")
    if not failures:
        print("sweep parts: verdicts other than proved/refuted/undecided/skipped are refused")

    # ---- 7 and 10e: killed in the middle of writing (SIGXFSZ): whole or absent
    def killed_mid_write(args, path, label):
        # (sweep writes sweep.csv, then sweep.json, then sweep.html: sweep.csv is under 2 KiB and
        # written whole; the run dies writing sweep.json.)
        with open(path, "w") as f:
            f.write("previous\n")
        script = 'ulimit -f 2; exec "$@"'  # 2 KiB: every output below is larger
        p = subprocess.run(["bash", "-c", script, "bash", CLI] + args, capture_output=True, text=True)
        if p.returncode != -25 and p.returncode != 128 + 25:
            fail(f"{label}: expected death by SIGXFSZ mid-write, got exit {p.returncode}: {p.stderr.strip()[:200]}")
            return
        left = open(path).read()
        if left != "previous\n":
            fail(f"{label}: a run killed mid-write left {len(left)} bytes in {os.path.basename(path)}, not the previous file")
            return
        leftovers = [n for n in os.listdir(os.path.dirname(path)) if ".partial-" in n]
        if leftovers:
            # A temporary file killed mid-write stays (no handler runs); it is never the output.
            for n in leftovers:
                os.unlink(os.path.join(os.path.dirname(path), n))
        print(f"{label}: killed mid-write (SIGXFSZ), the previous file is intact")

    d = os.path.join(tmp, "kill-sweep")
    os.makedirs(d)
    killed_mid_write(["sweep", "--masses", "1,m,1", "--restitution", "1/2", "--vary", "m=1/2..2:9", "--jobs", "1",
                      "-o", d], os.path.join(d, "sweep.json"), "sweep")
    d = os.path.join(tmp, "kill-part")
    os.makedirs(d)
    killed_mid_write(["sweep", "--masses", "1,m,1", "--restitution", "1/2", "--vary", "m=1/2..2:9", "--jobs", "1",
                      "--shard", "1/2", "-o", d], os.path.join(d, "sweep.part-1-of-2.json"), "sweep --shard")
    d = os.path.join(tmp, "kill-certify")
    os.makedirs(d)
    killed_mid_write(["certify", "-o", os.path.join(d, "cert.json")], os.path.join(d, "cert.json"), "certify")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
print("ok" if not failures else f"{len(failures)} failure(s)")
sys.exit(1 if failures else 0)
