#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Output files (reliability round four, item 8): a symbolic link planted at the temporary name a
run would once use, FILE.partial-PID, must not be followed. bash plants the link under its own PID
and then execs impactcert, which keeps that PID; the link's target must be left as it was, the
output written whole, and no temporary file left behind.
Usage: output_symlink_test.py IMPACTCERT"""
import os
import shutil
import subprocess
import sys
import tempfile

from testkit import finish

CLI = sys.argv[1]
tmp = tempfile.mkdtemp(prefix="impactcert-symlink-")
failures = []
try:
    victim = os.path.join(tmp, "victim.txt")
    with open(victim, "w") as f:
        f.write("precious\n")
    for cmd in (["certify"], ["derive", "newton", "--masses", "1,2,3"]):
        out = os.path.join(tmp, "out.json")
        if os.path.exists(out):
            os.unlink(out)
        script = 'ln -s "$1" "$2.partial-$$" && exec "$3" "${@:4}" -o "$2"'
        p = subprocess.run(["bash", "-c", script, "bash", victim, out, CLI] + cmd, capture_output=True, text=True)
        if p.returncode not in (0, 1):
            failures.append(f"{cmd}: exit {p.returncode}: {p.stderr.strip()}")
        if open(victim).read() != "precious\n":
            failures.append(f"{cmd}: the planted link was followed: its target was overwritten")
            with open(victim, "w") as f:
                f.write("precious\n")
        if not os.path.exists(out) or not open(out).read().startswith("{"):
            failures.append(f"{cmd}: the output was not written")
        left = [n for n in os.listdir(tmp) if ".partial-" in n and not os.path.islink(os.path.join(tmp, n))]
        if left:
            failures.append(f"{cmd}: temporary files left: {left}")
        for n in os.listdir(tmp):
            if os.path.islink(os.path.join(tmp, n)):
                os.unlink(os.path.join(tmp, n))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish(failures)
