"""The `edmd` Python module (crates/edmd-py): `Simulation.from_spec(spec, replica=i)` advanced to
the spec's τ_max holds positions and velocities bit-identical to the final snapshot `edmd run`
writes for replica i (2D cells, 3D with walls, rough grains, a sheared box); `run_sweep` writes
the files `edmd run` writes, bit for bit (scripts/compare-outputs.py), and returns the phase table;
a bad spec raises ValueError with the command's message; Ctrl-C stops a long run within a second
and leaves the simulation usable."""

import _thread
import importlib.util
import json
import os
import threading
import time

import h5py
import numpy as np
import pytest
from conftest import REPO, run_edmd

if os.environ.get("EDMD_TEST_MODULE"):
    import edmd  # `make test` stages the module its own build made: it must import
else:
    edmd = pytest.importorskip("edmd", reason="the module is built by `make python-module`")

SPEC = {"name": "py", "seed": 4,
        "grid": [
            {"dim": 2, "eps": [0.9, 0.7], "phi": 0.25, "n": 500},
            {"dim": 3, "boundary": "walls", "eps": 0.8, "phi": 0.2, "n": 400},
            {"dim": 2, "eps": 0.8, "beta": 0.5, "phi": 0.2, "n": 300},
            {"dim": 2, "boundary": "lees-edwards", "shear_rate": 0.05, "eps": 0.9, "phi": 0.1, "n": 300},
        ],
        "stop": {"tau_max": 30}, "samples": {"every": 5, "per_decade": 0}}


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    d = tmp_path_factory.mktemp("py")
    (d / "s.json").write_text(json.dumps(SPEC))
    run_edmd("run", d / "s.json", "-o", d / "cli", "-q")
    return d


def test_the_version_is_the_workspaces():
    assert edmd.__version__.count(".") == 2


@pytest.mark.parametrize("replica", range(5))
def test_from_spec_reaches_the_runs_final_state_bit_for_bit(ran, replica):
    sim = edmd.Simulation.from_spec(SPEC, replica=replica)
    sim.run(tau=SPEC["stop"]["tau_max"])
    with h5py.File(ran / "cli" / "replicas" / f"r{replica:05d}.h5", "r") as f:
        pos = f["particles/gas/position/value"][-1]
        vel = f["particles/gas/velocity/value"][-1]
        collisions = f["parameters"].attrs["collisions"]
    assert sim.collisions == collisions
    assert np.array_equal(sim.positions, pos) and np.array_equal(sim.velocities, vel)
    assert sim.positions.shape == (sim.n, sim.dim)
    o = sim.observe()
    assert o["temperature"] == sim.temperature and o["pair_collisions"] == collisions


def test_spins_of_rough_grains_are_the_files(ran):
    sim = edmd.Simulation.from_spec(SPEC, replica=3)
    sim.run(tau=SPEC["stop"]["tau_max"])
    with h5py.File(ran / "cli" / "replicas" / "r00003.h5", "r") as f:
        spin = f["particles/gas/angular_velocity/value"][-1]
    assert sim.spins.shape == (sim.n, 1) and np.abs(spin).max() > 0
    assert np.array_equal(sim.spins, spin)


def test_run_sweep_writes_what_the_command_writes(ran, capsys):
    spec = importlib.util.spec_from_file_location("compare_outputs", REPO / "scripts" / "compare-outputs.py")
    compare = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(compare)
    table = edmd.run_sweep(SPEC, ran / "py", threads=2)
    assert compare.main(str(ran / "cli"), str(ran / "py")) == 0, capsys.readouterr().out
    assert len(table) == 5 and set(table["done"]) == {1}


def test_a_bad_spec_raises_value_error_with_the_commands_line(tmp_path):
    bad = dict(SPEC, grid=[{"eps": 1.5, "phi": 0.25, "n": 100}])
    with pytest.raises(ValueError, match=r"eps = 1.5"):
        edmd.Simulation.from_spec(bad)
    with pytest.raises(ValueError, match="the sweep has 5 replicas"):
        edmd.Simulation.from_spec(SPEC, replica=7)
    with pytest.raises(ValueError, match="eps = 1.5"):
        edmd.run_sweep(bad, tmp_path / "o")
    assert not (tmp_path / "o").exists()


def test_ctrl_c_stops_a_run_and_leaves_the_simulation_usable():
    sim = edmd.Simulation.from_spec(dict(SPEC, grid=[{"eps": 1.0, "phi": 0.25, "n": 4000}]))
    threading.Timer(0.5, _thread.interrupt_main).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        sim.run(tau=1e6)
    assert time.monotonic() - start < 1.5
    tau = sim.tau
    assert 0 < tau < 1e6
    sim.run(collisions=10_000)
    assert sim.tau > tau and abs(sim.temperature - 1) < 0.1


BAD = REPO / "tests" / "specs" / "bad"


@pytest.mark.parametrize("case", sorted(p.stem for p in BAD.glob("*.json")))
def test_every_bad_spec_of_the_corpus_raises_value_error_with_the_commands_line(case, monkeypatch):
    """The corpus `edmd run` refuses (tests/specs/bad/, each with the line it prints): built as one
    replica, each raises ValueError holding that line. `init.from` paths are the corpus folder's."""
    monkeypatch.chdir(BAD)
    expect = (BAD / f"{case}.expect").read_text().strip()
    with pytest.raises(ValueError) as e:
        edmd.Simulation.from_spec((BAD / f"{case}.json").read_text())
    assert expect in str(e.value) and "\n" not in str(e.value), str(e.value)
