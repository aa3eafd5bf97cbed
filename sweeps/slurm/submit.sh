#!/bin/bash
# Submits an edmd sweep as a Slurm job array of K shards plus a dependent merge job.
#
#   sweeps/slurm/submit.sh SPEC OUT K [sbatch options...]
#
# Rerunning the same command after a task died (or was cancelled) resumes the sweep: finished replicas
# are skipped, so no replica is lost or run twice. Set EDMD to the binary's path if it is not on PATH.
set -euo pipefail
if [ $# -lt 3 ]; then
    echo "usage: $0 SPEC OUT K [sbatch options...]" >&2
    exit 1
fi
spec=$1 out=$2 tasks=$3
shift 3
EDMD=${EDMD:-edmd}
here=$(cd "$(dirname "$0")" && pwd)
"$EDMD" validate-spec "$spec"
mkdir -p "$out"
array=$(sbatch --parsable --array="0-$((tasks - 1))" --export=ALL,EDMD="$EDMD" "$@" \
    "$here/edmd-array.sbatch" "$spec" "$out")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterany:$array" --job-name=edmd-merge \
    --output="$out/merge-%j.log" "$@" --wrap "\"$EDMD\" merge \"$out\"")
echo "submitted array job $array ($tasks tasks) and merge job $merge; output in $out"
