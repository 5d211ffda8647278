#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""`impactcert derive sequential --stream` from the command line: its refusals (one line, exit 2),
and a derivation killed half-way leaves the output as it was (whole or absent), while a run after
it writes the law.

Usage: derive_stream_cli_test.py IMPACTCERT"""

import glob
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

cli = sys.argv[1]
src = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
tmp = tempfile.mkdtemp(prefix="impactcert-derive-stream-")
failures = 0


def check(ok, what):
    global failures
    print(("ok   " if ok else "FAIL ") + what)
    failures += not ok


def run(*args):
    return subprocess.run([cli, "derive", "sequential", *args], capture_output=True, text=True)


try:
    law = os.path.join(tmp, "law.json")
    for args, needle in ((["--masses", "1,1,1,1", "--stream"], "-o FILE"),
                         (["--masses", "1,1,1,1", "--stream", "-o", "-"], "-o FILE"),
                         (["--masses", "1,1,1,1", "--stream", "--rule", "any", "-o", law], "--rule any"),
                         (["--system", os.path.join(src, "proofs/kane/gains/system.json"), "--stream", "-o", law],
                          "friction")):
        r = run(*args)
        check(r.returncode == 2 and needle in r.stderr and r.stderr.count("\n") == 1 and not os.path.exists(law),
              f"refused in one line, exit 2: {' '.join(args[-3:])}: {r.stderr.strip()}")

    # An old law at the path; a long streamed derivation (6 balls, e = 9/10: about a minute) killed
    # after a second: the old law is there, whole.
    old = run("--masses", "1,1,1", "-o", law)
    check(old.returncode == 0, "a first law written")
    before = open(law).read()
    p = subprocess.Popen([cli, "derive", "sequential", "--masses", "1,1,1,1,1,1", "--restitution", "9/10", "--stream",
                          "-o", law], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(1.5)
    check(p.poll() is None, "the long derivation still running after 1.5 s")
    p.send_signal(signal.SIGKILL)
    p.wait()
    check(open(law).read() == before, "killed: the law file is the old one, whole")
    partial = [f for f in os.listdir(tmp) if f != "law.json" and not f.startswith(".law.json.derive-spill-")]
    check(partial == [] or all(".partial-" in f for f in partial), f"killed: no other file beside it ({partial})")
    spills = glob.glob(os.path.join(tmp, ".law.json.derive-spill-*"))
    check(len(spills) == 1, "killed: its spill directory is left, named for the law")
    # Interrupted (SIGINT, SIGTERM: a user's Ctrl-C, a job's time limit): the spill is removed too.
    for sig in (signal.SIGINT, signal.SIGTERM):
        q = subprocess.Popen([cli, "derive", "sequential", "--masses", "1,1,1,1,1,1", "--restitution", "9/10", "--stream",
                              "-o", os.path.join(tmp, "other.json")], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(1.0)
        q.send_signal(sig)
        rc = q.wait()
        check(rc == -sig and not glob.glob(os.path.join(tmp, ".other.json.derive-spill-*")) and
              not os.path.exists(os.path.join(tmp, "other.json")),
              f"{signal.Signals(sig).name}: died of it, no law and no spill directory left")
    # A run after the kill writes the law (the stale spill directory is no obstacle).
    r = run("--masses", "1,1,1,1,1", "--restitution", "9/10", "--stream", "-o", law)
    check(r.returncode == 0 and "1400 pieces" in r.stderr, f"the next run writes the law: {r.stderr.strip()}")
    m = run("--masses", "1,1,1,1,1", "--restitution", "9/10", "-o", os.path.join(tmp, "memory.json"))
    check(m.returncode == 0 and os.path.getsize(law) == os.path.getsize(os.path.join(tmp, "memory.json")),
          "the streamed law has the in-memory law's size (the same text, pieces reordered)")
    check(len(glob.glob(os.path.join(tmp, ".law.json.derive-spill-*"))) == 1, "the finished run removed its own spill directory")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

print(f"{failures} failure(s)")
sys.exit(1 if failures else 0)
