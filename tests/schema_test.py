#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""The formats of docs/formats.md against their JSON Schemas (docs/schemas/), with Debian's
python3-jsonschema (Draft 2020-12): every committed law, system, scene and certificate, and the
real outputs of the programs -- verify --json (proved, refuted, undecided), certificates and their
shard parts, derived laws, derive's --json witnesses, fuzz --json in both modes, sweep.json and
sweep parts. Negative controls: documents one change away from valid are rejected by the schema.
Usage: schema_test.py BINDIR SOURCE_DIR"""
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile

from testkit import finish

try:
    import jsonschema
except ImportError:  # a Python of its own on PATH (pyenv): Debian's python3 has the package
    if os.path.exists("/usr/bin/python3") and os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3"] + sys.argv)
    print("FAIL: python3-jsonschema is not installed (scripts/test installs it)")
    sys.exit(1)
from jsonschema import Draft202012Validator

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
CLI = os.path.join(BIN, "impactcert")
SCHEMAS = os.path.join(SRC, "docs", "schemas")
store = {}
for path in glob.glob(os.path.join(SCHEMAS, "*.schema.json")):
    s = json.load(open(path))
    Draft202012Validator.check_schema(s)
    store[s["$id"]] = s
    store[os.path.basename(path)] = s
failures = []
validated = {}


def validator(name):
    return Draft202012Validator(store[name])  # each schema stands alone (no references between files)


def check(name, doc, where):
    errors = sorted(validator(name).iter_errors(doc), key=lambda e: list(e.path))
    if errors:
        e = errors[0]
        failures.append(f"{where}: not a valid {name}: at {'/'.join(map(str, e.path))}: {e.message[:200]}")
    validated[name] = validated.get(name, 0) + 1
    if name.startswith("certificate") and isinstance(doc, dict) and "law" in doc:
        check("law.schema.json", doc["law"], where + ": its law")


def rejects(name, doc, what):
    if not list(validator(name).iter_errors(doc)):
        failures.append(f"negative control accepted by {name}: {what}")


def run(args, expect, stdout=True):
    p = subprocess.run([CLI] + args, capture_output=True, text=True)
    if p.returncode != expect:
        failures.append(f"impactcert {' '.join(args)}: exit {p.returncode}, expected {expect}: {p.stderr.strip()[:200]}")
        return None
    return json.loads(p.stdout) if stdout else p


tmp = tempfile.mkdtemp(prefix="impactcert-schema-")
try:
    # ---- committed documents
    by_format = {"impactcert-law/1": "law.schema.json", "impactcert-system/1": "system.schema.json",
                 "impactcert-scene/1": "scene.schema.json", "impactcert-certificate/1": "certificate.schema.json"}
    committed = 0
    for path in sorted(glob.glob(os.path.join(SRC, "proofs", "**", "*.json"), recursive=True) +
                       glob.glob(os.path.join(SRC, "examples", "**", "*.json"), recursive=True)):
        doc = json.load(open(path))
        fmt = doc.get("format") if isinstance(doc, dict) else None
        if fmt in by_format:
            check(by_format[fmt], doc, os.path.relpath(path, SRC))
            committed += 1
    if committed < 30:
        failures.append(f"only {committed} committed documents found")

    # ---- outputs
    law = os.path.join(tmp, "law.json")
    for args in (["derive", "sequential", "--masses", "1,2,3", "--restitution", "1/2"],
                 ["derive", "newton", "--masses", "1,1,1,1"], ["derive", "poisson", "--masses", "1,2,1", "--walls", "left"],
                 ["derive", "cradle", "--balls", "4"], ["derive", "newton", "--system",
                                                       os.path.join(SRC, "proofs", "kane", "gains", "system.json")]):
        if run(args + ["-o", law], 0, stdout=False):
            check("law.schema.json", json.load(open(law)), " ".join(args))
    verify_runs = ((["verify", "--json"], 0, False),
                   (["verify", "--json", "--law", os.path.join(SRC, "proofs", "classical3", "newton", "law.json")], 1, False),
                   (["verify", "--json", "--law", os.path.join(SRC, "proofs", "kane", "gains", "law.json")], 1, False),
                   # energetic undecided there (not claimed), another claim refuted: exit 1
                   (["verify", "--json", "--max-faces", "100", "--law", os.path.join(SRC, "tests", "laws", "one-piece-c8.json")], 1, True),
                   (["verify", "--stream", "--json", "--law", os.path.join(SRC, "proofs", "cradle4", "law.json")], 0, False))
    for args, expect, undecided in verify_runs:
        doc = run(args, expect)
        if doc is not None:
            check("verdict.schema.json", doc, " ".join(args))
            if undecided and not any(o["verdict"] == "undecided" for o in doc["obligations"]):
                failures.append("the undecided run has no undecided obligation")
    # --worst-case in the verdict and the certificate (a rational and an irrational value)
    for args in (["verify", "--json", "--worst-case", "--law", os.path.join(SRC, "proofs", "classical3", "newton-approaching", "law.json")],
                 ["verify", "--json", "--worst-case"]):
        doc = run(args, 1 if "--law" in args else 0)
        if doc is not None:
            check("verdict.schema.json", doc, " ".join(args))
            if "worst_case" not in doc:
                failures.append("verify --worst-case --json has no worst_case")
    cert = os.path.join(tmp, "cert.json")
    if run(["certify", "--worst-case", "--law", os.path.join(SRC, "proofs", "classical3", "newton-approaching", "law.json"),
            "-o", cert], 1, stdout=False):
        check("certificate.schema.json", json.load(open(cert)), "certify --worst-case")
    for lawfile in ("proofs/classical3/newton-approaching/law.json", "proofs/kane/gains/law.json"):
        if run(["certify", "--law", os.path.join(SRC, lawfile), "-o", cert], 1, stdout=False):
            check("certificate.schema.json", json.load(open(cert)), "certify " + lawfile)
        if "kane" in lawfile:
            continue  # laws with friction are not sharded
        for k in (1, 2):
            part = os.path.join(tmp, f"part{k}.json")
            if run(["certify", "--law", os.path.join(SRC, lawfile), "--shard", f"{k}/2", "-o", part], 0, stdout=False):
                check("certificate-part.schema.json", json.load(open(part)), f"certify --shard {k}/2 " + lawfile)
    # One JUnit shape for verify, fuzz (law mode) and fuzz (consistency): the same elements and
    # attributes, counts that agree with the cases.
    import xml.etree.ElementTree as ET
    junit_runs = [(["verify", "--law", os.path.join(SRC, "proofs", "classical3", "newton-approaching", "law.json")], 1),
                  (["fuzz", "--law", os.path.join(SRC, "proofs", "newton4", "law.json"), "--impl-cmd",
                    "python3 " + os.path.join(SRC, "tests", "impls", "newton4_impl.py") + " sorted", "--samples", "200", "--max-rel-error", "1e-12"], 0),
                  (["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
                    "python3 " + os.path.join(SRC, "tests", "impls", "cradle_controls.py") + " stuck", "--samples", "200"], 1)]
    for args, expect in junit_runs:
        xml_path = os.path.join(tmp, "junit.xml")
        if os.path.exists(xml_path):
            os.remove(xml_path)
        p = subprocess.run([CLI] + args + ["--junit", xml_path], capture_output=True, text=True)
        if p.returncode != expect or not os.path.exists(xml_path):
            failures.append(f"{' '.join(args[:2])} --junit: exit {p.returncode}")
            continue
        root = ET.parse(xml_path).getroot()
        suites = list(root)
        want = {"name", "tests", "failures", "errors", "skipped", "time"}
        if root.tag != "testsuites" or set(root.attrib) != want or len(suites) != 1 or set(suites[0].attrib) != want:
            failures.append(f"{' '.join(args[:2])} --junit: not the one shape: {root.tag} {root.attrib}")
            continue
        cases = list(suites[0])
        failed = sum(1 for c in cases if c.find("failure") is not None)
        skipped = sum(1 for c in cases if c.find("skipped") is not None)
        if any(c.tag != "testcase" or set(c.attrib) != {"classname", "name", "time"} for c in cases) or \
                int(root.attrib["tests"]) != len(cases) or int(root.attrib["failures"]) != failed or \
                int(root.attrib["skipped"]) != skipped or (failed > 0) != (expect == 1):
            failures.append(f"{' '.join(args[:2])} --junit: counts or cases disagree: {root.attrib}")
    # derive's witnesses
    doc = run(["derive", "sequential", "--masses", "1,2,1", "--rule", "any", "--json"], 1)
    if doc:
        check("derive.schema.json", doc, "derive --rule any (order-dependent)")
    doc = run(["derive", "sequential", "--masses", "1,1,1", "--restitution", "0", "--json"], 3)
    if doc:
        check("derive.schema.json", doc, "derive at --max-impacts (undecided)")
    kane = json.load(open(os.path.join(SRC, "proofs", "kane", "gains", "system.json")))
    kane["contacts"]["friction"][0]["mu"] = "1/2"
    ksys = os.path.join(tmp, "kane-half.json")
    json.dump(kane, open(ksys, "w"))
    doc = run(["derive", "newton", "--system", ksys, "--restitution", "1/2", "--json", "-o", law], 1)
    if doc:
        check("derive.schema.json", doc, "derive newton with friction (two solutions)")
        if doc["verdict"] != "two-solutions":
            failures.append(f"kane at mu = 1/2: {doc['verdict']}")
    # fuzz, both modes, with and without violations
    impls = os.path.join(SRC, "tests", "impls")
    for args, expect in ((["fuzz", "--samples", "3000", "--json"], 0),
                         (["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
                           f"python3 {impls}/cradle_controls.py damped", "--samples", "300", "--json"], 1),
                         (["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
                           f"python3 {impls}/cradle_controls.py sort", "--samples", "300", "--require",
                           "nonexpansive,continuity", "--json"], 0),
                         (["fuzz", "--law", os.path.join(SRC, "proofs", "newton4", "law.json"), "--impl",
                           os.path.join(BIN, "tests", "libimpactcert_example_newton4.so") + ":newton4_two_sweeps",
                           "--samples", "20000", "--json"], 1)):
        doc = run(args, expect)
        if doc:
            check("fuzz.schema.json", doc, " ".join(args[:4]))
    # the effort sweep
    doc = run(["fuzz", "--masses", "1,1,1", "--velocities", "--impl-cmd",
               f"python3 {impls}/chain_engine.py threshold --iterations {{iterations}}", "--efforts", "1,8",
               "--restitution", "1", "--reference", "approaching", "--samples", "200", "--json"], 1)
    if doc:
        check("fuzz.schema.json", doc, "fuzz --efforts")
        bad = json.loads(json.dumps(doc))
        bad["effort"]["diagnosis"] = "maybe"
        rejects("fuzz.schema.json", bad, "an unknown diagnosis")
    # the gate's strength
    doc = run(["fuzz", "--law", os.path.join(SRC, "proofs", "newton4", "law.json"), "--mutants", "60",
               "--max-rel-error", "1e-12", "--allow", "extreme", "--range", "1e-3..1e3", "--samples", "2000",
               "--json"], 0)
    if doc:
        check("mutants.schema.json", doc, "fuzz --mutants")
        rejects("mutants.schema.json", dict(doc, kill_rate=1.5), "a kill rate above 1")
    # sweep and its parts
    sw = os.path.join(tmp, "sweep")
    if run(["sweep", "--masses", "1,m,1", "--restitution", "e", "--vary", "m=1/2..2:3", "--vary", "e=0..1:3",
            "--jobs", "1", "-o", sw], 0, stdout=False):
        check("sweep.schema.json", json.load(open(os.path.join(sw, "sweep.json"))), "sweep.json")
    kane = os.path.join(SRC, "proofs", "kane", "gains", "system.json")
    if run(["sweep", "--system", kane, "--law", "newton", "--restitution", "1/2", "--vary", "mu=0..1/2:6",
            "--thresholds", "--jobs", "1", "-o", sw + "-kane"], 0, stdout=False):
        doc = json.load(open(os.path.join(sw + "-kane", "sweep.json")))
        check("sweep.schema.json", doc, "sweep.json of a system, with thresholds")
        if not any(p["derive"] == "not-a-function" for p in doc["points"]) or not doc.get("thresholds"):
            failures.append("the system sweep has no not-a-function point or no threshold to check")
        bad = json.loads(json.dumps(doc))
        bad["thresholds"][0]["in"] = ["0.1"]
        rejects("sweep.schema.json", bad, "an enclosure with one end")
    if run(["sweep", "--masses", "1,m,1", "--restitution", "1/2", "--vary", "m=1/2..2:3", "--jobs", "1",
            "--shard", "1/2", "-o", sw], 0, stdout=False):
        check("sweep-part.schema.json", json.load(open(os.path.join(sw, "sweep.part-1-of-2.json"))), "sweep part")

    # ---- negative controls: one change from a valid document
    paper = json.load(open(os.path.join(SRC, "proofs", "newton3", "law.json")))
    both = dict(paper, M=[["1", "0", "0"], ["0", "1", "0"], ["0", "0", "1"]])
    rejects("law.schema.json", both, "masses and M both given")
    floaty = json.loads(json.dumps(paper))
    floaty["pieces"][0]["Q"][0][0] = 0.5
    rejects("law.schema.json", floaty, "a JSON float where a rational is written as a string")
    rejects("law.schema.json", dict(paper, colour="red"), "an unknown key")
    rejects("law.schema.json", {k: v for k, v in paper.items() if k != "pieces"}, "no pieces")
    c = json.load(open(os.path.join(SRC, "proofs", "newton3", "certificate.json")))
    rejects("certificate.schema.json", {k: v for k, v in c.items() if k != "law_sha256"}, "no law_sha256")
    c2 = json.loads(json.dumps(c))
    c2["obligations"][0]["verdict"] = "refuted"
    rejects("certificate.schema.json", c2, "a refutation without a counterexample")
    v = run(["verify", "--json"], 0)
    if v:
        v["obligations"][3]["verdict"] = "undecided"
        rejects("verdict.schema.json", v, "an undecided obligation without its limit")
    scene = json.load(open(os.path.join(SRC, "examples", "scenes", "two-disks.json")))
    scene["bodies"][0]["position"] = ["0", "1", "2"]
    rejects("scene.schema.json", scene, "a position with three coordinates")
finally:
    shutil.rmtree(tmp, ignore_errors=True)
print("validated: " + ", ".join(f"{n} {k}" for k, n in sorted(((k, n) for k, n in validated.items()))))
finish(failures)
