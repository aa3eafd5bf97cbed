"""``python -m edmd_analysis report OUT -o REPORT``: every figure of a sweep as PNG, and an index.html
that shows them with the sweep's parameters and phase table.

Figures (one panel per grid point, first seed; at most ``max_points`` grid points), each drawn
only where the sweep has what it shows: cooling (log-log and semi-log, with Haff's law), snapshots
with velocity arrows (2D; grains to scale, coloured by species in mixtures and by spin in rough
scenes), velocity histograms of the whole box and the half-boxes, T_rot/T_tr against the
two-temperature theory (rough grains), species temperature ratios against Garzo-Dufty (mixtures),
density profiles against the barometric one (gravity), order parameters and the phase diagram
(classified free-cooling sweeps), and a short movie (GIF) of one replica per class, for replicas that
store two or more snapshots. The phase table and its theory columns come from OUT/phase.json, written
by the edmd binary. The page's phase table scrolls inside its own box on narrow screens; every
figure keeps its aspect and carries a line saying what it shows.
"""

from __future__ import annotations

import html
import io as io_bytes
import json
import multiprocessing
import os
import re
import shutil
import signal
import sys
from pathlib import Path
from typing import Optional

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import driven, files, io, movie, plots, shaken  # noqa: E402

# The index columns that tell grid points apart (the seed aside).
POINT_COLUMNS = ("dim", "boundary", "remedy", "n", "phi", "box_side", "eps", "beta", "species",
                 "gravity", "shear_rate", "wall_eps", "floor_temperature", "white_noise", "shake_s",
                 "shake_gamma", "aspect")


def _first_seed_per_point(index: io.Index, max_points: int):
    """Indices of the first finished replica of each grid point, in sweep order."""
    seen, chosen = set(), []
    for i in range(len(index)):
        key = tuple(index[c][i] for c in POINT_COLUMNS if c in index.columns)
        if key in seen or index["status"][i] in ("failed", "missing", "corrupt"):
            continue
        seen.add(key)
        chosen.append(i)
    return chosen[:max_points]


def _resumes(index: io.Index, i: int) -> int:
    """Times replica row `i` went on from a saved state (0 in outputs older than checkpoints)."""
    return int(index["resumes"][i]) if "resumes" in index.columns else 0


def _continued(index: io.Index) -> str:
    """A paragraph naming the replicas that went on from a checkpoint or an extension, if any."""
    runs = [(int(index["index"][i]), _resumes(index, i)) for i in range(len(index))
            if _resumes(index, i)]
    if not runs:
        return ""
    names = ", ".join(f"r{r:05d} ({k}×)" for r, k in runs)
    return (f"<p class=\"continued\">Continued replicas ({len(runs)} of {len(index)}): went on from a "
            f"checkpoint after a stop, or from their final state by <code>edmd extend</code>, "
            f"bit-identical to an uninterrupted run: {html.escape(names)}.</p>")


def _title(index: io.Index, i: int) -> str:
    extra = ""
    col = index.columns
    if "beta" in col and index["beta"][i] > -1:
        extra += f" beta={index['beta'][i]:g}"
    if "species" in col and index["species"][i]:
        extra += f" species={index['species'][i]}"
    if "shear_rate" in col and index["boundary"][i] == "lees-edwards":
        extra += f" a={index['shear_rate'][i]:g}"
    if "gravity" in col and index["gravity"][i] > 0:
        extra += f" g={index['gravity'][i]:g}"
    if "floor_temperature" in col and index["floor_temperature"][i] > 0:
        extra += f" floor_T={index['floor_temperature'][i]:g}"
    if "white_noise" in col and index["white_noise"][i] > 0:
        extra += f" noise={index['white_noise'][i]:g}"
    if "shake_s" in col and index["shake_s"][i] > 0:
        extra += f" S={index['shake_s'][i]:g} Gamma={index['shake_gamma'][i]:g} {index['shaken_state'][i]}"
    if _resumes(index, i):
        extra += " continued"
    # Two lines: the grid point, then the scene and the class (titles of narrow panels stay short).
    return (f"eps={index['eps'][i]:g} N={index['n'][i]} phi={index['phi'][i]:.3g}\n"
            f"{extra.strip()} {index['boundary'][i]} ({index['class'][i]})").replace("\n ", "\n")


def _panels(count: int, width: float = 4.0, height: float = 3.4):
    cols = min(count, 4)
    rows = int(np.ceil(count / cols))
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows), squeeze=False)
    for ax in axes.flat[count:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:count])


def _save(fig, dest: Path, name: str, saved: list):
    fig.tight_layout()
    path = dest / f"{name}.png"
    buffer = io_bytes.BytesIO()
    fig.savefig(buffer, dpi=80, format="png")
    plt.close(fig)
    files.write_bytes(path, buffer.getvalue())
    saved.append(path.name)


def _x_axis(rows):
    """The phase diagram's abscissa: the grid axis that varies (L/L_perp for box scans)."""
    sheared = any(r.get("homogeneous") is not None for r in rows)
    if sheared and len({r.get("shear_rate", 0.0) for r in rows}) > 1:
        return "shear_rate"
    for key, x in (("box_side", "box_side" if sheared else "l_over_l_perp"), ("phi", "phi"), ("n", "n")):
        if len({r[key] for r in rows}) > 1:
            return x
    return "l_over_l_perp"


def _y_axis(rows):
    """The phase diagram's ordinate: eps, or the scene axis that varies when eps does not."""
    if len({r["eps"] for r in rows}) > 1:
        return "eps"
    for key in ("beta", "species"):
        if len({str(r.get(key)) for r in rows}) > 1:
            return key
    return "eps"


# What each figure shows, by the start of its file name (the page's caption under the figure).
LEGENDS = {
    "cooling-loglog": "T/T0 against tau (collisions per particle), log-log, first seed of each grid "
                      "point; dashed: Haff's law with its first Sonine correction (docs/PHYSICS.md).",
    "cooling-semilog": "The same cooling on a linear tau axis: Haff's law is a straight line here, and "
                       "the clustering gas leaves it upwards.",
    "snapshots-": "Disks to scale at each stored snapshot, arrows: velocities in units of the rms "
                  "speed; colours by species (mixtures) or spin omega (rough disks).",
    "velocity-histograms": "One velocity component over the whole box and over the two half-boxes, at "
                           "the last snapshot: a shear band shows as two shifted half-box histograms.",
    "rotational-ratio": "T_rot/T_tr of rough grains against the two-temperature theory from the same "
                        "start (dashed) and its Sonine stationary ratio (dotted).",
    "species-temperatures": "Each species' temperature over the last species' against Garzo-Dufty's "
                            "homogeneous-cooling ratio (dashed).",
    "density-profiles": "Number density along gravity, averaged over the last half of the samples, "
                        "against the barometric profile (elastic columns).",
    "order-parameters": "The classifier's order parameters over their thresholds (dotted line = 1): "
                        "crossing it marks shear (S_perp) or clustering (density variance).",
    "phase-diagram": "Each grid point as a pie of its replicas' classes (kinetic, shearing, "
                     "clustering; for a sheared gas homogeneous or inhomogeneous flow) over the grid "
                     "axis that varies; against L/L_perp, dashed and dotted lines mark the theory's "
                     "L = L_perp and L = L_par.",
    "phase-boundary": "The phase diagram of a refined sweep (edmd refine): the start grid's points as "
                      "large pies of their replicas' classes, the points the refinement added as small "
                      "ones; open symbols: where the majority class changes between two neighbouring "
                      "points, at their midpoint with the pair as error bar (OUT/boundary.json); "
                      "dashed and dotted: the linear theory's L = L_perp and L = L_par. The title "
                      "counts the replicas against the full grid of the same resolution.",
    "shear-rheology": "The steady sheared gas against restitution, averaged over the second half of "
                      "each run (replicas at phi <= 0.05): reduced shear rate a* = a/nu0, viscosity "
                      "eta* and normal stresses P_ii/(nT) (points) against kinetic theory, the Enskog "
                      "gas with the anisotropic-Gaussian closure (dashed; docs/PHYSICS.md 7.2).",
    "white-noise": "Gases heated by white noise, averaged over the second half of each run: the "
                   "temperature over the theory's T_s (1 in theory) and the speed kurtosis against "
                   "(d+2)/d (1 + a2) of van Noije & Ernst (dashed; docs/PHYSICS.md 8.1).",
    "shaken-states": "Beds on a vibrating floor in the plane of the shaking strength S and the layers "
                     "F: each replica coloured by its state, read from its uniform-time samples over "
                     "the second half of the run (parameters/shaken_state; thresholds in "
                     "docs/PHYSICS.md 8.4).",
    "shaken-profiles": "Packing fraction and granular temperature against height, averaged over the "
                       "floor's period in the second half of each shaken run (the file's /bed), one "
                       "line per replica coloured by its state: a bouncing bed is dense at the floor, "
                       "a Leidenfrost bed floats a dense layer on a hot dilute one.",
    "shaken-flow": "The time-averaged vertical velocity of the most convective shaken replica (red "
                   "up, blue down, in sqrt(g d)): convection rolls show as columns of alternating "
                   "sign; its amplitude and noise are in the title (docs/PHYSICS.md 8.4).",
    "stream-profiles": "Stream velocity u_x(y) of sheared replicas over the second half of the run "
                       "against the imposed a (y - L_y/2); orange: density along y over its mean "
                       "(flat when the flow is homogeneous).",
    "movie-": "Movie of one replica of this class (or shaken bed's state): disks to scale coloured by speed in units of the "
              "current rms speed (or by species / spin), tau and T/T0 in the title; a sheared box "
              "shows its sliding images faded around it, speeds relative to the flow.",
}

# The heading of each figure, by the start of its file name ({k}: the replica number in the name,
# {c}: the class of a movie).
TITLES = {
    "cooling-loglog": "Cooling: temperature against collisions per particle",
    "cooling-semilog": "Cooling on a linear tau axis",
    "snapshots-": "Snapshots of replica {k}",
    "velocity-histograms": "Velocity distributions in the two half-boxes",
    "rotational-ratio": "Rotational against translational temperature",
    "species-temperatures": "Temperatures of the species",
    "density-profiles": "Density profiles of the columns",
    "order-parameters": "Order parameters of the classifier",
    "phase-diagram": "Phase diagram",
    "phase-boundary": "Phase boundary found by refinement",
    "shear-rheology": "Rheology of the steady shear flow",
    "white-noise": "The steady state of gases heated by white noise",
    "shaken-states": "States of the shaken bed",
    "shaken-profiles": "Height profiles of the shaken beds",
    "shaken-flow": "Mean flow of the most convective shaken bed",
    "stream-profiles": "Stream velocity and density across the flow",
    "movie-": "Movie of a {c} replica ({k})",
}

MOVIE_CLASSES = ("kinetic", "shearing", "clustering", "homogeneous", "inhomogeneous")
SNAPSHOT_PANELS = 6


def title(name: str) -> str:
    """The heading of the figure file ``name`` (never the file name itself)."""
    stem = name.rsplit(".", 1)[0]
    number = re.search(r"-r(\d+)$", stem)
    k = str(int(number.group(1))) if number else ""
    c = stem.split("-")[1] if stem.startswith("movie-") and stem.count("-") >= 2 else "sample"
    for prefix, text in TITLES.items():
        if name.startswith(prefix):
            return text.format(k=k, c="sample" if c == "replica" else c)
    return "Figure"


def legend(name: str) -> str:
    """The caption of the figure file ``name``."""
    for prefix, text in LEGENDS.items():
        if name.startswith(prefix):
            return text
    return ""


def _movie_tasks(index: io.Index, dest: Path, max_frames: int = 40):
    """One short GIF per class (the first replica of each class with two or more snapshots; one
    movie of the first such replica when the sweep is not classified; shaken beds by their state,
    shaken.MOVIE_STATES), as tasks."""
    column, kinds = ("class", MOVIE_CLASSES)
    if "shaken_state" in index.columns and any(str(s) for s in index["shaken_state"]):
        column, kinds = ("shaken_state", shaken.MOVIE_STATES)
    classes = [str(c) for c in index[column]] if column in index.columns else [""] * len(index)
    wanted = [c for c in kinds if c in classes] or [None]
    tasks = []
    for c in wanted:
        for i in range(len(index)):
            if (c is not None and classes[i] != c) or index["status"][i] in ("failed", "missing", "corrupt"):
                continue
            path = index.replica_path(i)
            try:
                if io.snapshot_count(path) < 2:
                    continue
            except (io.SchemaError, FileNotFoundError):
                continue
            name = f"movie-{c or 'replica'}-r{int(index['index'][i]):05d}.gif"
            tasks.append((_movie_figure, (path, dest / name, max_frames)))
            break
    return tasks


def _movie_figure(path: Path, output: Path, max_frames: int):
    movie.movie(path, output=output, max_frames=max_frames)
    return [output.name]


def _panel_figure(dest: Path, name: str, draw, paths, titles, read=io.read_replica):
    """One panel per replica file: ``draw(ax, read(path))``, titled."""
    saved: list = []
    fig, axes = _panels(len(paths))
    for ax, path, title in zip(axes, paths, titles):
        draw(ax, read(path))
        ax.set_title(title, fontsize="small")
    _save(fig, dest, name, saved)
    return saved


def _cooling_log(ax, rep):
    plots.cooling(ax, rep, log_tau=True)


def _cooling_linear(ax, rep):
    plots.cooling(ax, rep, log_tau=False)


def _snapshot_figure(dest: Path, name: str, path: Path, title: str):
    saved: list = []
    snaps = io.read_snapshots(path)
    # At most SNAPSHOT_PANELS snapshots, evenly spread over those stored (first and last kept);
    # the movies show them all.
    k = len(snaps.step)
    shown = np.unique(np.linspace(0, k - 1, min(k, SNAPSHOT_PANELS)).round().astype(int))
    fig, axes = _panels(len(shown), 4.0, 4.0)
    for j, ax in zip(shown, axes):
        plots.snapshot(ax, snaps, k=j)
    fig.suptitle(title)
    _save(fig, dest, name, saved)
    return saved


def _phase_figure(dest: Path, rows):
    saved: list = []
    fig, ax = plt.subplots(figsize=(6.5, 5))
    plots.phase_diagram(ax, rows, x=_x_axis(rows), y=_y_axis(rows))
    _save(fig, dest, "phase-diagram", saved)
    return saved


def _boundary_figure(dest: Path, rows, boundary, spec):
    saved: list = []
    fig, ax = plt.subplots(figsize=(7, 5.5))
    x, y = plots.boundary_axes(rows, boundary)
    points = [g for r in (spec.get("refinement") or {}).get("rounds", []) for g in r]
    refined = [(float(p[x]), float(p[y])) for p in points if p.get(x) is not None and p.get(y) is not None]
    plots.boundary_diagram(ax, rows, boundary, refined=refined)
    _save(fig, dest, "phase-boundary", saved)
    return saved


def _rheology_figure(dest: Path, paths):
    saved: list = []
    reps = [io.read_replica(p) for p in paths]
    # Dilute replicas only (phi <= 0.05): the figure is against eps, and replicas of other densities,
    # whose stresses carry the collisional transfer, would be averaged with them.
    reps = [r for r in reps if np.isfinite(float(r.params.get("shear_theory_reduced_rate", np.nan)))
            and float(r.params["phi"]) <= 0.05]
    if not reps:
        return saved
    dims = sorted({int(r.params["dim"]) for r in reps})
    fig, axes = plt.subplots(len(dims), 3, figsize=(12, 3.6 * len(dims)), squeeze=False)
    plots.shear_rheology(axes, reps)
    _save(fig, dest, "shear-rheology", saved)
    return saved


def _white_noise_figure(dest: Path, paths):
    saved: list = []
    reps = [r for r in map(io.read_replica, paths)
            if np.isfinite(float(r.params.get("white_noise_theory_temperature", np.nan)))]
    if reps:
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
        driven.white_noise_steady_state(axes, reps)
        _save(fig, dest, "white-noise", saved)
    return saved


def _shaken_figure(dest: Path, index: io.Index):
    saved: list = []
    betas = sorted({p[4] for p in shaken.shaken_points(index)})
    if not betas:
        return saved
    fig, axes = plt.subplots(1, len(betas), figsize=(6 * len(betas), 4), squeeze=False)
    for ax, beta in zip(axes[0], betas):
        shaken.shaken_states(ax, index, beta if len(betas) > 1 else None)
    _save(fig, dest, "shaken-states", saved)
    reps = shaken.read(index)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5))
    if shaken.profiles(axes, reps):
        _save(fig, dest, "shaken-profiles", saved)
    else:
        plt.close(fig)
    rolls = shaken.most_convective(reps)
    if rolls is not None:
        fig, ax = plt.subplots(figsize=(8, 4))
        shaken.flow(ax, rolls)
        _save(fig, dest, "shaken-flow", saved)
    return saved


def _run(task):
    draw, args = task
    return draw(*args)


def _ignore_interrupts():
    """In a worker: Ctrl-C is the parent's to handle (one line, not a traceback per worker)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _render(tasks, jobs: int):
    """Runs the figure tasks, ``jobs`` at a time in worker processes (each figure is independent
    and matplotlib is single-threaded); returns the files written, in the tasks' order."""
    jobs = max(1, min(jobs, len(tasks)))
    if jobs == 1:
        return [name for task in tasks for name in _run(task)]
    # fork shares the imported matplotlib with the workers (spawn re-imports it, ~2 s each);
    # macOS forbids fork after its GUI frameworks load, so it spawns.
    method = "fork" if sys.platform.startswith("linux") else "spawn"
    with multiprocessing.get_context(method).Pool(jobs, initializer=_ignore_interrupts) as pool:
        # The longest tasks (the movies) first, one task per dispatch, results in task order.
        order = sorted(range(len(tasks)), key=lambda k: tasks[k][0] is not _movie_figure)
        done = pool.map(_run, [tasks[k] for k in order], chunksize=1)
    names = [None] * len(tasks)
    for k, result in zip(order, done):
        names[k] = result
    return [name for result in names for name in result]


def report(out, dest, max_points: int = 24, movies: bool = True, jobs: Optional[int] = None) -> Path:
    """Writes the report of the sweep in ``out`` into ``dest``; returns the path of index.html.
    ``movies=False`` skips the movies (one per class); ``jobs`` figures are drawn at a time (default:
    one per core)."""
    out, dest = Path(out), Path(dest)
    if not out.is_dir():
        raise ValueError(f"{out}: not a sweep output directory (edmd run -o OUT)")
    if jobs is not None and jobs < 1:
        raise ValueError(f"--jobs {jobs}: must be at least 1")
    index = io.read_index(out)
    created = not os.path.lexists(dest)
    files.ensure_dir(dest)
    try:
        return _write_report(out, dest, index, max_points, movies, jobs or os.cpu_count() or 1)
    except BaseException:
        # A report that failed leaves no empty or half-written directory of its own making.
        if created and dest.is_dir():
            shutil.rmtree(dest, ignore_errors=True)
        raise


def _write_report(out: Path, dest: Path, index, max_points: int, movies: bool, jobs: int) -> Path:
    """The body of :func:`report`, into the existing directory ``dest``."""
    phase_path = out / "phase.json"
    rows = io.read_json(phase_path) if phase_path.exists() else []
    if not isinstance(rows, list) or not all(isinstance(r, dict) for r in rows):
        raise ValueError(f"{phase_path}: not a phase table (a list of rows expected)")
    for i in range(len(index)):
        if index["status"][i] == "corrupt":
            message = index["message"][i] if "message" in index.columns else ""
            print(f"warning: {index.replica_path(i)}: left out of the figures: {message}",
                  file=sys.stderr)
    chosen = _first_seed_per_point(index, max_points)
    paths = [index.replica_path(i) for i in chosen]
    titles = [_title(index, i) for i in chosen]
    # What each replica holds decides the figures; the tasks read their data themselves.
    held = [set(io.read_replica(p).observables) for p in paths]
    tasks = []
    if chosen:
        tasks.append((_panel_figure, (dest, "cooling-loglog", _cooling_log, paths, titles)))
        tasks.append((_panel_figure, (dest, "cooling-semilog", _cooling_linear, paths, titles)))
    for i, path in zip(chosen, paths):
        if index["dim"][i] == 2:
            tasks.append((_snapshot_figure, (dest, f"snapshots-r{int(index['index'][i]):05d}", path,
                                             _title(index, i))))
    if chosen:
        tasks.append((_panel_figure, (dest, "velocity-histograms", plots.velocity_histograms, paths,
                                      titles, io.read_snapshots)))
    for name, plot, needs in (("rotational-ratio", plots.rotational_ratio, "rotational_temperature"),
                              ("species-temperatures", plots.species_temperatures, "species_temperature"),
                              ("density-profiles", plots.density_profile, "density_profile")):
        having = [k for k in range(len(chosen)) if needs in held[k]]
        if having:
            tasks.append((_panel_figure, (dest, name, plot, [paths[k] for k in having],
                                          [titles[k] for k in having])))
    classified = [k for k in range(len(chosen))
                  if "s_perp" in held[k] and index["class"][chosen[k]] != "not_applicable"]
    if classified:
        tasks.append((_panel_figure, (dest, "order-parameters", plots.order_parameters,
                                      [paths[k] for k in classified], [titles[k] for k in classified])))
        if rows and any(r.get("kinetic") is not None for r in rows):
            tasks.append((_phase_figure, (dest, rows)))
    elif rows and any(r.get("homogeneous") is not None for r in rows):
        tasks.append((_phase_figure, (dest, rows)))
    if rows and (out / "boundary.json").exists():
        tasks.append((_boundary_figure, (dest, rows, io.read_boundary(out), index.spec)))
    sheared = [k for k in range(len(chosen)) if "pressure_tensor" in held[k]]
    if sheared:
        tasks.append((_panel_figure, (dest, "stream-profiles", plots.stream_profile,
                                      [paths[k] for k in sheared], [titles[k] for k in sheared])))
        all_sheared = [index.replica_path(i) for i in range(len(index))
                       if index["boundary"][i] == "lees-edwards" and index["status"][i] == "done"]
        tasks.append((_rheology_figure, (dest, all_sheared)))
    if "white_noise" in index.columns and (index["white_noise"] > 0).any():
        tasks.append((_white_noise_figure, (dest, [index.replica_path(i) for i in range(len(index))
                                                    if index["white_noise"][i] > 0 and index["status"][i] == "done"])))
    if "shake_s" in index.columns and (index["shake_s"] > 0).any():
        tasks.append((_shaken_figure, (dest, index)))
    if movies:
        tasks += _movie_tasks(index, dest)
    saved = _render(tasks, jobs)
    page = dest / "index.html"
    files.write_bytes(page, _html(index, rows, saved).encode())
    return page


def _html(index: io.Index, rows, images) -> str:
    spec = index.spec
    head = ["eps", "beta", "species", "scene", "n", "phi", "box_side", "boundary", "remedy", "seeds", "done", "collapsed",
            "stalled", "failed", "tau_end", "log10_t_ratio", "log10_t_haff", "l_over_l_perp", "l_over_l_par",
            "kinetic", "shearing", "clustering", "shear_onset_tau", "cluster_onset_tau"]
    if any(r.get("homogeneous") is not None for r in rows):
        head += ["homogeneous", "inhomogeneous"]

    def cell(v):
        if v is None:
            return "-"
        if isinstance(v, float):
            return f"{v:.3g}"
        return html.escape(str(v))

    table = "<tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>\n"
    for r in rows:
        table += "<tr>" + "".join(f"<td>{cell(r.get(h))}</td>" for h in head) + "</tr>\n"
    figures = "\n".join(
        f'<figure><h3>{html.escape(title(name))}</h3><a href="{html.escape(name)}">'
        f'<img src="{html.escape(name)}" alt="{html.escape(name)}"></a>'
        f'<figcaption>{html.escape(legend(name))}</figcaption></figure>'
        for name in images)
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>edmd sweep {html.escape(index.name)}</title>
<style>body{{font-family:sans-serif;margin:1em auto;max-width:80em;padding:0 1em}}
.table-box{{overflow-x:auto;max-width:100%;border:1px solid #ddd}}
table{{border-collapse:collapse;font-size:small;white-space:nowrap}}
td,th{{border:1px solid #ccc;padding:2px 6px;text-align:right}}
figure{{margin:1.5em 0}} img{{max-width:100%;height:auto;display:block}}
figcaption{{font-size:small;color:#444;max-width:50em}}
pre{{overflow-x:auto;max-width:100%}}</style></head><body>
<h1>Sweep {html.escape(index.name)}</h1>
<p>{html.escape(spec.get("description", ""))}</p>
<h2>Phase table</h2>
<p>One row per grid point over its seeds: replicas done, collapsed, stalled and failed, the end of the run, T/T0
against Haff's law, the box over the theory's unstable lengths, the class fractions and onset times.</p>
<div class="table-box">
<table>
{table}</table>
</div>
{_continued(index)}
<h2>Figures</h2>
{figures}
<h2>Spec</h2>
<pre>{html.escape(json.dumps(spec, indent=2))}</pre>
</body></html>
"""
