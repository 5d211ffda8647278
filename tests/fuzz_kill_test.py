#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Reliability round four, item 6: `kill -9` of the fuzzer must not leave the implementation's
background processes running. The command starts `sleep 300 &` in every process the fuzzer starts
(one per worker) and records its PID; once the fuzzer is running, it is killed with SIGKILL, which
no handler sees. Every recorded sleep must be gone (or a zombie) within 5 s. A control run ends
normally (SIGTERM) and must clean up too.
Usage: fuzz_kill_test.py IMPACTCERT"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from testkit import finish

CLI = sys.argv[1]
tmp = tempfile.mkdtemp(prefix="impactcert-kill-")
failures = []


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
        return state not in ("Z", "X")
    except FileNotFoundError:
        return False


def run_and_kill(sig, label):
    pids_file = os.path.join(tmp, f"pids-{sig}")
    answer = os.path.join(tmp, "sorted.py")
    with open(answer, "w") as f:
        f.write("import sys\n"
                "for line in sys.stdin:\n"
                "    u = [float.fromhex(t) if 'x' in t.lower() else float(t) for t in line.split()]\n"
                "    print(' '.join(repr(x) for x in sorted(u)), flush=True)\n")
    cmd = f"sleep 300 & echo $! >> {pids_file}; exec python3 {answer}"
    p = subprocess.Popen([CLI, "fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd", cmd,
                          "--seconds", "120", "--jobs", "2"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    deadline = time.time() + 30
    pids = []
    while time.time() < deadline:
        if os.path.exists(pids_file):
            pids = [int(x) for x in open(pids_file).read().split()]
            if len(pids) >= 2:
                break
        time.sleep(0.1)
    if not pids:
        failures.append(f"{label}: the command never started (pids {pids}, fuzzer {p.poll()})")
        p.kill()
        p.wait()
        return
    time.sleep(0.5)
    os.kill(p.pid, sig)
    p.wait()
    if p.returncode != -sig:
        failures.append(f"{label}: the fuzzer ended with {p.returncode}, not by signal {sig}")
    deadline = time.time() + 5
    while time.time() < deadline and any(alive(x) for x in pids):
        time.sleep(0.1)
    left = [x for x in pids if alive(x)]
    for x in left:
        os.kill(x, signal.SIGKILL)
    if left:
        failures.append(f"{label}: {len(left)} of {len(pids)} background processes outlived the fuzzer")
    else:
        print(f"{label}: all {len(pids)} background processes ended with the fuzzer")


try:
    run_and_kill(signal.SIGKILL, "kill -9")
    run_and_kill(signal.SIGTERM, "SIGTERM")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
finish(failures)
