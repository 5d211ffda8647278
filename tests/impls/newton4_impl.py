#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""newton4_impl.py -- the 4-ball cradle law (proofs/newton4/law.json) in Python, for
`impactcert fuzz --law proofs/newton4/law.json --impl-cmd 'python3 newton4_impl.py MODE'`.

Protocol: each input line holds the 3 contact velocities gamma- as hex doubles (float.hex
format); the answer is one line with gamma+ (any format float() or float.fromhex() reads back
exactly; float.hex is exact). Flush after each line, or at least before waiting for input.

MODE sorted     correct, not correctly rounded (ball velocities by summation, sorted)
MODE plain      correct in the physical range, as a plain solver is: pairwise exchanges while a
                contact approaches, no rescaling (its sums overflow beyond about 1e308)
MODE tolerance  WRONG: exchanges only when a contact approaches faster than 1e-9
MODE threshold  WRONG: the plain solver with an absolute threshold, a contact approaches only if
                gamma < -1e-6 (the newcomer's bug of docs/fuzzing.md)
"""
import sys


def plain(g, threshold):
    u = [0.0, g[0], g[0] + g[1], g[0] + g[1] + g[2]]
    for _ in range(4):
        for k in range(3):
            if u[k + 1] - u[k] < -threshold:
                u[k], u[k + 1] = u[k + 1], u[k]
    return [u[1] - u[0], u[2] - u[1], u[3] - u[2]]


def law(g, mode):
    if mode in ("plain", "threshold"):
        return plain(g, 0.0 if mode == "plain" else 1e-6)
    scale = 0.25 if max(abs(x) for x in g) > 2.0**1020 else 1.0  # keep the sums finite (exact)
    g = [x * scale for x in g]
    u = [0.0, g[0], g[0] + g[1], g[0] + g[1] + g[2]]
    if mode == "sorted":
        u.sort()
    elif mode == "tolerance":
        for _ in range(3):
            for k in range(3):
                if u[k + 1] - u[k] < -1e-9:
                    u[k], u[k + 1] = u[k + 1], u[k]
    else:
        raise SystemExit("unknown mode " + mode)
    return [(u[1] - u[0]) / scale, (u[2] - u[1]) / scale, (u[3] - u[2]) / scale]


def main():
    mode = sys.argv[1] if len(sys.argv) > 1 else "sorted"
    out = sys.stdout
    for line in sys.stdin:
        g = [float.fromhex(t) for t in line.split()]
        out.write(" ".join(x.hex() for x in law(g, mode)) + "\n")
        out.flush()


if __name__ == "__main__":
    main()
