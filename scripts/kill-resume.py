#!/usr/bin/env python3
"""A sweep killed at random moments and run again ends bit-identical to an uninterrupted run
(scripts/compare-outputs.py), and each rerun goes on from the replicas' checkpoints, not from τ = 0.

The sweep holds one replica of each kind a checkpoint must carry: 2D disks in cells, 3D spheres in
neighbour lists between walls, a sheared (Lees-Edwards) box, rough grains with the TC remedy, and
3D rough spheres. Checkpoints come every `--every-tau` τ so that kills land between them. Each trial
kills `edmd run` with SIGKILL after a random delay, up to `--kills` times, then lets it finish;
`--signals` trials stop it with SIGTERM, SIGINT or SIGUSR1 instead (exit status 75, every replica
in flight checkpointed). Prints one row per trial; exits 1 at the first that differs.

    .venv/bin/python scripts/kill-resume.py [--edmd target/release/edmd] [--trials 10] [--signals 3]
"""

import argparse
import json
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py

REPO = Path(__file__).resolve().parents[1]
EXIT_INTERRUPTED = 75

SPEC = {
    "name": "kill-resume",
    "seed": 7,
    "grid": [
        {"dim": 2, "eps": 0.8, "phi": 0.25, "n": 3000},
        {"dim": 3, "boundary": "walls", "eps": 0.9, "phi": 0.45, "n": 2000},
        {"dim": 2, "boundary": "lees-edwards", "shear_rate": 0.05, "eps": 0.7, "phi": 0.2, "n": 2000},
        {"dim": 2, "eps": 0.7, "beta": 0.5, "phi": 0.3, "n": 2000,
         "remedy": {"kind": "tc", "tc": 0.0001}},
        {"dim": 3, "eps": 0.8, "beta": 0.0, "phi": 0.2, "n": 1500},
    ],
    "stop": {"tau_max": 800},
    "samples": {"every": 5, "per_decade": 5},
    "snapshots": {"every": 50, "final": True},
    "classify": {},
}


def load_compare():
    import importlib.util

    s = importlib.util.spec_from_file_location("compare_outputs", REPO / "scripts" / "compare-outputs.py")
    m = importlib.util.module_from_spec(s)
    s.loader.exec_module(m)
    return m


def run(edmd, spec, out, stop=None, after=0.0, threads=2):
    """Runs `edmd run`; with `stop`, sends that signal after `after` seconds. Returns (rc, stderr)."""
    p = subprocess.Popen([str(edmd), "run", str(spec), "-o", str(out), "-q", "--threads", str(threads)],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if stop is not None:
        try:
            p.wait(timeout=after)
        except subprocess.TimeoutExpired:
            p.send_signal(stop)
    _, err = p.communicate()
    return p.returncode, err


def resumed(stderr):
    """The replicas a run said it continued from their checkpoints."""
    m = re.search(r", (\d+) going on from their checkpoints", stderr)
    return int(m.group(1)) if m else 0


def trial(edmd, spec, ref, out, rng, kills, sig, wall, compare):
    """Kills (or signals) a run `kills` times, finishes it, compares; returns a row of facts."""
    stops, went_on = 0, 0
    for k in range(kills):
        # Each rerun has less left to do: its stop comes sooner.
        rc, err = run(edmd, spec, out, stop=sig, after=rng.uniform(0.3, wall) * 0.6**k)
        went_on += resumed(err)
        if rc == 0:
            break  # finished before the signal
        stops += 1
        if sig != signal.SIGKILL and rc != EXIT_INTERRUPTED:
            raise SystemExit(f"signal {sig.name}: exit status {rc}, not {EXIT_INTERRUPTED}: {err.strip()}")
        if sig != signal.SIGKILL and "interrupted:" not in err:
            raise SystemExit(f"signal {sig.name}: no interrupt message: {err.strip()}")
    rc, err = run(edmd, spec, out)
    if rc != 0:
        raise SystemExit(f"the final run failed ({rc}): {err.strip()}")
    went_on += resumed(err)
    left = sorted(p.name for p in (out / "replicas").iterdir() if not p.name.endswith(".h5"))
    left += sorted(p.name for p in (out / "states").iterdir() if not p.name.endswith(".final"))
    if left:
        raise SystemExit(f"{out}: left behind {left}")
    same = compare.main(str(ref), str(out)) == 0
    # The index records the resumes along the history that made each file: some once a run went on
    # from a checkpoint (a SIGKILLed run announces nothing, so the counts need not agree), none
    # without a stop.
    with h5py.File(out / "sweep.h5", "r") as f:
        recorded = int(f["replicas/resumes"][()].sum())
    if (went_on > 0 and recorded == 0) or (stops == 0 and recorded > 0):
        raise SystemExit(f"{out}: the index records {recorded} resumes after {stops} stops, {went_on} announced")
    return stops, went_on, same


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--edmd", default=str(REPO / "target" / "release" / "edmd"))
    ap.add_argument("--trials", type=int, default=10, help="SIGKILL trials")
    ap.add_argument("--signals", type=int, default=3, help="trials with SIGTERM, SIGINT, SIGUSR1 in turn")
    ap.add_argument("--kills", type=int, default=3, help="stops per trial before the run may finish")
    ap.add_argument("--tau-max", type=float, default=SPEC["stop"]["tau_max"])
    ap.add_argument("--every-tau", type=float, default=3.0)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args(argv)
    compare = load_compare()
    rng = random.Random(a.seed)
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        spec = dict(SPEC, stop={"tau_max": a.tau_max}, checkpoint={"every_s": 0, "every_tau": a.every_tau})
        (d / "spec.json").write_text(json.dumps(spec))
        t = time.monotonic()
        rc, err = run(a.edmd, d / "spec.json", d / "ref")
        if rc != 0:
            raise SystemExit(f"the uninterrupted run failed ({rc}): {err.strip()}")
        wall = time.monotonic() - t
        print(f"uninterrupted run: {wall:.1f} s; the k-th stop of a trial lands uniformly in [0.3, {wall:.1f}] s × 0.6^k")
        cycle = [signal.SIGTERM, signal.SIGINT, signal.SIGUSR1]
        plan = [signal.SIGKILL] * a.trials + [cycle[k % 3] for k in range(a.signals)]
        failed = 0
        for k, sig in enumerate(plan):
            stops, went_on, same = trial(a.edmd, d / "spec.json", d / "ref", d / f"t{k}", rng, a.kills, sig,
                                         wall, compare)
            print(f"trial {k:2d} {sig.name:8s} stopped {stops}x, replicas resumed from checkpoints {went_on:2d}: "
                  f"{'bit-identical' if same else 'DIFFERS'}")
            failed += not same
        print(f"{len(plan) - failed} of {len(plan)} trials bit-identical to the uninterrupted run")
        return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
