#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs examples/slurm/certify-array.sh as a Slurm job array of three tasks would (separate
# processes, SLURM_ARRAY_TASK_ID / SLURM_ARRAY_TASK_COUNT set), then merges and checks the parts,
# and requires the merged certificate to hold what a single run's does; a missing part must fail.
set -euo pipefail
bin=${1:?build directory}
src=${2:?source directory}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export PATH="$bin:$PATH"
impactcert derive sequential --masses 1,1/3,1 --restitution 1/3 -o "$dir/law.json" 2>/dev/null
for k in 1 2 3; do
    SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=3 SLURM_CPUS_PER_TASK=1 \
        bash "$src/examples/slurm/certify-array.sh" "$dir/law.json" "$dir/parts" 2>/dev/null
done
impactcert-check "$dir"/parts/part-*-of-3.json --merged "$dir/merged.json"
impactcert certify --law "$dir/law.json" -o "$dir/single.json" 2>/dev/null || [ $? -eq 1 ]
python3 - "$dir/merged.json" "$dir/single.json" <<'PY'
import json, sys
merged, single = (json.load(open(p)) for p in sys.argv[1:3])
assert merged == single, "the merged certificate differs from the single run's"
print("merged certificate = single run:", single["verdict"])
PY
if impactcert-check "$dir/parts/part-1-of-3.json" "$dir/parts/part-3-of-3.json" 2>/dev/null; then
    echo "two parts of three were accepted" >&2
    exit 1
fi
