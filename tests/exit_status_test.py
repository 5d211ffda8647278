#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""docs/exit-status.md's examples, run as written: every row between <!-- exit-examples --> and
<!-- /exit-examples --> is a command (in backticks) and the status it must end with; `impactcert`
and `impactcert-check` are the programs just built, the directory is the source tree. Each run
must end by exit(), never by a signal, and a status 2 or 3 must come with exactly one line on
stderr naming something (an option or a path).
Usage: exit_status_test.py BINDIR SOURCE_DIR"""
import os
import re
import shlex
import subprocess
import sys

from testkit import finish

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
text = open(os.path.join(SRC, "docs", "exit-status.md")).read()
block = text.split("<!-- exit-examples -->")[1].split("<!-- /exit-examples -->")[0]
rows = re.findall(r"^\| `(.+)` \| (\d) \|$", block, re.M)
failures = []
if len(rows) < 20:
    failures.append(f"only {len(rows)} examples found")
for cmd, want in rows:
    argv = shlex.split(cmd)
    argv[0] = os.path.join(BIN, argv[0])
    p = subprocess.run(argv, cwd=SRC, capture_output=True, text=True, timeout=300)
    if p.returncode < 0:
        failures.append(f"{cmd}: killed by signal {-p.returncode}")
    elif p.returncode != int(want):
        failures.append(f"{cmd}: exit {p.returncode}, the table says {want}: {p.stderr.strip()[:200]}")
    elif p.returncode in (2, 3) and "--help" not in cmd:
        lines = p.stderr.strip().splitlines()
        if len(lines) != 1:
            failures.append(f"{cmd}: exit {p.returncode} with {len(lines)} lines on stderr: {p.stderr[:300]!r}")
    else:
        print(f"exit {p.returncode}: {cmd}")
finish(failures)
