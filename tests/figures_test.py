#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Figures and tables for papers: `report` writes law.tex, verdicts.tex and standalone figures
(figures/cones, unit-circle, planes: SVG and PDF), `sweep` one figure per map.

Checked by a second route:
- law.tex read back (\\frac, pmatrix) equals the law file exactly, piece by piece (Q exactly, each
  ray a positive multiple of the file's: the tables show primitive rays); names with
  every LaTeX special character come out escaped; verdicts.tex equals `verify --json`.
- unit-circle.svg: the ratio of the drawn radius
  to the dashed circle's is ||S(g)||_H / ||g||_H: exactly 1 everywhere for the paper's elastic law,
  and for the approaching-only Newton law of three balls at most sqrt(4/3) (its exact sup, Lemma
  W) and within 1% of it.
- planes.svg (c = 4): in every panel, random rational directions of the plane are located in a
  cone by solving R lambda = x exactly; that cone is among the panel's ring, and every ring cone
  contains a direction of the plane (negative control: a cone that misses the plane is not drawn).
- Every SVG is XML with a viewBox, the title and the legend; every PDF is one page of the SVG's
  size (pdfinfo, poppler-utils) and renders (pdftoppm).
- Without rsvg-convert on PATH: the SVGs only, and one note on stderr. A converter that fails or
  writes without end: exit 2, one line naming the PDF, and no PDF and no temporary file left.
- c = 12: no plane view, and report.html and report.md say why.
Usage: figures_test.py BIN_DIR [--light]  (light, for the sanitizer build: fewer exact directions per
plane, and the sweep's figures left to the Release build; every program run and assertion else the
same)"""
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from fractions import Fraction as F

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from testkit import finish  # noqa: E402

BIN = os.path.abspath(sys.argv[1])
CLI = os.path.join(BIN, "impactcert")
LIGHT = "--light" in sys.argv[2:]
HERE = os.path.dirname(os.path.abspath(__file__))
tmp = tempfile.mkdtemp(prefix="impactcert-figures-")
failures = []
SVG = "{http://www.w3.org/2000/svg}"


def fail(msg):
    failures.append(msg)


def run(args, env=None, ok=(0,)):
    r = subprocess.run([CLI] + args, capture_output=True, text=True, env=env)
    if r.returncode not in ok:
        fail(f"{' '.join(args)}: exit {r.returncode}: {r.stderr.strip()}")
    return r


def derive(kind, *args):
    out = os.path.join(tmp, f"{kind}-{len(os.listdir(tmp))}.json")
    run(["derive", kind] + list(args) + ["-o", out])
    return out


# ---------------------------------------------------------------------------------------------
# LaTeX read back: \frac{a}{b}, integers, pmatrix rows.

def tex_number(t):
    t = t.strip()
    m = re.fullmatch(r"(-?)\\frac\{(\d+)\}\{(\d+)\}", t)
    if m:
        return (-1 if m.group(1) else 1) * F(int(m.group(2)), int(m.group(3)))
    if not re.fullmatch(r"-?\d+", t):
        raise ValueError(f"not a number: {t!r}")
    return F(int(t))


def pmatrices(t):
    return [[[tex_number(x) for x in row.split("&")] for row in body.split("\\\\")]
            for body in re.findall(r"\\begin\{pmatrix\}(.*?)\\end\{pmatrix\}", t)]


def tex_unescape(t):
    for a, b in [("\\textbackslash{}", "\\"), ("\\textasciicircum{}", "^"), ("\\textasciitilde{}", "~"), ("\\{", "{"),
                 ("\\}", "}"), ("\\$", "$"), ("\\&", "&"), ("\\#", "#"), ("\\_", "_"), ("\\%", "%")]:
        t = t.replace(a, b)
    return t


def check_law_tex(law_path, tex_path, what):
    law = json.load(open(law_path))
    text = open(tex_path).read()
    rows = [line for line in text.splitlines() if line.startswith("\\texttt{")]
    if len(rows) != len(law["pieces"]):
        fail(f"{what}: law.tex has {len(rows)} rows for {len(law['pieces'])} pieces")
        return
    for row, piece in zip(rows, law["pieces"]):
        m = re.match(r"\\texttt\{(.*?)\} & \$(.*)\$ & \$(.*)\$ \\\\$", row)
        if not m:
            fail(f"{what}: a row not of the form name & rays & Q: {row}")
            continue
        name = tex_unescape(m.group(1))
        rays = [[r[0] for r in col] for col in pmatrices(m.group(2))]
        Q = pmatrices(m.group(3))[0]
        if name != piece["name"]:
            fail(f"{what}: name {name!r} != {piece['name']!r}")
        if Q != [[F(x) for x in r] for r in piece["Q"]]:
            fail(f"{what}: {name}: Q read back {Q} != the law's")
        if "rays" in piece:
            for got, want in zip(rays, piece["rays"]):
                want = [F(x) for x in want]
                k = next(F(g) / w for g, w in zip(got, want) if w != 0)
                if k <= 0 or [k * w for w in want] != got:
                    fail(f"{what}: {name}: ray {got} is not a positive multiple of {want}")
            if len(rays) != len(piece["rays"]):
                fail(f"{what}: {name}: {len(rays)} rays for {len(piece['rays'])}")
    if "\\begin{tabular}" not in text and "\\begin{longtable}" not in text:
        fail(f"{what}: no table environment")


# ---------------------------------------------------------------------------------------------
# SVG and PDF

def parse_svg(path, title_prefix, legend):
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        fail(f"{path}: not XML: {e}")
        return None
    if root.tag != SVG + "svg" or "viewBox" not in root.attrib:
        fail(f"{path}: no <svg> with a viewBox")
    texts = ["".join(t.itertext()) for t in root.iter(SVG + "text")]
    if not any(t.startswith(title_prefix) for t in texts):
        fail(f"{path}: no title starting {title_prefix!r}")
    for label in legend:
        if label not in texts:
            fail(f"{path}: legend lacks {label!r}")
    return root


def check_pdf(svg_path):
    pdf = svg_path[:-4] + ".pdf"
    if not os.path.exists(pdf):
        fail(f"{pdf}: not written")
        return
    data = open(pdf, "rb").read()
    if not data.startswith(b"%PDF-") or b"%%EOF" not in data[-64:]:
        fail(f"{pdf}: not a whole PDF")
    info = subprocess.run(["pdfinfo", pdf], capture_output=True, text=True).stdout
    pages = re.search(r"Pages:\s+(\d+)", info)
    size = re.search(r"Page size:\s+([\d.]+) x ([\d.]+) pts", info)
    root = ET.parse(svg_path).getroot()
    w, h = float(root.attrib["width"]), float(root.attrib["height"])
    if not pages or pages.group(1) != "1":
        fail(f"{pdf}: not one page: {info!r}")
    # rsvg-convert: 96 pixels per inch, 72 points per inch.
    elif not size or abs(float(size.group(1)) - w * 0.75) > 1 or abs(float(size.group(2)) - h * 0.75) > 1:
        fail(f"{pdf}: page size {size and size.groups()} is not the SVG's {w} x {h} px")
    png = pdf[:-4] + "-render"
    r = subprocess.run(["pdftoppm", "-png", "-r", "30", "-singlefile", pdf, png], capture_output=True, text=True)
    if r.returncode != 0 or os.path.getsize(png + ".png") < 1000:
        fail(f"{pdf}: pdftoppm could not render it: {r.stderr.strip()}")


def circles_and_curves(root):
    """Per panel centre: the dashed circle's radius and every curve point as (cx, cy, x, y, class)."""
    dashed = [(float(c.attrib["cx"]), float(c.attrib["cy"]), float(c.attrib["r"])) for c in root.iter(SVG + "circle")
              if c.attrib.get("stroke-dasharray")]
    points = []
    for g in root.iter(SVG + "g"):
        cls = g.attrib.get("class", "")
        if cls not in ("image-curve", "ratio-curve"):
            continue
        poly = g.find(SVG + "polyline")
        for pair in poly.attrib["points"].split():
            x, y = map(float, pair.split(","))
            points.append((x, y, cls))
    return dashed, points


def ratios(root, cls):
    dashed, points = circles_and_curves(root)
    out = []
    for x, y, c in points:
        if c != cls:
            continue
        cx, cy, r = min(dashed, key=lambda d: (d[0] - x) ** 2 + (d[1] - y) ** 2)
        out.append(math.hypot(x - cx, y - cy) / r)
    return out


# ---------------------------------------------------------------------------------------------
# The paper's law: c = 2, elastic

paper = os.path.join(tmp, "paper")
r = run(["report", "-o", paper])
want = [f"{paper}/{f}" for f in ["report.md", "report.html", "law.tex", "verdicts.tex", "figures/cones.svg",
                                 "figures/cones.pdf", "figures/unit-circle.svg", "figures/unit-circle.pdf"]]
if r.stdout.split() != want:
    fail(f"report's output lists {r.stdout.split()}, not {want}")
if r.stderr:
    fail(f"report wrote to stderr with rsvg-convert present: {r.stderr!r}")
paper_law = os.path.join(HERE, "..", "proofs", "newton3", "law.json")  # the embedded default
check_law_tex(paper_law, f"{paper}/law.tex", "paper law.tex")
verdict = json.loads(subprocess.run([CLI, "verify", "--json"], capture_output=True, text=True).stdout)
vt = open(f"{paper}/verdicts.tex").read()
for o in verdict["obligations"]:
    row = re.search(r"\\texttt\{" + re.escape(o["id"]) + r"\} & (yes|no) & (\d+) & (\w+) \\\\", vt)
    if not row or row.group(3) != o["verdict"] or (row.group(1) == "yes") != o["claimed"] or int(row.group(2)) != o["checks"]:
        fail(f"verdicts.tex: {o['id']}: {row and row.groups()} != {o['claimed'], o['checks'], o['verdict']}")
if f"Gate: {verdict['verdict']}" not in vt:
    fail("verdicts.tex: no gate line")
root = parse_svg(f"{paper}/figures/unit-circle.svg", "newton3-sequential: S along the unit circle",
                 ["‖γ⁻‖_H = 1", "I", "IIa", "IVa"])
if root is not None:
    rs = ratios(root, "ratio-curve") + ratios(root, "image-curve")
    if len(rs) < 100 or max(abs(x - 1) for x in rs) > 0.003:
        fail(f"paper's law is elastic: every curve point should be on the unit circle; {len(rs)} points, "
             f"off by up to {max(abs(x - 1) for x in rs) if rs else None}")
parse_svg(f"{paper}/figures/cones.svg", "newton3-sequential: the cones", ["I", "IIb"])
for stem in ["cones", "unit-circle"]:
    check_pdf(f"{paper}/figures/{stem}.svg")
if 'class="image-curve"' not in open(f"{paper}/report.html").read():
    fail("report.html lacks the unit-circle figure")

# ---------------------------------------------------------------------------------------------
# The approaching-only Newton law of three balls: sup T+/T- = 4/3 exactly (Lemma W)

ap3 = derive("newton", "--masses", "1,1,1", "--restitution", "1", "--restitution-on", "approaching")
run(["report", "--law", ap3, "-o", os.path.join(tmp, "ap3")])
check_law_tex(ap3, os.path.join(tmp, "ap3", "law.tex"), "approaching-3 law.tex")
root = parse_svg(os.path.join(tmp, "ap3", "figures", "unit-circle.svg"), "newton-approaching-3-balls", ["free", "J12/e1"])
if root is not None:
    rs = ratios(root, "ratio-curve")
    top = max(rs)
    if not (math.sqrt(4 / 3) * 0.99 <= top <= math.sqrt(4 / 3) + 0.003):
        fail(f"approaching-3: largest drawn ratio {top}, the exact sup is sqrt(4/3) = {math.sqrt(4 / 3)}")
    if min(rs) < 1 - 0.003:
        fail(f"approaching-3: a drawn ratio {min(rs)} below 1 (the law never loses energy at e = 1)")
    # Energy is gained off the positive cone: some drawn point is outside the circle.
    if sum(1 for x in rs if x > 1.01) < 10:
        fail("approaching-3: the ratio curve never leaves the unit circle")

# ---------------------------------------------------------------------------------------------
# A gain hidden in a thin-ray cone (review): cone A between (1000, 1) and (0, 1) with
# Q = 3/5 [[1, 1], [1, 1]] reaches T+/T- = 36/25 at (1, 1); the other cones are the identity.
# Sampled by equal steps between the rays, A was one chord that stayed inside the circle and the
# identity D dipped to 0.52. The curves must follow the angle: every identity point at ratio 1,
# A's largest within 1% of sqrt(36/25) = 6/5, and no gap between neighbouring points over 3 degrees.

hide = os.path.join(tmp, "hide.json")
json.dump({"format": "impactcert-law/1", "name": "hidden-gain", "masses": ["1", "1", "1"], "pieces": [
    {"name": "A", "Q": [["3/5", "3/5"], ["3/5", "3/5"]], "rays": [["1000", "1"], ["0", "1"]]},
    {"name": "B", "Q": [["1", "0"], ["0", "1"]], "rays": [["0", "1"], ["-1", "0"]]},
    {"name": "C", "Q": [["1", "0"], ["0", "1"]], "rays": [["-1", "0"], ["0", "-1"]]},
    {"name": "D", "Q": [["1", "0"], ["0", "1"]], "rays": [["0", "-1"], ["1000", "1"]]}]}, open(hide, "w"))
run(["report", "--law", hide, "-o", os.path.join(tmp, "hide")], ok=(0, 1))
root = parse_svg(os.path.join(tmp, "hide", "figures", "unit-circle.svg"), "hidden-gain: S along", ["A", "D"])
if root is not None:
    dashed, _ = circles_and_curves(root)
    right = max(dashed)  # the right panel: the ratio in the direction of gamma-
    by_piece = {}
    for g in root.iter(SVG + "g"):
        if g.attrib.get("class") != "ratio-curve":
            continue
        name = "".join(g.find(SVG + "title").itertext())
        pts = [tuple(map(float, p.split(","))) for p in g.find(SVG + "polyline").attrib["points"].split()]
        by_piece.setdefault(name, []).append(pts)
    for name, curves in by_piece.items():
        for pts in curves:
            rs = [math.hypot(x - right[0], y - right[1]) / right[2] for x, y in pts]
            angles = [math.atan2(right[1] - y, x - right[0]) for x, y in pts]
            gaps = [abs(math.remainder(b - a, 2 * math.pi)) for a, b in zip(angles, angles[1:])]
            if max(gaps) > math.radians(3):
                fail(f"hidden-gain {name}: neighbouring curve points {math.degrees(max(gaps)):.1f} degrees apart")
            if name != "A" and max(abs(r - 1) for r in rs) > 0.005:
                fail(f"hidden-gain {name}: the identity drawn at ratios {min(rs):.3f}..{max(rs):.3f}, not 1")
            if name == "A" and not (1.2 * 0.99 <= max(rs) <= 1.2 + 0.005):
                fail(f"hidden-gain A: largest drawn ratio {max(rs):.4f}, the exact sup is 6/5")
    if sorted(by_piece) != ["A", "B", "C", "D"]:
        fail(f"hidden-gain: ratio curves for {sorted(by_piece)}")

# ---------------------------------------------------------------------------------------------
# Cones narrower than a double can tell (review): rays (10^20 + 1, 1) and (10^20, 1) have the same
# angle in double. Sampled between them, the arc gave the zero vector and a division by zero
# (SIGFPE). c = 2 (the unit circle) and c = 3 (a plane of the plane view).

big = "100000000000000000000"
for name, rays in [("thin-2", [[big[:-1] + "1", "1"], [big, "1"]]),
                   ("thin-3", [[big[:-1] + "1", "1", "0"], [big, "1", "0"], ["0", "0", "1"]])]:
    c = len(rays)
    thin = os.path.join(tmp, name + ".json")
    json.dump({"format": "impactcert-law/1", "name": name, "masses": ["1"] * (c + 1),
               "pieces": [{"name": "T", "Q": [[str(int(i == j)) for j in range(c)] for i in range(c)], "rays": rays}]},
              open(thin, "w"))
    r = run(["report", "--law", thin, "-o", os.path.join(tmp, name)])
    for f in ["unit-circle.svg"] if c == 2 else ["cones.svg", "planes.svg"]:
        parse_svg(os.path.join(tmp, name, "figures", f), name + ":", [])

# ---------------------------------------------------------------------------------------------
# Names the figures and tables must survive: XML non-characters, 200,000 characters, non-ASCII

law = json.load(open(os.path.join(HERE, "..", "proofs", "newton3", "law.json")))
law["name"] = "x\ufffey\uffff" + "L" * 200000
law["pieces"][0]["name"] = "γ⁻\ufffe"
odd_names = os.path.join(tmp, "odd-names.json")
json.dump(law, open(odd_names, "w"))
started = time.monotonic()
r = run(["report", "--law", odd_names, "-o", os.path.join(tmp, "odd-names")])
if time.monotonic() - started > 60:
    fail(f"a 200,000-character name: report took {time.monotonic() - started:.0f} s")
for f in ["cones.svg", "unit-circle.svg"]:
    root = parse_svg(os.path.join(tmp, "odd-names", "figures", f), "x\ufffdy\ufffdLLL", [])
    if root is not None:
        title = "".join(next(root.iter(SVG + "text")).itertext())
        if len(title) > 130 or not title.endswith("..."):
            fail(f"{f}: a 200,000-character name gives a title of {len(title)} characters")
tex = open(os.path.join(tmp, "odd-names", "law.tex")).read() if os.path.exists(os.path.join(tmp, "odd-names", "law.tex")) else ""
if "\\texttt{[U+03B3][U+207B][U+FFFE]}" not in tex or any(ord(ch) > 127 for ch in tex):
    fail("law.tex: non-ASCII names are not written as [U+XXXX]")

# ---------------------------------------------------------------------------------------------
# c = 4: the plane view, checked by locating directions exactly

# (Left to the Release run under --light: the sanitizer build draws the planes of a c = 4 law
# in-process in tests/report_test.cpp, and this law's verification alone takes 21 s there.)
if not LIGHT:
    ap5 = derive("newton", "--masses", "1,1,1,1,1", "--restitution", "1", "--restitution-on", "approaching")
    d5 = os.path.join(tmp, "ap5")
    r = run(["report", "--law", ap5, "-o", d5])
    if r.stdout.split() != [f"{d5}/{f}" for f in ["report.md", "report.html", "law.tex", "verdicts.tex",
                                                    "figures/planes.svg", "figures/planes.pdf"]]:
        fail(f"c = 4 report lists {r.stdout.split()}")
    check_law_tex(ap5, os.path.join(d5, "law.tex"), "approaching-5 law.tex")
    if "\\begin{longtable}" not in open(os.path.join(d5, "law.tex")).read():
        fail("92 pieces: law.tex should be a longtable")
    root = parse_svg(os.path.join(d5, "figures", "planes.svg"), "newton-approaching-5-balls: the law on the planes",
                     ["no cone in a sector"])
    check_pdf(os.path.join(d5, "figures", "planes.svg"))
    if "figures/planes.svg" not in open(os.path.join(d5, "report.md")).read():
        fail("report.md of a c = 4 law does not point to the plane view")


    def solve(R, x):
        """lambda with R lambda = x, exactly (Gauss-Jordan over fractions); R given as columns."""
        n = len(x)
        A = [[R[j][i] for j in range(n)] + [x[i]] for i in range(n)]
        for col in range(n):
            piv = next(r for r in range(col, n) if A[r][col] != 0)
            A[col], A[piv] = A[piv], A[col]
            for r in range(n):
                if r != col and A[r][col] != 0:
                    k = A[r][col] / A[col][col]
                    A[r] = [a - k * b for a, b in zip(A[r], A[col])]
        return [A[i][n] / A[i][i] for i in range(n)]


    if root is not None:
        law = json.load(open(ap5))
        pieces = [(p["name"], [[F(v) for v in ray] for ray in p["rays"]]) for p in law["pieces"]]
        panels = [g for g in root.iter(SVG + "g") if g.attrib.get("class") == "plane"]
        c = 4
        planes = [(i, j) for i in range(c) for j in range(i + 1, c)]
        if len(panels) != len(planes):
            fail(f"c = 4: {len(panels)} panels, not {len(planes)}")
        rng = random.Random(7)
        drawn_total = 0
        for (i, j), panel in zip(planes, panels):
            head = "".join(next(panel.iter(SVG + "text")).itertext())
            if head != f"γ{i + 1}, γ{j + 1}":
                fail(f"panel {head!r} is not the plane of contacts {i + 1}, {j + 1}")
            ring = {"".join(p.find(SVG + "title").itertext()).split(":")[0] for p in panel.iter(SVG + "path")}
            drawn_total += len(ring)
            for _ in range(20 if LIGHT else 60):
                x = [F(0)] * c
                x[i], x[j] = F(rng.randint(-50, 50), rng.randint(1, 9)), F(rng.randint(-50, 50), rng.randint(1, 9))
                if x[i] == 0 and x[j] == 0:
                    continue
                inside = [name for name, rays in pieces if all(v >= 0 for v in solve(rays, x))]
                if not inside:
                    fail(f"plane {i + 1},{j + 1}: {x} in no cone (the law tiles)")
                elif all(v not in ring for v in inside):
                    fail(f"plane {i + 1},{j + 1}: {x} lies in {inside}, none of which the ring draws")
            # Every ring cone meets the plane in a sector: some direction of the plane lies inside it
            # with two non-zero free coordinates (checked along a fine exact fan of directions).
            for name in ring:
                rays = dict(pieces)[name]
                hit = False
                fan = 240 if LIGHT else 720
                for k in range(fan):
                    a = 2 * math.pi * (k + 0.5) / fan
                    x = [F(0)] * c
                    x[i], x[j] = F(round(1000 * math.cos(a)), 1000), F(round(1000 * math.sin(a)), 1000)
                    if all(v >= 0 for v in solve(rays, x)):
                        hit = True
                        break
                if not hit:
                    fail(f"plane {i + 1},{j + 1}: ring draws {name}, which meets no direction of the plane")
        if drawn_total >= len(planes) * len(pieces):
            fail("negative control: every cone drawn in every plane")

# ---------------------------------------------------------------------------------------------
# Names with LaTeX's special characters

law = json.load(open(ap3))
law["pieces"][0]["name"] = "a_b&c%d$e#f{g}h~i^j\\k"
odd = os.path.join(tmp, "odd.json")
json.dump(law, open(odd, "w"))
run(["report", "--law", odd, "-o", os.path.join(tmp, "odd")], ok=(0, 1))
tex = open(os.path.join(tmp, "odd", "law.tex")).read()
if "\\texttt{a\\_b\\&c\\%d\\$e\\#f\\{g\\}h\\textasciitilde{}i\\textasciicircum{}j\\textbackslash{}k}" not in tex:
    fail("law.tex: a name with LaTeX specials is not escaped")
check_law_tex(odd, os.path.join(tmp, "odd", "law.tex"), "odd names law.tex")

# ---------------------------------------------------------------------------------------------
# c = 12: no plane view, and why

big = os.path.join(HERE, "laws", "one-piece-c12.json")
d12 = os.path.join(tmp, "c12")
r = run(["report", "--law", big, "-o", d12], ok=(0, 1))
if os.path.exists(os.path.join(d12, "figures")):
    fail("c = 12: a figures directory written")
for f in ["report.html", "report.md"]:
    if "12 contacts make 66 planes" not in open(os.path.join(d12, f)).read():
        fail(f"c = 12: {f} does not say why there is no plane view")

# ---------------------------------------------------------------------------------------------
# Sweep: one figure per map

sw = os.path.join(tmp, "sweep")
r = None if LIGHT else run(["sweep", "--masses", "1,m,1", "--vary", "m=1/2..2:3", "--vary", "e=1/2..1:2", "--restitution", "e", "-o", sw])
maps = [] if LIGHT else sorted(f for f in os.listdir(os.path.join(sw, "figures")) if f.endswith(".svg"))
ids = json.loads(subprocess.run([CLI, "verify", "--json"], capture_output=True, text=True).stdout)["obligations"]
want_maps = sorted([o["id"] + ".svg" for o in ids] + ["order-independent.svg"])
if not LIGHT and maps != want_maps:
    fail(f"sweep figures: {maps} != {want_maps}")
for m in maps:
    root = parse_svg(os.path.join(sw, "figures", m), m[:-4] + ": impactcert sweep: masses 1,m,1",
                     ["proved", "refuted", "undecided", "skipped", "no finite law"])
    if root is not None and len([x for x in root.iter(SVG + "rect") if x.find(SVG + "title") is not None]) != 6:
        fail(f"sweep figure {m}: not one cell per grid point (6)")
    check_pdf(os.path.join(sw, "figures", m))

# ---------------------------------------------------------------------------------------------
# Without rsvg-convert, with one that fails, with one that writes without end

bare = os.path.join(tmp, "bin-bare")
os.makedirs(bare)
env = dict(os.environ, PATH=bare)
r = run(["report", "-o", os.path.join(tmp, "nopdf")], env=env)
if sorted(os.listdir(os.path.join(tmp, "nopdf", "figures"))) != ["cones.svg", "unit-circle.svg"]:
    fail(f"without rsvg-convert: {os.listdir(os.path.join(tmp, 'nopdf', 'figures'))}")
if r.stderr.count("\n") != 1 or "rsvg-convert is not on PATH" not in r.stderr:
    fail(f"without rsvg-convert: stderr {r.stderr!r}")
for script, what in [("#!/bin/sh\necho half a PDF\nexit 1\n", "exited with status 1"),
                     ("#!/bin/sh\nexec cat /dev/zero\n", "more than 256 MiB")]:
    fake = os.path.join(tmp, "bin-fake")
    shutil.rmtree(fake, ignore_errors=True)
    os.makedirs(fake)
    with open(os.path.join(fake, "rsvg-convert"), "w") as f:
        f.write(script)
    os.chmod(os.path.join(fake, "rsvg-convert"), 0o755)
    out = os.path.join(tmp, "badpdf")
    shutil.rmtree(out, ignore_errors=True)
    r = run(["report", "-o", out], env=dict(os.environ, PATH=fake + ":/usr/bin:/bin"), ok=(2,))
    lines = r.stderr.strip().splitlines()
    if len(lines) != 1 or "figures/cones.pdf" not in lines[0] or what not in lines[0]:
        fail(f"a converter that fails ({what}): stderr {r.stderr!r}")
    left = os.listdir(os.path.join(out, "figures"))
    if left != ["cones.svg"]:
        fail(f"a converter that fails ({what}): left {left} (no PDF, no temporary file)")

# ---------------------------------------------------------------------------------------------
# c = 3: the sphere (issue 40, item 10). Each cone is clipped to its hemisphere along great-circle
# arcs and the rim (no chords across the disk: every drawn segment is short and every point lies
# on the disk), numbered once, and every number's place is located by a second route: the point
# is lifted back onto the sphere with the views' axes and solved exactly for the cone's
# coordinates (R lambda = x, lambda >= 0 up to the drawing's rounding). Neighbouring cones (two
# rays in common) have different colours; the key names every cone.

def sphere_checks(law_path, out):
    law = json.load(open(law_path))
    run(["report", "--law", law_path, "-o", out])
    root = ET.parse(os.path.join(out, "figures", "cones.svg")).getroot()
    inner = next(e for e in root.iter(SVG + "svg") if e is not root)
    disks = {}
    for cp in inner.iter(SVG + "clipPath"):
        circle = next(cp.iter(SVG + "circle"))
        disks[cp.attrib["id"]] = (float(circle.attrib["cx"]), float(circle.attrib["cy"]), float(circle.attrib["r"]))
    if sorted(disks) != ["hemisphere0", "hemisphere1"]:
        fail(f"{law_path}: the sphere has no two hemispheres: {sorted(disks)}")
        return
    s2, s3, s6 = math.sqrt(2), math.sqrt(3), math.sqrt(6)
    axes = {"hemisphere0": ((1 / s2, -1 / s2, 0), (-1 / s6, -1 / s6, 2 / s6), (1 / s3, 1 / s3, 1 / s3)),
            "hemisphere1": ((-1 / s2, 1 / s2, 0), (-1 / s6, -1 / s6, 2 / s6), (-1 / s3, -1 / s3, -1 / s3))}
    pieces = law["pieces"]
    colour = {}
    longest = 0.0
    for g in inner.iter(SVG + "g"):
        clip = g.attrib.get("clip-path", "")
        if not clip.startswith("url(#hemisphere"):
            continue
        cx, cy, r = disks[clip[5:-1]]
        for poly in g.iter(SVG + "polygon"):
            pts = [tuple(map(float, xy.split(","))) for xy in poly.attrib["points"].split()]
            number = int("".join(poly.find(SVG + "title").itertext()).split(".")[0])
            colour.setdefault(number, set()).add(poly.attrib["fill"])
            for k, (x, y) in enumerate(pts):
                if math.hypot(x - cx, y - cy) > r + 0.6:
                    fail(f"{law_path}: cone {number} spills outside its hemisphere at ({x}, {y})")
                    break
                x2, y2 = pts[(k + 1) % len(pts)]
                longest = max(longest, math.hypot(x2 - x, y2 - y) / r)
    if longest > 0.12:
        fail(f"{law_path}: a cone's outline has a straight segment of {longest:.2f} r (a chord, not an arc)")
    if any(len(fills) != 1 for fills in colour.values()) or sorted(colour) != list(range(1, len(pieces) + 1)):
        fail(f"{law_path}: cones drawn {sorted(colour)}, colours {colour}")
        return

    def direction(ray):
        v = [F(x) for x in ray]
        top = max(abs(x) for x in v)
        return tuple(x / top for x in v)
    rays = [[direction(ray) for ray in p["rays"]] for p in pieces]
    for a in range(len(pieces)):
        for b in range(a + 1, len(pieces)):
            if len(set(rays[a]) & set(rays[b])) >= 2 and colour[a + 1] == colour[b + 1]:
                fail(f"{law_path}: neighbouring cones {a + 1} and {b + 1} share the colour {colour[a + 1]}")
    # The numbers, each once, each inside its cone (lifted to the sphere, solved for lambda).
    elements = list(inner.iter())
    seen = []
    for i, e in enumerate(elements):
        if e.tag != SVG + "text" or e.attrib.get("class") != "cone-label":
            continue
        number = int("".join(e.itertext()))
        seen.append(number)
        if elements[i - 2].tag == SVG + "polyline":
            x, y = map(float, elements[i - 2].attrib["points"].split()[0].split(","))
        else:
            x, y = float(e.attrib["x"]), float(e.attrib["y"]) - 3.8
        view = next((v for v, (cx, cy, r) in disks.items() if math.hypot(x - cx, y - cy) < r), None)
        if view is None:
            fail(f"{law_path}: number {number} at ({x}, {y}) lies on no hemisphere")
            continue
        cx, cy, r = disks[view]
        a1, a2, n = axes[view]
        p, q = (x - cx) / r, -(y - cy) / r
        h = math.sqrt(max(0.0, 1 - p * p - q * q))
        X = [p * a1[k] + q * a2[k] + h * n[k] for k in range(3)]
        R = [[float(F(pieces[number - 1]["rays"][j][i])) for j in range(3)] for i in range(3)]
        # lambda = R^-1 X by Cramer's rule
        def det(m):
            return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                    + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
        d = det(R)
        lam = [det([[X[i] if j == col else R[i][j] for j in range(3)] for i in range(3)]) / d for col in range(3)]
        scale = max(abs(v) for v in lam)
        if min(lam) < -0.02 * scale:
            fail(f"{law_path}: number {number} is drawn outside cone {number} (lambda = {lam})")
    if sorted(seen) != list(range(1, len(pieces) + 1)):
        fail(f"{law_path}: numbers drawn {sorted(seen)}, not each of 1..{len(pieces)} once")
    texts = ["".join(t.itertext()) for t in inner.iter(SVG + "text")]
    for k, p in enumerate(pieces):
        if f"{k + 1}  {p['name']}" not in texts:
            fail(f"{law_path}: the key lacks {k + 1}  {p['name']}")
    if not failures:
        print(f"sphere of {law['name']}: {len(pieces)} cones inside their hemispheres, arcs no longer than "
              f"{longest:.3f} r, numbered inside their cones, neighbours coloured apart")


sphere_checks(os.path.join(HERE, "..", "proofs", "newton4", "law.json"), os.path.join(tmp, "sphere-newton4"))
sphere_checks(derive("newton", "--masses", "1,1,1,1", "--restitution", "1", "--restitution-on", "approaching"),
              os.path.join(tmp, "sphere-approaching4"))
# Bare figures (--bare-figures): no title and no caption drawn, the legend kept.
run(["report", "--law", os.path.join(HERE, "..", "proofs", "newton4", "law.json"), "--bare-figures", "-o",
     os.path.join(tmp, "bare")])
bare = ET.parse(os.path.join(tmp, "bare", "figures", "cones.svg")).getroot()
outer = ["".join(e.itertext()) for e in bare if e.tag == SVG + "text"]
if any(t.startswith("newton4-sort") or t.startswith("The cones") for t in outer):
    fail(f"--bare-figures: a title or caption is drawn: {[t[:40] for t in outer]}")
full = ET.parse(os.path.join(tmp, "sphere-newton4", "figures", "cones.svg")).getroot()
if not any("".join(e.itertext()).startswith("newton4-sort") for e in full if e.tag == SVG + "text"):
    fail("without --bare-figures the figure has no title (the negative control of the check above)")

finish(failures)
