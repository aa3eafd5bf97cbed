#!/bin/bash
# Refines a finished sweep (`edmd refine`) on Slurm, each round's replicas as a job array.
#
#   sweeps/slurm/refine.sh OUT K ROUNDS [sbatch options...]
#
# For each round r = 1 … ROUNDS it submits a plan job, `edmd refine OUT --rounds r --plan` (it builds the
# index and adds round r's points to OUT/spec.json), then an array of K tasks after it, task i running
# `edmd refine OUT --shard i/K` (the planned replicas not yet finished); a last plan job writes the index
# and OUT/boundary.json. Every job waits for the one before it to end, however it ended: a plan job
# that finds replicas missing (a task died) fails, the next array runs them, and the next plan job
# catches up. Rerunning the same command after a cancel resumes the refinement where it stopped; the
# result is the same as one `edmd refine OUT --rounds ROUNDS`. OUT must hold a finished sweep
# (submit.sh, then this after its merge job: add --dependency=afterany:MERGE_ID to the options).
# Set EDMD to the binary's path if it is not on PATH.
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 OUT K ROUNDS [sbatch options...]" >&2
    exit 1
fi
out=$1 tasks=$2 rounds=$3
shift 3
EDMD=${EDMD:-edmd}
[ -f "$out/spec.json" ] || { echo "$0: $out holds no sweep (no spec.json); run it first (submit.sh)" >&2; exit 1; }
after=()
jobs=""
for r in $(seq 1 "$rounds"); do
    p=$(sbatch --parsable "${after[@]}" "$@" --job-name=edmd-plan --output="$out/plan-%j.log" \
        --wrap "\"$EDMD\" refine \"$out\" --rounds $r --plan --format csv")
    a=$(sbatch --parsable --dependency="afterany:${p%%;*}" --array="0-$((tasks - 1))" "$@" \
        --job-name=edmd-refine --output="$out/refine-%A_%a.log" --export=ALL,EDMD="$EDMD" \
        --wrap "\"$EDMD\" refine \"$out\" --shard \$SLURM_ARRAY_TASK_ID/$tasks --threads \${SLURM_CPUS_PER_TASK:-1} --quiet")
    a=${a%%;*}
    after=(--dependency="afterany:$a")
    jobs="$jobs ${p%%;*}+$a"
done
last=$(sbatch --parsable "${after[@]}" "$@" --job-name=edmd-plan --output="$out/plan-%j.log" \
    --wrap "\"$EDMD\" refine \"$out\" --rounds $rounds --plan --format csv")
echo "submitted $rounds round(s) of a plan job and $tasks array tasks (plan+array:$jobs) and the final plan job ${last%%;*}; output in $out"
