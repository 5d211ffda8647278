# SPDX-License-Identifier: GPL-3.0-or-later
"""The Python module against the command line: the same law text, verdicts, witnesses, errors
and fuzz reports on the same inputs; exact values as Fractions; the GIL released."""

import json
import numbers
import os
import subprocess
import sys
import threading
import time
from fractions import Fraction

import numpy as np
import pytest

import impactcert as ic

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from report_details import strip_run_details  # noqa: E402

CLI = os.environ["IMPACTCERT_CLI"]


def cli(*args, check=None):
    r = subprocess.run([CLI, *args], capture_output=True, text=True)
    if check is not None:
        assert r.returncode == check, r.stderr
    return r


def test_derived_law_and_verdict_are_the_command_lines(tmp_path):
    d = ic.derive(ic.System.chain([1, 2, 1]), restitution=Fraction(9, 10))
    assert d.law is not None and d.refutation == "" and d.witness is None
    out = cli("derive", "sequential", "--masses", "1,2,1", "--restitution", "9/10", check=0).stdout
    assert d.law.to_json() == out
    path = tmp_path / "law.json"
    d.law.write(path)
    assert path.read_text() == out
    report = ic.verify(d.law)
    assert report.json == cli("verify", "--json", "--law", str(path)).stdout
    # At e < 1 the 3-ball chain is discontinuous (P1 refuted) and dissipative.
    assert report.verdict == "refuted" and report.exit_status == 1
    assert report["P1"].verdict == "refuted" and report["energetic"].verdict == "proved"
    with pytest.raises(KeyError):
        report["no-such-obligation"]
    assert "energetic" in repr(report) and "<table>" in report._repr_html_()
    # In a notebook the report shows the law's picture too (the report's cones figure).
    assert "<svg" in report._repr_html_() and d.law.figure_svg() in d.law._repr_html_()


def test_a_refutation_carries_the_exact_witness_as_fractions(tmp_path):
    law = ic.derive(ic.System.chain([1, 1, 1]), restitution="1/2").law
    report = ic.verify(law)
    path = tmp_path / "three.json"
    law.write(path)
    r = cli("verify", "--json", "--law", str(path))
    assert report.json == r.stdout and report.exit_status == r.returncode == 1
    p1 = report["P1"]
    assert p1.verdict == "refuted"
    cex = p1.counterexample
    # The witness's exact values are Fractions, and the two pieces' images differ at gamma.
    gamma = cex["gamma"]
    assert all(isinstance(x, Fraction) for x in gamma)
    assert cex["image_a"] != cex["image_b"]
    values = law.evaluate_all(gamma)
    assert tuple(cex["image_a"]) in values and tuple(cex["image_b"]) in values
    with pytest.raises(ic.InputError, match="evaluate_all"):
        law.evaluate(gamma)


def test_exact_values_in_every_rational_form_and_floats_refused():
    law = ic.Law.paper()

    class Half(numbers.Rational):  # a numbers.Rational that is not a Fraction
        numerator, denominator = 1, 2
        def __float__(self): return 0.5
        __abs__ = __add__ = __ceil__ = __eq__ = __floor__ = __floordiv__ = __le__ = __lt__ = __mod__ = None
        __mul__ = __neg__ = __pos__ = __pow__ = __radd__ = __rfloordiv__ = __rmod__ = __rmul__ = None
        __round__ = __rpow__ = __rtruediv__ = __truediv__ = __trunc__ = __hash__ = None

    for gamma in ([-1, Half()], ["-1", "1/2"], [Fraction(-2, 2), Fraction(1, 2)]):
        value = law.evaluate(gamma)
        assert all(isinstance(x, Fraction) for x in value)
        out = cli("eval", "--", "-1", "1/2", check=0).stdout.split()
        assert value == tuple(Fraction(x) for x in out)
    with pytest.raises(ic.InputError, match="is a float"):
        law.evaluate([-1.0, 0.5])
    with pytest.raises(ic.InputError, match="not a rational"):
        law.evaluate(["-1", "x"])
    with pytest.raises(ic.InputError):
        law.evaluate([1])  # wrong length
    with pytest.raises(ic.InputError, match="is a float"):
        ic.derive(ic.System.chain([1, 1, 1]), restitution=0.9)


def test_bad_input_and_limits_are_the_command_lines_errors(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "impactcert-law/1", "name": "x"}')
    with pytest.raises(ic.InputError) as e:
        ic.Law.read(bad)
    assert e.value.exit_status == 2
    r = cli("verify", "--law", str(bad))
    assert r.returncode == 2
    assert r.stderr.strip() == "impactcert: " + str(e.value)
    assert isinstance(e.value, ValueError) and isinstance(e.value, ic.Error)
    with pytest.raises(ic.InputError):
        ic.System.chain([1, -1])
    with pytest.raises(ic.InputError):
        ic.derive(ic.System.chain([1, 1, 1]), kind="elastic")
    with pytest.raises(ic.LimitError, match="--max-impacts") as e:
        ic.derive(ic.System.chain([1, 1, 1]), max_impacts=1)
    assert e.value.exit_status == 3 and isinstance(e.value, RuntimeError)


def test_certificate_round_trip_and_a_tampered_one_rejected(tmp_path):
    cert = ic.certify(ic.Law.paper())
    ok = ic.check_certificate(cert)
    assert ok.verified and ok.exit_status == 0
    path = tmp_path / "paper.cert.json"
    path.write_text(cert)
    checker = os.path.join(os.path.dirname(CLI), "impactcert-check")
    assert subprocess.run([checker, str(path)], capture_output=True).returncode == 0
    at = cert.index('"2"')
    tampered = cert[:at + 1] + "3" + cert[at + 2:]
    bad = ic.check_certificate(tampered)
    assert bad.exit_status != 0 and bad.message


SWAP = "import sys\nfor line in sys.stdin:\n    a, b = line.split()\n    print(b, a, flush=True)\n"


def test_fuzzing_a_python_callable_matches_the_command_line(tmp_path):
    law = ic.Law.paper()

    def swap(points):
        assert points.dtype == np.float64 and points.shape[1] == 2
        return points[:, ::-1].copy()

    r = ic.fuzz(law, swap, samples=3000, seed=5, max_rel_error=1e-12)
    assert r.verdict == "violations" and r.exit_status == 1 and r.samples == 3000
    script = tmp_path / "swap.py"
    script.write_text(SWAP)
    c = cli("fuzz", "--json", "--jobs", "1", "--samples", "3000", "--seed", "5", "--max-rel-error", "1e-12",
            "--impl-cmd", f"{sys.executable} {script}")
    assert c.returncode == 1
    assert strip_run_details(r.report) == strip_run_details(json.loads(c.stdout))


def test_a_correct_callable_passes_and_exceptions_come_back():
    law = ic.Law.paper()

    def exact(points):
        return np.array([[float(x) for x in law.evaluate([Fraction(a), Fraction(b)])] for a, b in points])

    r = ic.fuzz(law, exact, samples=1500, range="1e-100..1e100")
    assert r.verdict == "no violation" and r.exit_status == 0

    def broken(points):
        raise KeyError("mine")

    with pytest.raises(KeyError, match="mine"):
        ic.fuzz(law, broken, samples=100)
    with pytest.raises(ValueError, match="shape"):
        ic.fuzz(law, lambda p: p[:, :1], samples=100)


def test_the_gil_is_released_during_exact_work():
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.monotonic()
    law = ic.derive(ic.System.chain([1, 1, 1, 1, 1]), restitution="1/2").law
    ic.verify(law)
    elapsed = time.monotonic() - start
    done.set()
    t.join()
    # Held for the whole call, the GIL would have let the counter run only between the calls.
    assert elapsed > 0.2, elapsed
    assert ticks > 0.5 * elapsed / 0.002, (ticks, elapsed)


def test_consistency_fuzzing_of_a_python_callable_matches_the_command_line():
    # The map that changes nothing: balls pass through each other (kinematic), against the
    # Newton law as reference; the command line gets the same map through a pipe.
    echo = os.environ["IMPACTCERT_ECHO_IMPL"]
    r = ic.fuzz_consistency(ic.System.chain([1, 2, 1]), lambda p: p.copy(), samples=500, seed=4, velocities=True,
                            max_rel_error=1e-6, reference="approaching", restitution=1)
    assert r.verdict == "violations" and r.exit_status == 1
    assert r.report["violations"]["kinematic"] > 0
    c = cli("fuzz", "--json", "--jobs", "1", "--masses", "1,2,1", "--velocities", "--samples", "500", "--seed", "4",
            "--max-rel-error", "1e-6", "--reference", "approaching", "--restitution", "1", "--impl-cmd", echo)
    assert c.returncode == 1
    assert strip_run_details(r.report) == strip_run_details(json.loads(c.stdout))
    with pytest.raises(ic.InputError, match="--require: unknown property"):
        ic.fuzz_consistency(ic.System.chain([1, 1]), lambda p: p, require=["speed"])


def test_witness_names_stay_names_and_numbers_are_exact():
    law = ic.derive(ic.System.chain([1, 1, 1]), restitution="1/2").law
    cex = ic.verify(law)["P1"].counterexample
    # Sequential pieces are named by their words ("121"): names, not numbers.
    assert isinstance(cex["piece_a"], str) and isinstance(cex["piece_b"], str)
    assert cex["piece_a"] in law.piece_names() and cex["piece_b"] in law.piece_names()
    assert all(isinstance(x, Fraction) for x in cex["gamma"])


def test_numbers_beyond_pythons_decimal_limit():
    law = ic.Law.paper()
    e10, e01, e11 = law.energy([1, 0]), law.energy([0, 1]), law.energy([1, 1])
    cross = (e11 - e10 - e01) / 2
    big = 10 ** 5000  # beyond the 4,300 digits Python converts to decimal text
    assert law.energy([big, 1]) == big * big * e10 + e01 + 2 * big * cross
    # A decimal string of 5,001 digits, and the exact value back.
    assert law.evaluate(["1" + "0" * 5000, "0"]) == (Fraction(big), Fraction(0))


def test_the_command_lines_grammar_for_exact_text():
    chain = ic.System.chain([1, 1, 1])
    assert (ic.derive(chain, restitution="0.9").law.to_json() ==
            ic.derive(chain, restitution=Fraction(9, 10)).law.to_json())
    assert ic.Law.paper().evaluate(["-1e0", np.int64(0)]) == (Fraction(0), Fraction(1))
    for bad in ("1_000", "1/0", "", "nan"):
        with pytest.raises(ic.InputError, match="gamma-"):
            ic.Law.paper().evaluate([bad, 0])
    with pytest.raises(ic.InputError, match="is a float"):
        ic.Law.paper().evaluate([np.float64(-1), 0])


def test_bad_implementations_and_options_are_input_errors():
    law = ic.Law.paper()
    with pytest.raises(ic.InputError, match="complex"):
        ic.fuzz(law, lambda p: p.astype(complex), samples=10)
    with pytest.raises(ic.InputError, match="shape"):
        ic.fuzz(law, lambda p: p[:, :1], samples=10)
    with pytest.raises(ic.InputError, match="implementation"):
        ic.fuzz(law, "not a function", samples=10)
    with pytest.raises(ic.InputError, match="--samples"):
        ic.fuzz(law, lambda p: p, samples=-1)
    chain = ic.System.chain([1, 1, 1])
    for seconds in (float("nan"), -1.0, float("inf")):
        with pytest.raises(ic.InputError, match="--seconds"):
            ic.fuzz_consistency(chain, lambda p: p, seconds=seconds)
    # --require as one text, as the command line takes it.
    r = ic.fuzz_consistency(chain, lambda p: p.copy(), samples=50, require="nonexpansive", velocities=True)
    assert r.report["checked_properties"]["nonexpansive"] is True
    assert ic.fuzz(law, lambda p: p, samples=10, max_ulps=np.int64(2)).report["tolerance"] == "--max-ulps 2"


def test_messages_are_one_line(tmp_path):
    with pytest.raises(ic.InputError) as e:
        ic.Law.read(tmp_path / "no\nsuch")
    assert "\n" not in str(e.value) and "\\n" in str(e.value)


def test_the_command_lines_order_of_checks_in_consistency_mode(tmp_path):
    # --require is checked before --junit is written: a bad option leaves no file behind.
    junit = tmp_path / "j.xml"
    r = cli("fuzz", "--masses", "1,1,1", "--require", "bogus", "--junit", str(junit), "--impl-cmd", "cat")
    assert r.returncode == 2 and "--require: unknown property" in r.stderr and not junit.exists()
    r = cli("fuzz", "--masses", "1,1,1", "--range", "5..1", "--restitution", "abc", "--impl-cmd", "cat")
    assert r.returncode == 2 and "--range" in r.stderr
    r = cli("fuzz", "--masses", "1,1,1", "--require", "bogus", "--impl", "x.so:f", "--impl-cmd", "cat")
    assert r.returncode == 2 and "--require" in r.stderr
