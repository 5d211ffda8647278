#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The generated manual pages and bash completion (scripts/gen-manual.py): the pages render with
# groff without warnings and hold every command's options; the completion completes commands,
# derive's kinds and a command's options, and nothing for a word that is no command.
# Usage: manual_test.sh MANUAL_DIR
set -euo pipefail
dir="$1"
fail() { echo "FAIL: $*"; exit 1; }
for page in impactcert impactcert-check impactcert-verify; do
    [ -s "$dir/$page.1" ] || fail "$page.1 missing"
    [ "$(gzip -dc "$dir/$page.1.gz")" = "$(cat "$dir/$page.1")" ] || fail "$page.1.gz is not $page.1 compressed"
    warnings=$(groff -man -Tutf8 -ww -z "$dir/$page.1" 2>&1 || true)
    [ -z "$warnings" ] || fail "$page.1: groff: $warnings"
done
text=$(groff -man -Tutf8 "$dir/impactcert.1" 2>/dev/null | sed 's/.\x08//g')
for needle in "impactcert derive sequential" "--max-impacts" "impactcert fuzz" "--impl-cmd" "Exit statuses" "Examples:"; do
    grep -qF -- "$needle" <<<"$text" || fail "impactcert.1 does not mention $needle"
done
grep -qF -- "--merged" <(groff -man -Tutf8 "$dir/impactcert-check.1" 2>/dev/null | sed 's/.\x08//g') || fail "impactcert-check.1 lacks --merged"
complete_words() { # WORDS...: the completions of the last word
    bash -c 'source "$0"; COMP_WORDS=("${@}"); COMP_CWORD=$(( ${#COMP_WORDS[@]} - 1 )); _impactcert; echo "${COMPREPLY[*]}"' \
        "$dir/impactcert.bash" "$@"
}
[ "$(complete_words impactcert der)" = "derive" ] || fail "impactcert der -> $(complete_words impactcert der)"
[ "$(complete_words impactcert derive seq)" = "sequential" ] || fail "derive seq -> $(complete_words impactcert derive seq)"
got=$(complete_words impactcert derive sequential --max-i)
[ "$got" = "--max-impacts" ] || fail "derive sequential --max-i -> $got"
got=$(complete_words impactcert fuzz --impl)
for o in --impl --impl-cmd --impl-timeout; do grep -qw -- "$o" <<<"$got" || fail "fuzz --impl -> $got"; done
[ -z "$(complete_words impactcert frob)" ] || fail "a word that is no command completed"
# Option values, and the other two programs (issue 40, item 8).
[ "$(complete_words impactcert fuzz --allow e)" = "extreme" ] || fail "fuzz --allow e -> $(complete_words impactcert fuzz --allow e)"
[ "$(complete_words impactcert derive sequential --walls '')" = "none left right" ] || fail "--walls -> $(complete_words impactcert derive sequential --walls '')"
[ "$(complete_words impactcert fuzz --reference app)" = "approaching" ] || fail "--reference app"
complete_with() { # FUNCTION WORDS...
    local fn="$1"; shift
    bash -c 'source "$0"; fn="$1"; shift; COMP_WORDS=("${@}"); COMP_CWORD=$(( ${#COMP_WORDS[@]} - 1 )); "$fn"; echo "${COMPREPLY[*]}"' \
        "$dir/impactcert.bash" "$fn" "$@"
}
[ "$(complete_with _impactcert_check impactcert-check --mer)" = "--merged" ] || fail "impactcert-check --mer -> $(complete_with _impactcert_check impactcert-check --mer)"
grep -qw -- "--max-faces" <<<"$(complete_with _impactcert_verify impactcert-verify --max-f)" || fail "impactcert-verify --max-f"
grep -q "complete -o filenames -F _impactcert_check impactcert-check" "$dir/impactcert.bash" || fail "no completion for impactcert-check"
# The manual cites what the package installs (issue 40, item 4), never the developers' SPEC.
grep -qF "docs/formats.md" <<<"$text" || fail "impactcert.1 does not cite docs/formats.md"
grep -qF "/doc/impactcert" <<<"$text" || fail "impactcert.1 does not say where the documentation is installed"
! grep -q "SPEC" <<<"$text" || fail "impactcert.1 cites the SPEC, which no user has"
echo "ok: 3 pages render cleanly; completion of commands, kinds, options and their values, for the three programs"
