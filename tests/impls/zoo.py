#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""zoo.py -- a corpus of planted bugs (issue 44) in a plain solver of the 4-ball cradle of equal
masses (proofs/newton4/law.json: the exact law sorts the ball velocities), written as engines
write it: pairwise exchanges of approaching neighbours, sweep after sweep. tests/impls/zoo.c has
the same catalogue in C; tests/corpus_test.py runs the documented CI lines against every one.

  python3 zoo.py BUG               contact velocities gamma- in, gamma+ out (law mode)
  python3 zoo.py --velocities BUG  ball velocities u- in, u+ out (consistency mode)

One line of hex doubles in, one line out, flushed. BUG is `correct` (no bug) or one of BUGS.
"""
import math
import struct
import sys

BUGS = {
    "threshold": "exchanges only when a contact approaches faster than 1e-6 (a velocity threshold)",
    "reltol": "exchanges only when gamma < -1e-9 max|u| (a relative tolerance)",
    "one-sweep": "a single sweep (multiple collisions need three)",
    "two-sweeps": "two sweeps",
    "plastic": "approaching neighbours leave with their mean velocity (restitution 0)",
    "restitution": "restitution 0.9 instead of 1",
    "last-contact": "the loop over contacts stops one short: the last contact is never treated",
    "reversed": "the answer in the wrong order (descending velocities)",
    "separating": "in the last sweep the first contact exchanges even when it separates",
    "float32": "every operation in single precision",
    "leak": "an exchange keeps 1 - 1e-4 of one velocity",
    "stale": "every sweep tests the contacts of the input, not of the current velocities",
    "mass": "the last ball's mass typed as 1.001",
    "early-exit": "stops as soon as the first contact needs no exchange",
}
FLT_MAX = struct.unpack("f", bytes.fromhex("ffff7f7f"))[0]


def f32(x):
    if math.isnan(x) or math.isinf(x):
        return x
    if abs(x) >= FLT_MAX * (1 + 2.0 ** -25):
        return math.copysign(math.inf, x)
    return struct.unpack("f", struct.pack("f", x))[0]


def solve(u, bug):
    u = list(u)
    if bug == "float32":
        u = [f32(x) for x in u]
    masses = [1.0, 1.0, 1.0, 1.001 if bug == "mass" else 1.0]
    initial = list(u)
    sweeps = {"one-sweep": 1, "two-sweeps": 2}.get(bug, 4)
    last = 2 if bug == "last-contact" else 3
    big = max(abs(x) for x in u)
    for sweep in range(sweeps):
        for k in range(last):
            gamma = (initial[k + 1] - initial[k]) if bug == "stale" else (u[k + 1] - u[k])
            if bug == "float32":
                gamma = f32(gamma)
            limit = {"threshold": -1e-6, "reltol": -1e-9 * big}.get(bug, 0.0)
            approaching = gamma < limit
            if bug == "separating" and k == 0 and sweep == sweeps - 1:
                approaching = gamma != 0
            if not approaching:
                if bug == "early-exit" and k == 0:
                    break
                continue
            a, b = u[k], u[k + 1]
            if bug == "plastic":
                u[k] = u[k + 1] = (a + b) / 2
            elif bug == "restitution":
                e = 0.9
                u[k] = (a + b) / 2 - e * (a - b) / 2
                u[k + 1] = (a + b) / 2 + e * (a - b) / 2
            elif bug == "leak":
                u[k], u[k + 1] = b, a * (1 - 1e-4)
            elif bug == "mass":
                m1, m2 = masses[k], masses[k + 1]
                u[k] = ((m1 - m2) * a + 2 * m2 * b) / (m1 + m2)
                u[k + 1] = ((m2 - m1) * b + 2 * m1 * a) / (m1 + m2)
            else:
                u[k], u[k + 1] = b, a
        else:
            continue
        break  # early-exit
    if bug == "reversed":
        u = sorted(u, reverse=True)
    if bug == "float32":
        u = [f32(x) for x in u]
    return u


def main():
    args = sys.argv[1:]
    velocities = "--velocities" in args
    args = [a for a in args if a != "--velocities"]
    bug = args[0] if args else "correct"
    if bug != "correct" and bug not in BUGS:
        sys.exit(f"zoo.py: unknown bug {bug!r}")
    for line in sys.stdin:
        x = [float.fromhex(t) for t in line.split()]
        if velocities:
            out = solve(x, bug)
        else:
            u = [0.0, x[0], x[0] + x[1], x[0] + x[1] + x[2]]
            v = solve(u, bug)
            out = [v[1] - v[0], v[2] - v[1], v[3] - v[2]]
        print(" ".join(float.hex(y) for y in out), flush=True)


if __name__ == "__main__":
    main()
