#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""newton_cradle.py -- the impact law of box2d_cradle.cpp without an engine, for
`impactcert fuzz --velocities --impl-cmd 'python3 examples/engines/newton_cradle.py'`.

What it computes: a chain of n equal balls; contact k (balls k, k+1) approaches when
u[k+1] - u[k] < 0. Sequential impulses (projected Gauss-Seidel, K sweeps right to left, in
double) solve: u+[k+1] - u+[k] >= -E (u[k+1] - u[k]) at approaching contacts, >= 0 at the others,
impulses >= 0 and zero where the inequality is strict. That is the simultaneous Newton law with
restitution applied only to approaching contacts, as Box2D's contact solver computes it (there
in float): 1 0 0 -> -1/3 2/3 2/3, and 0 1 -1 -> -2/3 -2/3 4/3 with E = 1.

Protocol: each stdin line holds n numbers (C99 hex floats such as 0x1.8p-3, or decimals: what
strtod reads, finite); the answer is one line of n numbers printed with %.17g, flushed. A
malformed line is fatal: one line on stderr, exit 2. End of input: exit 0.

Usage: newton_cradle.py [--balls N] [--restitution E] [--iterations K]
"""
import re
import sys

DECIMAL = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?\Z")
HEX = re.compile(r"[+-]?0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)([pP][+-]?[0-9]+)?\Z")


def fail(message):
    sys.stderr.write("newton_cradle.py: " + message + "\n")
    sys.exit(2)


def number(text):
    """A finite number in strtod's syntax (float() alone would accept '1_0'), else None."""
    try:
        if DECIMAL.match(text):
            x = float(text)
        elif HEX.match(text):
            x = float.fromhex(text)
        else:
            return None
    except (ValueError, OverflowError):
        return None
    return x if abs(x) < float("inf") else None


def impact(u, e, iterations):
    # The law is positively homogeneous: scale huge inputs down (by a power of 2) so that the
    # differences stay finite.
    scale = 2.0**-4 if max(abs(x) for x in u) > 2.0**1019 else 1.0
    v = [x * scale for x in u]
    n = len(v)
    bias = [max(0.0, -e * (v[k + 1] - v[k])) for k in range(n - 1)]  # approaching only
    impulse = [0.0] * (n - 1)
    for _ in range(iterations):
        for k in reversed(range(n - 1)):  # Box2D's order (newest contact first)
            # effective mass of contact k: 1 / (1/m + 1/m) = 1/2 (equal masses m = 1)
            step = -0.5 * ((v[k + 1] - v[k]) - bias[k])
            new = max(impulse[k] + step, 0.0)
            delta = new - impulse[k]
            impulse[k] = new
            v[k] -= delta
            v[k + 1] += delta
    return [x / scale for x in v]


def main():
    balls, e, iterations = 3, 1.0, 200
    args = sys.argv[1:]
    usage = "usage: newton_cradle.py [--balls N] [--restitution E] [--iterations K]"
    if len(args) % 2:
        fail(usage)
    for flag, value in zip(args[::2], args[1::2]):
        x = number(value)
        if flag == "--balls" and x is not None and x == int(x) and 2 <= x <= 10000:
            balls = int(x)
        elif flag == "--restitution" and x is not None and 0 <= x <= 1:
            e = x
        elif flag == "--iterations" and x is not None and x == int(x) and 1 <= x <= 1e6:
            iterations = int(x)
        else:
            fail("bad option %s %s (%s)" % (flag, value, usage))
    out = sys.stdout
    for lineno, line in enumerate(sys.stdin, 1):
        u = [number(t) for t in line.split()]
        if len(u) != balls or None in u:
            fail("line %d: expected %d finite numbers: %r" % (lineno, balls, line.rstrip("\n")))
        out.write(" ".join("%.17g" % x for x in impact(u, e, iterations)) + "\n")
        out.flush()


if __name__ == "__main__":
    main()
