"""edmd_analysis.io on a finished sweep, a partial (killed or sharded) sweep and a file of another
schema version."""

import json
import shutil

import edmd_analysis as ea
import h5py
import numpy as np
import pytest


def test_read_index(sweep):
    idx = ea.read_index(sweep)
    assert idx.name == "pytest"
    assert len(idx) == 5
    assert list(idx["status"]) == ["done"] * 5
    assert list(idx["dim"]) == [2, 2, 2, 2, 3]
    assert list(idx["seed_index"]) == [0, 1, 0, 1, 0]
    np.testing.assert_allclose(idx["eps"], [0.9, 0.9, 0.7, 0.7, 0.8])
    assert idx.spec["stop"]["tau_max"] == 20
    for i in range(len(idx)):
        assert idx.replica_path(i).exists()
    # The index agrees with the files it links to.
    with h5py.File(sweep / "sweep.h5", "r") as f:
        assert float(f["files/r00004/parameters"].attrs["eps"]) == 0.8


def test_read_replica(sweep):
    rep = ea.read_replica(sweep / "replicas" / "r00000.h5")
    assert rep.status == "done"
    assert rep.params["n"] == 200 and rep.params["dim"] == 2
    assert rep.params["spec"]["name"] == "pytest"
    t = rep.observables["temperature"]
    assert t[0] == pytest.approx(1.0) and t[-1] < t[0]
    assert len(rep.step) == len(t) and np.all(np.diff(rep.step) > 0)
    assert np.all(np.isnan(rep.observables["haff_temperature"]) == False)  # noqa: E712


def test_read_observable(sweep):
    step, time, value = ea.read_observable(sweep / "replicas" / "r00001.h5", "kurtosis")
    assert step.shape == time.shape == value.shape
    with pytest.raises(KeyError, match="no observable 'nope'"):
        ea.read_observable(sweep / "replicas" / "r00001.h5", "nope")


def test_read_snapshots(sweep):
    s = ea.read_snapshots(sweep / "replicas" / "r00004.h5")
    assert s.position.shape == (3, 150, 3)  # tau = 0, 5 and the end
    np.testing.assert_allclose(s.tau, [0, 5, 20], atol=0.01)
    assert s.boundary == ["none"] * 3
    assert s.radius.shape == (150,) and np.all(s.radius == 0.5)
    # Zero total momentum at the start, and a kinetic temperature of 1.
    v0 = s.velocity[0]
    np.testing.assert_allclose(v0.sum(axis=0), 0, atol=1e-10)
    assert (s.mass[:, None] * v0**2).sum() / (3 * 150) == pytest.approx(1.0)


def test_partial_sweep(partial_sweep):
    with pytest.raises(FileNotFoundError, match="incomplete"):
        ea.read_index(partial_sweep)
    files = sorted((partial_sweep / "replicas").glob("*.h5"))
    assert [f.name for f in files] == ["r00000.h5", "r00002.h5", "r00004.h5"]
    for f in files:
        assert ea.read_replica(f).status == "done"


def test_wrong_schema_version(sweep, tmp_path):
    bad = tmp_path / "r.h5"
    shutil.copy(sweep / "replicas" / "r00000.h5", bad)
    with h5py.File(bad, "r+") as f:
        f["parameters"].attrs["schema_version"] = 99
    for reader in (ea.read_replica, ea.read_snapshots, lambda p: ea.read_observable(p, "tau")):
        with pytest.raises(ea.SchemaError, match="schema_version 99.*reads version 1"):
            reader(bad)
    idx = tmp_path / "sweep.h5"
    shutil.copy(sweep / "sweep.h5", idx)
    with h5py.File(idx, "r+") as f:
        f.attrs["schema_version"] = 2
    with pytest.raises(ea.SchemaError, match="schema_version 2"):
        ea.read_index(idx)


def test_not_an_edmd_file(tmp_path):
    p = tmp_path / "x.h5"
    with h5py.File(p, "w") as f:
        f["a"] = 1
    with pytest.raises(ea.SchemaError, match="not an edmd replica file"):
        ea.read_replica(p)


@pytest.mark.parametrize(
    "name, content, message",
    [
        ("r00000.h5.part", None, "still being written, or left by a killed run"),
        ("r00000.h5.corrupt", None, "found unreadable and moved aside"),
        ("r00000.h5", "truncated", "not a readable HDF5 file"),
        ("r00000.h5", "zeroed", "not a readable HDF5 file"),
    ],
)
def test_readers_name_partial_and_corrupt_files(sweep, tmp_path, name, content, message):
    """Every reader raises CorruptFileError (a SchemaError) naming the file and what it is, instead
    of h5py's raw OSError."""
    whole = (sweep / "replicas" / "r00000.h5").read_bytes()
    path = tmp_path / name
    data = {"truncated": whole[: len(whole) // 2], "zeroed": bytes(len(whole))}.get(content, whole)
    path.write_bytes(data)
    for reader in (ea.read_replica, ea.read_snapshots, lambda p: ea.read_observable(p, "tau")):
        with pytest.raises(ea.CorruptFileError, match=message) as info:
            reader(path)
        assert str(path) in str(info.value)
    with pytest.raises(ea.SchemaError):
        ea.read_replica(path)


@pytest.mark.parametrize("dim, width", [(2, 1), (3, 3)])
def test_rough_grains_read_back_spin_and_rotational_temperature(tmp_path, dim, width):
    """A rough sweep: read_snapshots gives the angular velocities ((k, N, 1) in 2D, (k, N, 3) in 3D),
    read_replica the rotational temperature, which the stored spins reproduce (I = q m (sigma/2)^2)."""
    from conftest import run_edmd

    spec = {
        "name": "rough", "grid": {"dim": dim, "eps": 0.9, "beta": 0.5, "phi": 0.2, "n": 200},
        "stop": {"tau_max": 5}, "snapshots": {"at": [0]},
    }
    (tmp_path / "s.json").write_text(json.dumps(spec))
    run_edmd("run", tmp_path / "s.json", "-o", tmp_path / "out", "-q")
    path = tmp_path / "out" / "replicas" / "r00000.h5"
    snaps = ea.read_snapshots(path)
    assert snaps.angular_velocity.shape == (2, 200, width)
    rep = ea.read_replica(path)
    t_rot = rep.observables["rotational_temperature"]
    q = 0.5 if dim == 2 else 0.4
    d_rot = 1 if dim == 2 else 3
    w = snaps.angular_velocity[-1]
    np.testing.assert_allclose((q * 0.25 * snaps.mass[:, None] * w**2).sum() / (d_rot * 200), t_rot[-1], rtol=1e-9)
    assert float(rep.params["beta"]) == 0.5


def test_smooth_grains_have_no_spin(sweep):
    assert ea.read_snapshots(sweep / "replicas" / "r00000.h5").angular_velocity is None
    assert "rotational_temperature" not in ea.read_replica(sweep / "replicas" / "r00000.h5").observables


def test_mixtures_read_back_species_and_their_temperatures(tmp_path):
    """A binary mixture: read_snapshots gives each grain's species, read_replica the species
    temperatures (s, S), which the stored velocities reproduce; pyh5md opens the fixed and the
    time-dependent elements."""
    from conftest import run_edmd

    spec = {
        "name": "mix",
        "grid": {"eps": 0.9, "phi": 0.1, "n": 300,
                 "species": [{"fraction": 0.5, "diameter": 1}, {"fraction": 0.5, "diameter": 1.4, "mass": 3}]},
        "stop": {"tau_max": 5}, "snapshots": {"at": [0]},
    }
    (tmp_path / "s.json").write_text(json.dumps(spec))
    run_edmd("run", tmp_path / "s.json", "-o", tmp_path / "out", "-q")
    path = tmp_path / "out" / "replicas" / "r00000.h5"
    snaps = ea.read_snapshots(path)
    assert np.bincount(snaps.species).tolist() == [150, 150]
    np.testing.assert_array_equal(snaps.mass, np.where(snaps.species == 0, 1.0, 3.0))
    np.testing.assert_array_equal(2 * snaps.radius, np.where(snaps.species == 0, 1.0, 1.4))
    rep = ea.read_replica(path)
    ts = rep.observables["species_temperature"]
    assert ts.shape == (len(rep.observables["temperature"]), 2)
    v2 = (snaps.velocity[-1] ** 2).sum(axis=1) * snaps.mass
    for k in range(2):
        np.testing.assert_allclose(v2[snaps.species == k].sum() / (2 * 150), ts[-1, k], rtol=1e-9)
    theory = np.asarray(rep.params["species_temperature_theory"], dtype=float)
    assert theory.shape == (2,) and theory[0] < 1 < theory[1]
    pyh5md = pytest.importorskip("pyh5md")
    with pyh5md.File(path, "r") as f:
        gas = f.particles_group("gas")
        np.testing.assert_array_equal(gas["species"][()], snaps.species)
        el = pyh5md.element(f["observables"], "species_temperature")
        assert el.value.shape == ts.shape
