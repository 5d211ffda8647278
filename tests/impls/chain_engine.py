#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""chain_engine.py -- an engine-like sequential-impulse solver of a free chain of balls, in ball
velocities, for the consistency fuzzer's tests (`impactcert fuzz --masses ... --velocities
--impl-cmd 'python3 tests/impls/chain_engine.py MODE'`).

Usage: chain_engine.py MODE [--masses 1,1,1] [--restitution E] [--iterations K]
Each contact k gets a velocity target gamma+_k >= -E gamma-_k where it approaches (computed once,
before the iterations, as Box2D does), and K Gauss-Seidel sweeps of accumulated, clamped impulses;
with K large enough it computes the Newton law with restitution on approaching contacts.

MODE correct    as above
MODE threshold  WRONG model: restitution only where the contact approaches faster than 1 (Box2D's
                velocity threshold, 1 m/s): consistent, but not the law it means to compute
MODE tolerance  WRONG: a contact counts as approaching only if gamma < -1e-6 (no impulse otherwise)
MODE restcrash  correct, but the process ends on the input at rest
"""
import sys


def solve(u, masses, e, iterations, mode):
    n = len(u)
    u = list(u)
    gm = [u[k + 1] - u[k] for k in range(n - 1)]
    threshold = 1.0 if mode == "threshold" else 1e-6 if mode == "tolerance" else 0.0
    target = []
    for g in gm:
        if mode == "tolerance":
            target.append(-e * g if g < -threshold else None)
        else:
            target.append(-e * g if g < -threshold else 0.0)
    acc = [0.0] * (n - 1)
    for _ in range(iterations):
        for k in range(n - 1):
            if target[k] is None:
                continue
            g = u[k + 1] - u[k]
            meff = 1.0 / (1.0 / masses[k] + 1.0 / masses[k + 1])
            dl = (target[k] - g) * meff
            new = max(acc[k] + dl, 0.0)
            dl = new - acc[k]
            acc[k] = new
            u[k] -= dl / masses[k]
            u[k + 1] += dl / masses[k + 1]
    return u


def main():
    args = sys.argv[1:]
    mode = args[0]
    opts = dict(zip(args[1::2], args[2::2]))
    masses = [float(x) for x in opts.get("--masses", "1,1,1").split(",")]
    e = float(opts.get("--restitution", "1"))
    iterations = int(opts.get("--iterations", "200"))
    for line in sys.stdin:
        u = [float.fromhex(t) if "0x" in t.lower() else float(t) for t in line.split()]
        if mode == "restcrash" and all(x == 0 for x in u):
            sys.exit(3)
        out = solve(u, masses, e, iterations, mode)
        sys.stdout.write(" ".join(x.hex() for x in out) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
