"""The `edmd` Python module (crates/edmd-py): `Simulation.from_spec(spec, replica=i)` advanced to
the spec's τ_max holds positions and velocities bit-identical to the final snapshot `edmd run`
writes for replica i (2D cells, 3D with walls, rough grains, a sheared box); `run_sweep` writes
the files `edmd run` writes, bit for bit (scripts/compare-outputs.py), and returns the phase table;
a bad spec raises ValueError with the command's message; Ctrl-C stops a long run within a second
and leaves the simulation usable."""

import importlib.util
import json
import os
import signal
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

SPEC = {"name": "py", "seed": 4,  # replicas: 2D ε 0.9 and 0.7, 3D walls, rough, sheared, a mixture
        "grid": [
            {"dim": 2, "eps": [0.9, 0.7], "phi": 0.25, "n": 500},
            {"dim": 3, "boundary": "walls", "eps": 0.8, "phi": 0.2, "n": 400},
            {"dim": 2, "eps": 0.8, "beta": 0.5, "phi": 0.2, "n": 300},
            {"dim": 2, "boundary": "lees-edwards", "shear_rate": 0.05, "eps": 0.9, "phi": 0.1, "n": 300},
            {"dim": 2, "eps": 0.9, "phi": 0.1, "n": 300,
             "species": [[{"fraction": 0.5, "diameter": 1}, {"fraction": 0.5, "diameter": 1.4, "mass": 4}]]},
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


@pytest.mark.parametrize("replica", range(6))
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


def test_a_mixtures_species_radii_and_masses_are_the_files(ran):
    sim = edmd.Simulation.from_spec(SPEC, replica=5)
    with h5py.File(ran / "cli" / "replicas" / "r00005.h5", "r") as f:
        species = f["particles/gas/species"][()]
    assert np.array_equal(sim.species, species) and set(species) == {0, 1}
    assert np.array_equal(sim.radii, np.where(species == 0, 0.5, 0.7))
    assert np.array_equal(sim.masses, np.where(species == 0, 1.0, 4.0))


def test_spins_of_rough_grains_are_the_files(ran):
    sim = edmd.Simulation.from_spec(SPEC, replica=3)
    sim.run(tau=SPEC["stop"]["tau_max"])
    with h5py.File(ran / "cli" / "replicas" / "r00003.h5", "r") as f:
        spin = f["particles/gas/angular_velocity/value"][-1]
    assert sim.spins.shape == (sim.n, 1) and np.abs(spin).max() > 0
    assert np.array_equal(sim.spins, spin)


def load_compare():
    spec = importlib.util.spec_from_file_location("compare_outputs", REPO / "scripts" / "compare-outputs.py")
    compare = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(compare)
    return compare


def test_run_sweep_writes_what_the_command_writes(ran, capsys):
    table = edmd.run_sweep(SPEC, ran / "py", threads=2)
    assert load_compare().main(str(ran / "cli"), str(ran / "py")) == 0, capsys.readouterr().out
    assert len(table) == 6 and set(table["done"]) == {1}


def test_a_bad_spec_raises_value_error_with_the_commands_line(tmp_path):
    bad = dict(SPEC, grid=[{"eps": 1.5, "phi": 0.25, "n": 100}])
    with pytest.raises(ValueError, match=r"eps = 1.5"):
        edmd.Simulation.from_spec(bad)
    with pytest.raises(ValueError, match="the sweep has 6 replicas"):
        edmd.Simulation.from_spec(SPEC, replica=7)
    with pytest.raises(ValueError, match="eps = 1.5"):
        edmd.run_sweep(bad, tmp_path / "o")
    assert not (tmp_path / "o").exists()


def sigint():
    """Ctrl-C as a terminal sends it: SIGINT to this process."""
    os.kill(os.getpid(), signal.SIGINT)


def test_ctrl_c_stops_a_run_and_leaves_the_simulation_usable():
    sim = edmd.Simulation.from_spec(dict(SPEC, grid=[{"eps": 1.0, "phi": 0.25, "n": 4000}]))
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    threading.Timer(0.5, sigint).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        sim.run(tau=5000)  # 2·10⁷ collisions: ten seconds and more, where a lost signal ends
    assert time.monotonic() - start < 1.5
    tau = sim.tau
    assert 0 < tau < 5000
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


def test_a_changed_rule_takes_effect_in_the_next_run():
    """ε set to 1 between runs: the cooling gas keeps its energy from then on (to rounding); a bad
    value is refused with the spec's message and changes nothing."""
    sim = edmd.Simulation.from_spec(SPEC, replica=0)
    interval = sim.run(tau=5)
    cooled = sim.temperature
    assert cooled < 0.9 and interval["z"] > 1 and interval["collision_frequency"] > 0
    sim.set_rule(eps=1.0)
    assert sim.eps == 1.0
    sim.run(tau=10)
    assert sim.temperature == pytest.approx(cooled, rel=1e-12)
    with pytest.raises(ValueError, match="eps"):
        sim.set_rule(eps=1.5)
    with pytest.raises(ValueError, match="rule: unknown variant"):
        sim.set_rule(rule={"kind": "sticky"})
    assert sim.eps == 1.0
    sim.set_rule(eps=0.5, remedy={"kind": "tc", "tc": 1e-3})
    sim.run(tau=11)
    assert sim.temperature < 0.99 * cooled


def test_run_until_a_temperature_stops_where_it_is_first_reached():
    sim = edmd.Simulation.from_spec(SPEC, replica=1)  # ε 0.7, N 500
    sim.run(until_temperature=0.25)
    # The last chunks are 10 collisions: each costs ~(1 − ε²)/N of the energy, 0.1 % here.
    assert 0.25 * 0.98 < sim.temperature <= 0.25
    tau = sim.tau
    sim.run(until_temperature=1e-9, tau=tau + 1)
    assert sim.tau == pytest.approx(tau + 1) and sim.temperature > 1e-9
    with pytest.raises(ValueError, match="until_temperature = -1"):
        sim.run(until_temperature=-1.0)


def test_a_saved_state_loads_exactly_and_the_command_reads_it(tmp_path):
    for replica in (0, 3):  # smooth; rough (with spins)
        sim = edmd.Simulation.from_spec(SPEC, replica=replica)
        sim.run(tau=3)
        path = tmp_path / f"state{replica}.txt"
        sim.save(path)
        again = edmd.Simulation.load(path, SPEC, replica=replica)
        assert again.tau == 0 and again.n == sim.n
        for name in ("positions", "velocities", "spins", "radii", "masses"):
            assert np.array_equal(getattr(again, name), getattr(sim, name)), name
    spec = dict(SPEC, grid=SPEC["grid"][3], init={"from": {"file": str(tmp_path / "state3.txt")}})
    (tmp_path / "s.json").write_text(json.dumps(spec))
    assert "valid" in run_edmd("validate-spec", tmp_path / "s.json").stdout


def test_order_parameters_are_those_of_the_files(ran):
    """observe(grid=g) gives the classifier's order parameters (the sweep's classify grid)."""
    grid = 4
    spec = dict(SPEC, classify={"grid": grid})
    sim = edmd.Simulation.from_spec(spec, replica=0)
    sim.run(tau=SPEC["stop"]["tau_max"])
    o = sim.observe(grid=grid)
    d = ran / "classified"
    (ran / "classified.json").write_text(json.dumps(spec))
    run_edmd("run", ran / "classified.json", "-o", d, "-q")
    with h5py.File(d / "replicas" / "r00000.h5", "r") as f:
        for name in ("f_flow", "s_perp", "delta_rho2", "f_2x", "s_rho"):
            assert o[name] == f[f"observables/{name}/value"][-1], name


def test_run_sweep_reports_progress_and_runs_shards(ran, capsys, tmp_path):
    calls = []
    table = edmd.run_sweep(SPEC, tmp_path / "o", threads=1, progress=lambda *a: calls.append(a))
    assert len(table) == 6
    assert calls and calls[-1][2] == calls[-1][3] == 6, calls[-1]
    assert all(a[0] <= b[0] for a, b in zip(calls, calls[1:])), "collisions never go back"
    for k in range(3):
        part = edmd.run_sweep(SPEC, tmp_path / "s", shard=f"{k}/3", progress=False)
    assert len(part) == 6, "the last shard completes the sweep"
    assert load_compare().main(str(ran / "cli"), str(tmp_path / "s")) == 0, capsys.readouterr().out


def test_ctrl_c_stops_a_sweep_with_checkpoints_and_it_goes_on(ran, capsys, tmp_path):
    spec = dict(SPEC, checkpoint={"every_s": 0, "every_tau": 2})
    spec["stop"] = {"tau_max": 400}
    threading.Timer(0.5, sigint).start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt):
        edmd.run_sweep(spec, tmp_path / "a", threads=2, progress=False)
    assert time.monotonic() - start < 2.0
    assert list((tmp_path / "a" / "states").glob("*.ckpt")), "the replicas in flight were checkpointed"
    edmd.run_sweep(spec, tmp_path / "a", threads=2, progress=False)
    edmd.run_sweep(spec, tmp_path / "b", threads=2, progress=False)
    assert load_compare().main(str(tmp_path / "b"), str(tmp_path / "a")) == 0, capsys.readouterr().out


def test_refine_writes_what_the_command_writes(capsys, tmp_path):
    import shutil
    spec = {"name": "rf", "seed": 2, "grid": {"eps": [0.6, 1.0], "phi": 0.25, "box": [40, 80]},
            "stop": {"tau_max": 200}, "samples": {"every": 5, "per_decade": 0}, "classify": {}}
    edmd.run_sweep(spec, tmp_path / "a", progress=False)
    shutil.copytree(tmp_path / "a", tmp_path / "b")
    run_edmd("refine", tmp_path / "a", "--rounds", "2", "-q")
    table = edmd.refine(tmp_path / "b", rounds=2, progress=False)
    assert load_compare().main(str(tmp_path / "a"), str(tmp_path / "b")) == 0, capsys.readouterr().out
    assert len(table) > 4 and (tmp_path / "b" / "boundary.json").exists()
    with pytest.raises(ValueError, match="unknown axis"):
        edmd.refine(tmp_path / "b", axes=["zeta"])


def test_a_sheared_runs_stress_is_the_files(ran):
    """run() over one sampling interval of the sheared replica returns the pressure tensor and
    dissipation rate the file holds for that interval, bit for bit."""
    sim = edmd.Simulation.from_spec(SPEC, replica=4)
    with h5py.File(ran / "cli" / "replicas" / "r00004.h5", "r") as f:
        tau = f["observables/tau/value"][()]
        pressure = f["observables/pressure_tensor/value"][()]
        dissipation = f["observables/dissipation_rate/value"][()]
    sim.run(tau=tau[1])
    for k in (2, 3):
        interval = sim.run(tau=tau[k])
        np.testing.assert_array_equal(interval["pressure_tensor"], pressure[k])
        assert interval["dissipation_rate"] == dissipation[k]
    assert interval["pressure_tensor"][0][1] < 0, "a positive shear rate: P_xy < 0"
