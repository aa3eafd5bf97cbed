"""`edmd extend OUT --tau-max T` equals a sweep run to T from the start, file for file
(scripts/compare-outputs.py): the quick sweep's settings (samples on both grids, snapshots, the
classifier), a sheared box, rough grains; a replica that stopped early runs again from the start
and ends as the direct run's."""

import importlib.util
import json

import pytest
from conftest import REPO, run_edmd
from edmd_analysis import read_index
from edmd_analysis.report import _continued

spec = importlib.util.spec_from_file_location("compare_outputs", REPO / "scripts" / "compare-outputs.py")
compare_outputs = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_outputs)

QUICK = json.loads((REPO / "sweeps" / "quick.json").read_text())
SMALL_QUICK = dict(QUICK, grid=dict(QUICK["grid"], n=[256, 1024], eps=[0.9, 0.7], seeds=1))
SHEARED = {"name": "sheared", "seed": 2,
           "grid": {"dim": 2, "boundary": "lees-edwards", "shear_rate": 0.02, "eps": [0.9, 0.7],
                    "phi": 0.05, "n": 400},
           "samples": {"every": 5, "per_decade": 0}, "snapshots": {"every": 50}}
ROUGH = {"name": "rough", "seed": 3,
         "grid": {"dim": [2, 3], "eps": 0.9, "beta": [0.0, 1.0], "phi": 0.2, "n": 300},
         "stop": {"tau_max": 40, "temperature_ratio": 0.02},
         "samples": {"every": 4, "per_decade": 5}, "snapshots": {"per_decade": 3}, "classify": {}}


SHAKEN = {"name": "shaken", "seed": 4,
          "grid": {"boundary": "channel", "eps": 0.9, "n": 100, "box": 100, "aspect": [0.25, 1],
                   "gravity": 1, "wall_eps": 0.9, "remedy": {"kind": "tc", "tc": 0.001},
                   "shake_s": [2, 20], "shake_gamma": 10},
          "samples": {"every": 10, "per_decade": 0}, "snapshots": {"at": [30, 60]}}


@pytest.mark.parametrize("base,short,long", [(SMALL_QUICK, 200, 400), (SHEARED, 60, 150), (ROUGH, 40, 130),
                                             (SHAKEN, 30, 60)],
                         ids=["quick", "sheared", "rough", "shaken"])
def test_extend_equals_a_direct_run(tmp_path, capsys, base, short, long):
    def write(tau_max, name):
        s = dict(base, stop=dict(base.get("stop", {}), tau_max=tau_max))
        p = tmp_path / name
        p.write_text(json.dumps(s))
        return p

    run_edmd("run", write(long, "long.json"), "-o", tmp_path / "direct", "-q")
    run_edmd("run", write(short, "short.json"), "-o", tmp_path / "extended", "-q")
    finals = list((tmp_path / "extended" / "states").glob("*.final"))
    assert finals, "no final states kept"
    r = run_edmd("extend", tmp_path / "extended", "--tau-max", long, "-q")
    assert "go on from their final state" in r.stderr, r.stderr
    assert compare_outputs.main(str(tmp_path / "direct"), str(tmp_path / "extended")) == 0, capsys.readouterr().out
    left = [p.name for p in (tmp_path / "extended" / "states").iterdir() if p.suffix != ".final"]
    assert not left
    # The index and the report say which replicas went on from their final state.
    direct, extended = read_index(tmp_path / "direct"), read_index(tmp_path / "extended")
    assert not direct["resumes"].any() and _continued(direct) == ""
    went_on = [int(i) for i, k in zip(extended["index"], extended["resumes"]) if k]
    assert went_on and set(extended["resumes"]) <= {0, 1}
    assert all(f"r{i:05d} (1×)" in _continued(extended) for i in went_on)


def test_a_shaken_bed_extended_less_than_twice_runs_again_and_equals_a_direct_run(tmp_path, capsys):
    """Its longer run records the uniform-time samples from tau 20 on, before the final state at 30:
    it cannot go on from there, so it runs from the start."""
    for name, tau in (("short", 30), ("long", 40)):
        (tmp_path / f"{name}.json").write_text(json.dumps(dict(SHAKEN, stop={"tau_max": tau})))
    run_edmd("run", tmp_path / "long.json", "-o", tmp_path / "direct", "-q")
    run_edmd("run", tmp_path / "short.json", "-o", tmp_path / "extended", "-q")
    r = run_edmd("extend", tmp_path / "extended", "--tau-max", 40)
    assert "a shaken bed whose longer run samples from before its final state" in r.stderr, r.stderr
    assert compare_outputs.main(str(tmp_path / "direct"), str(tmp_path / "extended")) == 0, capsys.readouterr().out


def test_extend_refuses_a_shorter_tau_max_and_an_unfinished_sweep(tmp_path):
    s = dict(SHEARED, stop={"tau_max": 10})
    (tmp_path / "s.json").write_text(json.dumps(s))
    run_edmd("run", tmp_path / "s.json", "-o", tmp_path / "o", "-q")
    r = run_edmd("extend", tmp_path / "o", "--tau-max", 5, check=False)
    assert r.returncode == 1 and "must be finite and above the sweep's stop.tau_max = 10" in r.stderr, r.stderr
    next((tmp_path / "o" / "replicas").glob("*.h5")).unlink()
    r = run_edmd("extend", tmp_path / "o", "--tau-max", 20, check=False)
    assert r.returncode == 1 and "not finished" in r.stderr, r.stderr
