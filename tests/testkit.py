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
