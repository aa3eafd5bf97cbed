"""The one module that touches h5py: reads edmd output into numpy arrays and small dataclasses.

Every reader checks the file's ``schema_version`` (see docs/output.md) and raises SchemaError with
the path and both versions when it is not the one this package understands.
"""

from __future__ import annotations

import json
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict

import h5py
import numpy as np

from .jsonfiles import read_boundary, read_json  # noqa: F401 (part of this module's API)

SCHEMA_VERSION = 1


class SchemaError(ValueError):
    """A file is not edmd output, or is of a schema version this package does not read."""


class CorruptFileError(SchemaError):
    """A file that edmd never finished (``.part``), moved aside (``.corrupt``), or that is not
    readable HDF5 (truncated, overwritten)."""


@contextmanager
def _open(path: Path):
    """h5py.File(path, "r") with clear errors for the files edmd leaves that are not results."""
    name = path.name
    if name.endswith(".part") or ".tmp" in name:
        raise CorruptFileError(
            f"{path}: a file still being written, or left by a killed run; not a result "
            "(rerunning `edmd run` with the same spec and -o finishes it)"
        )
    if ".corrupt" in name:
        raise CorruptFileError(
            f"{path}: a replica file edmd found unreadable and moved aside; its replica was run again "
            f"as {path.name.split('.corrupt')[0]}"
        )
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such file")
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise CorruptFileError(
            f"{path}: not a readable HDF5 file ({e}); `edmd status OUT` lists corrupt replicas and "
            "rerunning `edmd run` redoes them"
        ) from e
    with f:
        yield f


def _check_version(path: Path, attrs) -> None:
    if "schema_version" not in attrs:
        raise SchemaError(f"{path}: not an edmd file (no schema_version attribute)")
    version = int(attrs["schema_version"])
    if version != SCHEMA_VERSION:
        raise SchemaError(
            f"{path}: schema_version {version}, but edmd_analysis reads version {SCHEMA_VERSION}"
        )


def _str(x) -> str:
    return x.decode() if isinstance(x, bytes) else str(x)


@dataclass
class Index:
    """The sweep index: one entry per replica, as columns."""

    path: Path
    name: str
    spec: dict
    columns: Dict[str, np.ndarray]

    def __len__(self) -> int:
        return len(self.columns["index"])

    def __getitem__(self, column: str) -> np.ndarray:
        return self.columns[column]

    def to_frame(self):
        """The index as a pandas DataFrame, one row per replica (needs pandas; see frames.py)."""
        from .frames import index_frame

        return index_frame(self)

    def replica_path(self, i: int) -> Path:
        """Path of replica i's file (whether or not it exists)."""
        return self.path.parent / "replicas" / f"r{int(self.columns['index'][i]):05d}.h5"


def read_index(out) -> Index:
    """Reads OUT/sweep.h5 (OUT may be the directory or the file)."""
    path = Path(out)
    if path.is_dir():
        path = path / "sweep.h5"
    if not path.exists():
        raise FileNotFoundError(
            f"{path}: no sweep index (the sweep is incomplete: rerun `edmd run` or `edmd merge`)"
        )
    with _open(path) as f:
        _check_version(path, f.attrs)
        columns = {}
        for name, ds in f["replicas"].items():
            data = ds[()]
            if data.dtype.kind == "O":
                data = np.array([_str(x) for x in data])
            columns[name] = data
        spec_hash = _str(f.attrs["spec_hash"]) if "spec_hash" in f.attrs else None
        index = Index(path, _str(f.attrs["sweep_name"]), json.loads(_str(f.attrs["spec"])), columns)
    if spec_hash is not None:
        _mark_foreign(index, spec_hash)
    return index


# The statuses of replicas that have a file (edmd's `Status::has_file`).
WITH_FILE = ("done", "collapsed", "stalled", "failed")


def _mark_foreign(index: Index, spec_hash: str) -> None:
    """Marks `corrupt`, as `edmd status` does, every replica whose file is now missing, unreadable
    or written by another spec (its /parameters spec_hash differs from the index's): such a file is
    not a result of this sweep, and readers must not draw it."""
    status = index.columns["status"].astype(object)
    message = index.columns.get("message", np.array([""] * len(index))).astype(object)
    for i in range(len(index)):
        if status[i] not in WITH_FILE:
            continue
        path = index.replica_path(i)
        try:
            with h5py.File(path, "r") as f:
                theirs = _str(f["parameters"].attrs.get("spec_hash", b""))
        except (OSError, KeyError):
            status[i], message[i] = "corrupt", f"{path}: missing or unreadable"
            continue
        if theirs != spec_hash:
            status[i] = "corrupt"
            message[i] = f"written by a different spec (hash {theirs}, expected {spec_hash})"
    index.columns["status"] = np.array(status, dtype=str)
    index.columns["message"] = np.array(message, dtype=str)


@dataclass
class Replica:
    """A replica's parameters, status and observables."""

    path: Path
    params: dict
    observables: Dict[str, np.ndarray] = field(default_factory=dict)
    step: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    time: np.ndarray = field(default_factory=lambda: np.zeros(0))
    # Under gravity: the bin centres of observables/density_profile, and the barometric profile with
    # its temperature where the file has it (elastic columns).
    profile_position: np.ndarray | None = None
    profile_theory: np.ndarray | None = None
    profile_theory_temperature: float | None = None
    # The bin centres of every profile observable (those with a `position` dataset), by name.
    positions: Dict[str, np.ndarray] = field(default_factory=dict)
    # A shaken bed's uniform-time profiles (/bed: height, packing, temperature, phase_packing,
    # vertical_velocity); empty elsewhere.
    bed: Dict[str, np.ndarray] = field(default_factory=dict)

    @property
    def status(self) -> str:
        return self.params["status"]

    def to_frame(self):
        """The scalar observables as a pandas DataFrame, one row per sample (needs pandas)."""
        from .frames import observables_frame

        return observables_frame(self)


def _params(path: Path, f: h5py.File) -> dict:
    if "parameters" not in f:
        raise SchemaError(f"{path}: not an edmd replica file (no /parameters group)")
    attrs = f["parameters"].attrs
    _check_version(path, attrs)
    out = {}
    for k, v in attrs.items():
        if isinstance(v, (bytes, str)):
            out[k] = _str(v)
        elif np.ndim(v) == 0:
            out[k] = v.item() if hasattr(v, "item") else v
        else:
            out[k] = np.asarray(v)
    out["spec"] = json.loads(out["spec"])
    return out


def read_replica(path) -> Replica:
    """Reads a replica file: parameters (attributes of /parameters) and every observable."""
    path = Path(path)
    with _open(path) as f:
        rep = Replica(path, _params(path, f))
        if "bed" in f:
            rep.bed = {name: d[()] for name, d in f["bed"].items()}
        if "observables" in f:
            for name, g in f["observables"].items():
                rep.observables[name] = g["value"][()]
                if "position" in g:
                    rep.positions[name] = g["position"][()]
            first = next(iter(f["observables"].values()))
            rep.step = first["step"][()]
            rep.time = first["time"][()]
            if "density_profile" in f["observables"]:
                g = f["observables/density_profile"]
                rep.profile_position = g["position"][()]
                if "theory" in g:
                    rep.profile_theory = g["theory"][()]
                    rep.profile_theory_temperature = float(g.attrs["theory_temperature"])
        return rep


def read_observable(path, name: str):
    """(step, time, value) arrays of one observable of a replica file."""
    path = Path(path)
    with _open(path) as f:
        _params(path, f)
        if name not in f.get("observables", {}):
            raise KeyError(f"{path}: no observable {name!r}")
        g = f["observables"][name]
        return g["step"][()], g["time"][()], g["value"][()]


@dataclass
class Snapshots:
    """Stored particle states of a replica: arrays of shape (k,), (k, N, D)."""

    step: np.ndarray
    time: np.ndarray
    tau: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    box: np.ndarray
    boundary: list
    radius: np.ndarray
    mass: np.ndarray
    # Angular velocities of rough grains, (k, N, 1) in 2D or (k, N, 3) in 3D; None for smooth grains.
    angular_velocity: np.ndarray | None = None
    # Species index of each grain of a mixture, (N,); zeros for one species.
    species: np.ndarray | None = None
    # Lees-Edwards boxes: the sliding images' x offset at each snapshot, (k,), and the shear rate;
    # None and 0 elsewhere (docs/output.md).
    offset: np.ndarray | None = None
    shear_rate: float = 0.0

    def images(self, k: int, margin: float):
        """Indices and positions of the images that show within ``margin`` outside the box in frame
        ``k``: the periodic images across every face, and across the y faces of a sheared box the
        sliding ones, shifted by +-offset along x. For drawing; (indices, positions (m, D))."""
        pos = self.position[k]
        box = np.asarray(self.box, dtype=float)
        dim = pos.shape[1]
        idx, out = [], []
        shifts = [-1, 0, 1]
        for sx in shifts:
            for sy in shifts:
                if sx == 0 and sy == 0:
                    continue
                if (sx and self.boundary[0] != "periodic") or (sy and self.boundary[1] != "periodic"):
                    continue
                p = pos.copy()
                p[:, 0] += sx * box[0]
                p[:, 1] += sy * box[1]
                if sy and self.offset is not None:
                    p[:, 0] += sy * self.offset[k]
                    p[:, 0] = np.where(p[:, 0] > box[0] + margin, p[:, 0] - box[0], p[:, 0])
                    p[:, 0] = np.where(p[:, 0] < -margin, p[:, 0] + box[0], p[:, 0])
                keep = np.all((p[:, :2] > -margin) & (p[:, :2] < box[:2] + margin), axis=1)
                idx.append(np.nonzero(keep)[0])
                out.append(p[keep])
        if not idx:
            return np.zeros(0, dtype=np.int64), np.zeros((0, dim))
        return np.concatenate(idx), np.concatenate(out)


def snapshot_count(path) -> int:
    """How many snapshots a replica file stores (0 when none), without reading them."""
    path = Path(path)
    with _open(path) as f:
        _params(path, f)
        return f["particles/gas/position/step"].shape[0] if "particles/gas/position" in f else 0


def read_snapshots(path) -> Snapshots:
    """Every stored snapshot of a replica file."""
    path = Path(path)
    with _open(path) as f:
        params = _params(path, f)
        if "particles" not in f:
            raise SchemaError(f"{path}: no particles stored (status {params['status']})")
        gas = f["particles/gas"]
        step = gas["position/step"][()]
        n = int(params["n"])
        return Snapshots(
            step=step,
            time=gas["position/time"][()],
            tau=step / n,
            position=gas["position/value"][()],
            velocity=gas["velocity/value"][()],
            box=gas["box/edges"][()],
            boundary=[_str(b) for b in gas["box"].attrs["boundary"]],
            radius=gas["radius"][()],
            mass=gas["mass"][()],
            angular_velocity=gas["angular_velocity/value"][()] if "angular_velocity" in gas else None,
            species=gas["species"][()] if "species" in gas else np.zeros(n, dtype=np.int64),
            offset=gas["box/offset/value"][()] if "offset" in gas["box"] else None,
            shear_rate=float(gas["box/offset"].attrs["shear_rate"]) if "offset" in gas["box"] else 0.0,
        )
