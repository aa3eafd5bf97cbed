"""Builds small sweeps with the edmd binary once per test session (no committed data files)."""

import json
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def edmd_binary() -> Path:
    """The edmd binary: $EDMD_BIN, or target/release/edmd (built if missing)."""
    env = os.environ.get("EDMD_BIN")
    if env:
        return Path(env)
    path = REPO / "target" / "release" / "edmd"
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--release", "-p", "edmd-cli", "--bin", "edmd"], cwd=REPO, check=True
        )
    return path


SPEC = {
    "name": "pytest",
    "seed": 3,
    "grid": [
        {"dim": 2, "boundary": "periodic", "eps": [0.9, 0.7], "phi": 0.2, "n": 200, "seeds": 2},
        {"dim": 3, "boundary": "walls", "eps": 0.8, "phi": 0.1, "n": 150, "seeds": 1},
    ],
    "stop": {"tau_max": 20},
    "samples": {"every": 2, "per_decade": 5},
    "snapshots": {"at": [0, 5], "final": True},
}


def run_edmd(*args, check=True, cwd=None):
    return subprocess.run(
        [str(edmd_binary()), *map(str, args)], capture_output=True, text=True, check=check,
        cwd=cwd,
    )


@pytest.fixture(scope="session")
def sweep(tmp_path_factory) -> Path:
    """A finished sweep: 4 disk replicas (periodic) and 1 sphere replica (walls)."""
    d = tmp_path_factory.mktemp("sweep")
    spec = d / "spec.json"
    spec.write_text(json.dumps(SPEC))
    run_edmd("run", spec, "-o", d / "out", "-q")
    return d / "out"


@pytest.fixture(scope="session")
def partial_sweep(tmp_path_factory) -> Path:
    """A sweep of which only shard 0/2 ran: no index, some replica files (as after a kill)."""
    d = tmp_path_factory.mktemp("partial")
    spec = d / "spec.json"
    spec.write_text(json.dumps(SPEC))
    run_edmd("run", spec, "-o", d / "out", "-q", "--shard", "0/2")
    return d / "out"


@pytest.fixture(scope="session")
def classified_sweep(tmp_path_factory) -> Path:
    """A sweep with order parameters and classification, and its phase table as JSON."""
    d = tmp_path_factory.mktemp("classified")
    spec = dict(SPEC, name="pytest-classified", grid=SPEC["grid"][0], classify={})
    (d / "spec.json").write_text(json.dumps(spec))
    run_edmd("run", d / "spec.json", "-o", d / "out", "-q")
    table = run_edmd("summarize", d / "out", "--format", "json").stdout
    (d / "out" / "phase.json").write_text(table)
    return d / "out"
