#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""misbehaving_impl.py MODE -- --impl-cmd programs that fail the protocol, for the tests:
crash (exits on an input with a negative first component), hang (stops answering there),
short (answers that input with too few numbers), extra (answers it twice), trickle (writes
spaces without ever ending a line); otherwise it answers with the input."""
import os
import sys
import time

mode = sys.argv[1]
if mode == "trickle":
    sys.stdin.readline()
    while True:
        sys.stdout.write(" ")
        sys.stdout.flush()
        time.sleep(0.1)
for line in sys.stdin:
    g = [float.fromhex(t) for t in line.split()]
    if g[0] < 0:
        if mode == "crash":
            os._exit(3)
        if mode == "hang":
            time.sleep(3600)
        if mode == "short":
            sys.stdout.write(g[0].hex() + "\n")
            sys.stdout.flush()
            continue
        if mode == "extra":
            sys.stdout.write(" ".join(x.hex() for x in g) + "\n")
    sys.stdout.write(" ".join(x.hex() for x in g) + "\n")
    sys.stdout.flush()
