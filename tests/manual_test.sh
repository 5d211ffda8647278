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
echo "ok: 3 pages render cleanly; completion of commands, kinds and options"
