#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The streamed derivation against the in-memory one, in one run (scripts/bench): the 6-ball
chain at e = 9/10 both ways, the 7-ball chain streamed (the in-memory one needs more memory than
the machine has: it was stopped by --max-memory, then ran out of memory at 15.5 GB). Wall time,
peak resident memory (GNU time) and pieces.

Usage: derive_bench.py IMPACTCERT [--quick]   (--quick: 5 and 6 balls only)"""

import os
import re
import subprocess
import sys
import tempfile

cli = sys.argv[1]
quick = "--quick" in sys.argv[2:]
rows = []
with tempfile.TemporaryDirectory() as tmp:
    runs = [(5, False), (5, True), (6, False), (6, True)] + ([] if quick else [(7, True)])
    for balls, stream in runs:
        out = os.path.join(tmp, f"law-{balls}.json")
        args = [cli, "derive", "sequential", "--masses", ",".join(["1"] * balls), "--restitution", "9/10",
                "--max-memory", "16384", "-o", out] + (["--stream"] if stream else [])
        r = subprocess.run(["/usr/bin/time", "-f", "TIME %e %M"] + args, capture_output=True, text=True)
        time_line = re.search(r"TIME ([0-9.]+) ([0-9]+)", r.stderr)
        pieces = re.search(r"\(([0-9]+) pieces, ([0-9]+) regions", r.stderr)
        size = os.path.getsize(out) if os.path.exists(out) else 0
        rows.append((balls, "streamed" if stream else "in memory", r.returncode,
                     float(time_line.group(1)) if time_line else 0, int(time_line.group(2)) // 1024 if time_line else 0,
                     pieces.group(1) if pieces else "-", pieces.group(2) if pieces else "-", size >> 20))
        if os.path.exists(out):
            os.remove(out)
print("derive sequential, chains at e = 9/10 (this run)")
print(f"  {'balls':>5}  {'how':<10}{'exit':>5}{'time s':>10}{'peak MB':>9}{'pieces':>10}{'regions':>10}{'file MB':>9}")
for balls, how, rc, secs, mb, pieces, regions, size in rows:
    print(f"  {balls:>5}  {how:<10}{rc:>5}{secs:>10.1f}{mb:>9}{pieces:>10}{regions:>10}{size:>9}")
