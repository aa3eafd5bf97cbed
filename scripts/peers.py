"""Running the public peer codes beside edmd-bench (used by bench-nightly.py).

The peers are two public event-driven MD codes kept outside the product: Smallenburg's Single (3D hard
spheres) and its 2D fork for hard disks. A folder holding their sources and a `build.sh OUTDIR` that
compiles them (binaries `hdd2d` and `single3d_N` for N = 10976, 97556, 1000188, FCC start at phi 0.45,
`maxtime` from argv[1]) is found through `--peers DIR`, the environment variable EDMD_PEERS, or a
`shared/peers` folder beside the checkout. A peer's rate is the difference of a short and a long run
(its set-up excluded), as edmd-bench excludes its melt.
"""

from __future__ import annotations

import os
import re
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# (D, N) of the side-by-side cases: the sizes the 3D peer is built for, and 2D at 1e4-1e6; elastic,
# periodic, 2D phi 0.3, 3D phi 0.45.
CASES = [(2, 10_000), (2, 100_000), (2, 1_000_000), (3, 10_976), (3, 97_556), (3, 1_000_188)]
PHI = {2: 0.3, 3: 0.45}
NAME = {2: "hdd2d (2D fork of Smallenburg's Single)", 3: "Smallenburg's Single"}
# Collisions per particle per unit time, to size a peer run at about 2e6 collisions.
RATE_PER_TIME = {2: 12.0, 3: 14.0}


def find(explicit: str | None) -> Path | None:
    """The peers' folder (holding build.sh), or None."""
    for cand in (explicit, os.environ.get("EDMD_PEERS"), str(ROOT.parent / "shared" / "peers")):
        if cand and (Path(cand) / "build.sh").is_file():
            return Path(cand)
    return None


def build(folder: Path) -> Path:
    """Compiles the peers into a temporary folder; returns it."""
    out = Path(tempfile.mkdtemp(prefix="edmd-peers-"))
    subprocess.run(["bash", str(folder / "build.sh"), str(out)], check=True, capture_output=True, text=True)
    return out


def _timed(cmd: list[str], cwd: str) -> tuple[float, int]:
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, check=True).stdout
    wall = time.perf_counter() - t0
    counts = re.findall(r"Collisions: (\d+)", out)
    if not counts:
        raise RuntimeError(f"{cmd[0]} printed no collision count")
    return wall, int(counts[-1])


def _hdd2d(binaries: Path, n: int, phi: float, tmax: float) -> tuple[float, int]:
    work = tempfile.mkdtemp(prefix="edmd-hdd2d-")
    spec = Path(work) / f"in{tmax}.dat"
    spec.write_text(
        f"N_particles {n}\narea_fraction {phi}\ninitial_configuration random\nsize_ratio 1.0\n"
        f"large_spheres_fraction 1.0\ntime {tmax}\nsnapshots 1e9\nwrite_interval {tmax}\nseed 1\n"
    )
    return _timed([str(binaries / "hdd2d"), str(spec)], work)


def _single3d(binaries: Path, n: int, tmax: float) -> tuple[float, int]:
    work = tempfile.mkdtemp(prefix="edmd-single-")
    return _timed([str(binaries / f"single3d_{n}"), str(tmax)], work)


def peer_rate(binaries: Path, d: int, n: int) -> float:
    """Collisions per second of the peer on case (d, n): (C_long - C_short) / (t_long - t_short)."""
    t = max(1.0, 2e6 / n / RATE_PER_TIME[d])
    if d == 2:
        (w1, c1), (w2, c2) = _hdd2d(binaries, n, PHI[2], t), _hdd2d(binaries, n, PHI[2], 3 * t)
    else:
        (w1, c1), (w2, c2) = _single3d(binaries, n, t), _single3d(binaries, n, 3 * t)
    return (c2 - c1) / (w2 - w1)


def our_rate(bench: Path, d: int, n: int) -> float:
    """Collisions per second of edmd-bench on case (d, n), its default run length."""
    out = subprocess.run(
        [str(bench), "--d", str(d), "--n", str(n), "--phi", str(PHI[d]), "--repeats", "1"],
        capture_output=True, text=True, check=True,
    ).stdout
    return float(re.search(r"collisions_per_s=([0-9.e+]+)", out).group(1))
