"""`init.from`: a sweep starts from a configuration in a file. From an earlier replica's final
snapshot the new replica starts in that state (its first sample's temperature is the old final one,
to round-off); from a plain-text file of positions and velocities likewise. A file with an overlap,
a particle outside the box, a NaN, the wrong N, D or box is refused by `validate-spec` and `run`
with one line naming the file (and the particle), and nothing is written."""

import json

import h5py
import numpy as np
import pytest
from conftest import run_edmd

BASE = {"name": "from", "seed": 1, "grid": {"dim": 2, "eps": 0.9, "phi": 0.25, "n": 400},
        "stop": {"tau_max": 20}, "samples": {"every": 5, "per_decade": 0}, "snapshots": {"final": True}}


@pytest.fixture(scope="module")
def earlier(tmp_path_factory):
    d = tmp_path_factory.mktemp("earlier")
    (d / "a.json").write_text(json.dumps(BASE))
    run_edmd("run", d / "a.json", "-o", d / "a", "-q")
    return d / "a" / "replicas" / "r00000.h5"


def final_state(path):
    with h5py.File(path, "r") as f:
        g = f["particles/gas"]
        return (g["position/value"][-1], g["velocity/value"][-1], g["box/edges"][()],
                f["observables/temperature/value"][-1])


def spec_from(tmp_path, file, **grid):
    s = dict(BASE, name="b", init={"from": {"file": str(file)}}, grid=dict(BASE["grid"], **grid))
    p = tmp_path / "b.json"
    p.write_text(json.dumps(s))
    return p


@pytest.mark.parametrize("kind", ["h5", "text"])
def test_a_sweep_starts_from_a_final_snapshot(tmp_path, earlier, kind):
    pos, vel, _, t_final = final_state(earlier)
    source = earlier
    if kind == "text":
        source = tmp_path / "c.txt"
        np.savetxt(source, np.hstack([pos, vel]), fmt="%.17g")
    run_edmd("run", spec_from(tmp_path, source), "-o", tmp_path / "b", "-q")
    with h5py.File(tmp_path / "b" / "replicas" / "r00000.h5", "r") as f:
        t0 = f["observables/temperature/value"][0]
        start = f["particles/gas/position/value"][0]
    assert t0 == pytest.approx(t_final, rel=1e-12)
    assert np.allclose(start, pos, rtol=0, atol=1e-12)


def bad_file(tmp_path, earlier, what):
    pos, vel, box, _ = final_state(earlier)
    pos, vel = pos.copy(), vel.copy()
    if what == "overlap":
        pos[5] = pos[6] + [0.3, 0]
    elif what == "outside":
        pos[7, 0] = box[0] + 1
    elif what == "nan":
        vel[9, 1] = np.nan
    p = tmp_path / f"{what}.txt"
    np.savetxt(p, np.hstack([pos, vel]))
    return p


@pytest.mark.parametrize("what,expect", [
    ("overlap", "particles 5 and 6 overlap"),
    ("outside", "particle 7, axis 0: outside"),
    ("nan", "particle 9: velocity = NaN"),
])
def test_a_bad_configuration_is_refused_in_one_line(tmp_path, earlier, what, expect):
    spec = spec_from(tmp_path, bad_file(tmp_path, earlier, what))
    for args in (["validate-spec", spec], ["run", spec, "-o", tmp_path / "out"]):
        r = run_edmd(*args, check=False)
        assert r.returncode == 1, r.stderr
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and expect in lines[0] and f"{what}.txt" in lines[0], r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("grid,expect", [
    ({"n": 300}, "the file holds 400 particles, the grid point N = 300"),
    ({"phi": 0.3}, "the file's box is"),
    ({"dim": 3}, "2D particles, the grid's dim is 3"),
])
def test_grid_axes_that_conflict_with_the_file_are_refused(tmp_path, earlier, grid, expect):
    r = run_edmd("run", spec_from(tmp_path, earlier, **grid), "-o", tmp_path / "out", check=False)
    assert r.returncode == 1 and expect in r.stderr and "r00000.h5" in r.stderr, r.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("dim,kind", [(2, "h5"), (2, "text"), (3, "h5"), (3, "text")])
def test_rough_grains_start_with_the_files_spins(tmp_path, dim, kind):
    """Spins are read from a rough replica's file (its `angular_velocity`) or from the text columns
    after radius and mass, so the rotational temperature carries over too."""
    rough = dict(BASE, grid=dict(BASE["grid"], dim=dim, n=300, phi=0.2, beta=0.5),
                 stop={"tau_max": 10})
    (tmp_path / "a.json").write_text(json.dumps(rough))
    run_edmd("run", tmp_path / "a.json", "-o", tmp_path / "a", "-q")
    source = tmp_path / "a" / "replicas" / "r00000.h5"
    with h5py.File(source, "r") as f:
        g = f["particles/gas"]
        pos, vel, spin = (g[k + "/value"][-1] for k in ("position", "velocity", "angular_velocity"))
        radius, mass = g["radius"][()], g["mass"][()]
    if kind == "text":
        source = tmp_path / "c.txt"
        np.savetxt(source, np.column_stack([pos, vel, radius, mass, spin]), fmt="%.17g")
    s = dict(rough, name="b", init={"from": {"file": str(source)}})
    (tmp_path / "b.json").write_text(json.dumps(s))
    run_edmd("run", tmp_path / "b.json", "-o", tmp_path / "b", "-q")
    with h5py.File(tmp_path / "b" / "replicas" / "r00000.h5", "r") as f:
        start = f["particles/gas/angular_velocity/value"][0]
    assert np.abs(spin).max() > 0
    assert np.allclose(start, spin, rtol=1e-12, atol=0)
