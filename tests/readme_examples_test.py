#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Every example in README.md and docs/*.md is run as shown and its output compared.

An example is a fenced code block whose first line starts with `$ `: those lines are commands
(run with bash, standard error joined to standard output), the lines after each its expected
output. A line `...` (alone, any indentation) stands for any number of lines. The commands run in
a scratch directory where proofs/, examples/, tests/, docs/, scripts/ and include/ are the source tree's and
build/ is the build directory; /tmp/ is a scratch directory too. Times and rates are masked
(`0.035 ms`, `in 0.20 s, 9958 samples/s`, `2 jobs`, the fuzzer's `time` line), and a replay's
`cd` into the scratch directory reads `cd ~/impactcert` (a checkout), nothing else. Blocks
marked `<!-- heavy: REASON -->` are left out of the sanitizer build's run (--light), and said so. A block may be excluded only by
a `<!-- not-run: REASON -->` line right before it, and the reason is printed.
With --update (for a developer, never in CI), the shown output of every command that differs
and has no `...` line is replaced in the file by the output of the run (unmasked).
With --times, the ten slowest commands are listed at the end (to keep the CI's budget).
Usage: readme_examples_test.py BUILD_DIR SOURCE_DIR [--light] [--update] [--times]"""
import glob
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

BUILD, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
LIGHT = "--light" in sys.argv[3:]
UPDATE = "--update" in sys.argv[3:]
TIMES = "--times" in sys.argv[3:]
times = []  # (seconds, place, command)
updates = {}  # path -> [(first line index, end index, new lines)]
MASKS = [(re.compile(r" +[0-9]+\.[0-9]+ ms\b"), " T ms"),
         (re.compile(r"in [0-9]+\.[0-9]+ s, [0-9]+ samples/s"), "in T s, R samples/s"),
         (re.compile(r"\b[0-9]+ jobs?\)"), "J jobs)"),
         (re.compile(r"^(  time +)[0-9.]+ s \(.*\)$"), r"\1T")]


def mask(line):
    for pattern, repl in MASKS:
        line = pattern.sub(repl, line)
    return line.rstrip()


def matches(got, want):
    """want, with `...` lines standing for any lines, against got."""
    segments, cur = [], []
    for w in want:
        if w.strip() == "...":
            segments.append(cur)
            cur = []
        else:
            cur.append(w)
    segments.append(cur)
    if len(segments) == 1:
        return got == want
    pos = 0
    if got[:len(segments[0])] != segments[0]:
        return False
    pos = len(segments[0])
    for k, seg in enumerate(segments[1:], 1):
        last = k == len(segments) - 1
        if last:
            return len(got) - pos >= len(seg) and (not seg or got[len(got) - len(seg):] == seg)
        found = next((i for i in range(pos, len(got) - len(seg) + 1) if got[i:i + len(seg)] == seg), None)
        if found is None:
            return False
        pos = found + len(seg)
    return True


def blocks(path):
    lines = open(path).read().splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("```"):
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            body = lines[i + 1:j]
            before = " ".join(lines[max(0, i - 2):i])
            if body and body[0].startswith("$ "):
                skip = re.search(r"<!-- not-run: (.*?) -->", before)
                heavy = re.search(r"<!-- heavy: (.*?) -->", before)
                reason = skip.group(1) if skip else ("heavy: " + heavy.group(1)) if heavy and LIGHT else None
                yield i + 1, body, reason
            i = j + 1
        else:
            i += 1


tmp = tempfile.mkdtemp(prefix="impactcert-readme-")
work = os.path.join(tmp, "work")
scratch = os.path.join(tmp, "scratch")
os.makedirs(work)
os.makedirs(scratch)
for name in ("proofs", "examples", "tests", "docs", "scripts", "include"):
    os.symlink(os.path.join(SRC, name), os.path.join(work, name))
os.symlink(BUILD, os.path.join(work, "build"))
failures = commands_run = 0
files = [os.path.join(SRC, "README.md")] + sorted(glob.glob(os.path.join(SRC, "docs", "*.md")))
try:
    for path in files:
        rel = os.path.relpath(path, SRC)
        for line_no, body, skip in blocks(path):
            if skip:
                print(f"not run: {rel}:{line_no}: {skip}")
                continue
            commands, expected, starts = [], [], []
            continued = False
            for k, line in enumerate(body):
                if continued:  # a command continued with a backslash
                    commands[-1] = commands[-1][:-1] + " " + line.strip()
                    starts[-1] = line_no + k + 1
                elif line.startswith("$ "):
                    commands.append(line[2:])
                    expected.append([])
                    starts.append(line_no + k + 1)  # 0-based index of the first output line
                else:
                    expected[-1].append(line)
                continued = bool(commands) and commands[-1].endswith("\\") and not expected[-1]
            for cmd, want, start in zip(commands, expected, starts):
                real = cmd.replace("/tmp/", scratch + "/")
                began = time.monotonic()
                p = subprocess.run(["bash", "-c", "{ " + real + "\n} 2>&1"], capture_output=True, text=True, cwd=work,
                                   timeout=900)
                times.append((time.monotonic() - began, f"{rel}:{start}", cmd))
                raw = [x.replace(scratch + "/", "/tmp/").replace("cd " + work + " && ", "cd ~/impactcert && ").rstrip()
                       for x in p.stdout.splitlines()]
                got = [mask(x) for x in raw]
                shown = want
                want = [mask(x) for x in want]
                if UPDATE and not matches(got, want) and not any(w.strip() == "..." for w in shown):
                    updates.setdefault(path, []).append((start, start + len(shown), raw))
                commands_run += 1
                if not matches(got, want):
                    failures += 1
                    print(f"FAIL: {rel}:{line_no}: `{cmd}`")
                    for g, w in zip(got + [""] * len(want), want + [""] * len(got)):
                        if g != w:
                            print(f"  shown: {w}\n  run:   {g}")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
for path, edits in updates.items():
    lines = open(path).read().splitlines()
    for first, end, new_lines in sorted(edits, reverse=True):
        lines[first:end] = new_lines
    open(path, "w").write("\n".join(lines) + "\n")
    print(f"updated: {os.path.relpath(path, SRC)} ({len(edits)} outputs)")
if TIMES:
    for seconds, place, cmd in sorted(times, reverse=True)[:10]:
        print(f"{seconds:7.2f} s  {place}: {cmd[:90]}")
print(f"{commands_run} commands of README.md and docs/ run, {failures} differ")
sys.exit(1 if failures or commands_run < 30 else 0)
