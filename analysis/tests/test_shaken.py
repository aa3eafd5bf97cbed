"""Beds on a vibrating floor (`grid.shake_s`, `grid.shake_gamma`; docs/PHYSICS.md 8.3-8.4): a small
shaken sweep carries its floor and its uniform-time samples (`/bed`) in the files and the index, and
the report draws its (S, F) plane, its height profiles and its mean flow, and picks its movies by
state.
The engine's tests (`crates/edmd-core/tests/engine/shaken_bed.rs`) check the floor against theory."""

import json

import h5py
from conftest import run_edmd
from edmd_analysis import io, movie, report, shaken


def test_a_shaken_sweep_reads_back_and_draws_its_states(tmp_path):
    spec = {"name": "shaken", "seed": 3,
            "grid": {"boundary": "channel", "eps": 0.9, "n": [100, 200], "box": 100,
                     "aspect": [0.25, 1], "gravity": 1, "wall_eps": 0.9,
                     "remedy": {"kind": "tc", "tc": 0.001}, "shake_s": [2, 20], "shake_gamma": 10},
            "stop": {"tau_max": 40}, "samples": {"every": 10, "per_decade": 0},
            "snapshots": {"at": [36, 40]}}
    path = tmp_path / "spec.json"
    path.write_text(json.dumps(spec))
    out = tmp_path / "out"
    run_edmd("run", path, "-o", out, "-q")
    index = io.read_index(out)
    points = shaken.shaken_points(index)
    assert len(points) == 4
    # F = N d / W with W = 100 * 0.25.
    assert sorted({round(p[1], 9) for p in points}) == [4.0, 8.0]
    assert {p[3] for p in points} <= set(shaken.SHAKEN_COLOURS)
    with h5py.File(out / "replicas" / "r00000.h5") as f:
        a = f["parameters"].attrs
        assert a["floor_amplitude"] == 2 / 10 and a["shaken_state"] == points[0][3]
        assert len(f["observables/floor_work/value"]) == len(f["observables/temperature/value"])
    rep = io.read_replica(out / "replicas" / "r00000.h5")
    z = len(rep.bed["height"])
    assert rep.bed["phase_packing"].shape == (16, z) and rep.bed["vertical_velocity"].shape == (z, 12)
    # Every grain is in some bin at every sample: the packing sums to N grains of area pi/4.
    assert abs(rep.bed["packing"].sum() * 25 / (3.141592653589793 / 4) - 100) < 1e-6
    assert 0 <= rep.params["shaken_contact_fraction"] <= 1 and rep.params["shaken_samples"] > 100
    page = report.report(out, tmp_path / "report", movies=False, jobs=1)
    for name in ("shaken-states", "shaken-profiles", "shaken-flow"):
        assert (page.parent / f"{name}.png").exists(), name
    text = page.read_text()
    assert "States of the shaken bed" in text and "Height profiles of the shaken beds" in text
    # Movies by state: the first replica of each state asked for that has two snapshots.
    states = [p[3] for p in points]
    tasks = report._movie_tasks(index, tmp_path, max_frames=2)
    wanted = [s for s in shaken.MOVIE_STATES if s in states]
    assert [t[1][1].name.split("-")[1] for t in tasks] == (wanted or ["replica"])
    # A shaken bed's movie shows the height its grains reach and the floor where it is.
    snaps = io.read_snapshots(out / "replicas" / "r00000.h5")
    top, floor = movie._gravity_view(snaps, rep.params)
    assert floor == (rep.params["floor_amplitude"], rep.params["floor_omega"])
    assert snaps.position[:, :, 1].max() < top <= 100
    assert movie.movie(out / "replicas" / "r00000.h5", output=tmp_path / "bed.gif")[0].exists()
