#!/usr/bin/env python3
"""Nightly throughput benchmark of the engine (`make bench-nightly`).

Runs a fixed matrix of cases with the `edmd-bench` binary of the dist profile (`make bench-nightly`: compiled
for the processor it runs on, as the peers' build.sh compiles theirs; --bench), one process per case (so peak memory
is per case): D in {2, 3}; N in {1e3, 1e4, 1e5, 1e6}; phi in {0.05, 0.3, 0.7} (2D) or {0.05, 0.3, 0.5}
(3D); elastic and eps = 0.9; periodic box; each case equilibrated elastically for 2 collisions per
particle (1 from N = 1e5 on), then timed over about 1e6 collisions (at least half a collision per
particle). Three passes over the matrix: a case's entry is the median and spread of its three
measurements, taken minutes apart. Runs in about 10 minutes on 2 cores.

Appends one JSON line per case to the history file (commit, date, machine, CPU model, the instruction
set the binary was compiled for, collisions/s median and spread, peak heap bytes per particle), prints
a table, and flags every case that is more than 10 % slower than the previous entry of the same case
on the same machine and instruction set. A case that comes out
slower is first measured twice more (--confirm) and its entry becomes the median of all its
measurements, so that a neighbour on a shared machine slowing some measurements is not taken for a
regression, while a slower build, slow every time, is flagged.

Then, side by side: where the public peer codes are found (scripts/peers.py: --peers DIR, EDMD_PEERS,
or a shared/peers folder beside the checkout), they are built, and edmd-bench and the peer alternate
on each peer case (2D phi 0.3 N = 1e4, 1e5, 1e6 against the 2D fork of Smallenburg's Single; 3D phi
0.45 N = 10976, 97556, 1000188 against Single), --passes times. The entry records both medians and
their ratio edmd/peer, and a ratio more than --threshold below the previous entry's is flagged: ratios
measured in one run survive the machine's noise better than absolute rates. Without the peers this
part is skipped with a note. About 10 more minutes on 2 cores. Beside the rates, each peer case up to
--instructions-max-n (default 1e5) records the instructions per collision of both codes by cachegrind
(scripts/instructions.py, with the generic x86-64 build of both codes, --instructions-bench:
deterministic, so a growth of edmd's count by more than 3 % over the
previous entry is flagged however noisy the machine); about 5 more minutes where valgrind is
installed, skipped with a note where it is not.

Last, the free-cooling cases of scripts/cooling_bench.py (eps = 1, 0.9, 0.7 timed from tau 200 to 400,
N = 4096 and 1e5 up to --cooling-max-n, 2D and 3D; --passes times), each recorded with `cool_from`,
its rate relative to the elastic one of the same pass and its events per collision by kind, and
flagged like the matrix; about 15 more minutes (skipped with --only).
Exits 1 when a case is flagged (unless --no-fail), 2 on usage errors.

    scripts/bench-nightly.py [--bench BIN] [--instructions-bench BIN]
                             [--history benches/history.jsonl] [--only D=2,N=10000]
                             [--threshold 0.10] [--passes 3] [--confirm 2] [--peers DIR | --no-peers]
                             [--instructions-max-n N]
"""

from __future__ import annotations

import argparse
import datetime as dt
import json
import os
import platform
import shutil
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import cooling_bench  # noqa: E402
import instructions  # noqa: E402
import peers  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
NS = [1_000, 10_000, 100_000, 1_000_000]
PHIS = {2: [0.05, 0.3, 0.7], 3: [0.05, 0.3, 0.5]}
EPSS = [1.0, 0.9]


def matrix() -> list[dict]:
    return [
        {"d": d, "n": n, "phi": phi, "eps": eps}
        for d in (2, 3)
        for n in NS
        for phi in PHIS[d]
        for eps in EPSS
    ]


def per_particle(n: int) -> float:
    """Collisions per particle of one timed repeat: about 1e6 collisions, within [0.5, 300]."""
    return min(300.0, max(0.5, 1e6 / n))


def melt_tau(n: int) -> float:
    """Elastic equilibration before timing, in collisions per particle (the lattice starts at high phi
    melt in a few)."""
    return 2.0 if n < 100_000 else 1.0


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def git(*args: str) -> str:
    try:
        return subprocess.run(
            ["git", *args], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def commit_id() -> str:
    head = git("rev-parse", "--short=12", "HEAD") or "unknown"
    # A build from a modified tree is not the commit: mark it, so history never confuses the two.
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", "crates", "src", "Cargo.toml", "Cargo.lock")
    return head + ("-dirty" if dirty else "")


def key(row: dict) -> tuple:
    # Builds for different instruction sets are different programs: each is compared with its own
    # kind (entries from before the field were all of the generic x86-64 build).
    return (row["machine"], row.get("isa", "x86-64"), row["d"], row["n"], row["phi"], row["eps"], row.get("peer"),
            row.get("cool_from"))


def built_for(bench: Path) -> str | None:
    """The instruction set `bench` was compiled for (its `isa` field), from one short run; None (after
    an error message) if it does not run."""
    cmd = [str(bench), "--json", "--d", "2", "--n", "1000", "--phi", "0.3", "--repeats", "1",
           "--collisions-per-particle", "0.5", "--melt-tau", "0.5"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        print(f"error: {bench} does not run: {p.stderr.strip() or p.stdout.strip()}", file=sys.stderr)
        return None
    return json.loads(p.stdout.strip().splitlines()[-1]).get("isa", "x86-64")


def parse_only(text: str | None) -> dict:
    if not text:
        return {}
    out = {}
    for part in text.split(","):
        name, _, value = part.partition("=")
        name = name.strip().lower()
        if name not in ("d", "n", "phi", "eps") or not value:
            raise SystemExit(f"error: invalid --only item {part!r}: expected D=, N=, PHI= or EPS= with a value")
        try:
            out[name] = float(value)
        except ValueError:
            raise SystemExit(f"error: invalid --only value {part!r}: not a number") from None
    return out


def measure(bench: Path, c: dict, run: dict) -> dict | None:
    """One run of edmd-bench on case c: a history row, or None (after an error message) on failure."""
    cmd = [
        str(bench), "--json", "--d", str(c["d"]), "--n", str(c["n"]), "--phi", str(c["phi"]),
        "--eps", str(c["eps"]), "--repeats", "1",
        "--collisions-per-particle", str(per_particle(c["n"])), "--melt-tau", str(melt_tau(c["n"])),
    ]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        print(f"error: case {c} failed: {p.stderr.strip() or p.stdout.strip()}", file=sys.stderr)
        return None
    out = json.loads(p.stdout.strip().splitlines()[-1])
    keep = ("collisions_per_s", "bytes_per_particle", "collisions", "seconds")
    return {**run, **c, **{k: out[k] for k in keep}}


def summarize(ms: list[dict]) -> dict:
    """A case's history row from its measurements: median collisions/s, spread (max - min) / median,
    the largest peak bytes per particle, total collisions and seconds."""
    rates = sorted(m["collisions_per_s"] for m in ms)
    mid = len(rates) // 2
    median = rates[mid] if len(rates) % 2 else 0.5 * (rates[mid - 1] + rates[mid])
    return {
        **{k: ms[0][k] for k in ("commit", "date", "machine", "cpu", "cores", "isa", "d", "n", "phi", "eps")},
        "collisions_per_s": round(median),
        "spread": round((rates[-1] - rates[0]) / median, 4),
        "bytes_per_particle": max(m["bytes_per_particle"] for m in ms),
        "repeats": len(ms),
        "collisions": sum(m["collisions"] for m in ms),
        "seconds": round(sum(m["seconds"] for m in ms), 4),
    }


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--history", default=str(ROOT / "benches" / "history.jsonl"), help="JSON-lines history file (appended)")
    ap.add_argument("--bench", default=str(ROOT / "target" / "dist" / "edmd-bench"), help="edmd-bench binary timed (`make bench-nightly`: built for this processor, as the peers are)")
    ap.add_argument("--instructions-bench", default=str(ROOT / "target" / "dist" / "edmd-bench"), help="edmd-bench binary counted by cachegrind (the generic x86-64 build, as the peers are for the count)")
    ap.add_argument("--machine", default=os.environ.get("EDMD_BENCH_MACHINE"), help="machine name (default: CPU model and core count; env EDMD_BENCH_MACHINE)")
    ap.add_argument("--only", help="run the matching cases only, e.g. D=2,N=10000")
    ap.add_argument("--threshold", type=float, default=0.10, help="flag cases slower than the previous entry by more than this fraction (default 0.10)")
    ap.add_argument("--passes", type=int, default=3, help="passes over the matrix; a case's entry is the median over them (default 3)")
    ap.add_argument("--confirm", type=int, default=2, help="measure a slow case this many more times before flagging it (default 2)")
    ap.add_argument("--no-fail", action="store_true", help="exit 0 even when cases are flagged")
    ap.add_argument("--no-record", action="store_true", help="do not append to the history file")
    ap.add_argument("--peers", help="folder of the peer codes (with build.sh); default: env EDMD_PEERS or shared/peers beside the checkout")
    ap.add_argument("--no-peers", action="store_true", help="skip the side-by-side part")
    ap.add_argument("--cooling-max-n", type=int, default=100_000, help="free-cooling cases (scripts/cooling_bench.py) up to this N; 0: none; skipped with --only (default 1e5)")
    ap.add_argument("--instructions-max-n", type=int, default=100_000, help="count instructions per collision (cachegrind) on the peer cases up to this N; 0: none (default 1e5)")
    args = ap.parse_args()
    if not 0 < args.threshold < 1:
        print(f"error: invalid --threshold {args.threshold}: must lie in (0, 1)", file=sys.stderr)
        return 2
    if args.passes < 1:
        print(f"error: invalid --passes {args.passes}: must be >= 1", file=sys.stderr)
        return 2
    if args.confirm < 0:
        print(f"error: invalid --confirm {args.confirm}: must be >= 0", file=sys.stderr)
        return 2
    bench = Path(args.bench)
    if not bench.is_file():
        print(f"error: benchmark binary {bench} not found: build it with `make bench-bin` (or `cargo build --profile dist --bin edmd-bench`)", file=sys.stderr)
        return 2
    only = parse_only(args.only)
    cases = [c for c in matrix() if all(abs(c[k] - v) < 1e-12 for k, v in only.items())]
    if not cases:
        print(f"error: --only {args.only!r} matches no case of the matrix", file=sys.stderr)
        return 2

    history_path = Path(args.history)
    history = []
    if history_path.exists():
        for i, line in enumerate(history_path.read_text().splitlines(), 1):
            if line.strip():
                try:
                    history.append(json.loads(line))
                except json.JSONDecodeError as e:
                    print(f"error: {history_path}:{i}: not JSON ({e})", file=sys.stderr)
                    return 2
    cpu = cpu_model()
    cores = os.cpu_count() or 1
    machine = args.machine or f"{cpu} x{cores}"
    isa = built_for(bench)
    if isa is None:
        return 2
    run = {
        "commit": commit_id(),
        "date": dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ"),
        "machine": machine,
        "cpu": cpu,
        "cores": cores,
        "isa": isa,
    }
    previous = {}
    for row in history:
        previous[key(row)] = row  # the latest entry of each case wins

    print(
        f"bench-nightly: commit {run['commit']}, {run['date']}, machine {machine!r}, edmd-bench built for {isa}, {len(cases)} cases, "
        f"{args.passes} passes"
    )
    # Each pass times every case once, in its own process; a case's entry is the median over the passes.
    # Spreading a case's measurements over the whole run keeps a neighbour's burst on a shared machine
    # (which moves the cache-sized cases, N = 1e5, by up to 20 %) from deciding its number.
    samples: dict[tuple, list[dict]] = {key({**run, **c}): [] for c in cases}
    start = time.monotonic()
    for k in range(args.passes):
        for c in cases:
            out = measure(bench, c, run)
            if out is None:
                return 2
            samples[key(out)].append(out)
        print(f"  pass {k + 1}/{args.passes} done after {time.monotonic() - start:.0f} s", flush=True)

    header = f"{'D':>2} {'N':>8} {'phi':>5} {'eps':>4} {'collisions/s':>13} {'spread':>7} {'B/N':>6} {'previous':>13} {'change':>7}"
    print(header)
    rows, flagged = [], []
    for c in cases:
        ms = samples[key({**run, **c})]
        prev = previous.get(key({**run, **c}))
        row = summarize(ms)
        change, mark = "", ""
        if prev:
            ratio = row["collisions_per_s"] / prev["collisions_per_s"]
            # A slow case is measured --confirm more times before it is flagged; its entry becomes the
            # median of all its measurements. A slower build is slow every time.
            extra = 0
            while ratio < 1 - args.threshold and extra < args.confirm:
                out = measure(bench, c, run)
                if out is None:
                    return 2
                ms.append(out)
                extra += 1
                row = summarize(ms)
                ratio = row["collisions_per_s"] / prev["collisions_per_s"]
            change = f"{100 * (ratio - 1):+6.1f}%"
            if ratio < 1 - args.threshold:
                mark = f"  SLOWER (previous {prev['commit']}, {prev['date']}; {len(ms)} measurements)"
                flagged.append((row, prev, ratio))
            elif extra:
                mark = f"  ({len(ms)} measurements)"
        rows.append(row)
        prev_rate = f"{prev['collisions_per_s']:13.0f}" if prev else f"{'-':>13}"
        print(
            f"{c['d']:>2} {c['n']:>8} {c['phi']:>5} {c['eps']:>4} {row['collisions_per_s']:13.0f} "
            f"{100 * row['spread']:6.1f}% {row['bytes_per_particle']:6.0f} {prev_rate} {change:>7}{mark}",
            flush=True,
        )
    side = [] if args.no_peers else side_by_side(args, bench, run, previous, only)
    for row, prev in side:
        rows.append(row)
        if prev and row["ratio"] < prev["ratio"] * (1 - args.threshold):
            flagged.append((row, prev, row["ratio"] / prev["ratio"]))
        grown = instruction_growth(row, prev)
        if grown is not None and grown > 1 + INSTRUCTION_THRESHOLD:
            flagged.append((row, prev, grown))
    if args.cooling_max_n > 0 and not only:
        for row in cooling_bench.run(bench, args.cooling_max_n, args.passes, base=run):
            prev = previous.get(key(row))
            rows.append(row)
            if prev and row["collisions_per_s"] < prev["collisions_per_s"] * (1 - args.threshold):
                flagged.append((row, prev, row["collisions_per_s"] / prev["collisions_per_s"]))
    if not args.no_record:
        history_path.parent.mkdir(parents=True, exist_ok=True)
        with history_path.open("a") as f:
            for row in rows:
                f.write(json.dumps(row, sort_keys=True) + "\n")
    print(f"bench-nightly: {len(rows)} cases in {time.monotonic() - start:.0f} s; history: {history_path}{' (not recorded)' if args.no_record else ''}")
    if flagged:
        print(f"bench-nightly: {len(flagged)} case(s) more than {100 * args.threshold:.0f} % slower than the previous entry on this machine:")
        for row, prev, ratio in flagged:
            if ratio > 1:
                print(f"  instructions D={row['d']} N={row['n']}: {row['instructions_per_collision']:.0f} per collision vs {prev['instructions_per_collision']:.0f} ({100 * (ratio - 1):+.1f} %) at {prev['commit']}")
            elif "peer" in row:
                print(f"  side by side D={row['d']} N={row['n']}: edmd/peer {row['ratio']:.2f} vs {prev['ratio']:.2f} ({100 * (ratio - 1):+.1f} %) at {prev['commit']}")
            else:
                cooling = f" cooling from tau {row['cool_from']:.0f}" if "cool_from" in row else ""
                print(f"  D={row['d']} N={row['n']} phi={row['phi']} eps={row['eps']}{cooling}: {row['collisions_per_s']:.0f} vs {prev['collisions_per_s']:.0f} collisions/s ({100 * (ratio - 1):+.1f} %) at {prev['commit']}")
        return 0 if args.no_fail else 1
    print("bench-nightly: no case slower than the threshold")
    return 0


# A growth of edmd's instructions per collision beyond this fraction is flagged (deterministic counts).
INSTRUCTION_THRESHOLD = 0.03


def instruction_growth(row: dict, prev: dict | None) -> float | None:
    """edmd's instructions per collision over the previous entry's, where both have them."""
    if not prev or "instructions_per_collision" not in row or "instructions_per_collision" not in prev:
        return None
    return row["instructions_per_collision"] / prev["instructions_per_collision"]


def median(xs: list[float]) -> float:
    xs = sorted(xs)
    mid = len(xs) // 2
    return xs[mid] if len(xs) % 2 else 0.5 * (xs[mid - 1] + xs[mid])


def side_by_side(args, bench: Path, run: dict, previous: dict, only: dict) -> list[tuple[dict, dict | None]]:
    """edmd-bench and the peer alternating on every peer case: (history row, previous row) pairs."""
    folder = peers.find(args.peers)
    if folder is None:
        print("bench-nightly: side by side skipped: no peer codes found (--peers DIR or EDMD_PEERS: a folder with build.sh)")
        return []
    binaries = peers.build(folder)
    cases = [
        (d, n) for d, n in peers.CASES
        if all(abs({"d": d, "n": n, "phi": peers.PHI[d], "eps": 1.0}[k] - v) < 1e-12 for k, v in only.items())
    ]
    print(f"bench-nightly: side by side with the peers of {folder} ({len(cases)} cases, {args.passes} rounds, alternating)")
    print(f"{'D':>2} {'N':>8} {'phi':>5} {'edmd/s':>11} {'peer/s':>11} {'ratio':>6} {'previous':>8}  peer")
    out = []
    for d, n in cases:
        ours, theirs = [], []
        for _ in range(args.passes):
            ours.append(peers.our_rate(bench, d, n))
            theirs.append(peers.peer_rate(binaries, d, n))
        o, p = median(ours), median(theirs)
        row = {
            **run, "d": d, "n": n, "phi": peers.PHI[d], "eps": 1.0, "peer": peers.NAME[d],
            "collisions_per_s": round(o), "peer_collisions_per_s": round(p), "ratio": round(o / p, 4),
            "spread": round((max(ours) - min(ours)) / o, 4),
            "peer_spread": round((max(theirs) - min(theirs)) / p, 4), "repeats": len(ours),
        }
        prev = previous.get(key(row))
        was = f"{prev['ratio']:8.2f}" if prev else f"{'-':>8}"
        print(f"{d:>2} {n:>8} {peers.PHI[d]:>5} {o:11.0f} {p:11.0f} {o / p:6.2f} {was}  {peers.NAME[d]}", flush=True)
        out.append((row, prev))
    count_instructions(args, folder, out)
    return out


def count_instructions(args, folder: Path, out: list[tuple[dict, dict | None]]) -> None:
    """Adds both codes' instructions per collision (cachegrind) to the rows up to --instructions-max-n."""
    todo = [row for row, _ in out if row["n"] <= args.instructions_max_n]
    if not todo:
        return
    if shutil.which("valgrind") is None:
        print("bench-nightly: instruction counts skipped: valgrind is not installed")
        return
    counted = Path(args.instructions_bench)
    if not counted.is_file():
        print(f"bench-nightly: instruction counts skipped: {counted} not found (cargo build --profile dist --bin edmd-bench)")
        return
    instructions.BENCH = counted
    generic = instructions.build_generic(folder)
    print(f"{'D':>2} {'N':>8} {'edmd instr/coll':>16} {'peer instr/coll':>16} {'ratio':>6}")
    for row in todo:
        ours = instructions.edmd_per_collision(row["d"], row["n"])
        theirs = instructions.peer_per_collision(generic, row["d"], row["n"])
        row["instructions_per_collision"] = round(ours, 1)
        row["peer_instructions_per_collision"] = round(theirs, 1)
        print(f"{row['d']:>2} {row['n']:>8} {ours:16.0f} {theirs:16.0f} {ours / theirs:6.2f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
