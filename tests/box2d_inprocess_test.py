#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Box2D's cradle fuzzed in-process through the library (examples/engines/box2d_inprocess.cpp)
gives the report the command line gives for the same engine through a pipe
(examples/engines/box2d_cradle.cpp, --impl-cmd): the same samples, findings, levels and worst
cases, at e = 1 with the Newton law (restitution on approaching contacts) as reference.

Usage: box2d_inprocess_test.py IMPACTCERT BOX2D_CRADLE BOX2D_INPROCESS"""

import json
import subprocess
import sys

from report_details import strip_run_details

impactcert, cradle, inprocess = sys.argv[1:4]


mine = subprocess.run([inprocess, "--json", "--samples", "1500", "--restitution", "1", "--reference", "approaching"],
                      capture_output=True, text=True)
pipe = subprocess.run([impactcert, "fuzz", "--json", "--jobs", "1", "--masses", "1,1,1", "--velocities", "--samples",
                       "1500", "--max-rel-error", "1e-5", "--range", "1e-3..60", "--restitution", "1", "--reference",
                       "approaching", "--impl-cmd", cradle], capture_output=True, text=True)
a, b = json.loads(mine.stdout), json.loads(pipe.stdout)
assert mine.returncode == pipe.returncode == 1, (mine.returncode, pipe.returncode, mine.stderr, pipe.stderr)
# At e = 1 Box2D's law (restitution on approaching contacts) gains energy: law-level findings.
assert a["violations"]["energy"] > 0 and a["levels"]["energy"]["law"] > 0, a["violations"]
assert strip_run_details(a) == strip_run_details(b), "the in-process report differs from the --impl-cmd one"
print(f"box2d in-process: {a['samples']} samples, {a['violations']['energy']} energy gains "
      f"({a['levels']['energy']['law']} law-level), the same report as through the pipe")
