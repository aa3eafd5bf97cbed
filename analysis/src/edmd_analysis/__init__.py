"""Analysis of edmd sweeps: read the H5MD replica files and the sweep index into numpy arrays."""

from .io import (
    SCHEMA_VERSION,
    CorruptFileError,
    Index,
    Replica,
    SchemaError,
    Snapshots,
    read_index,
    read_observable,
    read_replica,
    read_snapshots,
)

__all__ = [
    "SCHEMA_VERSION",
    "CorruptFileError",
    "Index",
    "Replica",
    "SchemaError",
    "Snapshots",
    "read_index",
    "read_observable",
    "read_replica",
    "read_snapshots",
]
