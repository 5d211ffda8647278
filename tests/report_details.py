# SPDX-License-Identifier: GPL-3.0-or-later
"""What two fuzz reports of the same samples must share, for the tests that compare an in-process
run with the command line's (tests/python/test_impactcert.py, tests/box2d_inprocess_test.py)."""


def strip_run_details(report):
    """A fuzz report (impactcert-fuzz/1, parsed) without what names the implementation and how to
    reach it (its description, the replay commands, a process's standard error), the times, and
    nondeterminism (only a separate process can answer one input twice differently)."""
    for key in ("seconds", "samples_per_second", "implementation", "stderr"):
        report.pop(key, None)
    for section in ("checked_properties", "violations"):
        report.get(section, {}).pop("nondeterministic", None)

    def walk(x):
        if isinstance(x, dict):
            x.pop("replay", None)
            for v in x.values():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)
    walk(report)
    return report
