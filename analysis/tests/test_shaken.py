"""Beds on a vibrating floor (`grid.shake_s`, `grid.shake_gamma`; docs/PHYSICS.md 8.3-8.4): a small
shaken sweep carries its floor in the files and the index, and the report draws its (S, F) plane.
The engine's tests (`crates/edmd-core/tests/engine/shaken_bed.rs`) check the floor against theory."""

import json

import h5py
from conftest import run_edmd
from edmd_analysis import driven, io, report


def test_a_shaken_sweep_reads_back_and_draws_its_states(tmp_path):
    spec = {"name": "shaken", "seed": 3,
            "grid": {"boundary": "channel", "eps": 0.9, "n": [100, 200], "box": 100,
                     "aspect": [0.25, 1], "gravity": 1, "wall_eps": 0.9,
                     "remedy": {"kind": "tc", "tc": 0.001}, "shake_s": [2, 20], "shake_gamma": 10},
            "stop": {"tau_max": 40}, "samples": {"every": 10, "per_decade": 0}}
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(spec))
    out = tmp_path / "out"
    run_edmd("run", path, "-o", out, "-q")
    index = io.read_index(out)
    points = driven.shaken_points(index)
    assert len(points) == 4
    # F = N d / W with W = 100 * 0.25.
    assert sorted({round(p[1], 9) for p in points}) == [4.0, 8.0]
    assert {p[3] for p in points} <= set(driven.SHAKEN_COLOURS)
    with h5py.File(out / "replicas" / "r00000.h5") as f:
        a = f["parameters"].attrs
        assert a["floor_amplitude"] == 2 / 10 and a["shaken_state"] == points[0][3]
        assert len(f["observables/floor_work/value"]) == len(f["observables/temperature/value"])
    page = report.report(out, tmp_path / "report", movies=False, jobs=1)
    assert (page.parent / "shaken-states.png").exists()
    assert "States of the shaken bed" in page.read_text()
