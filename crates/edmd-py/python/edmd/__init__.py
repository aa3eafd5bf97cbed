"""edmd in-process: the event-driven engine of granular gases, one replica at a time
(:class:`Simulation`), and whole sweeps (:func:`run_sweep`) writing what ``edmd run`` writes.

    import edmd
    sim = edmd.Simulation.from_spec(spec, replica=0)   # a sweep spec as a dict
    sim.run(tau=100)
    sim.positions, sim.velocities, sim.temperature
    table = edmd.run_sweep(spec, "out", threads=2)     # the phase table as a DataFrame
"""

import json
import os

from ._native import Simulation, __version__, run_sweep_json

__all__ = ["Simulation", "run_sweep", "__version__"]


def run_sweep(spec, out, threads=None, force=False):
    """Runs the sweep ``spec`` (a dict, JSON text, or the path of a spec file) into the directory
    ``out``, writing the files ``edmd run`` writes, bit for bit, and returns the phase table as a
    pandas DataFrame (a list of dicts without pandas). Raises ValueError for a bad spec, with the
    line the command prints."""
    if isinstance(spec, (str, os.PathLike)) and os.path.exists(spec):
        with open(spec) as f:
            text = f.read()
    elif isinstance(spec, str):
        text = spec
    else:
        text = json.dumps(spec)
    rows = json.loads(run_sweep_json(text, os.fspath(out), threads, force))
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)
