#!/bin/bash
# End-to-end test of sweeps on a real Slurm (`make test-slurm`, run by CI).
#
# Stands up a single-node Slurm on this machine from Debian's packages (munge, slurmctld, slurmd on
# localhost; generated slurm.conf; proctrack/linuxproc, task/none; no systemd), then:
#   1. submits tests/slurm/spec.json as a 4-task array with sweeps/slurm/submit.sh, waits, and checks that
#      the merged output equals a local `edmd run` of the same spec (every dataset and attribute);
#   2. submits it again into a fresh directory, cancels one running array task with scancel, lets the
#      rest finish, reruns the same submit command, and checks again: no replica lost, none duplicated,
#      the output equal to the local run;
#   3. refines the sweep of 1 in two rounds with sweeps/slurm/refine.sh (a plan job and 4 array tasks
#      per round, `edmd refine --plan` / `--shard`) and checks that it equals an unsharded `edmd refine`;
#   4. submits it once more, sends one running task's batch shell SIGUSR1 (what `--signal` sends before
#      a time limit): edmd checkpoints and exits 75, the task requeues itself, its rerun goes on from
#      the checkpoints, and the output equals the local run;
#   5. with EDMD_SLURM_TIME_LIMIT=1 (make stress), runs one replica of about 150 s under a real 1-minute
#      time limit: Slurm signals it, it requeues until done, and equals the local run.
# Daemons are started and stopped by PID. Skipped (exit 0, with a message) only where the packages are
# missing and cannot be installed.
set -euo pipefail

root=$(cd "$(dirname "$0")/../.." && pwd)
EDMD=${EDMD:-$root/target/release/edmd}
PY=${PY:-$root/.venv/bin/python}
spec=$root/tests/slurm/spec.json
start_time=$SECONDS

say() { echo "test-slurm: $*"; }

# --- packages --------------------------------------------------------------------------------------
need=""
for p in slurmctld slurmd slurm-client munge; do dpkg -s "$p" >/dev/null 2>&1 || need="$need $p"; done
if [ -n "$need" ]; then
    say "installing:$need"
    if [ "$(id -u)" = 0 ]; then
        (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $need) >/dev/null 2>&1 || true
    elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
        (sudo apt-get update -qq && sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $need) >/dev/null 2>&1 || true
    fi
    for p in $need; do
        if ! dpkg -s "$p" >/dev/null 2>&1; then
            say "SKIPPED: Debian package $p is missing and this machine cannot install packages (need root or sudo and apt)"
            exit 0
        fi
    done
fi
if [ "$(id -u)" != 0 ]; then
    # slurmd must run as root to start jobs as their user; without root there is no real Slurm here.
    if command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
        exec sudo -E env "PATH=$PATH" bash "$0" "$@"
    fi
    say "SKIPPED: slurmd needs root (or passwordless sudo)"
    exit 0
fi
[ -x "$EDMD" ] || { echo "test-slurm: error: $EDMD not built (make cli)" >&2; exit 1; }
[ -x "$PY" ] || { echo "test-slurm: error: $PY missing (make deps)" >&2; exit 1; }

# --- a private single-node cluster ------------------------------------------------------------------
work=$(mktemp -d /tmp/edmd-slurm.XXXXXX)
chmod 755 "$work"
mkdir -p "$work/munge" "$work/spool" "$work/state" "$work/log" "$work/out"
chmod 700 "$work/munge"
pids=()
cleanup() {
    local rc=$?
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${pids[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    done
    if [ $rc -ne 0 ]; then
        say "FAILED; daemon logs:"
        tail -n 30 "$work"/log/*.log 2>/dev/null || true
    fi
    [ -n "${KEEP:-}" ] || rm -rf "$work"
    exit $rc
}
trap cleanup EXIT

mungekey --create --keyfile "$work/munge/munge.key" --force >/dev/null 2>&1 \
    || dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
sock=$work/munge/munge.sock
munged --foreground --force --socket="$sock" --key-file="$work/munge/munge.key" \
    --pid-file="$work/munge/munged.pid" --log-file="$work/log/munged.log" \
    --seed-file="$work/munge/munged.seed" >/dev/null 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$sock" ] && break; sleep 0.1; done
[ -S "$sock" ] || { echo "test-slurm: error: munged did not start" >&2; exit 1; }

host=$(hostname -s)
cpus=$(nproc)
port0=$((20000 + RANDOM % 20000))
export SLURM_CONF=$work/slurm.conf
cat > "$SLURM_CONF" <<EOF
ClusterName=edmdtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port0
SlurmdPort=$((port0 + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=2
MinJobAge=300
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
EOF
slurmctld -D -i -f "$SLURM_CONF" >"$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
    state=$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)
    [ "$state" = idle ] && break
    sleep 0.2
done
[ "$state" = idle ] || { echo "test-slurm: error: node not idle (state '$state')" >&2; exit 1; }
say "single-node Slurm up ($(sinfo -V), node $host, $cpus CPUs) after $((SECONDS - start_time)) s"

# Waits until no job of ours is pending or running.
wait_idle() {
    for _ in $(seq 1200); do
        [ -z "$(squeue -h -o %i 2>/dev/null)" ] && return 0
        sleep 0.25
    done
    echo "test-slurm: error: jobs still queued after 300 s" >&2
    squeue >&2
    return 1
}

# The reference: the same spec run locally.
"$EDMD" run "$spec" -o "$work/local" --quiet >/dev/null
replicas=$(ls "$work/local/replicas" | grep -c '\.h5$')

check_equal() {
    local dir=$1
    local files parts
    files=$(ls "$dir/replicas" | grep -c '\.h5$' || true)
    parts=$(ls "$dir/replicas" | grep -c '\.part$' || true)
    [ "$files" = "$replicas" ] || { echo "test-slurm: error: $dir has $files replica files, expected $replicas" >&2; return 1; }
    [ "$parts" = 0 ] || { echo "test-slurm: error: $dir has $parts partial files" >&2; return 1; }
    [ -f "$dir/sweep.h5" ] || { echo "test-slurm: error: $dir has no index (merge did not run)" >&2; return 1; }
    "$PY" "$root/scripts/compare-outputs.py" "$work/local" "$dir"
}

submit() {
    # The command a user runs: 4 array tasks of one CPU each, output in $1.
    EDMD="$EDMD" "$root/sweeps/slurm/submit.sh" "$spec" "$1" 4 \
        --cpus-per-task=1 --output="$1/slurm-%A_%a.log" --chdir="$work"
}

# --- 1. a 4-task array sweep and its merge ------------------------------------------------------------
t0=$SECONDS
submit "$work/out/a"
wait_idle
check_equal "$work/out/a"
say "4-task array + merge equal to the local run ($replicas replicas) in $((SECONDS - t0)) s"

# --- 2. scancel one running task, rerun the submit command -------------------------------------------
t0=$SECONDS
line=$(submit "$work/out/b")
echo "$line"
array=$(echo "$line" | sed -n 's/^submitted array job \([0-9]*\).*/\1/p')
[ -n "$array" ] || { echo "test-slurm: error: no job id in '$line'" >&2; exit 1; }
victim=""
for _ in $(seq 400); do
    victim=$(squeue -h -j "$array" -t RUNNING -o %i 2>/dev/null | grep '_' | head -1 || true)
    [ -n "$victim" ] && break
    sleep 0.05
done
[ -n "$victim" ] || { echo "test-slurm: error: no array task ever ran" >&2; exit 1; }
# Cancelled 0.4 s after it shows as running: the task runs 2 replicas of about a second each (one core
# of the test build), so it is caught mid-run; should a machine finish both by then, the check after
# the cancel fails and names the spec as too short.
sleep 0.4
scancel "$victim"
say "cancelled running task $victim"
wait_idle
done_files=$(ls "$work/out/b/replicas" 2>/dev/null | grep -c '\.h5$' || true)
[ "$done_files" -lt "$replicas" ] || { echo "test-slurm: error: the cancelled task's replicas all finished anyway ($done_files of $replicas); the spec is too short for this test" >&2; exit 1; }
merge_id=$(echo "$line" | sed -n 's/.*merge job \([0-9]*\).*/\1/p')
grep -q "replica(s) missing" "$work/out/b"/slurm-"$merge_id"_*.log \
    || { echo "test-slurm: error: the merge job did not report the missing replicas" >&2; exit 1; }
say "after the cancel: $done_files of $replicas replicas finished; the merge job reported the missing ones"
# Finished files must survive the rerun untouched (same inode and modification time): not rerun.
before=$(cd "$work/out/b/replicas" && stat -c '%n %i %Y.%y' *.h5 | sort)
submit "$work/out/b" >/dev/null
wait_idle
check_equal "$work/out/b"
after=$(cd "$work/out/b/replicas" && stat -c '%n %i %Y.%y' *.h5 | sort)
kept=$(comm -12 <(echo "$before") <(echo "$after") | wc -l)
[ "$kept" = "$done_files" ] || { echo "test-slurm: error: the rerun rewrote finished replicas ($kept of $done_files untouched)" >&2; exit 1; }
say "rerun of the submit command completed the sweep: $replicas replicas, the $done_files finished ones untouched, none lost or duplicated, equal to the local run, in $((SECONDS - t0)) s"
# --- 3. a refinement in sharded rounds equals the unsharded refinement --------------------------------
t0=$SECONDS
cp -a "$work/local" "$work/local-refined"
"$EDMD" refine "$work/local-refined" --rounds 2 --quiet >/dev/null 2>&1
added=$(( $(ls "$work/local-refined/replicas" | grep -c '\.h5$') - replicas ))
[ "$added" -gt 0 ] || { echo "test-slurm: error: the refinement of the test sweep added no replica" >&2; exit 1; }
mkdir -p "$work/out/r"
cp -a "$work/out/a/replicas" "$work/out/a/spec.json" "$work/out/r/"
EDMD="$EDMD" "$root/sweeps/slurm/refine.sh" "$work/out/r" 4 2 --cpus-per-task=1 --chdir="$work"
wait_idle
"$PY" "$root/scripts/compare-outputs.py" "$work/local-refined" "$work/out/r"
for f in spec.json boundary.json phase.json; do
    cmp -s "$work/local-refined/$f" "$work/out/r/$f" || { echo "test-slurm: error: $f of the sharded refinement differs" >&2; exit 1; }
done
say "refinement in 2 rounds of a plan job + 4 array tasks equal to the unsharded refine ($added replicas added) in $((SECONDS - t0)) s"
# --- 4. a task signalled as before its time limit requeues itself and goes on from its checkpoints ---
# Slurm's `--signal=B:USR1@120` has a minute's resolution and `scancel --batch --signal` races the
# task's own requeue in this Slurm, so the test does what slurmstepd does: SIGUSR1 to the task's
# batch shell (the parent of its edmd), which passes it on.
t0=$SECONDS
line=$(submit "$work/out/q")
array=$(echo "$line" | sed -n 's/^submitted array job \([0-9]*\).*/\1/p')
edmd_pid=""
for _ in $(seq 400); do
    edmd_pid=$(pgrep -f "out/q --shard 1/4" | head -1 || true)
    [ -n "$edmd_pid" ] && break
    sleep 0.05
done
[ -n "$edmd_pid" ] || { echo "test-slurm: error: task 1 never ran" >&2; exit 1; }
sleep 0.3
shell_pid=$(ps -o ppid= -p "$edmd_pid" | tr -d ' ')
kill -USR1 "$shell_pid"
victim="${array}_1"
say "sent SIGUSR1 to the batch shell of running task $victim"
# Slurm holds a requeued job back for a while (BeginTime); the test lets it start at once.
for _ in $(seq 200); do
    state=$(squeue -h -j "$victim" -o %T 2>/dev/null || true)
    [ "$state" = PENDING ] && { scontrol update JobId="$victim" StartTime=now; break; }
    sleep 0.05
done
wait_idle
check_equal "$work/out/q"
log="$work/out/q/slurm-${victim}.log"
grep -q "requeueing task" "$log" \
    || { echo "test-slurm: error: task $victim did not requeue itself ($log):" >&2; cat "$log" >&2; exit 1; }
grep -q "going on from their checkpoints" "$log" \
    || { echo "test-slurm: error: the requeued task $victim did not go on from its checkpoints ($log):" >&2; cat "$log" >&2; exit 1; }
ls "$work/out/q/states" | grep -q '\.ckpt' && { echo "test-slurm: error: checkpoints left behind" >&2; exit 1; }
say "a task signalled before its time limit checkpointed, requeued itself and finished from its checkpoints: equal to the local run, in $((SECONDS - t0)) s"

# --- 5. (EDMD_SLURM_TIME_LIMIT=1, make stress) a real time limit shorter than the replica -------------
# One replica of about 150 s on one core under a 1-minute limit with `--signal=B:USR1@30`: Slurm itself
# signals each run 30-60 s in, and the array task must requeue until the replica is done.
if [ "${EDMD_SLURM_TIME_LIMIT:-0}" = 1 ]; then
    t0=$SECONDS
    long=$work/long.json
    make_long() {  # the spec's first grid point as one replica to tau_max $1
        "$PY" -c 'import json, sys; s = json.load(open(sys.argv[1])); s["name"] = "slurm-time-limit"
s["grid"].update(eps=0.9, seeds=1); s["stop"]["tau_max"] = float(sys.argv[3])
json.dump(s, open(sys.argv[2], "w"))' "$spec" "$long" "$1"
    }
    make_long 400
    t1=$(date +%s.%N); "$EDMD" run "$long" -o "$work/calibrate" --quiet >/dev/null; t2=$(date +%s.%N)
    tau=$("$PY" -c "print(round(400 * 150 / max($t2 - $t1, 0.1)))")
    make_long "$tau"
    "$EDMD" run "$long" -o "$work/long-local" --quiet >/dev/null
    EDMD="$EDMD" "$root/sweeps/slurm/submit.sh" "$long" "$work/out/t" 1 --cpus-per-task=1 \
        --time=1 --signal=B:USR1@30 --output="$work/out/t/slurm-%A_%a.log" --chdir="$work" >/dev/null
    # A requeued task is held back (BeginTime); let it start at once, until the queue is empty.
    for _ in $(seq 2400); do
        # Done once the replica's file is in place and the queue is empty (an answer, not a failed
        # call): a requeued task passes through moments outside the queue, and the merge job that
        # waits on the array may run after its first end and report the replica missing.
        jobs=$(squeue -h -o "%i %T" 2>/dev/null) || { sleep 0.25; continue; }
        [ -z "$jobs" ] && [ -f "$work/out/t/replicas/r00000.h5" ] && [ -f "$work/out/t/sweep.h5" ] && break
        echo "$jobs" | awk '$2 == "PENDING" {print $1}' | while read -r j; do
            scontrol update JobId="$j" StartTime=now 2>/dev/null || true
        done
        sleep 0.25
    done
    requeues=$(cat "$work"/out/t/slurm-*.log | grep -c "requeueing task" || true)
    [ "$requeues" -ge 1 ] || { echo "test-slurm: error: the time-limited task never requeued:" >&2; cat "$work"/out/t/slurm-*.log >&2; exit 1; }
    "$PY" "$root/scripts/compare-outputs.py" "$work/long-local" "$work/out/t" \
        || { echo "test-slurm: error: the time-limited sweep differs; its logs:" >&2; tail -n 5 "$work"/out/t/*.log >&2; exit 1; }
    say "a replica of tau $tau under a 1-minute time limit finished after $requeues requeues, equal to the local run, in $((SECONDS - t0)) s"
fi
say "PASSED in $((SECONDS - start_time)) s"
