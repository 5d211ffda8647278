#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# libfuzzer_test.sh FUZZER SOURCE_DIR WORK_DIR -- the coverage-guided target of tests/fuzzing (built
# with clang by scripts/test, in build-fuzz/) run for a short campaign from an empty corpus with a
# fixed seed: 10 s on the paper's law, 5 s on the 4-ball law. A failed check aborts the target, and
# so does a report of ASan or UBSan (halt_on_error): a non-zero exit, the crashing input left in
# WORK_DIR and the log's end printed.
set -euo pipefail
fuzzer="$1" src="$2" work="$3"
rm -rf "$work"
mkdir -p "$work/corpus-paper" "$work/corpus-newton4"
cd "$work"
campaign() { # NAME SECONDS [ENV=VALUE...]
    local name="$1" seconds="$2"
    shift 2
    if ! env UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 "$@" "$fuzzer" -seed=1 -max_total_time="$seconds" -print_final_stats=1 "corpus-$name" >"$name.log" 2>&1; then
        tail -n 40 "$name.log"
        echo "libfuzzer_test: the campaign on the $name law failed (log: $work/$name.log)" >&2
        exit 1
    fi
    if grep -q "runtime error:" "$name.log"; then # UBSan's report, should it ever recover
        grep -m1 -A5 "runtime error:" "$name.log"
        exit 1
    fi
    grep -E "^stat::number_of_executed_units|^Done [0-9]+ runs" "$name.log"
    grep -qE "^Done [1-9][0-9]* runs" "$name.log"
}
campaign paper 10
campaign newton4 5 IMPACTCERT_FUZZ_LAW="$src/proofs/newton4/law.json"
