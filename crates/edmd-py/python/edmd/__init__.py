"""edmd in-process: the event-driven engine of granular gases, one replica at a time
(:class:`Simulation`), and whole sweeps (:func:`run_sweep`) writing what ``edmd run`` writes.

    import edmd
    sim = edmd.Simulation.from_spec(spec, replica=0)   # a sweep spec as a dict
    sim.run(tau=100)
    sim.positions, sim.velocities, sim.temperature
    sim.set_rule(eps=0.7); sim.run(until_temperature=0.01)
    table = edmd.run_sweep(spec, "out", threads=2)     # the phase table as a DataFrame
    table = edmd.refine("out", rounds=2)               # bisected where the regimes differ
"""

import json
import os
import sys

from ._native import Simulation, __version__, refine_json, run_sweep_json

__all__ = ["Simulation", "refine", "run_sweep", "__version__"]


def _spec_text(spec):
    if isinstance(spec, (str, os.PathLike)) and os.path.exists(spec):
        with open(spec) as f:
            return f.read()
    if isinstance(spec, str):
        return spec
    return json.dumps(spec)


class _Bar:
    """Progress in collisions: tqdm's bar (a widget in a notebook) where tqdm is installed, else a
    line on stderr rewritten in place."""

    def __init__(self):
        try:
            from tqdm.auto import tqdm
        except ImportError:
            tqdm = None
        self._tqdm = tqdm
        self._bar = None

    def __call__(self, collisions, total, done, replicas):
        if self._tqdm is not None:
            if self._bar is None:
                self._bar = self._tqdm(total=total, unit=" coll", unit_scale=True, desc="edmd")
            self._bar.total = total
            self._bar.n = min(collisions, total)
            self._bar.set_postfix_str(f"{done}/{replicas} replicas", refresh=False)
            self._bar.refresh()
        elif total:
            print(f"\redmd: {100 * collisions / total:5.1f} % of {total:.3g} collisions, "
                  f"{done}/{replicas} replicas", end="", file=sys.stderr, flush=True)

    def close(self):
        if self._bar is not None:
            self._bar.close()
        elif self._tqdm is None:
            print(file=sys.stderr)


def run_sweep(spec, out, threads=None, force=False, shard=None, progress=True):
    """Runs the sweep ``spec`` (a dict, JSON text, or the path of a spec file) into the directory
    ``out``, writing the files ``edmd run`` writes, bit for bit, and returns the phase table as a
    pandas DataFrame (a list of dicts without pandas; empty while other shards are missing).

    ``threads``: worker threads (default every core); ``shard``: ``"K/N"``, run only share K of N
    of the replicas, as ``edmd run --shard``; ``force``: replace the output of another spec.
    ``progress``: True for a bar (tqdm's where installed), False for none, or a callable
    ``f(collisions, total, replicas_done, replicas)`` called a few times a second.

    Ctrl-C stops the run with each replica in flight checkpointed and raises KeyboardInterrupt;
    calling ``run_sweep`` again goes on from there. A bad spec raises ValueError with the line the
    command prints."""
    return _table(lambda callback: run_sweep_json(_spec_text(spec), os.fspath(out), threads, force, shard,
                                                  callback), progress)


def refine(out, rounds=3, budget=None, axes=None, threads=None, progress=True):
    """Refines the classified sweep in ``out`` (written by :func:`run_sweep` or ``edmd run``) as
    ``edmd refine`` does, writing the same files: rounds of bisection where neighbouring grid
    points differ in regime, up to ``rounds`` rounds in all (a second call goes on to that many),
    adding at most ``budget`` replicas, along ``axes`` (e.g. ``["eps", "box"]``; default those the
    grid varies). Returns the refined phase table as a DataFrame; ``boundary.json`` in ``out``
    holds the boundary. ``progress`` and Ctrl-C as in :func:`run_sweep`."""
    return _table(lambda callback: refine_json(os.fspath(out), rounds, budget, axes, threads, callback), progress)


def _table(call, progress):
    """Runs ``call(callback)`` with the progress asked for; its JSON table as a DataFrame."""
    bar = _Bar() if progress is True else None
    callback = bar if bar is not None else (progress or None)
    try:
        rows = json.loads(call(callback))
    finally:
        if bar is not None:
            bar.close()
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame(rows)
