#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The exact worst case of a law (verify/certify --worst-case; proofs/README.md, "The exact worst
case of a law"), checked by a second route and by the checker against forgeries.

- Laws: the paper's (sequential), the Newton law (restitution on every contact) and the Poisson
  law of three equal balls at e = 1/2 and e = 1, the approaching-only Newton law of three balls
  (e = 1: exactly 4/3) and of five balls (e = 1: 2 + sqrt(4/5), irrational).
- Second route, in Python fractions: a dense exact sampling of every cone (a simplex grid of its
  rays) never exceeds the certified upper end, and reaches the value to within 0.5%; the Lipschitz
  bound likewise on a grid of directions; the values are compared with their closed forms.
- impactcert-check verifies every certificate, and rejects each of 12 forgeries naming the path.
- The five-ball certificate is committed (tests/certificates/worst-case/): this run certifies it
  afresh and requires the very bytes, so the file cannot go stale; the sanitized run checks the
  committed file instead of certifying the 92-piece law again (about a minute of CPU under the
  sanitizers; the prover's four-contact worst case still runs there, on trap-513).
Usage: worst_case_test.py BIN_DIR [--sanitized]  (sanitized: the five-ball sampling coarser, and
the committed five-ball certificate; the checker's work is the same)"""
import copy
import itertools
import json
import os
import subprocess
import sys
import tempfile
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testkit import finish  # noqa: E402

BIN = os.path.abspath(sys.argv[1])
SANITIZED = "--sanitized" in sys.argv[2:]
CLI, CHECK = os.path.join(BIN, "impactcert"), os.path.join(BIN, "impactcert-check")
tmp = tempfile.mkdtemp(prefix="impactcert-worst-")
failures = []


def fail(msg):
    failures.append(msg)


def mat(rows):
    return [[F(x) for x in r] for r in rows]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(len(b))) for j in range(len(b[0]))] for i in range(len(a))]


def mv(a, x):
    return [sum(a[i][k] * x[k] for k in range(len(x))) for i in range(len(a))]


def form(h, x):
    return sum(x[i] * h[i][j] * x[j] for i in range(len(x)) for j in range(len(x)))


def transpose(a):
    return [list(r) for r in zip(*a)]


def inverse(a):
    n = len(a)
    m = [list(r) + [F(int(i == j)) for j in range(n)] for i, r in enumerate(a)]
    for col in range(n):
        piv = next(r for r in range(col, n) if m[r][col] != 0)
        m[col], m[piv] = m[piv], m[col]
        p = m[col][col]
        m[col] = [x / p for x in m[col]]
        for r in range(n):
            if r != col and m[r][col] != 0:
                f = m[r][col]
                m[r] = [x - f * y for x, y in zip(m[r], m[col])]
    return [r[n:] for r in m]


def grid(c, n):
    """Every z >= 0 with integer entries summing to n (a simplex grid of the cone's rays)."""
    for cut in itertools.combinations(range(n + c - 1), c - 1):
        parts, last = [], -1
        for x in cut + (n + c - 1,):
            parts.append(x - last - 1)
            last = x
        yield parts


def law_of(name, args):
    path = os.path.join(tmp, name + ".json")
    p = subprocess.run([CLI, "derive"] + args + ["-o", path], capture_output=True, text=True)
    if p.returncode != 0:
        fail(f"{name}: derive exit {p.returncode}: {p.stderr[-300:]}")
    return path


LAWS = [  # name, derive arguments (None: the paper's law), closed form of sup T+/T- (None: check 1)
    ("paper", None, F(1)),
    ("newton-half", ["newton", "--masses", "1,1,1", "--restitution", "1/2"], F(1)),
    ("newton-one", ["newton", "--masses", "1,1,1", "--restitution", "1"], F(1)),
    ("poisson-half", ["poisson", "--masses", "1,1,1", "--restitution", "1/2"], F(1)),
    ("poisson-one", ["poisson", "--masses", "1,1,1", "--restitution", "1"], F(1)),
    ("approaching-3", ["newton", "--masses", "1,1,1", "--restitution", "1", "--restitution-on", "approaching"], F(4, 3)),
    ("approaching-5", ["newton", "--masses", "1,1,1,1,1", "--restitution", "1", "--restitution-on", "approaching"],
     "2+sqrt(4/5)"),
]

# Laws from the review where the start vector 1 is exactly an eigenvector of a smaller root (the
# prover gave up on them: undecided). The first has a closed form: the root of
# 240100 x^2 - 2171141 x + 73441 near 9.0087; the others are checked by sampling alone.
SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
TRAPS = [("trap-linear", os.path.join(SRC, "tests", "laws", "worst-case-one-is-an-eigenvector.json"),
          (F(240100), F(-2171141), F(73441))),
         ("trap-418", os.path.join(SRC, "tests", "laws", "worst-case-random-418.json"), None),
         ("trap-513", os.path.join(SRC, "tests", "laws", "worst-case-random-513.json"), None)]
LAWS += [(name, path, quad) for name, path, quad in TRAPS]

FIXTURE = {"approaching-5": os.path.join(SRC, "tests", "certificates", "worst-case", "newton-approaching-5.json")}

certs = {}
for name, args, closed in LAWS:
    if SANITIZED and name in FIXTURE:
        cert_path = FIXTURE[name]
    else:
        law = args if isinstance(args, str) else law_of(name, args) if args else None
        cert_path = os.path.join(tmp, name + ".cert.json")
        p = subprocess.run([CLI, "certify", "--worst-case", "-o", cert_path] + (["--law", law] if law else []),
                           capture_output=True, text=True)
        if p.returncode not in (0, 1) or not os.path.exists(cert_path):
            fail(f"{name}: certify --worst-case exit {p.returncode}: {p.stderr[-300:]}")
            continue
        if name in FIXTURE and open(cert_path, "rb").read() != open(FIXTURE[name], "rb").read():
            fail(f"{name}: the committed {os.path.relpath(FIXTURE[name], SRC)} is not the certificate made now: "
                 f"impactcert derive {' '.join(args)} -o l.json && impactcert certify --worst-case --law l.json "
                 f"-o {os.path.relpath(FIXTURE[name], SRC)}")
    cert = json.load(open(cert_path))
    certs[name] = (cert_path, cert)
    r = subprocess.run([CHECK, cert_path], capture_output=True, text=True)
    if "verified" not in r.stdout + r.stderr:
        fail(f"{name}: the checker does not verify the certificate: {(r.stdout + r.stderr)[-300:]}")
    wc = cert["worst_case"]
    e = wc["energy_ratio"]
    if e["status"] != "decided":
        fail(f"{name}: energy ratio undecided: {e}")
        continue
    lo, hi = (F(x) for x in e["value"]["interval"])
    # Closed forms.
    if isinstance(closed, tuple):  # a x^2 + b x + c: a sign change (or a root) across [lo, hi], lo > 9
        a, b, c0 = closed
        f_lo, f_hi = a * lo * lo + b * lo + c0, a * hi * hi + b * hi + c0
        if not (lo > 9 and f_lo * f_hi <= 0):
            fail(f"{name}: sup T+/T- interval [{lo}, {hi}] does not hold the root of {closed}")
    elif closed is None:
        pass  # sampling below
    elif isinstance(closed, F):
        if F(e["value"].get("exact", "-1")) != closed or not lo <= closed <= hi:
            fail(f"{name}: sup T+/T- is {e['value']}, expected exactly {closed}")
    else:  # 2 + sqrt(4/5): lo <= value <= hi iff (lo - 2)^2 <= 4/5 <= (hi - 2)^2 (both above 2)
        if not (lo > 2 and (lo - 2) ** 2 <= F(4, 5) <= (hi - 2) ** 2) or "exact" in e["value"]:
            fail(f"{name}: sup T+/T- interval [{lo}, {hi}] does not hold 2 + sqrt(4/5)")
    # Dense exact sampling of every cone.
    H = mat(cert["system"]["H"])
    pieces = cert["law"]["pieces"]
    c = len(H)
    best, worst_over = F(0), None
    for piece, entry in zip(pieces, e["pieces"]):
        # Finest on the piece that attains the value (four contacts: 12,341 points there, 165 elsewhere).
        n = 60 if c <= 2 else (20 if SANITIZED else 40) if piece["name"] == e["piece"] else (4 if SANITIZED else 8)
        Q = mat(piece["Q"])
        rays = mat(piece["rays"]) if "rays" in piece else transpose(inverse(Q))
        R = transpose(rays)
        # The certified point is in the cone and attains the piece's lower end.
        pt = [F(x) for x in entry["point"]]
        if any(v < 0 for v in mv(inverse(R), pt)) or form(H, mv(Q, pt)) / form(H, pt) != F(entry["lower"]):
            fail(f"{name}/{piece['name']}: the certified point is not in the cone or does not attain lower")
        for z in grid(c, n):
            g = mv(R, [F(v) for v in z])
            ratio = form(H, mv(Q, g)) / form(H, g)
            best = max(best, ratio)
            if ratio > F(entry["upper"]):
                worst_over = (piece["name"], z, ratio)
    if worst_over:
        fail(f"{name}: a sampled point exceeds its piece's certified upper end: {worst_over}")
    if not (best <= hi and best >= lo * (F(98, 100) if SANITIZED else F(995, 1000))):
        fail(f"{name}: dense sampling reaches {float(best)}, the value is in [{float(lo)}, {float(hi)}]")
    # Lipschitz: present for a continuous tiling; sampled directions never exceed it.
    lip = wc.get("lipschitz_squared")
    if lip and lip["status"] == "decided":
        lhi = F(lip["value"]["interval"][1])
        lbest = F(0)
        for piece in pieces:
            if c > 2 and piece["name"] != lip["piece"]:
                continue  # four contacts: the directions of the piece that attains it
            Q = mat(piece["Q"])
            for d in itertools.product(range(-4, 5), repeat=c):
                if any(d):
                    v = [F(x) for x in d]
                    lbest = max(lbest, form(H, mv(Q, v)) / form(H, v))
        if lbest > lhi or lbest < F(lip["value"]["interval"][0]) * F(9, 10):
            fail(f"{name}: Lipschitz^2 sampled {float(lbest)} against [{lip['value']['interval']}]")
    print(f"{name}: sup T+/T- = {e['value'].get('exact', e['value']['decimal'])}, dense sampling {float(best):.6f}"
          + (f", Lipschitz^2 {lip['value'].get('exact', lip['value']['decimal'])}" if lip else ""))

# Forgeries: each must be rejected (exit 1) naming the path.
if "approaching-3" in certs and "approaching-5" in certs:
    base3 = certs["approaching-3"][1]
    base5 = certs["approaching-5"][1]

    def top(c):
        w = c["worst_case"]["energy_ratio"]
        return next(i for i, p in enumerate(w["pieces"]) if p["piece"] == w["piece"])

    def forge(c, path_hint, edit):
        c = copy.deepcopy(c)
        edit(c)
        path = os.path.join(tmp, "forged.json")
        json.dump(c, open(path, "w"))
        r = subprocess.run([CHECK, path], capture_output=True, text=True)
        out = r.stdout + r.stderr
        if r.returncode != 1 or path_hint not in out:
            fail(f"forgery {path_hint}: exit {r.returncode}: {out[-300:]}")

    t3, t5 = top(base3), top(base5)
    E = ["worst_case", "energy_ratio"]

    def w(c):
        return c["worst_case"]["energy_ratio"]

    forge(base3, f"pieces[{t3}].upper", lambda c: w(c)["pieces"][t3].update(upper="5/4"))  # below the sup
    forge(base3, f"pieces[{t3}].", lambda c: w(c)["pieces"][t3].update(lower="5/4"))  # not the ratio at the point
    forge(base3, f"pieces[{t3}].point", lambda c: w(c)["pieces"][t3].update(point=["2", "-1"]))  # outside the cone
    forge(base3, f"pieces[{t3}].polynomial", lambda c: w(c)["pieces"][t3].update(polynomial=["-5/4", "1"]))
    forge(base3, f"pieces[{t3}].face", lambda c: w(c)["pieces"][t3].update(face=[2, 1]))
    forge(base3, "value.exact", lambda c: w(c)["value"].update(exact="5/4"))
    forge(base3, "value.interval", lambda c: w(c)["value"].update(interval=["1", "2"]))
    forge(base3, "energy_ratio.", lambda c: w(c).update(piece="free"))
    forge(base3, "lipschitz_squared", lambda c: c["worst_case"].pop("lipschitz_squared"))
    # Five balls: an interval widened to hold another face's root, a certificate of another piece,
    # and a value below another piece's.
    forge(base5, f"pieces[{t5}]", lambda c: w(c)["pieces"][t5].update(lower="0", point=w(c)["pieces"][t5]["point"]))
    forge(base5, f"pieces[{t5}].certificate",
          lambda c: w(c)["pieces"][t5].update(certificate={"method": "nonnegative-entries"}))
    forge(base5, "pieces[", lambda c: w(c)["pieces"][t5].update(piece="J1"))
    # The decimal a reader sees is checked (issue 40, item 1): a value edited to ~1.5, a Lipschitz
    # decimal set to ~9, the "~" dropped from a rounded value, one digit off in the last place, an
    # 18th digit; the five balls' algebraic value (2 + sqrt(4/5)) one unit off.
    L = ["worst_case", "lipschitz_squared"]
    forge(base3, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal="~1.5"))
    forge(base3, "lipschitz_squared.value.decimal", lambda c: c["worst_case"]["lipschitz_squared"]["value"].update(decimal="~9"))
    forge(base3, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal="1.3333333333333333"))
    forge(base3, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal="~1.3333333333333334"))
    forge(base3, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal="~1.33333333333333333"))
    forge(base3, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal="~4/3"))
    d5 = w(base5)["value"]["decimal"]
    last = str((int(d5[-1]) + 1) % 10)
    forge(base5, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal=d5[:-1] + last))
    forge(base5, "energy_ratio.value.decimal", lambda c: w(c)["value"].update(decimal=d5[1:]))  # no "~"
    # An undecided worst case the prover could not have reached (issue 40, item 2): a made-up
    # limit, and --max-faces 3 on a law whose pieces have 2^2 - 1 = 3 faces. The prover's own
    # undecided (--max-faces 2) is verified.
    undecided = {"status": "undecided", "limit": "copositivity beyond --max-faces 1"}
    forge(base3, "energy_ratio.limit", lambda c: c["worst_case"].update(energy_ratio=dict(undecided)))
    first = base3["law"]["pieces"][0]["name"]
    forge(base3, "energy_ratio.limit", lambda c: c["worst_case"].update(energy_ratio={
        "status": "undecided", "limit": f"the worst case of piece {first} needs 2^2 - 1 faces (--max-faces 3)"}))
    forge(base3, "lipschitz_squared.limit", lambda c: c["worst_case"].update(lipschitz_squared={
        "status": "undecided", "limit": f"the worst case of piece {first} needs 2^2 - 1 faces (--max-faces 2)"}))
    lim = os.path.join(tmp, "limited.json")
    r = subprocess.run([CLI, "certify", "--law", os.path.join(SRC, "proofs", "classical3", "newton-approaching", "law.json"),
                        "--worst-case", "--max-faces", "2", "-o", lim], capture_output=True, text=True)
    rc = subprocess.run([CHECK, lim], capture_output=True, text=True)
    if json.load(open(lim))["worst_case"]["energy_ratio"]["status"] != "undecided" or rc.returncode != 0:
        fail(f"the prover's own undecided worst case (--max-faces 2): exit {rc.returncode} {rc.stdout}{rc.stderr}")
    # Values below 1 ("0.09" once read "0.11" as octal 9/100) and an exact tie at the 17th digit
    # without "exact" (10.0000005681450625: ~10.000000568145063, away from zero); the honest
    # certificates verify, one digit off is rejected.
    def one_contact(q):
        return {"format": "impactcert-law/1", "name": "one-contact", "masses": ["1", "1"], "contacts": "chain",
                "pieces": [{"name": "A", "Q": [[q]], "rays": [["1"]]}, {"name": "B", "Q": [[q]], "rays": [["-1"]]}]}

    for q, forged in (("3/10", "0.11"), ("1/2", "0.24"), ("1/3", "~0.11111111111111112"),
                      ("316227775/100000000", "~10.000000568145062")):
        lp, cp = os.path.join(tmp, "one.json"), os.path.join(tmp, "one.cert.json")
        json.dump(one_contact(q), open(lp, "w"))
        subprocess.run([CLI, "certify", "--law", lp, "--worst-case", "-o", cp], capture_output=True)
        if not os.path.exists(cp):
            fail(f"q = {q}: no certificate")
            continue
        one = json.load(open(cp))
        r = subprocess.run([CHECK, cp], capture_output=True, text=True)
        if r.returncode != 0:
            fail(f"q = {q}: the honest certificate ({w(one)['value']['decimal']}) is rejected: {r.stdout}{r.stderr}")
        forge(one, "energy_ratio.value.decimal", lambda c, f=forged: w(c)["value"].update(decimal=f))
    print("28 forgeries of worst-case certificates rejected, each naming its path")

finish(failures)
