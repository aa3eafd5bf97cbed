"""pandas DataFrames of edmd output: the sweep index (``read_index(OUT).to_frame()``), the phase table
(``read_phase_table(OUT)``) and a replica's scalar observables (``read_replica(path).to_frame()``).

pandas is an optional dependency (``pip install 'edmd-analysis[frames]'``); the rest of the package
works without it. The columns and their dtypes are listed in docs/output.md ("DataFrames"): integers
stay int64 (uint64 for seeds and collision counts), reals float64 with NaN for "none", labels with a
few values (status, class, boundary, remedy) are categorical, other text is pandas' string dtype.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from .jsonfiles import read_boundary, read_json

# The index's columns in the order of summary.csv (`Record` in crates/edmd-sweep/src/record.rs).
INDEX_COLUMNS = (
    "index", "file", "status", "message", "dim", "boundary", "eps", "beta", "species", "gravity",
    "shear_rate", "wall_eps", "floor_temperature", "white_noise", "shake_s", "shake_gamma",
    "shaken_state", "aspect", "phi", "box_side", "n", "seed_index", "seed", "remedy",
    "tau", "time", "ln_temperature_ratio", "collisions", "collapse_tau", "class", "shear_onset_tau",
    "cluster_onset_tau", "f_flow", "s_perp", "delta_rho2", "wall_s",
    "resumes",
)
CATEGORIES = ("status", "class", "boundary", "remedy")

# The phase table's columns (`edmd summarize --format json`, OUT/phase.json) and their dtypes.
PHASE_COLUMNS = {
    "dim": "int64", "boundary": "category", "remedy": "category", "n": "int64", "phi": "float64",
    "box_side": "float64", "eps": "float64", "beta": "float64", "species": "string",
    "scene": "string", "shear_rate": "float64", "seeds": "int64", "done": "int64", "collapsed": "int64", "stalled": "int64",
    "failed": "int64",
    "missing": "int64", "tau_end": "float64", "log10_t_ratio": "float64", "log10_t_haff": "float64",
    "l_over_l_perp": "float64", "l_over_l_par": "float64", "kinetic": "float64",
    "shearing": "float64", "clustering": "float64", "homogeneous": "float64",
    "inhomogeneous": "float64", "shear_onset_tau": "float64",
    "cluster_onset_tau": "float64",
}


def pandas():
    """The pandas module, or an ImportError that says how to install it."""
    try:
        import pandas as pd
    except ImportError as e:  # pragma: no cover - exercised only without pandas
        raise ImportError(
            "DataFrames need pandas: pip install 'edmd-analysis[frames]' (or pip install pandas); "
            "without it, Index.columns and Replica.observables hold the same data as numpy arrays"
        ) from e
    return pd


def _text(values) -> bool:
    return np.asarray(values).dtype.kind in "OUS"


def index_frame(index):
    """One row per replica, columns in the order of summary.csv (unknown columns after, sorted)."""
    pd = pandas()
    names = [c for c in INDEX_COLUMNS if c in index.columns]
    names += sorted(c for c in index.columns if c not in INDEX_COLUMNS)
    data = {}
    for c in names:
        v = index.columns[c]
        if c in CATEGORIES:
            data[c] = pd.Categorical([str(x) for x in v])
        elif _text(v):
            data[c] = pd.array([str(x) for x in v], dtype="string")
        else:
            data[c] = v
    return pd.DataFrame(data)


def read_phase_table(out):
    """OUT/phase.json (one row per grid point) as a DataFrame; ``None`` values become NaN."""
    pd = pandas()
    path = Path(out)
    if path.is_dir():
        path = path / "phase.json"
    if not path.exists():
        raise FileNotFoundError(
            f"{path}: no phase table (`edmd run` writes it at the end; for a merged or older "
            f"sweep: edmd summarize {path.parent} --format json > {path})"
        )
    rows = read_json(path)
    if not isinstance(rows, list):
        raise ValueError(f"{path}: not a phase table (a JSON list of rows expected)")
    keys = list(PHASE_COLUMNS)
    keys += sorted({k for r in rows for k in r} - set(keys))
    data = {}
    for k in keys:
        values = [r.get(k) for r in rows]
        dtype = PHASE_COLUMNS.get(k)
        if dtype == "float64":
            data[k] = np.array([np.nan if x is None else float(x) for x in values], dtype=float)
        elif dtype == "int64":
            data[k] = np.array([0 if x is None else int(x) for x in values], dtype=np.int64)
        elif dtype == "category":
            data[k] = pd.Categorical(["" if x is None else str(x) for x in values])
        elif dtype == "string":
            data[k] = pd.array(["" if x is None else str(x) for x in values], dtype="string")
        else:
            data[k] = values
    return pd.DataFrame(data)


def read_boundary_frame(out):
    """OUT/boundary.json (``edmd refine``) as a DataFrame, one row per regime change: ``axis``,
    ``regime_a`` and ``regime_b`` (table order), ``below`` and ``above`` (the classes at the lower and
    upper end), ``lower``, ``upper``, ``at``, ``half_width``, then the fields fixed along the line
    (``dim``, ``boundary``, ``eps``, ``phi``, ``box``, ``n``, ... where the grid gives them; NaN where
    not)."""
    pd = pandas()
    crossings = read_boundary(out)["crossings"]
    fixed = sorted({k for c in crossings for k in c["line"]})
    data = {
        "axis": pd.Categorical([c["axis"] for c in crossings]),
        "regime_a": pd.Categorical([c["regimes"][0] for c in crossings]),
        "regime_b": pd.Categorical([c["regimes"][1] for c in crossings]),
        "below": pd.Categorical([c["below"] for c in crossings]),
        "above": pd.Categorical([c["above"] for c in crossings]),
    }
    for k in ("lower", "upper", "at", "half_width"):
        data[k] = np.array([float(c[k]) for c in crossings], dtype=float)
    for k in fixed:
        values = [c["line"].get(k) for c in crossings]
        if all(isinstance(v, (int, float)) or v is None for v in values):
            data[k] = np.array([np.nan if v is None else float(v) for v in values], dtype=float)
        else:
            data[k] = pd.array([json.dumps(v, sort_keys=True) if isinstance(v, (dict, list)) else
                                ("" if v is None else str(v)) for v in values], dtype="string")
    return pd.DataFrame(data)


def observables_frame(rep):
    """A replica's scalar observables, one row per sample (step and time first)."""
    pd = pandas()
    data = {"step": rep.step, "time": rep.time}
    for name, v in rep.observables.items():
        if np.ndim(v) == 1 and len(v) == len(rep.step):
            data[name] = v
    return pd.DataFrame(data)
