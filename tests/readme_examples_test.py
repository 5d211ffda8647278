#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Every README block marked `<!-- tested-example ... -->` is run as shown and its output compared.

A block is a fenced code block whose lines starting with `$ ` are commands (run with bash from the
source directory, standard error joined to standard output, `build/` being the build directory
and `/tmp/` a scratch directory) and whose other lines are the expected output. Times and rates
are masked (`0.035 ms`, `in 0.20 s, 9958 samples/s`, `2 jobs`), nothing else.
Usage: readme_examples_test.py BUILD_DIR SOURCE_DIR
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

BUILD, SRC = sys.argv[1], sys.argv[2]
MASKS = [(re.compile(r"[0-9]+\.[0-9]+ ms"), "T ms"),
         (re.compile(r"in [0-9]+\.[0-9]+ s, [0-9]+ samples/s"), "in T s, R samples/s"),
         (re.compile(r"\b[0-9]+ jobs?\)"), "J jobs)")]


def mask(line):
    for pattern, repl in MASKS:
        line = pattern.sub(repl, line)
    return line


readme = open(os.path.join(SRC, "README.md")).read()
parts = readme.split("<!-- tested-example")[1:]
if not parts:
    sys.exit("README.md has no tested example")
tmp = tempfile.mkdtemp(prefix="impactcert-readme-")
failures = commands_run = 0
build_rel = os.path.relpath(BUILD, SRC)
try:
    for part in parts:
        block = part.split("```\n", 2)[1]
        commands, expected = [], []
        for line in block.splitlines():
            if line.startswith("$ "):
                commands.append(line[2:])
                expected.append([])
            elif commands:
                expected[-1].append(line)
        for cmd, want in zip(commands, expected):
            real = cmd.replace("build/", build_rel + "/").replace("/tmp/", tmp + "/")
            p = subprocess.run(["bash", "-c", "{ " + real + "; } 2>&1"], capture_output=True, text=True, cwd=SRC)
            # the build directory as README names it (the sanitizer tree is build-sanitize)
            got = [mask(x.replace(build_rel + "/", "build/")) for x in p.stdout.splitlines()]
            want = [mask(x).replace("/tmp/", tmp + "/") for x in want]
            commands_run += 1
            if got != want:
                failures += 1
                print(f"FAIL: `{cmd}`")
                for g, w in zip(got + [""] * len(want), want + [""] * len(got)):
                    if g != w:
                        print(f"  README: {w}\n  run:    {g}")
finally:
    shutil.rmtree(tmp)
print(f"{commands_run} README commands run, {failures} differ")
sys.exit(1 if failures or commands_run == 0 else 0)
