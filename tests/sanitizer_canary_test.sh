#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# sanitizer_canary_test.sh CANARY -- each error of tests/sanitizer_canary.cpp is stopped by its
# sanitizer under the sanitizer build's flags and the tests' ASAN_OPTIONS/UBSAN_OPTIONS (non-zero
# exit, the sanitizer's own report); the same program without an error exits 0.
set -uo pipefail
canary="$1"
status=0
expect() { # MODE REPORT
    local out code
    out=$("$canary" "$1" 4 2>&1)
    code=$?
    if [ "$code" -eq 0 ] || ! grep -qE "$2" <<<"$out"; then
        echo "FAIL: $1: exit $code, no '$2' in: ${out:0:400}"
        status=1
    else
        echo "ok: $1 stopped (exit $code): $(grep -m1 -E "$2" <<<"$out" | cut -c1-120)"
    fi
}
expect heap-buffer-overflow "ERROR: AddressSanitizer: heap-buffer-overflow"
expect heap-use-after-free "ERROR: AddressSanitizer: heap-use-after-free"
expect stack-buffer-overflow "ERROR: AddressSanitizer: stack-buffer-overflow"
expect memory-leak "ERROR: LeakSanitizer: detected memory leaks"
expect signed-integer-overflow "runtime error: signed integer overflow"
expect shift-exponent "runtime error: shift exponent 32"
if ! out=$("$canary" none 4 2>&1); then
    echo "FAIL: none: the program without an error failed: ${out:0:400}"
    status=1
else
    echo "ok: none exits 0"
fi
exit $status
