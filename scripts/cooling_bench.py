#!/usr/bin/env python3
"""The engine's speed where the sweeps live: free cooling through the regime change (`make bench`,
after the elastic matrix; `make bench-nightly`, after the side by side).

Each case is one `edmd-bench --cool-from 200 --collisions-per-particle 200` run: a new gas at
phi = 0.25, periodic, run untimed from its elastic melt to tau = 200, then timed from tau = 200 to
400 as it cools (no rescale), for eps = 1, 0.9 and 0.7 at N = 4096 and 1e5, in 2D and 3D (cells or
neighbour lists as the engine chooses: cells at this phi; the table prints which). The rate of each inelastic case is given relative to the elastic rate of the same
D and N measured in the same pass, beside the events per pair collision by kind (docs/output.md):
where an inelastic gas spends its time (docs/benchmarks.md, "Inelastic gases: where the time goes").

    scripts/cooling_bench.py [--bench BIN] [--max-n 100000] [--passes 1]
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# (D, N) of the cooling cases; 3D N 4000 is the cubic lattice size nearest 4096.
CASES = [(2, 4096), (3, 4000), (2, 100_000), (3, 100_000)]
PHI = 0.25
EPSS = [1.0, 0.9, 0.7]
COOL_FROM = 200.0
WINDOW = 200.0


def measure(bench: Path, d: int, n: int, eps: float) -> dict:
    """One timed window of case (d, n, eps): edmd-bench's JSON report."""
    cmd = [
        str(bench), "--json", "--d", str(d), "--n", str(n), "--phi", str(PHI), "--eps", str(eps),
        "--cool-from", str(COOL_FROM), "--collisions-per-particle", str(WINDOW), "--repeats", "1",
    ]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed: {p.stderr.strip() or p.stdout.strip()}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def run(bench: Path, max_n: int, passes: int, base: dict | None = None) -> list[dict]:
    """Every case up to `max_n`, `passes` times (a case's entry: the median over the passes, its
    relative rate the median of the passes' ratios to the elastic run of the same pass). Prints a
    table; returns history rows (each with `base`'s fields: commit, date, machine, …)."""
    cases = [(d, n) for d, n in CASES if n <= max_n]
    rates: dict[tuple, list[float]] = {}
    relative: dict[tuple, list[float]] = {}
    last: dict[tuple, dict] = {}
    for _ in range(passes):
        for d, n in cases:
            elastic = None
            for eps in EPSS:
                out = measure(bench, d, n, eps)
                rate = out["collisions_per_s"]
                elastic = elastic or rate
                rates.setdefault((d, n, eps), []).append(rate)
                relative.setdefault((d, n, eps), []).append(rate / elastic)
                last[(d, n, eps)] = out
    print(f"free cooling, phi {PHI}, timed from tau {COOL_FROM:.0f} to {COOL_FROM + WINDOW:.0f} ({passes} pass(es)):")
    print(f"{'D':>2} {'N':>7} {'eps':>4} {'mode':>5} {'collisions/s':>13} {'vs eps=1':>8} "
          f"{'events':>7} {'stale':>6} {'cross':>6} {'restart':>8}  (per pair collision)")
    rows = []
    for (d, n, eps), rs in rates.items():
        out, per = last[(d, n, eps)], last[(d, n, eps)]["events_per_collision"]
        row = {
            **(base or {}), "d": d, "n": n, "phi": PHI, "eps": eps, "cool_from": COOL_FROM,
            "collisions_per_s": round(statistics.median(rs)),
            "spread": round((max(rs) - min(rs)) / statistics.median(rs), 4), "repeats": len(rs),
            "relative_to_elastic": round(statistics.median(relative[(d, n, eps)]), 4),
            "neighbours": out["neighbours"], "events_per_collision": per,
            "bytes_per_particle": out["bytes_per_particle"],
        }
        rows.append(row)
        print(f"{d:>2} {n:>7} {eps:>4} {out['neighbours']:>5} {row['collisions_per_s']:13.0f} "
              f"{row['relative_to_elastic']:8.3f} {per['events']:7.3f} {per['stale']:6.3f} "
              f"{per['crossings']:6.3f} {per['restarts']:8.5f}", flush=True)
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bench", default=str(ROOT / "target" / "dist" / "edmd-bench"), help="edmd-bench binary")
    ap.add_argument("--max-n", type=int, default=100_000, help="largest N (default 1e5)")
    ap.add_argument("--passes", type=int, default=1, help="passes over the cases (default 1)")
    args = ap.parse_args()
    if args.passes < 1:
        print(f"error: invalid --passes {args.passes}: must be >= 1", file=sys.stderr)
        return 2
    if not Path(args.bench).is_file():
        print(f"error: benchmark binary {args.bench} not found: build it with `make bench-bin`", file=sys.stderr)
        return 2
    run(Path(args.bench), args.max_n, args.passes)
    return 0


if __name__ == "__main__":
    sys.exit(main())
