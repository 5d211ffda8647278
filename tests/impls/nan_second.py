#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""An impact map (3 equal balls in ball velocities: u+ = sorted(u-), exact) that answers NaN
wherever the first component's last mantissa bit is 1, and logs each such answer (one line per
NaN, appended to LOG), so that a test can count the NaN answers the fuzzer must report.
Usage: nan_second.py LOG"""
import math
import sys

log = sys.argv[1]
for line in sys.stdin:
    u = [float.fromhex(t) if "0x" in t.lower() else float(t) for t in line.split()]
    m, _ = math.frexp(u[0])
    odd = u[0] != 0 and int(abs(m) * 2**53) & 1
    if odd:
        with open(log, "a") as f:
            f.write(line)
        out = [float("nan")] + sorted(u)[1:]
    else:
        out = sorted(u)
    sys.stdout.write(" ".join(repr(x) if x == x else "nan" for x in out) + "\n")
    sys.stdout.flush()
