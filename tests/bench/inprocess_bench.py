#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""In-process fuzzing against the --impl-cmd protocol, the same implementation both ways, in one
run (scripts/bench): Box2D's cradle (examples/engines/box2d_inprocess.cpp against box2d_cradle
through the pipe), and Python callables (the library's module against the same Python code as an
--impl-cmd script). Samples per second of checked samples, one job each.

Usage: inprocess_bench.py BUILD_DIR [SAMPLES]   (PYTHONPATH must reach BUILD_DIR/python)"""

import json
import os
import subprocess
import sys
import tempfile

import numpy as np

import impactcert as ic

BUILD = os.path.abspath(sys.argv[1])
N = int(sys.argv[2]) if len(sys.argv) > 2 else 20000
CLI = os.path.join(BUILD, "impactcert")
rows = []


def cli_rate(*args):
    r = subprocess.run([CLI, "fuzz", "--json", "--jobs", "1", "--samples", str(N), *args], capture_output=True, text=True)
    return json.loads(r.stdout)["samples_per_second"]


def row(name, inproc, pipe):
    rows.append((name, inproc, pipe))


inproc = os.path.join(BUILD, "examples", "engines", "box2d_inprocess")
cradle = os.path.join(BUILD, "examples", "engines", "box2d_cradle")
if os.path.exists(inproc):
    r = subprocess.run([inproc, "--json", "--samples", str(N)], capture_output=True, text=True)
    row("Box2D cradle, consistency (C++)", json.loads(r.stdout)["samples_per_second"],
        cli_rate("--masses", "1,1,1", "--velocities", "--max-rel-error", "1e-5", "--range", "1e-3..60",
                 "--impl-cmd", cradle))

with tempfile.TemporaryDirectory() as tmp:
    swap = os.path.join(tmp, "swap.py")
    with open(swap, "w") as f:
        f.write("import sys\nfor line in sys.stdin:\n    a, b = line.split()\n    print(b, a, flush=True)\n")
    r = ic.fuzz(ic.Law.paper(), lambda p: p[:, ::-1].copy(), samples=N, max_rel_error=1e-12)
    row("Python callable, law mode (swap)", r.report["samples_per_second"],
        cli_rate("--max-rel-error", "1e-12", "--impl-cmd", f"{sys.executable} {swap}"))
    echo = os.path.join(tmp, "echo.py")
    with open(echo, "w") as f:
        f.write("import sys\nfor line in sys.stdin:\n    sys.stdout.write(line)\n    sys.stdout.flush()\n")
    r = ic.fuzz_consistency(ic.System.chain([1, 1, 1]), lambda p: p.copy(), samples=N, velocities=True)
    row("Python callable, consistency (identity)", r.report["samples_per_second"],
        cli_rate("--masses", "1,1,1", "--velocities", "--impl-cmd", f"{sys.executable} {echo}"))

print(f"in-process fuzzing against --impl-cmd, {N} samples each, one job (samples/s, this run)")
print(f"  {'implementation':<42}{'in-process':>12}{'--impl-cmd':>12}{'ratio':>8}")
for name, a, b in rows:
    print(f"  {name:<42}{a:>12.0f}{b:>12.0f}{a / b:>8.1f}")
