"""Analysis of edmd sweeps: read the H5MD replica files and the sweep index into numpy arrays (and
pandas DataFrames when pandas is installed), draw figures, reports and movies."""

from .checkpoints import checkpoints, read_checkpoint_header
from .frames import read_boundary_frame, read_phase_table
from .io import (
    SCHEMA_VERSION,
    CorruptFileError,
    Index,
    Replica,
    SchemaError,
    Snapshots,
    read_boundary,
    read_index,
    read_observable,
    read_replica,
    read_snapshots,
    snapshot_count,
)

__all__ = [
    "SCHEMA_VERSION",
    "CorruptFileError",
    "Index",
    "Replica",
    "SchemaError",
    "Snapshots",
    "checkpoints",
    "read_boundary",
    "read_boundary_frame",
    "read_checkpoint_header",
    "read_index",
    "read_observable",
    "read_phase_table",
    "read_replica",
    "read_snapshots",
    "snapshot_count",
]
