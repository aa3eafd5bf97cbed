"""Gases heated by white noise (`grid.white_noise`, PHYSICS.md §8.1) reach the steady state of the
theory written into their files: the time-averaged temperature within its statistical error (batch
means over 8 batches) plus 1 % of T_s (the kicks' own bias is below 0.3 %, and the density effect at
φ 0.005 below 0.5 %: docs/benchmarks.md, "The white-noise thermostat"), and the kurtosis within
three errors plus 0.01 of (d+2)/d (1 + a₂). A replica's momentum stays at zero. The engine's tests
(`crates/edmd-core/tests/engine/white_noise.rs`) check the same at 1000 grains and longer runs."""

import json

import h5py
import numpy as np
import pytest
from conftest import run_edmd

SPEC = {"name": "wn", "seed": 3, "grid": {"dim": [2, 3], "eps": [0.9, 0.5], "phi": 0.005, "n": 500,
                                         "white_noise": 1.0},
        "stop": {"tau_max": 300}, "samples": {"every": 2, "per_decade": 0}}


def batch_error(v):
    b = np.array([c.mean() for c in np.array_split(v, 8)])
    return b.std(ddof=1) / np.sqrt(8)


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    d = tmp_path_factory.mktemp("wn")
    (d / "s.json").write_text(json.dumps(SPEC))
    run_edmd("run", d / "s.json", "-o", d / "o", "-q")
    return d / "o"


@pytest.mark.parametrize("replica", range(4))
def test_the_steady_state_matches_the_theory(out, replica):
    with h5py.File(out / "replicas" / f"r{replica:05d}.h5", "r") as f:
        p = f["parameters"].attrs
        d, t_s, a2 = int(p["dim"]), p["white_noise_theory_temperature"], p["white_noise_theory_a2"]
        temperature = f["observables/temperature/value"][()]
        kurtosis = f["observables/kurtosis/value"][()]
        momentum = f["observables/momentum_error/value"][()]
        assert p["kick_interval"] > 0 and p["white_noise"] == 1.0
    steady = slice(len(temperature) // 4, None)  # from τ 75: ten cooling times and more
    t, k = temperature[steady] / t_s, kurtosis[steady]
    assert abs(t.mean() - 1) < 3 * batch_error(t) + 0.01, (t.mean(), batch_error(t))
    want = (d + 2) / d * (1 + a2)
    assert abs(k.mean() - want) < 3 * batch_error(k) + 0.01, (k.mean(), want, batch_error(k))
    assert np.abs(momentum).max() < 1e-9


def test_the_report_draws_the_steady_state(out, tmp_path):
    from edmd_analysis import driven, io, report

    paths = sorted((out / "replicas").glob("r*.h5"))
    assert report._white_noise_figure(tmp_path, paths) == ["white-noise.png"]
    states = [driven.steady_white_noise(io.read_replica(p)) for p in paths]
    assert {s["dim"] for s in states} == {2, 3} and all(abs(s["t_ratio"] - 1) < 0.05 for s in states)
