#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""3 equal balls, u+ = sorted(u-) (exact), except for the first input with a moving ball that the
process receives, and that input whenever it comes again: it is answered with one number too many
(mode `extra`) or with a NUL byte inside the line (mode `nul`: "a b c\\0 99 garbage").
Usage: one_bad_answer.py extra|nul"""
import sys

mode = sys.argv[1]
bad = None
out = sys.stdout.buffer
for line in sys.stdin:
    u = [float.fromhex(t) if "0x" in t.lower() else float(t) for t in line.split()]
    if bad is None and any(x != 0 for x in u):
        bad = line
    text = " ".join(repr(x) for x in sorted(u))
    if line == bad:
        text = text + " 1" if mode == "extra" else text + "\0 99 garbage"
    out.write(text.encode() + b"\n")
    out.flush()
