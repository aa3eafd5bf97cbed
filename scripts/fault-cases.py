"""The fault cases of the second hardening round, rerun as a user would: a markdown table of
case | exit code | message for one edmd binary.

usage: fault-cases.py EDMD PYTHON REPO
  EDMD    the edmd binary under test
  PYTHON  a Python with edmd_analysis installed (the venv of `make venv`)
  REPO    this repository (for scripts/compare-outputs.py)

Case 8's read-only output is a read-only bind mount when run as root (root ignores permissions),
a chmod 555 directory otherwise; case 11 needs strace.
"""

import json
import os
import pathlib
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

EDMD = sys.argv[1]
PY = sys.argv[2]
REPO = sys.argv[3]
tmp = pathlib.Path(tempfile.mkdtemp())
rows = []


def run(*a, env=None):
    p = subprocess.run([EDMD, *a], capture_output=True, text=True, env=env, timeout=900)
    return p.returncode, (p.stderr.strip().splitlines() or [""])[-1][:150]


def spec(name, grid, stop, rule=None, extra=None):
    s = {"name": name, "seed": 1, "grid": grid, "stop": stop, "samples": {"every": 5, "per_decade": 0}}
    if rule:
        s["rule"] = rule
    if extra:
        s.update(extra)
    f = tmp / f"{name}.json"
    f.write_text(json.dumps(s))
    return str(f)


def summary(out):
    try:
        r = json.loads((pathlib.Path(out) / "summary.json").read_text())
        return "; ".join(f"{x['status']}: {x['message'][:110]}" for x in r)
    except Exception as e:
        return f"(no summary: {e})"


def kept(v):
    return "kept" if v.read_text() == "precious\n" else "OVERWRITTEN"


def row(case, rc, msg):
    rows.append((case, rc, msg))
    print(f"| {case} | {rc} | {msg} |", flush=True)


small = spec("small", {"dim": 2, "eps": 0.9, "phi": 0.1, "n": 64}, {"tau_max": 2})
# 1
for lock, extra in [(".lock", []), (".lock.shard-0-of-2", ["--shard", "0/2"])]:
    victim = tmp / "victim"
    victim.write_text("precious\n")
    out = tmp / f"o1{lock}"
    out.mkdir()
    os.symlink(victim, out / lock)
    rc, m = run("run", small, "-o", str(out), "-q", *extra)
    row(f"1 run, {lock} -> file", rc, f"{m} [target {kept(victim)}]")
a = tmp / "o1a"
run("run", small, "-o", str(a), "-q")
b = tmp / "o1b"
b.mkdir()
victim.write_text("precious\n")
os.symlink(victim, b / ".lock")
rc, m = run("merge", str(a), "-o", str(b))
row("1 merge, .lock -> file", rc, f"{m} [target {kept(victim)}]")
# 2
for i, (g, st) in enumerate(
    [
        ({"boundary": "walls", "eps": 0.9, "phi": 0.1, "wall_eps": 0, "gravity": 1}, 50),
        ({"boundary": "walls", "eps": 0.5, "phi": 0.1, "wall_eps": 0.5, "gravity": 1}, 200),
        ({"boundary": "walls", "eps": 0.5, "phi": 0.1, "gravity": 1e6}, 100),
        ({"boundary": "walls", "eps": 0.9, "phi": 0.1, "gravity": 1, "floor_temperature": 1e-12}, 50),
    ]
):
    g = {"dim": 2, "n": 256, **g}
    out = tmp / f"o2{i}"
    rc, _ = run("run", spec(f"col{i}", g, {"tau_max": st}), "-o", str(out), "-q")
    row(
        f"2 column {json.dumps({k: v for k, v in g.items() if k not in ('dim', 'n', 'phi')})} tau_max {st}",
        rc,
        summary(out),
    )
# 3
for st in [50, 200]:
    g = {
        "dim": 2,
        "eps": 0.9,
        "phi": 0.1,
        "n": 256,
        "species": [
            {"fraction": 0.5, "diameter": 1, "mass": 1},
            {"fraction": 0.5, "diameter": 1, "mass": 1e6},
        ],
    }
    out = tmp / f"o3{st}"
    rc, _ = run(
        "run",
        spec(f"mix{st}", g, {"tau_max": st}, extra={"samples": {"every": 1, "per_decade": 0}}),
        "-o",
        str(out),
        "-q",
    )
    row(f"3 mixture masses 1, 1e6, tau_max {st}", rc, summary(out))
# 4
for sp in [1, 1e-4, 1e-6, 1e-8]:
    out = tmp / f"o4{sp}"
    rc, m = run(
        "run",
        spec(
            f"ve{sp}",
            {"dim": 3, "eps": 0.9, "phi": 0.1, "n": 256},
            {"tau_max": 50},
            rule={"kind": "viscoelastic", "speed": sp},
        ),
        "-o",
        str(out),
        "-q",
    )
    T = ""
    try:
        with h5py.File(next((out / "replicas").glob("*.h5"))) as f:
            T = f" T(tau 50) = {f['observables/temperature/value'][-1]:.3g}"
    except Exception:
        pass
    row(f"4 viscoelastic speed {sp}", rc, (m if rc else "ran") + T)
# 5
for q, beta, eps in [(1e-9, 1, 0.5), (1e-4, 1, 1), (1e-6, 1, 1), (1e-7, 1, 1), (1e-9, 1, 1)]:
    out = tmp / f"o5{q}{eps}"
    rc, m = run(
        "run",
        spec(
            "rough", {"dim": 2, "eps": eps, "phi": 0.1, "n": 256, "beta": beta, "inertia": q}, {"tau_max": 5}
        ),
        "-o",
        str(out),
        "-q",
    )
    try:
        with h5py.File(next((out / "replicas").glob("*.h5"))) as f:
            th = f["parameters"].attrs.get("rotational_ratio_theory", None)
            if th is None and "rotational_ratio_theory" in f["parameters"]:
                th = f["parameters/rotational_ratio_theory"][()]
            so = (
                f["parameters/rotational_ratio_sonine"][()]
                if "rotational_ratio_sonine" in f["parameters"]
                else f["parameters"].attrs.get("rotational_ratio_sonine")
            )
            obs = f["observables/rotational_ratio_theory/value"][:]
            m = f"theory {float(th):.6g}, sonine {float(so):.6g}, non-finite samples {int((~np.isfinite(obs)).sum())} of {obs.size}"
            if eps == 1:
                m += f", exact N/(N-1) = {256 / 255:.6g}"
    except Exception as e:
        m = f"{m} ({e})"
    row(f"5 rough q {q} beta {beta} eps {eps}", rc, m)
# 6
f6 = tmp / "dup.json"
f6.write_text(
    '{"name": "d", "grid": {"dim": 2, "eps": [1, 0.95, 0.9], "eps": 0.5, "phi": 0.1, "n": 64}, "stop": {"tau_max": 1}}'
)
row("6 duplicate grid.eps", *run("validate-spec", str(f6)))
# 7
for n in [2, 3, 200]:
    out = tmp / f"o7{n}"
    rc, m = run(
        "run",
        spec(
            f"n{n}",
            {"dim": 2, "eps": 0.9, "phi": 0.1, "n": n},
            {"tau_max": 50},
            extra={"samples": {"every": 1, "per_decade": 10, "log_from": 0.1}},
        ),
        "-o",
        str(out),
        "-q",
    )
    try:
        with h5py.File(next((out / "replicas").glob("*.h5"))) as f:
            st = (
                f["observables/pressure/step"][:]
                if "step" in f["observables/pressure"]
                else f["observables/pressure/time"][:]
            )
            p = f["observables/pressure/value"][:]
            m = f"{p.size} samples, repeated steps {p.size - np.unique(st).size}, NaN pressures {int(np.isnan(p).sum())}"
    except Exception as e:
        m = f"{m} ({e})"
    row(f"7 N = {n} samples", rc, m)
# 8
q = tmp / "o1a"
ro = tmp / "ro"
if os.geteuid() == 0:
    ro.mkdir()
    subprocess.run(["mount", "--bind", str(q), str(ro)], check=True)
    subprocess.run(["mount", "-o", "remount,ro,bind", str(ro)], check=True)
    target = ro
else:
    subprocess.run(["cp", "-r", str(q), str(ro)], check=True)
    os.chmod(ro, 0o555)
    target = ro
for args in [
    ["report", str(target)],
    ["report", str(q / "summary.json")],
    ["movie", str(q), "--dpi", "0"],
    ["movie", str(q), "--dpi", "-5"],
]:
    p = subprocess.run([PY, "-m", "edmd_analysis", *args], capture_output=True, text=True)
    e = p.stderr.strip().splitlines()
    row(
        f"8 python {' '.join(a if not a.startswith('/') else pathlib.Path(a).name for a in args)}",
        p.returncode,
        f"{len(e)} line(s): {(e or [''])[-1][:120]}",
    )
if os.geteuid() == 0:
    subprocess.run(["umount", str(ro)], check=True)
# 9: a replica file of another spec put in place of one of this spec's
other = tmp / "o9"
run("run", spec("small", {"dim": 2, "eps": 0.5, "phi": 0.1, "n": 64}, {"tau_max": 2}), "-o", str(other), "-q")
mix = tmp / "o9mix"
subprocess.run(["cp", "-r", str(a), str(mix)], check=True)
subprocess.run(["cp", str(other / "replicas/r00000.h5"), str(mix / "replicas/r00000.h5")], check=True)
p = subprocess.run([EDMD, "status", str(mix)], capture_output=True, text=True)
row(
    "9 replica of another spec: edmd status",
    p.returncode,
    " / ".join(p.stdout.strip().splitlines()[:2])[:150],
)
p = subprocess.run(
    [PY, "-m", "edmd_analysis", "report", str(mix), "-o", str(tmp / "r9"), "--no-movies"],
    capture_output=True,
    text=True,
)
drawn = sorted(x.name for x in (tmp / "r9").glob("*.png")) if (tmp / "r9").exists() else []
row("9 replica of another spec: python report", p.returncode, f"figures drawn from it: {len(drawn)}")
# 10
for x, y in [(a, other), (other, a)]:
    p = subprocess.run(
        [PY, f"{REPO}/scripts/compare-outputs.py", str(x), str(y)], capture_output=True, text=True
    )
    row(
        f"10 compare-outputs {x.name} {y.name}",
        p.returncode,
        (p.stdout.strip().splitlines() or p.stderr.strip().splitlines() or [""])[-1][:140],
    )
# 11
c = tmp / "o11"
p = subprocess.run(
    [
        "strace",
        "-f",
        "-e",
        "trace=fsync,fdatasync,rename,renameat,renameat2",
        "-o",
        str(tmp / "st"),
        EDMD,
        "merge",
        str(a),
        "-o",
        str(c),
    ],
    capture_output=True,
    text=True,
)
tr = (tmp / "st").read_text()
row(
    "11 merge syncs",
    p.returncode,
    f"fsync/fdatasync calls {tr.count('fsync(') + tr.count('fdatasync(')}, renames {tr.count('rename')}",
)
# 12
f12a = spec(
    "lat", {"dim": 2, "eps": 0.9, "phi": 0.9, "n": 64}, {"tau_max": 1}, extra={"init": {"melt_tau": 20}}
)
row("12 validate-spec phi 0.9", *run("validate-spec", f12a))
f12b = spec("bx", {"dim": 2, "eps": 0.9, "box": 1e6, "n": 2}, {"tau_max": 1})
row("12 validate-spec box 1e6 N 2", *run("validate-spec", f12b))
big = spec("big", {"dim": 2, "eps": 0.99, "phi": 0.2, "n": 20000, "seeds": 2}, {"tau_max": 400})
o12 = tmp / "o12"
h = subprocess.Popen([EDMD, "run", big, "-o", str(o12), "-q", "--threads", "2"])
time.sleep(3)
p = subprocess.run([EDMD, "status", str(o12)], capture_output=True, text=True)
h.kill()
h.wait()
row(
    "12 status while 2 replicas run",
    p.returncode,
    " / ".join(x for x in p.stdout.splitlines() if "flight" in x or "running" in x or "progress" in x)[:150],
)
# 13
m = [line for line in open("/proc/mounts") if line.split()[2] == "tmpfs" and "/tmp" in line.split()[1]]
row("13 tmpfs mounts under /tmp (after make test)", 0, f"{len(m)} left")
