#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""shove.py -- an impact map whose velocity change is not made of contact impulses, for the
consistency fuzzer's tests (`--masses 1,1,1 --velocities --impl-cmd 'python3 shove.py'`): the
exact law of the equal-mass cradle (a sort of the ball velocities), then the first ball pushed
forwards by a tenth of the largest speed, from nowhere (as an engine that moves bodies between
finding contacts and solving them). Momentum fails; the pulling impulses and negative contact
velocities the fuzzer then reports are projections of that push, which the report must say."""
import sys

for line in sys.stdin:
    u = [float.fromhex(t) for t in line.split()]
    v = sorted(u)
    v[0] += 0.1 * max(abs(x) for x in u)
    print(" ".join(float.hex(x) for x in v), flush=True)
