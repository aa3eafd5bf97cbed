"""The JSON files edmd writes beside the index: the phase table (phase.json) and a refinement's
boundary (boundary.json), read with errors that name the file."""

from __future__ import annotations

import json
from pathlib import Path


def read_boundary(out) -> dict:
    """OUT/boundary.json of a refined sweep (``edmd refine``; docs/output.md): the axes, rounds and
    replica counts, and ``crossings``, each regime change along a line of the grid with its
    bracketing pair (``lower``, ``upper``), estimate ``at`` and ``half_width``."""
    path = Path(out)
    if path.is_dir():
        path = path / "boundary.json"
    if not path.exists():
        raise FileNotFoundError(f"{path}: no boundary (written by `edmd refine {path.parent}`)")
    data = read_json(path)
    if not isinstance(data, dict) or not {"crossings", "axes"} <= data.keys():
        raise ValueError(f"{path}: not a boundary file (an object with 'axes' and 'crossings' "
                         "expected); rerun `edmd refine` to write it again")
    return data


def read_json(path) -> object:
    """A JSON file edmd wrote (phase.json, boundary.json), with errors that name it."""
    path = Path(path)
    try:
        return json.loads(path.read_text())
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ValueError(f"{path}: not valid JSON ({e}); rerun `edmd run` (or `edmd summarize`) "
                         "with the same spec and -o to write it again") from e
