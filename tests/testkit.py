# SPDX-License-Identifier: GPL-3.0-or-later
"""What the Python tests share: failures collected as they come, one summary at the end, and the
exit status ctest reads (1 when anything failed). Imported from the tests' own directory."""
import sys


def finish(failures):
    """Prints every failure, then `ok` or their count, and exits 0 or 1."""
    for f in failures:
        print("FAIL:", f)
    print("ok" if not failures else f"{len(failures)} failure(s)")
    sys.exit(1 if failures else 0)


def run_replay(cmd, cli):
    """A replay as the fuzzer prints it, `cd DIR && PROGRAM eval ...`, run by the shell from the
    root directory (a replay must run from any directory). Raises AssertionError unless it has
    that shape and names `cli`, the impactcert under test."""
    import subprocess
    if not cmd.startswith("cd ") or f" && {cli} eval " not in cmd:
        raise AssertionError(f"a replay not of the form `cd DIR && {cli} eval ...`: {cmd}")
    return subprocess.run(cmd, shell=True, capture_output=True, text=True, cwd="/")


def newton4_exact(g):
    """The 4-ball law (proofs/newton4) in Fractions, independently of impactcert: the ball
    velocities 0, g1, g1+g2, g1+g2+g3 sorted, and their differences."""
    u = [0]
    for x in g:
        u.append(u[-1] + x)
    u.sort()
    return [u[k + 1] - u[k] for k in range(3)]


def newton4_h_norm2(v):
    """|v|^2 in the contact metric of the 4-ball chain of unit masses: 2 T of the relative
    motion, the sum over balls of (u_i - mean)^2 with u the partial sums."""
    from fractions import Fraction
    u = [Fraction(0)]
    for x in v:
        u.append(u[-1] + x)
    mean = sum(u) / 4
    return sum((x - mean) ** 2 for x in u)
