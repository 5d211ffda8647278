#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Every command's --help: exit 0, its examples and the exit statuses; and every example shown
there runs (from a scratch directory where proofs/, examples/ and tests/ are the source tree's and
build/ the build directory, with the programs on PATH), ending by exit 0 or 1 (a witness), never
2 (bad input: the example is stale) or a signal. Also impactcert-check --help and --version.
Usage: help_examples_test.py BINDIR SOURCE_DIR [--light]
(--light, the sanitizer build: the --help texts are checked, the examples are run by the Release
build only, and it says so.)"""
import os
import shutil
import subprocess
import sys
import tempfile

from testkit import finish

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
LIGHT = "--light" in sys.argv[3:]
CLI = os.path.join(BIN, "impactcert")
COMMANDS = [["verify"], ["certify"], ["report"], ["smt"], ["eval"], ["derive", "sequential"], ["derive", "newton"],
            ["derive", "poisson"], ["derive", "cradle"], ["sweep"], ["fuzz"]]
failures = []
tmp = tempfile.mkdtemp(prefix="impactcert-help-")
try:
    for name in ("proofs", "examples", "tests"):
        os.symlink(os.path.join(SRC, name), os.path.join(tmp, name))
    os.symlink(BIN, os.path.join(tmp, "build"))
    env = dict(os.environ, PATH=BIN + os.pathsep + os.environ.get("PATH", ""))
    top = subprocess.run([CLI, "--help"], capture_output=True, text=True)
    if top.returncode != 0 or "docs/exit-status.md" not in top.stdout:
        failures.append(f"impactcert --help: exit {top.returncode}, exit statuses named: {'docs/exit-status.md' in top.stdout}")
    ran = 0
    for cmd in COMMANDS:
        p = subprocess.run([CLI] + cmd + ["--help"], capture_output=True, text=True)
        label = "impactcert " + " ".join(cmd)
        if p.returncode != 0:
            failures.append(f"{label} --help: exit {p.returncode}")
            continue
        text = p.stdout
        if "Examples:" not in text or "Exit statuses" not in text:
            failures.append(f"{label} --help: no examples or no exit statuses")
            continue
        if cmd[0] in ("verify", "certify", "derive", "sweep", "fuzz") and cmd[-1] != "cradle" and "3 " not in text.split("Usage:")[0]:
            failures.append(f"{label} --help: exit 3 is not named")
        examples = text.split("Examples:")[1].split("Exit statuses")[0]
        for line in examples.splitlines():
            line = line.strip()
            if not line:
                continue
            shell = line.split("  #")[0].strip()
            if LIGHT:
                print(f"not run here (the Release build runs it): {shell}")
                continue
            r = subprocess.run(["bash", "-c", shell], cwd=tmp, env=env, capture_output=True, text=True, timeout=600)
            ran += 1
            if r.returncode not in (0, 1):
                failures.append(f"{label}: the example `{shell}` ended with {r.returncode}: {r.stderr.strip()[:200]}")
            else:
                print(f"exit {r.returncode}: {shell}")
    if ran < 18 and not LIGHT:
        failures.append(f"only {ran} examples ran")
    checker = os.path.join(BIN, "impactcert-check")
    for args, want in ((["--help"], 0), (["--version"], 0)):
        r = subprocess.run([checker] + args, capture_output=True, text=True)
        if r.returncode != want or not r.stdout:
            failures.append(f"impactcert-check {args[0]}: exit {r.returncode}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish(failures)
