#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Impact maps of a 3-ball cradle (equal masses, ball velocities) for the consistency fuzzer's tests.

Protocol of `impactcert fuzz --impl-cmd`: one line of doubles in (hex or decimal), one line out.
Modes:
  sort    u+ = sorted(u-): the exact elastic law of equal masses (sorting doubles is exact)
  damped  u+ = 0.9 sorted(u-): momentum is lost (a change outside the range of M^-1 W)
  stuck   u+ = u-: approaching balls pass through each other (negative contact velocity)
  pull    u+ = 2 u- - sorted(u-): the impulses reversed (contacts pull)
  restless  sort, but balls at rest are answered with the first one moving (energy from nothing)
  chatty  sort, and a warning on stderr for every line answered (an engine that logs each step)
  jitter  sort, but the last ball's velocity drifts by 2^-40 per line answered (an engine whose
          answer depends on what it computed before: the same input is answered differently)
"""
import sys


def parse(token):
    return float.fromhex(token) if "0x" in token.lower() else float(token)


def main():
    mode = sys.argv[1]
    answered = 0
    for line in sys.stdin:
        u = [parse(t) for t in line.split()]
        s = sorted(u)
        if mode == "sort":
            out = s
        elif mode == "damped":
            out = [0.9 * x for x in s]
        elif mode == "stuck":
            out = u
        elif mode == "restless":
            out = s if any(x != 0 for x in u) else [1.0 / 1024] + [0.0] * (len(u) - 1)
        elif mode == "chatty":
            out = s
            sys.stderr.write(f"warning: step {answered} clamped\n")
        elif mode == "jitter":
            out = s[:-1] + [s[-1] + answered * 2.0 ** -40]
        elif mode == "pull":
            out = [2 * a - b for a, b in zip(u, s)]
        else:
            sys.exit("unknown mode " + mode)
        answered += 1
        sys.stdout.write(" ".join("%.17g" % x for x in out) + "\n")
        sys.stdout.flush()


main()
