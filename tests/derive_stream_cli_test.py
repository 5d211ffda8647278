#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""`impactcert derive sequential --stream` from the command line: its refusals (one line, exit 2),
and a derivation killed half-way leaves the output as it was (whole or absent), while a run after
it writes the law.

Usage: derive_stream_cli_test.py IMPACTCERT"""

import glob
import json
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


def canonical(path):
    d = json.load(open(path))
    d["pieces"].sort(key=lambda p: p["name"])
    d.get("identities", []).sort(key=lambda p: p["lhs"])
    return d


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
              not glob.glob(os.path.join(tmp, "other.json*")),
              f"{signal.Signals(sig).name}: died of it, no law and no spill directory left")
    # A run after the kill writes the law (the stale spill directory is no obstacle).
    r = run("--masses", "1,1,1,1,1", "--restitution", "9/10", "--stream", "-o", law)
    check(r.returncode == 0 and "1400 pieces" in r.stderr, f"the next run writes the law: {r.stderr.strip()}")
    m = run("--masses", "1,1,1,1,1", "--restitution", "9/10", "-o", os.path.join(tmp, "memory.json"))
    check(m.returncode == 0 and canonical(law) == canonical(os.path.join(tmp, "memory.json")),
          "the streamed law is the in-memory law (pieces and identities sorted)")
    check(len(glob.glob(os.path.join(tmp, ".law.json.derive-spill-*"))) == 1, "the finished run removed its own spill directory")
    # Interrupted while the pieces are written (its longest phase for a large law): no temporary
    # output file, no spill. (5 balls, e = 1/3: 22,670 pieces in about 8 s; the writing starts
    # once the exploration ends.)
    slow = ["--masses", "1,3,2,1,2", "--restitution", "1/3", "--stream"]
    out = os.path.join(tmp, "slow.json")
    q = subprocess.Popen([cli, "derive", "sequential", *slow, "-o", out], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    # The temporary file exists from the start (the output is checked before the exploration);
    # the pieces are being written once it holds text.
    deadline = time.time() + 60
    writing = False
    while time.time() < deadline and not writing and q.poll() is None:
        writing = any(os.path.getsize(f) > 0 for f in glob.glob(out + ".partial-*"))
        time.sleep(0.02)
    q.send_signal(signal.SIGINT)
    q.wait()
    check(writing and not glob.glob(out + "*") and
          not glob.glob(os.path.join(tmp, ".slow.json.derive-spill-*")),
          "SIGINT while writing: neither the law, its temporary file nor the spill is left")
    # A signal the caller ignores stays ignored (nohup, a background job): the run goes on.
    q = subprocess.Popen([cli, "derive", "sequential", "--masses", "1,1,1,1,1", "--restitution", "1/3", "--stream",
                          "-o", out], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                         preexec_fn=lambda: signal.signal(signal.SIGHUP, signal.SIG_IGN))
    time.sleep(0.3)
    q.send_signal(signal.SIGHUP)
    check(q.wait() == 0 and os.path.exists(out), "SIGHUP ignored by the caller: the derivation finishes")
    # An output through a symbolic link is written in place: a run stopped by a limit leaves the
    # target as it was; a run that finishes writes it whole.
    target, link = os.path.join(tmp, "target.json"), os.path.join(tmp, "link.json")
    with open(target, "w") as f:
        f.write("OLD\n")
    os.symlink(target, link)
    r = run("--masses", "1,3,2,1,2", "--restitution", "1/3", "--stream", "--max-memory", "1", "-o", link)
    check(r.returncode == 3 and open(target).read() == "OLD\n", "a limit: the link's target untouched")
    r = run("--masses", "1,2,1,3", "--restitution", "1/2", "--stream", "-o", link)
    m = run("--masses", "1,2,1,3", "--restitution", "1/2", "-o", os.path.join(tmp, "m.json"))
    check(r.returncode == 0 and os.path.islink(link) and canonical(target) == canonical(os.path.join(tmp, "m.json")),
          "through the link: the target holds the law, the link stays a link")
    # A FIFO with a reader gets the whole law once; a dangling link gets its target made.
    fifo, got = os.path.join(tmp, "fifo"), os.path.join(tmp, "got.json")
    os.mkfifo(fifo)
    reader = subprocess.Popen(["sh", "-c", f"cat '{fifo}' > '{got}'"])
    r = run("--masses", "1,2,1,3", "--restitution", "1/2", "--stream", "-o", fifo)
    reader.wait(timeout=60)
    check(r.returncode == 0 and canonical(got) == canonical(os.path.join(tmp, "m.json")), "through a FIFO: the whole law")
    dangling = os.path.join(tmp, "dangling.json")
    os.symlink(os.path.join(tmp, "made.json"), dangling)
    r = run("--masses", "1,2,1,3", "--restitution", "1/2", "--stream", "-o", dangling)
    check(r.returncode == 0 and canonical(os.path.join(tmp, "made.json")) == canonical(os.path.join(tmp, "m.json")),
          "through a dangling link: its target made, with the law")
finally:
    shutil.rmtree(tmp, ignore_errors=True)

print(f"{failures} failure(s)")
sys.exit(1 if failures else 0)
