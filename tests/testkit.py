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
