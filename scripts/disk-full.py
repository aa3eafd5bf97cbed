#!/usr/bin/env python3
"""A disk that fills during `edmd run` (a fresh sweep, and the rerun of a finished one, which writes the
index and summaries again), `edmd merge`, `edmd refine` and the Python report, at every
free size from 0 to 64 KiB in steps of 4 KiB (`make disk-full`; needs root to mount a tmpfs).

For each command and free size: the command's starting state is laid out on a fresh tmpfs, a filler
file leaves that much free, and the command runs. Then every file under a final name must open (HDF5
files with h5py, JSON parsed, PNG decoded, CSV read), no temporary file may be left, and an error must
be one line naming a file and the system's reason. Finally the filler goes, the same command runs
again and its output must equal an uninterrupted run's (scripts/compare-outputs.py; for the report,
the same files). Prints one row per case and exits 1 if any fails.

    sudo .venv/bin/python scripts/disk-full.py [--edmd target/release/edmd] [--sizes 0,4,...]
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import h5py
from PIL import Image

REPO = Path(__file__).resolve().parents[1]
SPEC = {"name": "full", "seed": 5, "grid": {"eps": [0.8, 0.9], "phi": 0.2, "n": 100, "seeds": 2},
        "stop": {"tau_max": 10}, "samples": {"every": 1, "per_decade": 0},
        "snapshots": {"every": 5}, "classify": {}}
REFINE = {"name": "refine", "seed": 5, "grid": {"eps": [0.6, 1.0], "phi": 0.25, "box": [12, 24]},
          "stop": {"tau_max": 60}, "samples": {"every": 5, "per_decade": 0}, "classify": {}}


def sh(args, **kw):
    return subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)


class Tmpfs:
    def __init__(self, where: Path, size: str = "24m"):
        self.dir = where
        where.mkdir(parents=True, exist_ok=True)
        if sh(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", where]).returncode != 0:
            sys.exit("disk-full: cannot mount a tmpfs (needs root)")

    def clear(self):
        for p in self.dir.iterdir():
            shutil.rmtree(p) if p.is_dir() and not p.is_symlink() else p.unlink()

    def leave_free(self, kib: int):
        st = os.statvfs(self.dir)
        fill = st.f_bavail * st.f_frsize - kib * 1024
        with open(self.dir / "filler", "wb") as f:
            while fill > 0:
                chunk = min(fill, 1 << 20)
                try:
                    f.write(b"\0" * chunk)
                    f.flush()
                except OSError:
                    break
                fill -= chunk

    def free(self):
        (self.dir / "filler").unlink(missing_ok=True)

    def close(self):
        sh(["umount", "-l", self.dir])


def unreadable(root: Path):
    """Files under a final name that do not open, and temporary files left behind."""
    bad = []
    for p in root.rglob("*"):
        if p.name == "filler" or p.is_dir():
            continue
        name = p.name
        if ".tmp" in name or ".part" in name:
            bad.append(f"{p.relative_to(root)}: temporary file left")
            continue
        try:
            if name.endswith(".h5"):
                with h5py.File(p, "r") as f:
                    f.visit(lambda _: None)
            elif name.endswith(".json"):
                json.loads(p.read_text())
            elif name.endswith(".png") or name.endswith(".gif"):
                with Image.open(p) as im:
                    im.load()
            elif name.endswith(".csv"):
                p.read_text().splitlines()
        except Exception as e:  # noqa: BLE001 - any failure to read is the finding
            bad.append(f"{p.relative_to(root)}: {type(e).__name__}")
    return bad


def one_line_naming_a_file(stderr: str) -> bool:
    errors = [line for line in stderr.splitlines() if line.startswith("error")]
    return len(errors) == 1 and "/" in errors[0]


def report_files(out: Path):
    return sorted(p.name for p in (out / "report").iterdir()) if (out / "report").is_dir() else []


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--edmd", default=str(REPO / "target/release/edmd"))
    ap.add_argument("--sizes", default=",".join(str(k) for k in range(0, 65, 4)))
    args = ap.parse_args()
    edmd, py = args.edmd, sys.executable
    sizes = [int(s) for s in args.sizes.split(",")]
    work = Path(tempfile.mkdtemp(prefix="edmd-disk-full."))
    ref = work / "ref"
    for name, spec in (("spec", SPEC), ("refine", REFINE)):
        (work / f"{name}.json").write_text(json.dumps(spec))
    # References, on the ordinary disk.
    sh([edmd, "run", work / "spec.json", "-o", ref / "run", "-q"], check=True)
    for k in (0, 1):
        sh([edmd, "run", work / "spec.json", "-o", ref / f"shard{k}", "--shard", f"{k}/2", "-q"], check=True)
    sh([edmd, "run", work / "refine.json", "-o", ref / "refine-start", "-q"], check=True)
    shutil.copytree(ref / "refine-start", ref / "refine")
    sh([edmd, "refine", ref / "refine", "--rounds", "2", "-q"], check=True)
    shutil.copytree(ref / "run", ref / "reported")
    sh([py, "-m", "edmd_analysis", "report", ref / "reported", "--no-movies"], check=True)
    fs = Tmpfs(work / "mnt")
    out = fs.dir / "out"
    commands = {
        "run": (lambda: None, [edmd, "run", work / "spec.json", "-o", out, "-q"], ref / "run"),
        # A rerun of a finished sweep: only the index and the summaries are written again.
        "rerun": (lambda: shutil.copytree(ref / "run", out),
                  [edmd, "run", work / "spec.json", "-o", out, "-q"], ref / "run"),
        "merge": (lambda: None, [edmd, "merge", "-o", out, ref / "shard0", ref / "shard1"], ref / "run"),
        "refine": (lambda: shutil.copytree(ref / "refine-start", out),
                   [edmd, "refine", out, "--rounds", "2", "-q"], ref / "refine"),
        "report": (lambda: shutil.copytree(ref / "run", out),
                   [py, "-m", "edmd_analysis", "report", out, "--no-movies"], ref / "reported"),
    }
    failures = 0
    print(f"{'command':8} {'free':>6} {'exit':>4}  {'after the fill':60} resumed")
    try:
        for name, (prepare, cmd, expect) in commands.items():
            for kib in sizes:
                fs.clear()
                prepare()
                fs.leave_free(kib)
                first = sh(cmd)
                bad = unreadable(fs.dir)
                clear = first.returncode == 0 or one_line_naming_a_file(first.stderr)
                fs.free()
                again = sh(cmd)
                if name == "report":
                    same = again.returncode == 0 and report_files(out) == report_files(expect)
                else:
                    cmp = sh([py, REPO / "scripts/compare-outputs.py", out, expect])
                    same = again.returncode == 0 and cmp.returncode == 0
                ok = not bad and clear and same
                failures += not ok
                last = (first.stderr.strip().splitlines() or [""])[-1].replace(f"{out}/", "OUT/")
                message = last.replace(str(out), "OUT")[:60] if first.returncode else "ok"
                print(f"{name:8} {kib:4}Ki {first.returncode:4}  {message:60} {'identical' if same else 'DIFFERS'}"
                      f"{'' if ok else '  FAIL: ' + '; '.join(bad or ['unclear error' if not clear else 'resume'])}",
                      flush=True)
    finally:
        fs.close()
        shutil.rmtree(work, ignore_errors=True)
    print(f"disk-full: {failures} failing case(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
