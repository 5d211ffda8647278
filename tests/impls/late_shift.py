#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""3 equal balls, u+ = sorted(u-), deterministic, but after its tenth answer the process writes one
line too many ("0 0 0"): every later answer is one line out of step. A shift, never
nondeterminism (the adversarial review of issue 31's detection). Usage: late_shift.py"""
import sys

answered = 0
for line in sys.stdin:
    u = sorted(float.fromhex(t) if "x" in t.lower() else float(t) for t in line.split())
    print(" ".join(repr(x) for x in u), flush=True)
    answered += 1
    if answered == 10:
        print("0 0 0", flush=True)
