#!/bin/bash
# SPDX-License-Identifier: GPL-3.0-or-later
# examples/slurm/certify-array.sh -- certify one law in N slices on a Slurm cluster, then merge and
# check them. impactcert schedules nothing: Slurm runs the slices, impactcert-check verifies that
# the parts cover every obligation and every pair block exactly once and checks the result.
#
#   sbatch --array=1-16 examples/slurm/certify-array.sh law.json parts/   # one slice per task
#   impactcert-check parts/part-*-of-16.json --merged law.cert.json         # after the array ends
#
# The same with any other scheduler (a job array, GNU parallel across hosts, a loop of ssh):
#   impactcert certify --law law.json --shard K/N -o part-K-of-N.json   for K = 1..N
#SBATCH --job-name=impactcert-certify
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=04:00:00
set -euo pipefail
law=${1:?usage: sbatch --array=1-N certify-array.sh LAW.json OUTDIR}
out=${2:?usage: sbatch --array=1-N certify-array.sh LAW.json OUTDIR}
k=${SLURM_ARRAY_TASK_ID:?run under sbatch --array}
n=${SLURM_ARRAY_TASK_COUNT:?run under sbatch --array}
mkdir -p "$out"
# Each task: its own obligations and its own pair blocks of nonexpansive, with their evidence.
impactcert certify --law "$law" --shard "$k/$n" --jobs "${SLURM_CPUS_PER_TASK:-1}" -o "$out/part-$k-of-$n.json"
