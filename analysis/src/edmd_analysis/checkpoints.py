"""The checkpoints of a sweep's unfinished replicas (OUT/states/rNNNNN.ckpt): how far each got.

A checkpoint starts with "EDMDCKPT", a little-endian u64 length and a JSON header (docs/output.md,
"Checkpoints"); only the header is read here, the states are the engine's own."""

import json
import struct
import time
from pathlib import Path

MAGIC = b"EDMDCKPT"


def read_checkpoint_header(path) -> dict:
    """The header of one checkpoint: format, spec_hash, replica, tau, collisions, wall_s, written
    (Unix time), reason. Raises ValueError for a file that is not an edmd checkpoint."""
    path = Path(path)
    with open(path, "rb") as f:
        if f.read(8) != MAGIC:
            raise ValueError(f"{path}: not an edmd checkpoint")
        (length,) = struct.unpack("<Q", f.read(8))
        if length > path.stat().st_size:
            raise ValueError(f"{path}: a header of {length} bytes, beyond the file")
        return json.loads(f.read(length))


def checkpoints(out) -> list:
    """Every checkpoint under OUT/replicas, by replica: its header plus `path` and `age_s` (seconds
    since it was written). Unreadable ones are listed with an `error` instead."""
    rows = []
    for p in sorted((Path(out) / "states").glob("r*.ckpt")):
        try:
            h = read_checkpoint_header(p)
            h["age_s"] = time.time() - h["written"]
        except (OSError, ValueError, struct.error) as e:
            h = {"error": str(e)}
        h["path"] = str(p)
        rows.append(h)
    return rows
