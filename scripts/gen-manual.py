#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Generates the manual pages and the bash completion from the programs' own --help, so that
neither can drift from the code (the build runs this; the package installs the results).
  impactcert.1          help2man on `impactcert`, with a COMMANDS section holding every
                        command's --help
  impactcert-check.1    help2man on impactcert-check
  impactcert-verify.1   help2man on impactcert-verify
  impactcert.bash       completion: the commands, then each command's options
(and each page compressed, PAGE.1.gz, as Debian installs them)
Usage: gen-manual.py BINDIR OUTDIR [DOCDIR]   (DOCDIR: where docs/ and proofs/ are installed, under the prefix)"""
import gzip
import os
import re
import subprocess
import sys
import tempfile

BIN, OUT = sys.argv[1], sys.argv[2]
DOCDIR = sys.argv[3] if len(sys.argv) > 3 else "share/doc/impactcert"
os.makedirs(OUT, exist_ok=True)
CLI = os.path.join(BIN, "impactcert")
COMMANDS = [["verify"], ["certify"], ["report"], ["smt"], ["eval"], ["derive", "sequential"], ["derive", "newton"],
            ["derive", "poisson"], ["derive", "cradle"], ["sweep"], ["fuzz"]]


def help_of(args):
    return subprocess.run([CLI] + args + ["--help"], capture_output=True, text=True, check=True).stdout


def roff_text(text):
    out = []
    for line in text.splitlines():
        line = line.replace("\\", "\\e")
        if line.startswith((".", "'")):
            line = "\\&" + line
        out.append(line)
    return "\n".join(out)


def write(path, text):
    tmp = path + ".partial"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


include = ["[COMMANDS]"]
for cmd in COMMANDS:
    include.append(".SS \"impactcert " + " ".join(cmd) + "\"")
    include.append(".nf")
    include.append(roff_text(help_of(cmd)))
    include.append(".fi")
include += ["[SEE ALSO]", ".BR impactcert-check (1),", ".BR impactcert-verify (1).",
            f"The package's documentation, in {DOCDIR} under the installation prefix (/usr/{DOCDIR} from",
            "the Debian package): docs/formats.md (the formats; their JSON Schemas",
            "in docs/schemas/), docs/commands.md, docs/exit-status.md, docs/fuzzing.md, docs/derive.md,",
            "docs/ci.md, and proofs/README.md (what is proved, and why the finite checks prove it)."]
with tempfile.NamedTemporaryFile("w", suffix=".h2m", delete=False) as f:
    f.write("\n".join(include) + "\n")
    inc = f.name
try:
    for prog, name in (("impactcert", "exact proofs and fuzzing for impact laws of nonsmooth mechanics"),
                       ("impactcert-check", "the independent checker of impactcert certificates"),
                       ("impactcert-verify", "decide the proof obligations of an impact law (impactcert verify alone)")):
        args = ["help2man", "--no-info", "--section", "1", "--name", name, "--output", os.path.join(OUT, prog + ".1.partial")]
        if prog == "impactcert":
            args += ["--include", inc]
        subprocess.run(args + [os.path.join(BIN, prog)], check=True)
        os.replace(os.path.join(OUT, prog + ".1.partial"), os.path.join(OUT, prog + ".1"))
        # Debian installs manual pages compressed (gzip -9n: no name, no time stamp).
        with open(os.path.join(OUT, prog + ".1"), "rb") as src, open(os.path.join(OUT, prog + ".1.gz.partial"), "wb") as raw:
            with gzip.GzipFile(filename="", mode="wb", compresslevel=9, fileobj=raw, mtime=0) as z:
                z.write(src.read())
        os.replace(os.path.join(OUT, prog + ".1.gz.partial"), os.path.join(OUT, prog + ".1.gz"))
finally:
    os.unlink(inc)

# bash completion
def options(text):
    return sorted(set(re.findall(r"^\s+(?:-\w,)?(--[a-z][a-z0-9-]*)", text, re.M)))


cases = []
for cmd in COMMANDS:
    key = " ".join(cmd)
    cases.append(f'        "{key}") opts="{" ".join(options(help_of(cmd)))}" ;;')
# Option values: the fixed ones; files where an option takes one (laws and systems end in .json).
VALUES = {"--walls": "none left right", "--allow": "extreme", "--rule": "most-negative left-first right-first any",
          "--restitution-on": "all approaching",
          "--require": "nonexpansive continuity nonexpansive,continuity"}
JSON_FILES = ["--law", "--system", "--float-law"]
value_cases = "\n".join(f'        {o}) COMPREPLY=($(compgen -W "{v}" -- "$cur")) ;;' for o, v in VALUES.items())
value_cases += "\n        " + "|".join(JSON_FILES) + ') COMPREPLY=($(compgen -f -X "!*.json" -- "$cur") $(compgen -d -- "$cur")) ;;'
value_cases += '\n        --reference) COMPREPLY=($(compgen -W "approaching newton poisson" -- "$cur") $(compgen -f -X "!*.json" -- "$cur") $(compgen -d -- "$cur")) ;;'
value_cases += '\n        -o|--output|--junit|--merged|--impl|--impl-cmd) COMPREPLY=($(compgen -f -- "$cur")) ;;'
check_opts = " ".join(options(subprocess.run([os.path.join(BIN, "impactcert-check"), "--help"], capture_output=True,
                                             text=True).stdout) or ["--merged", "--jobs"])
verify_opts = " ".join(options(subprocess.run([os.path.join(BIN, "impactcert-verify"), "--help"], capture_output=True,
                                              text=True).stdout))
derive_subs = " ".join(c[1] for c in COMMANDS if c[0] == "derive")
top = " ".join(dict.fromkeys(c[0] for c in COMMANDS))
write(os.path.join(OUT, "impactcert.bash"), f"""# SPDX-License-Identifier: GPL-3.0-or-later
# bash completion for impactcert, impactcert-check and impactcert-verify (generated from their
# --help by scripts/gen-manual.py)
# The value of the option before the cursor, if it takes one we know: returns 0 when it answered.
_impactcert_value() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}" prev="${{COMP_WORDS[COMP_CWORD-1]}}"
    [ "$COMP_CWORD" -ge 1 ] || return 1
    case "$prev" in
{value_cases}
        *) return 1 ;;
    esac
    return 0
}}
_impactcert_check() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}"
    _impactcert_value && return
    if [[ "$cur" == -* ]]; then
        COMPREPLY=($(compgen -W "{check_opts} --help --version" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -X "!*.json" -- "$cur") $(compgen -d -- "$cur"))
    fi
}}
_impactcert_verify() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}"
    _impactcert_value && return
    if [[ "$cur" == -* ]]; then
        COMPREPLY=($(compgen -W "{verify_opts} --help --version" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -X "!*.json" -- "$cur") $(compgen -d -- "$cur"))
    fi
}}
_impactcert() {{
    local cur="${{COMP_WORDS[COMP_CWORD]}}" cmd="" i opts=""
    for ((i = 1; i < COMP_CWORD; i++)); do
        case "${{COMP_WORDS[i]}}" in
            -*) ;;
            *) if [ -z "$cmd" ]; then cmd="${{COMP_WORDS[i]}}"; elif [ "$cmd" = derive ] && [ -z "${{sub:-}}" ]; then local sub="${{COMP_WORDS[i]}}"; cmd="derive $sub"; fi ;;
        esac
    done
    _impactcert_value && return
    if [ -z "$cmd" ]; then
        COMPREPLY=($(compgen -W "{top} --help --version" -- "$cur"))
        return
    fi
    if [ "$cmd" = derive ]; then
        COMPREPLY=($(compgen -W "{derive_subs}" -- "$cur"))
        return
    fi
    case "$cmd" in
{chr(10).join(cases)}
    esac
    if [[ "$cur" == -* ]]; then
        COMPREPLY=($(compgen -W "$opts" -- "$cur"))
    else
        COMPREPLY=($(compgen -f -- "$cur"))
    fi
}}
complete -o filenames -F _impactcert impactcert
complete -o filenames -F _impactcert_check impactcert-check
complete -o filenames -F _impactcert_verify impactcert-verify
""")
print(f"impactcert: wrote {OUT}/impactcert.1, impactcert-check.1, impactcert-verify.1, impactcert.bash")
