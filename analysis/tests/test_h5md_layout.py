"""The replica files follow H5MD 1.1 and open in h5py and pyh5md."""

import h5py
import numpy as np
import pytest


def replica_files(out):
    files = sorted((out / "replicas").glob("r*.h5"))
    assert files, "no replica files"
    return files


def test_h5md_metadata(sweep):
    for path in replica_files(sweep):
        with h5py.File(path, "r") as f:
            assert list(f["h5md"].attrs["version"]) == [1, 1]
            assert f["h5md/author"].attrs["name"]
            assert f["h5md/creator"].attrs["name"] == "edmd"
            assert f["h5md/creator"].attrs["version"]


def test_particles_layout(sweep):
    for path in replica_files(sweep):
        with h5py.File(path, "r") as f:
            p = f["parameters"].attrs
            d, n = int(p["dim"]), int(p["n"])
            box = f["particles/gas/box"]
            assert int(box.attrs["dimension"]) == d
            boundary = [b.decode() if isinstance(b, bytes) else b for b in box.attrs["boundary"]]
            assert len(boundary) == d
            expected = "periodic" if p["boundary"] == "periodic" else "none"
            assert boundary == [expected] * d
            edges = box["edges"][()]
            assert edges.shape == (d,) and np.all(edges > 0)
            for name in ("position", "velocity"):
                g = f["particles/gas"][name]
                step, time, value = g["step"][()], g["time"][()], g["value"][()]
                assert step.dtype.kind == "i" and time.dtype.kind == "f"
                assert value.shape == (len(step), n, d)
                assert np.all(np.diff(step) > 0), "step must increase"
                assert np.all(np.diff(time) > 0), "time must increase"
                assert step[0] == 0
                assert g["value"].chunks == (1, n, d)
                assert g["value"].compression == "gzip"
            pos = f["particles/gas/position/value"][()]
            assert np.all(pos >= 0) and np.all(pos <= edges)
            assert f["particles/gas/mass"].shape == (n,)


def test_observables_layout(sweep):
    required = {"tau", "temperature", "ln_temperature", "kinetic_energy", "kurtosis",
                "collisions", "wall_collisions", "compressibility", "pressure", "momentum_error",
                "haff_temperature"}
    for path in replica_files(sweep):
        with h5py.File(path, "r") as f:
            obs = f["observables"]
            assert required <= set(obs.keys())
            n = int(f["parameters"].attrs["n"])
            for name in obs:
                step, time, value = (obs[name][k][()] for k in ("step", "time", "value"))
                assert step.shape == time.shape == value.shape
                assert np.all(np.diff(step) > 0) and np.all(np.diff(time) >= 0)
            tau = obs["tau/value"][()]
            np.testing.assert_allclose(tau, obs["tau/step"][()] / n, rtol=1e-12)
            assert tau[-1] == pytest.approx(float(f["parameters"].attrs["final_tau"]))
            # Temperature starts at T0 = 1 and agrees with ln T.
            temp = obs["temperature/value"][()]
            assert temp[0] == pytest.approx(1.0, rel=1e-12)
            np.testing.assert_allclose(np.log(temp), obs["ln_temperature/value"][()], rtol=1e-10)


def test_parameters(sweep):
    for path in replica_files(sweep):
        with h5py.File(path, "r") as f:
            p = f["parameters"].attrs
            for key in ("schema_version", "spec", "spec_hash", "engine_version", "git_commit",
                        "eps", "phi", "n", "dim", "seed", "status", "final_tau"):
                assert key in p, key
            assert p["status"] == "done"
            assert float(f["parameters/spec"].attrs["stop.tau_max"]) == 20.0


def test_pyh5md_reads_the_files(sweep):
    pyh5md = pytest.importorskip("pyh5md")
    for path in replica_files(sweep):
        with pyh5md.File(path, "r") as f:
            gas = f.particles_group("gas")
            pos = pyh5md.element(gas, "position")
            with h5py.File(path, "r") as g:
                np.testing.assert_array_equal(pos.value[()], g["particles/gas/position/value"][()])
                np.testing.assert_array_equal(pos.step[()], g["particles/gas/position/step"][()])
            temp = pyh5md.element(f["observables"], "temperature")
            assert temp.value.shape == temp.step.shape
