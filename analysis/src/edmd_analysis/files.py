"""Files the report and the movies write, never through a symbolic link.

An output directory can be shared (a cluster's scratch space). A link planted under one of our
names (``OUT/report/index.html`` pointing at a file elsewhere) must never make us write through it:
every file is written under a fresh temporary name in its directory (created exclusively, so a
planted name cannot be ours) and renamed over the final name, which replaces a link rather than
following it; a directory we write into must be a real directory, not a link. The edmd binary does
the same for the files it writes.
"""

from __future__ import annotations

import os
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path

# The process's umask, read once (reading it means setting it).
_UMASK = os.umask(0)
os.umask(_UMASK)


def ensure_dir(path: Path) -> Path:
    """Creates ``path`` (and its parents) when missing; refuses a symbolic link or a non-directory."""
    path = Path(path)
    try:
        mode = os.lstat(path).st_mode
    except FileNotFoundError:
        path.mkdir(parents=True)
        return path
    if stat.S_ISLNK(mode):
        raise OSError(0, "a symbolic link, not a directory (the report never writes through links; "
                      "remove it or give the real path)", str(path))
    if not stat.S_ISDIR(mode):
        raise OSError(0, "not a directory", str(path))
    return path


@contextmanager
def replacing(path: Path):
    """Yields a fresh temporary path beside ``path`` to write; on success renames it over ``path``
    (replacing a link, never following it), on failure removes it. Errors name ``path``."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=f".part{path.suffix}")
    # mkstemp makes the file private (0600); a report is read like any file the user writes.
    os.fchmod(fd, 0o666 & ~_UMASK)
    os.close(fd)
    try:
        yield Path(tmp)
        os.replace(tmp, path)
    except OSError as e:
        _remove(tmp)
        raise OSError(e.errno or 0, e.strerror or str(e), str(path)) from e
    except BaseException:
        _remove(tmp)
        raise


def write_bytes(path: Path, data: bytes) -> None:
    """Writes ``data`` to ``path`` through a temporary file, synced before the rename."""
    with replacing(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())


def _remove(tmp) -> None:
    try:
        os.unlink(tmp)
    except FileNotFoundError:
        pass
