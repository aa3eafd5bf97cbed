#!/usr/bin/env python3
"""Run time against error (`make bench-accuracy`).

1. Collapse remedies (edmd-accuracy remedies): TC model, velocity threshold, random rotation and the
   thesis's combination at eps = 0.7 and 0.9; cost per collision against the exact-eps run and the
   error of the fitted cooling rate against the exact-eps run and against Haff's law.
2. Statistics (edmd-accuracy statistics): the error of the cooling rate (eps = 0.9) and of chi from the
   collision rate (elastic, phi = 0.25) against theory, against N x seeds x tau and wall time.
3. Classification: the McNamara-Young box (sweeps/mcnamara-young.json) run with tau_max = 250, 500,
   1000, 2000 and 4 seeds; the shear boundary (largest eps whose majority is not kinetic) and the
   clustering boundary (largest eps whose majority clusters) with 2 and 4 seeds, against wall time.

Writes OUT/accuracy.jsonl (every measurement), OUT/accuracy.md (tables) and OUT/accuracy.png.

    scripts/bench-accuracy.py [-o bench-out/accuracy] [--studies remedies,statistics,classification] [--threads 2]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run_lines(cmd: list[str]) -> list[dict]:
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"error: {' '.join(cmd)} failed: {p.stderr.strip()}")
    return [json.loads(line) for line in p.stdout.splitlines() if line.startswith("{")]


def boundaries(summary: list[dict], seeds: int) -> tuple[float | None, float | None]:
    """Largest eps whose majority (of the first `seeds` seeds) is not kinetic, and clusters."""
    by_eps: dict[float, list[str]] = {}
    for r in summary:
        if r["seed_index"] < seeds:
            by_eps.setdefault(r["eps"], []).append(r["class"])
    shear = [e for e, c in by_eps.items() if sum(x != "kinetic" for x in c) * 2 > len(c)]
    clust = [e for e, c in by_eps.items() if sum(x == "clustering" for x in c) * 2 > len(c)]
    return (max(shear) if shear else None, max(clust) if clust else None)


def classification(edmd: Path, threads: int) -> list[dict]:
    spec = json.loads((ROOT / "sweeps" / "mcnamara-young.json").read_text())
    rows = []
    for tau_max in (250, 500, 1000, 2000):
        s = dict(spec)
        s["name"] = f"mcnamara-young-tau{tau_max}"
        s["stop"] = {"tau_max": tau_max}
        s["snapshots"] = {"at": [], "final": False}
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "spec.json"
            path.write_text(json.dumps(s))
            out = Path(tmp) / "out"
            t0 = time.monotonic()
            p = subprocess.run([str(edmd), "run", str(path), "-o", str(out), "--quiet", "--threads", str(threads)], capture_output=True, text=True)
            wall = time.monotonic() - t0
            if p.returncode not in (0, 2):
                raise SystemExit(f"error: edmd run failed: {p.stderr.strip()}")
            summary = json.loads((out / "summary.json").read_text())
            summary = summary["replicas"] if isinstance(summary, dict) else summary
        for seeds in (2, 4):
            shear, clust = boundaries(summary, seeds)
            rows.append({
                "study": "classification", "tau_max": tau_max, "seeds": seeds,
                "shear_boundary": shear, "clustering_boundary": clust,
                # Seeds are a subset of the 4-seed run: its wall time scales with the seed count.
                "seconds": wall * seeds / 4, "threads": threads,
            })
            print(f"  classification tau_max {tau_max} seeds {seeds}: shear boundary {shear}, clustering boundary {clust}, {wall * seeds / 4:.1f} s", flush=True)
    return rows


def table(rows: list[dict]) -> str:
    out = []
    rem = [r for r in rows if r["study"] == "remedy"]
    if rem:
        out += ["## Collapse remedies", "",
                "Cooling rate -d ln T/d tau fitted on tau in [5, 40], mean over seeds, in two settings: a",
                "homogeneous box (half the shear-critical size, phi = 0.05) and the McNamara-Young box",
                "(N = 1024, phi = 0.25, 16 seeds). Error against the exact-eps run (same seeds) and against",
                "Haff's law k(eps); cost = wall time per collision over the exact run's.", "",
                "| setting | eps | N x seeds | remedy | parameter | k | error vs exact | error vs Haff | cost |",
                "|---|---|---|---|---|---|---|---|---|"]
        for r in rem:
            par = "-" if r["remedy"] == "none" else f"{r['param']:g} {r['unit']}"
            out.append(f"| {r.get('setting', '')} | {r['eps']} | {r['n']} x {r['seeds']} | {r['remedy']} | {par} | {r['k']:.4f} ± {r['k_se']:.4f} | {100 * r['error_vs_exact']:+.2f} % | {100 * r['error_vs_theory']:+.2f} % | {r['cost_ratio']:.2f} |")
        out.append("")
    haff = [r for r in rows if r["study"] == "haff"]
    if haff:
        out += ["## Statistics: cooling rate (eps = 0.9, phi = 0.05)", "",
                "| N | seeds | tau window | k / k_Haff - 1 | 1 s.e. | wall s |", "|---|---|---|---|---|---|"]
        for r in haff:
            out.append(f"| {r['n']} | {r['seeds']} | [5, {r['tau_end']:g}] | {100 * r['error']:+.2f} % | {100 * r['rel_se']:.2f} % | {r['seconds']:.2f} |")
        out.append("")
    chi = [r for r in rows if r["study"] == "chi"]
    if chi:
        out += ["## Statistics: chi from the collision rate (elastic, phi = 0.25)", "",
                "| N | seeds | tau | chi / chi_Luding - 1 | 1 s.e. | wall s |", "|---|---|---|---|---|---|"]
        for r in chi:
            out.append(f"| {r['n']} | {r['seeds']} | {r['tau']:g} | {100 * r['error']:+.3f} % | {100 * r['rel_se']:.3f} % | {r['seconds']:.2f} |")
        out.append("")
    cls = [r for r in rows if r["study"] == "classification"]
    if cls:
        out += ["## Classification: McNamara-Young box (N = 1024, phi = 0.25)", "",
                "Theory: shear boundary eps*_perp = 0.982, clustering boundary eps*_par = 0.907 (PHYSICS.md 3.3).", "",
                "| tau_max | seeds | largest non-kinetic eps | largest clustering eps | wall s |", "|---|---|---|---|---|"]
        for r in cls:
            out.append(f"| {r['tau_max']} | {r['seeds']} | {r['shear_boundary']} | {r['clustering_boundary']} | {r['seconds']:.1f} |")
        out.append("")
    return "\n".join(out)


def figure(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    ax = axes[0]
    markers = {"tc": "o", "threshold": "s", "rotation": "^", "threshold+rotation 5deg": "D", "none": "*"}
    for (setting, eps), color in ((("homogeneous", 0.7), "C3"), (("homogeneous", 0.9), "C0"), (("mcnamara-young", 0.7), "C1"), (("mcnamara-young", 0.9), "C2")):
        for name, m in markers.items():
            rs = [r for r in rows if r["study"] == "remedy" and r.get("setting") == setting and r["eps"] == eps and r["remedy"] == name]
            if rs:
                ax.scatter([r["cost_ratio"] for r in rs], [max(abs(r["error_vs_exact"]), 1e-5) for r in rs],
                           marker=m, color=color, label=(f"{setting}, eps {eps} (colour)" if name == "none" else None) if color != "C3" else f"{name} (marker); {setting}, eps {eps}" if name == "none" else f"{name} (marker)", s=30)
    ax.set_yscale("log")
    ax.set_xlabel("cost per collision / exact-eps run")
    ax.set_ylabel("|cooling-rate error| vs exact eps")
    ax.set_title("collapse remedies")
    ax.legend(fontsize=6)
    ax = axes[1]
    for study, label, color in (("haff", "Haff rate, eps 0.9", "C0"), ("chi", "chi(nu), phi 0.25", "C2")):
        rs = [r for r in rows if r["study"] == study]
        if rs:
            ax.scatter([r["seconds"] for r in rs], [max(abs(r["error"]), 1e-6) for r in rs], color=color, label=f"|error| {label}")
            ax.scatter([r["seconds"] for r in rs], [r["rel_se"] for r in rs], color=color, marker="x", label=f"1 s.e. {label}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time (s, one core)")
    ax.set_ylabel("relative error against theory")
    ax.set_title("statistics")
    ax.legend(fontsize=7)
    ax = axes[2]
    for seeds, m in ((2, "o"), (4, "s")):
        rs = [r for r in rows if r["study"] == "classification" and r["seeds"] == seeds]
        if rs:
            ax.plot([r["seconds"] for r in rs], [r["shear_boundary"] or float("nan") for r in rs], marker=m, label=f"largest non-kinetic eps, {seeds} seeds")
            ax.plot([r["seconds"] for r in rs], [r["clustering_boundary"] or float("nan") for r in rs], marker=m, ls="--", label=f"largest clustering eps, {seeds} seeds")
            for r in rs:
                ax.annotate(f"tau {r['tau_max']}", (r["seconds"], r["shear_boundary"] or 0.9), fontsize=6)
    ax.axhline(0.982, color="k", lw=0.8, ls=":")
    ax.axhline(0.907, color="k", lw=0.8, ls="-.")
    ax.set_xscale("log")
    ax.set_xlabel("wall time (s)")
    ax.set_ylabel("eps at the boundary")
    ax.set_title("McNamara-Young box: boundaries vs cost")
    ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--out", default=str(ROOT / "bench-out" / "accuracy"))
    ap.add_argument("--studies", default="remedies,statistics,classification",
                    help="comma-separated studies to run; rows of the others are kept from OUT/accuracy.jsonl")
    ap.add_argument("--threads", type=int, default=2, help="threads of the classification sweeps")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    acc = ROOT / "target" / "release" / "edmd-accuracy"
    edmd = ROOT / "target" / "release" / "edmd"
    for b in (acc, edmd):
        if not b.is_file():
            print(f"error: {b} not built (cargo build --release --workspace)", file=sys.stderr)
            return 2
    studies = [s.strip() for s in args.studies.split(",") if s.strip()]
    bad = [s for s in studies if s not in ("remedies", "statistics", "classification")]
    if bad:
        print(f"error: invalid --studies item(s) {bad}: expected remedies, statistics, classification", file=sys.stderr)
        return 2
    kinds = {"remedies": ("remedy",), "statistics": ("haff", "chi"), "classification": ("classification",)}
    rerun = {k for s in studies for k in kinds[s]}
    rows = []
    old = out / "accuracy.jsonl"
    if old.exists():
        rows = [r for r in map(json.loads, old.read_text().splitlines()) if r["study"] not in rerun]
    for study in ("remedies", "statistics"):
        if study in studies:
            t0 = time.monotonic()
            rows += run_lines([str(acc), study])
            print(f"  {study}: {time.monotonic() - t0:.0f} s", flush=True)
    if "classification" in studies:
        rows += classification(edmd, args.threads)
    order = {"remedy": 0, "haff": 1, "chi": 2, "classification": 3}
    rows.sort(key=lambda r: order[r["study"]])
    (out / "accuracy.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    text = table(rows)
    (out / "accuracy.md").write_text(text + "\n")
    figure(rows, out / "accuracy.png")
    print(text)
    print(f"bench-accuracy: wrote {out / 'accuracy.md'}, {out / 'accuracy.png'}, {out / 'accuracy.jsonl'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
