# SPDX-License-Identifier: GPL-3.0-or-later
"""impactcert: exact proofs, certificates and fuzzing of cone-wise linear impact laws.

The Python face of impactcert's C++ library (docs/python.md). Exact values go in as ``int``,
``fractions.Fraction``, any ``numbers.Rational`` or a string such as ``"3/4"``, and come out as
``Fraction``; a ``float`` where an exact value is meant is refused (it is rarely the number the
caller had in mind: 0.1 is 3602879701896397/36028797018963968). The exact work runs in C++ with
the GIL released.

    >>> import impactcert as ic
    >>> law = ic.derive(ic.System.chain([1, 1, 1])).law
    >>> ic.verify(law).verdict
    'proved'

docs/python.md walks through the module (a doctest that CI runs).
"""

import html as _html
import json as _json
import numbers as _numbers
from fractions import Fraction

from . import _impactcert

__all__ = ["Error", "InputError", "LimitError", "System", "Law", "Derivation", "Obligation", "Report",
           "CheckResult", "FuzzResult", "derive", "verify", "certify", "check_certificate", "fuzz", "fuzz_consistency",
           "version", "Fraction"]

__version__ = _impactcert.version()


def version():
    """The library's version, as the command line's --version prints it."""
    return _impactcert.version()


class Error(Exception):
    """An error of impactcert: the command line's one-line message and its exit status."""
    exit_status = 1


class InputError(Error, ValueError):
    """Bad input (exit status 2); the message names the place."""
    exit_status = 2


class LimitError(Error, RuntimeError):
    """A limit was reached (exit status 3); the message names the option that raises it."""
    exit_status = 3


def _hex(q):
    """An exact value as the compiled module takes it: hexadecimal "p/q" (no 4,300-digit limit)."""
    n, d = q.numerator, q.denominator
    return f"{'-' if n < 0 else ''}{abs(n):x}/{d:x}"


def _exact_text(x, where):
    """The text the compiled module takes for an exact value, or InputError saying why it is not one."""
    if isinstance(x, bool):
        raise InputError(f"{where}: expected a rational number, got a bool")
    if isinstance(x, float) or (hasattr(x, "dtype") and getattr(x.dtype, "kind", "") in "fc"):
        raise InputError(f"{where}: {x!r} is a float; give an exact value (int, Fraction or a string "
                         f"such as \"3/4\"): a float is rarely the number meant "
                         f"(0.1 is 3602879701896397/36028797018963968)")
    if isinstance(x, _numbers.Rational):
        return _hex(x)
    if hasattr(x, "dtype") and getattr(x.dtype, "kind", "") in "iu":  # NumPy integers
        return _hex(Fraction(int(x)))
    if isinstance(x, str):
        # The command line's grammar: integers, p/q, decimals ("0.9" is 9/10), exponents, hex floats.
        return _impactcert._parse_exact(x.strip(), where)
    raise InputError(f"{where}: expected a rational number (int, Fraction, numbers.Rational or a string "
                     f"such as \"3/4\"), got {type(x).__name__}")


def _exact_list(xs, where):
    if isinstance(xs, (str, _numbers.Number)) or (hasattr(xs, "dtype") and getattr(xs, "ndim", 1) == 0):
        xs = [xs]
    try:
        items = list(xs)
    except TypeError:
        raise InputError(f"{where}: expected a sequence of rational numbers") from None
    return [_exact_text(x, f"{where}[{i}]") for i, x in enumerate(items)]


def _fraction(text):
    """A Fraction from the compiled module's hexadecimal "p/q"."""
    n, _, d = text.partition("/")
    return Fraction(int(n, 16), int(d, 16) if d else 1)


# Keys of witnesses whose values are names (pieces, modes, words), never numbers: "121" there is
# the piece named 121.
_NAME_PARTS = ("piece", "mode", "word", "name", "reason", "detail", "symmetr", "identit", "outcome", "method", "limit")
_NAME_KEYS = ("id", "via", "what", "format", "verdict", "law", "kind", "generator")


def _is_name_key(key):
    return key is not None and (key in _NAME_KEYS or any(part in key.lower() for part in _NAME_PARTS))


def _exact_json(value, key=None):
    """A witness or report value with its exact numbers ("p/q", "-3") as Fractions, names kept."""
    if isinstance(value, dict):
        return {k: _exact_json(v, k) for k, v in value.items()}
    if isinstance(value, list):
        return [_exact_json(v, key) for v in value]
    if isinstance(value, str) and not _is_name_key(key):
        body = value[1:] if value.startswith("-") else value
        num, _, den = body.partition("/")
        if num.isdigit() and (not den or den.isdigit()):
            return _fraction(_impactcert._parse_exact(value, key or "witness"))
    return value


class System:
    """The mechanics a law is derived from: masses, contact directions, friction."""

    def __init__(self, _native):
        self._native = _native

    @staticmethod
    def chain(masses, walls="none"):
        """A chain of balls by their masses (walls: "none", "left", "right", "both")."""
        return System(_impactcert.System.chain(_exact_list(masses, "masses"), walls))

    @staticmethod
    def read(path):
        """An impactcert-system/1 or impactcert-scene/1 file."""
        return System(_impactcert.System.read(str(path)))

    @staticmethod
    def parse(text, origin="system"):
        return System(_impactcert.System.parse(text, origin))

    velocities = property(lambda self: self._native.velocities)
    contacts = property(lambda self: self._native.contacts)
    friction = property(lambda self: self._native.friction)

    def describe(self):
        return self._native.describe()

    def __repr__(self):
        return f"<impactcert.System: {self.describe()}>"


class Law:
    """A cone-wise linear impact law (an impactcert-law/1 file)."""

    def __init__(self, _native):
        self._native = _native

    @staticmethod
    def read(path, max_pieces=500000, max_memory_mb=640):
        return Law(_impactcert.Law.read(str(path), max_pieces, max_memory_mb))

    @staticmethod
    def parse(text, origin="law", max_pieces=500000, max_memory_mb=640):
        return Law(_impactcert.Law.parse(text, origin, max_pieces, max_memory_mb))

    @staticmethod
    def paper():
        """The 3-ball Newton's cradle law of Leine & Winandy (the embedded default)."""
        return Law(_impactcert.Law.paper())

    name = property(lambda self: self._native.name)
    contacts = property(lambda self: self._native.contacts)
    velocities = property(lambda self: self._native.velocities)
    pieces = property(lambda self: self._native.pieces)

    def piece_names(self):
        return list(self._native.piece_names())

    def to_json(self):
        """The law file's text, as `impactcert derive ... -o` writes it."""
        return self._native.to_json()

    def write(self, path):
        """Writes the law file (whole or absent)."""
        self._native.write(str(path))

    def evaluate(self, gamma_minus):
        """S(gamma-), exactly: a tuple of Fractions (InputError in a gap of the cones). On a
        boundary of a discontinuous law, where pieces disagree, every value (evaluate_all)."""
        values = self.evaluate_all(gamma_minus)
        if len(values) > 1:
            raise InputError(f"gamma- = {tuple(str(Fraction(x)) for x in _exact_list(gamma_minus, 'gamma-'))} "
                             f"lies where pieces {self.pieces_at(gamma_minus)} disagree: use evaluate_all")
        return values[0]

    def evaluate_all(self, gamma_minus):
        """The value of every piece whose closed cone holds gamma- (duplicates removed)."""
        texts = self._native._evaluate(_exact_list(gamma_minus, "gamma-"))
        return [tuple(_fraction(t) for t in v) for v in texts]

    def pieces_at(self, gamma_minus):
        """The names of the pieces whose closed cones hold gamma-."""
        return list(self._native._pieces_at(_exact_list(gamma_minus, "gamma-")))

    def energy(self, gamma):
        """|gamma|_H^2 = gamma^T H gamma (twice the kinetic energy gamma stands for), exactly."""
        return _fraction(self._native._energy(_exact_list(gamma, "gamma")))

    def figure_svg(self):
        """The law's picture as `impactcert report` draws it (SVG text; "" when it has none)."""
        return self._native.figure_svg()

    def __repr__(self):
        return f"<impactcert.Law {self.name}: {self.pieces} pieces, {self.contacts} contacts>"

    def _repr_html_(self):
        svg = self.figure_svg()
        head = f"<p><b>{_html.escape(self.name)}</b>: {self.pieces} pieces, {self.contacts} contacts</p>"
        return head + svg


class Derivation:
    """What derive() gives: the law, or (with friction) why there is none and the exact witness."""

    def __init__(self, law, refutation, witness):
        self.law = law
        self.refutation = refutation
        self.witness = _exact_json(_json.loads(witness)) if witness else None

    def __repr__(self):
        if self.law is not None:
            return f"<impactcert.Derivation: {self.law!r}>"
        return f"<impactcert.Derivation: no law: {self.refutation}>"


class Obligation:
    """One proof obligation's verdict, with its exact counterexample (Fractions) when refuted."""

    def __init__(self, native):
        self.id = native.id
        self.claimed = native.claimed
        self.verdict = native.verdict
        self.checks = native.checks
        self.method = native.method
        self.limit = native.limit
        self.counterexample = _exact_json(_json.loads(native.counterexample)) if native.counterexample else None

    def __repr__(self):
        return f"<{self.id}: {self.verdict}{' (claimed)' if self.claimed else ''}>"


class Report:
    """The verdict of verify(): every obligation, and the JSON `impactcert verify --json` prints."""

    def __init__(self, native, law=None):
        self._law = law
        self.json = native.json
        self.law = native.law
        self.verdict = native.verdict
        self.exit_status = native.exit_status
        self.obligations = [Obligation(o) for o in native.obligations]

    def __getitem__(self, obligation_id):
        for o in self.obligations:
            if o.id == obligation_id:
                return o
        raise KeyError(obligation_id)

    def __repr__(self):
        rows = [f"impactcert verify: {self.law}: {self.verdict}"]
        for o in self.obligations:
            rows.append(f"  {o.id:<20}{'yes' if o.claimed else 'no':<9}{o.verdict:<10}{o.checks:>8}   {o.method}")
            if o.counterexample is not None:
                rows.append(f"      counterexample: {_json.dumps(o.counterexample, default=str)}")
        return "\n".join(rows)

    def _repr_html_(self):
        colour = {"proved": "#1a7f37", "refuted": "#cf222e", "undecided": "#9a6700", "skipped": "#57606a"}
        rows = "".join(
            f"<tr><td><code>{_html.escape(o.id)}</code></td><td>{'yes' if o.claimed else 'no'}</td>"
            f"<td style='color:{colour.get(o.verdict, '#000')}'>{o.verdict}</td><td>{o.checks}</td>"
            f"<td>{_html.escape(o.method)}</td></tr>"
            + (f"<tr><td></td><td colspan='4'><small>counterexample: "
               f"{_html.escape(_json.dumps(o.counterexample, default=str))}</small></td></tr>"
               if o.counterexample is not None else "")
            for o in self.obligations)
        figure = self._law.figure_svg() if self._law is not None else ""
        return (f"<p><b>{_html.escape(self.law)}</b>: "
                f"<span style='color:{colour.get(self.verdict, '#000')}'>{self.verdict}</span></p>"
                f"<table><tr><th>obligation</th><th>claimed</th><th>verdict</th><th>checks</th>"
                f"<th>method</th></tr>{rows}</table>{figure}")


class CheckResult:
    """The independent checker's answer: exit status 0 verified, 1 rejected, 2 malformed, 3 undecided."""

    def __init__(self, exit_status, message):
        self.exit_status = exit_status
        self.message = message

    verified = property(lambda self: self.exit_status == 0)

    def __repr__(self):
        return f"<impactcert.CheckResult {self.exit_status}: {self.message}>"


class FuzzResult:
    """The report of fuzz(): the impactcert-fuzz/1 object, as `impactcert fuzz --json` prints it."""

    def __init__(self, text):
        self.json = text
        self.report = _json.loads(text)
        self.verdict = self.report["verdict"]
        self.samples = self.report["samples"]
        self.exit_status = {"violations": 1, "no violation": 0}.get(self.verdict, 3)
        self.examples = self.report["examples"]

    def __repr__(self):
        v = self.report["violations"]
        found = ", ".join(f"{k} {n}" for k, n in v.items() if n)
        return (f"<impactcert.FuzzResult: {self.verdict}; {self.samples} samples; "
                f"{found or 'nothing found'}; {self.report['coverage']['text']}>")


def derive(system, kind="sequential", restitution=(), rule="most-negative", max_impacts=100,
           max_bits=65536, max_memory_mb=2048):
    """The sequential, Newton or Poisson law of a System (`impactcert derive`).

    restitution: one value for every contact, or one per contact; empty: the system's own, else 1."""
    law, refutation, witness = _impactcert._derive(system._native, kind, _exact_list(restitution, "restitution"),
                                                   rule, max_impacts, max_bits, max_memory_mb)
    return Derivation(Law(law) if law is not None else None, refutation, witness)


def verify(law, max_pieces=500000, max_memory_mb=640, jobs=1):
    """Every proof obligation of the law, decided exactly (`impactcert verify`)."""
    return Report(_impactcert._verify(law._native, max_pieces, max_memory_mb, jobs), law)


def certify(law, max_pieces=500000, max_memory_mb=640, jobs=1):
    """The certificate text (impactcert-certificate/1), as `impactcert certify -o` writes it."""
    return _impactcert._certify(law._native, max_pieces, max_memory_mb, jobs)


def check_certificate(text):
    """The independent checker (impactcert-check) on a certificate's text."""
    return CheckResult(*_impactcert._check_certificate(text))


def _check_run(implementation, samples, seed, batch):
    if not callable(implementation):
        raise InputError(f"implementation: expected a function of an (N, n) array, got {type(implementation).__name__}")
    for name, value in (("--samples", samples), ("--seed", seed), ("batch", batch)):
        if isinstance(value, bool) or not isinstance(value, _numbers.Integral) or value < 0 or value >= 2 ** 64:
            raise InputError(f"{name}: expected an integer in [0, 2^64 - 1], got {value!r}")


def fuzz(law, implementation, samples=100000, seed=1, seconds=0.0, max_ulps=None, max_rel_error=None,
         velocities=False, range=None, allow_extreme=False, name="Python callable", batch=1024):
    """Fuzz a float implementation against the exact law, in-process (`impactcert fuzz --law`).

    implementation(points) takes an (N, n) NumPy array of float64 (n: the law's contacts, or its
    velocities with velocities=True) and returns an (N, n) array of floats. Each call holds the
    points of up to `batch` samples (a close pair is two points); the exact work runs in C++
    without the GIL."""
    _check_run(implementation, samples, seed, batch)
    if max_ulps is not None:
        if isinstance(max_ulps, bool) or not isinstance(max_ulps, _numbers.Integral) or max_ulps < 0:
            raise InputError("--max-ulps: expected an integer >= 0")
        max_ulps = int(max_ulps)
    return FuzzResult(_impactcert._fuzz(law._native, implementation, int(seed), int(samples), float(seconds), max_ulps,
                                        None if max_rel_error is None else float(max_rel_error), velocities,
                                        range or "", allow_extreme, name, int(batch)))


def fuzz_consistency(system, implementation, samples=100000, seed=1, seconds=0.0, max_rel_error=1e-9,
                     velocities=False, restitution=None, reference="", require=(), range=None,
                     name="Python callable", batch=2048):
    """Check a black-box impact map of a System against the laws of mechanics alone (no law needed):
    `impactcert fuzz --masses|--system` without --law, in-process. Findings are decided exactly at
    the implementation's doubles; with reference ("approaching", "newton", "poisson" or a law
    file) each is law-level or solver-level; restitution adds the restitution property."""
    _check_run(implementation, samples, seed, batch)
    if isinstance(require, str):
        require = [r for r in require.replace(",", " ").split() if r]
    return FuzzResult(_impactcert._fuzz_consistency(
        system._native, implementation, int(seed), int(samples), float(seconds), float(max_rel_error), velocities,
        None if restitution is None else _exact_list(restitution, "--restitution"), reference,
        list(require), range or "", name, int(batch)))
