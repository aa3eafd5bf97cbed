#!/usr/bin/env python3
"""Instructions per collision of edmd-bench and of the public peers, by cachegrind
(`make bench-instructions`).

The count is deterministic and does not depend on the machine's load, which makes it the measure to
decide the engine's hot loop by (docs/benchmarks.md). For each side-by-side case (scripts/peers.py:
2D phi 0.3 N = 1e4, 1e5, 1e6; 3D phi 0.45 N = 10976, 97556, 1000188; elastic, periodic):

* edmd: `valgrind --tool=cachegrind --cache-sim=no edmd-bench --repeats 1 --melt-tau 1
  --collisions-per-particle C` for two values of C (1 and 3; 0.25 and 0.75 at N = 10^6), the
  difference of the instruction totals over the difference of the timed collisions: set-up and melt
  cancel.
* peers (where scripts/peers.py finds them): the 2D fork of Smallenburg's Single and Single itself,
  a run to time t and one to 2t (t = 2 at N ~ 10^4, sized to about 10^6 collisions above), the
  difference of the totals over the difference of the printed collision counts. They are compiled
  by their build.sh without its -march=native: cachegrind cannot run every instruction of the host
  (AVX-512), and edmd is compiled for the generic x86-64 too, so both counts are of the same ISA.

Prints a table, appends one JSON line per case to the history (benches/instructions.jsonl: commit,
date, case, both counts, their ratio) and flags a case whose edmd count grew by more than
--threshold (3 %) over its previous entry. Exits 1 when a case is flagged (unless --no-fail).
Cachegrind runs programs some 50 times slower: about 15 minutes for the six cases on 2 cores.

    scripts/instructions.py [--only 2:10000,3:10976] [--history benches/instructions.jsonl]
                            [--threshold 0.03] [--peers DIR | --no-peers] [--no-fail]
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import peers  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT / "target" / "dist" / "edmd-bench"


def cachegrind(cmd: list[str], cwd: str | None = None) -> tuple[int, str]:
    """Total instructions of running ``cmd`` under cachegrind, and its standard output."""
    r = subprocess.run(
        ["valgrind", "--tool=cachegrind", "--cache-sim=no", "--cachegrind-out-file=/dev/null", *cmd],
        capture_output=True, text=True, cwd=cwd, check=True,
    )
    m = re.search(r"I\s+refs:\s+([\d,]+)", r.stderr)
    if not m:
        raise RuntimeError(f"cachegrind printed no instruction count for {cmd[0]}")
    return int(m.group(1).replace(",", "")), r.stdout


def edmd_per_collision(d: int, n: int) -> float:
    short, long = (0.25, 0.75) if n >= 500_000 else (1.0, 3.0)
    counts = []
    for c in (short, long):
        ins, out = cachegrind([str(BENCH), "--d", str(d), "--n", str(n), "--phi", str(peers.PHI[d]),
                               "--repeats", "1", "--melt-tau", "1", "--collisions-per-particle", str(c),
                               "--json"])
        counts.append((ins, json.loads(out)["collisions"]))
    (i1, c1), (i2, c2) = counts
    return (i2 - i1) / (c2 - c1)


def peer_per_collision(binaries: Path, d: int, n: int) -> float:
    t = 2.0 if n < 50_000 else 1e6 / n / peers.RATE_PER_TIME[d] * 2
    counts = []
    for tmax in (t, 2 * t):
        work = tempfile.mkdtemp(prefix="edmd-peer-")
        if d == 2:
            spec = Path(work) / "in.dat"
            spec.write_text(
                f"N_particles {n}\narea_fraction {peers.PHI[2]}\ninitial_configuration random\n"
                f"size_ratio 1.0\nlarge_spheres_fraction 1.0\ntime {tmax}\nsnapshots 1e9\n"
                f"write_interval {tmax}\nseed 1\n"
            )
            cmd = [str(binaries / "hdd2d"), str(spec)]
        else:
            cmd = [str(binaries / f"single3d_{n}"), str(tmax)]
        ins, out = cachegrind(cmd, cwd=work)
        shutil.rmtree(work, ignore_errors=True)
        found = re.findall(r"Collisions: (\d+)", out)
        if not found:
            raise RuntimeError(f"{cmd[0]} printed no collision count")
        counts.append((ins, int(found[-1])))
    (i1, c1), (i2, c2) = counts
    return (i2 - i1) / (c2 - c1)


def build_generic(folder: Path) -> Path:
    """The peers compiled by their build.sh without -march=native; returns the binaries' folder."""
    work = Path(tempfile.mkdtemp(prefix="edmd-peers-src-"))
    for f in folder.iterdir():
        (shutil.copytree if f.is_dir() else shutil.copy)(f, work / f.name)
    script = work / "build.sh"
    script.write_text(script.read_text().replace(" -march=native", ""))
    return peers.build(work)


def previous(history: Path, d: int, n: int) -> dict | None:
    if not history.exists():
        return None
    last = None
    for line in history.read_text().splitlines():
        e = json.loads(line)
        if e.get("d") == d and e.get("n") == n:
            last = e
    return last


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--only", help="cases as D:N, comma-separated (default: the six side-by-side cases)")
    p.add_argument("--history", default=str(ROOT / "benches" / "instructions.jsonl"))
    p.add_argument("--threshold", type=float, default=0.03)
    p.add_argument("--peers")
    p.add_argument("--no-peers", action="store_true")
    p.add_argument("--no-fail", action="store_true")
    a = p.parse_args(argv)
    if shutil.which("valgrind") is None:
        print("error: valgrind not on the PATH (apt-get install valgrind)", file=sys.stderr)
        return 2
    if not BENCH.exists():
        print(f"error: {BENCH} missing: cargo build --profile dist --bin edmd-bench", file=sys.stderr)
        return 2
    cases = peers.CASES
    if a.only:
        try:
            cases = [(int(c.split(":")[0]), int(float(c.split(":")[1]))) for c in a.only.split(",")]
        except (IndexError, ValueError):
            print(f"error: --only {a.only}: cases as D:N, e.g. 2:10000,3:10976", file=sys.stderr)
            return 2
    folder = None if a.no_peers else peers.find(a.peers)
    binaries = build_generic(folder) if folder else None
    if binaries is None:
        print("note: the peers were not found (--peers DIR, EDMD_PEERS): edmd only")
    commit = subprocess.run(["git", "rev-parse", "--short=12", "HEAD"], cwd=ROOT, capture_output=True,
                            text=True).stdout.strip() or "unknown"
    date = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    history = Path(a.history)
    flagged = []
    print("| D | N | phi | edmd (instructions/collision) | peer | ratio edmd/peer | change |")
    print("|---|---|---|---|---|---|---|")
    for d, n in cases:
        ours = edmd_per_collision(d, n)
        theirs = peer_per_collision(binaries, d, n) if binaries else None
        before = previous(history, d, n)
        change = ours / before["edmd"] - 1 if before else None
        if change is not None and change > a.threshold:
            flagged.append(f"D={d} N={n}: {ours:.0f} instructions per collision, {100 * change:+.1f} %")
        entry = {"commit": commit, "date": date, "d": d, "n": n, "phi": peers.PHI[d], "edmd": round(ours, 1),
                 "peer": round(theirs, 1) if theirs else None,
                 "ratio": round(ours / theirs, 4) if theirs else None}
        history.parent.mkdir(parents=True, exist_ok=True)
        with history.open("a") as f:
            f.write(json.dumps(entry, sort_keys=True) + "\n")
        print(f"| {d} | {n} | {peers.PHI[d]} | {ours:.0f} | {f'{theirs:.0f}' if theirs else '-'} | "
              f"{f'{ours / theirs:.2f}' if theirs else '-'} | "
              f"{f'{100 * change:+.1f} %' if change is not None else 'first entry'} |", flush=True)
    for line in flagged:
        print(f"FLAGGED (more than {100 * a.threshold:.0f} % more instructions): {line}")
    return 1 if flagged and not a.no_fail else 0


if __name__ == "__main__":
    sys.exit(main())
