#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
# examples/slurm/sweep-array.sh -- a sweep of thousands of laws in N slices (grid point k goes to
# shard k mod N + 1), merged into the single run's sweep.csv, sweep.json and sweep.html.
#
#   sbatch --array=1-32 examples/slurm/sweep-array.sh sweep-parts/
#   impactcert sweep --merge sweep-parts/*/sweep.part-*-of-32.json -o sweep/
#SBATCH --job-name=impactcert-sweep
#SBATCH --cpus-per-task=2
#SBATCH --mem=2G
#SBATCH --time=02:00:00
set -euo pipefail
out=${1:?usage: sbatch --array=1-N sweep-array.sh OUTDIR}
k=${SLURM_ARRAY_TASK_ID:?run under sbatch --array}
n=${SLURM_ARRAY_TASK_COUNT:?run under sbatch --array}
impactcert sweep --masses 1,m,1 --restitution e --vary m=1/4..4:100:log --vary e=0..1:100 \
    --shard "$k/$n" --jobs "${SLURM_CPUS_PER_TASK:-1}" -o "$out/$k"
