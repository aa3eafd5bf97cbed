"""``python -m edmd_analysis movie OUT [--replica K] [-o FILE]``: an animation of one replica, one frame
per stored snapshot (``snapshots.at``, ``snapshots.every``, ``snapshots.per_decade`` and the final
state of the spec; docs/sweep-spec.md).

Grains are drawn to scale. In 2D every disk is shown; in 3D the spheres cut by the mid-plane slab
|z - L_z/2| < sigma_max/2 are drawn as their cross-sections. Colours: the speed in units of the
current rms speed (|v_i| / sqrt(D T / m_i), so a frame of a gas cooled by 10^6 reads like the first),
one colour per species in mixtures, the spin omega in units of its rms in rough scenes; velocity
arrows (scaled by the rms speed) on request, and by default where the colour is not the speed. The
title gives tau and T/T0 from the replica's ``ln_temperature`` at the snapshot's step.

A GIF is written through Pillow always; an MP4 too when ffmpeg is on the PATH.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import List, Optional

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib import animation  # noqa: E402
from matplotlib.collections import EllipseCollection  # noqa: E402

from . import files, io, plots  # noqa: E402

COLOURINGS = ("speed", "species", "spin", "plain")
SPEED_MAX = 2.5  # top of the colour scale, in rms speeds


def has_ffmpeg() -> bool:
    """Whether MP4 files can be written (ffmpeg on the PATH)."""
    return shutil.which("ffmpeg") is not None


def default_colouring(snaps: io.Snapshots) -> str:
    """'species' for a mixture, 'spin' for rough grains, 'speed' otherwise."""
    picked = plots.snapshot_colouring(snaps)
    return "speed" if picked == "plain" else picked


def pick_replica(out) -> int:
    """The replica a movie shows by default: the finished one with the most snapshots (the first such
    in sweep order)."""
    index = io.read_index(out)
    best, most = None, 1
    for i in range(len(index)):
        if index["status"][i] in ("failed", "missing", "corrupt"):
            continue
        path = index.replica_path(i)
        if not path.exists():
            continue
        k = io.snapshot_count(path)
        if k > most:
            best, most = int(index["index"][i]), k
    if best is None:
        raise ValueError(f"{out}: no replica stores two or more snapshots; add snapshots.every to the spec")
    return best


def _temperature_ratio(rep: io.Replica, steps: np.ndarray) -> np.ndarray:
    """T/T0 at each snapshot step, from the sampled ln T (every snapshot is also a sample)."""
    ln_t = rep.observables["ln_temperature"]
    tau = rep.observables["tau"]
    n = float(rep.params["n"])
    return np.exp(np.interp(steps / n, tau, ln_t) - ln_t[0])


def _visible(snaps: io.Snapshots, k: int):
    """Indices, centres and drawn diameters of the grains in frame k (a mid-plane slab in 3D)."""
    pos = snaps.position[k]
    d = 2 * np.asarray(snaps.radius, dtype=float)
    if pos.shape[1] == 2:
        return np.arange(len(pos)), pos, d
    half = 0.5 * d.max()
    dz = pos[:, 2] - 0.5 * snaps.box[2]
    idx = np.flatnonzero(np.abs(dz) < half)
    cut = 2 * np.sqrt(np.maximum((d[idx] / 2) ** 2 - dz[idx] ** 2, 0.0))
    return idx, pos[idx, :2], cut


def _speed(snaps: io.Snapshots, k: int) -> np.ndarray:
    """|v_i| / sqrt(D T / m_i), T = sum m v^2 / (D N): the speed in rms speeds of its own mass."""
    v = snaps.velocity[k].copy()
    if snaps.offset is not None:  # relative to the flow u_x = a (y - L_y/2) of a sheared box
        v[:, 0] -= snaps.shear_rate * (snaps.position[k][:, 1] - 0.5 * snaps.box[1])
    m = np.asarray(snaps.mass, dtype=float)
    dim = v.shape[1]
    t = (m * (v**2).sum(axis=1)).sum() / (dim * len(m))
    return np.sqrt((v**2).sum(axis=1)) / (np.sqrt(dim * t / m) if t > 0 else 1.0)


def _with_images(snaps: io.Snapshots, k: int, idx, xy, d):
    """A sheared box: the drawn grains and, after them, their images within a margin of the box
    (the sliding ones across the y faces); returns (indices, centres, diameters, margin, how many
    are grains). Other boxes: what it was given, margin 0."""
    if snaps.offset is None:
        return idx, xy, d, 0.0, len(idx)
    margin = 0.15 * float(snaps.box[1])
    ii, pp = snaps.images(k, margin)
    where = {int(g): j for j, g in enumerate(idx)}
    keep = [n for n, g in enumerate(ii) if int(g) in where]
    rows = [where[int(ii[n])] for n in keep]
    return (np.concatenate([idx, ii[keep]]), np.concatenate([xy, pp[keep, :2]]),
            np.concatenate([d, d[rows]]), margin, len(idx))


def _draw(ax, snaps, k, colour, arrows, title, top=None, floor=None):
    """Frame k; ``top`` the height shown (the box's by default), ``floor`` a vibrating floor's
    (amplitude, angular frequency), drawn at its height at the frame's time."""
    ax.clear()
    idx, xy, d, margin, grains = _with_images(snaps, k, *_visible(snaps, k))
    style = dict(units="xy", offsets=xy, offset_transform=ax.transData, linewidth=0.2)
    if colour == "species":
        sp = np.asarray(snaps.species)[idx]
        face = [plots.SPECIES_COLOURS[s % len(plots.SPECIES_COLOURS)] for s in sp]
        edge = [plots.SPECIES_EDGES[s % len(plots.SPECIES_EDGES)] for s in sp]
        ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), facecolor=face, edgecolor=edge,
                                            **style))
    elif colour in ("speed", "spin"):
        if colour == "speed":
            value, cmap, lim = _speed(snaps, k)[idx], "viridis", (0.0, SPEED_MAX)
        else:
            omega = snaps.angular_velocity[k][:, -1]
            value, cmap, lim = (omega / (np.sqrt((omega**2).mean()) or 1.0))[idx], "coolwarm", (-2.5, 2.5)
        coll = EllipseCollection(d, d, np.zeros_like(d), cmap=cmap, edgecolor="none", **style)
        coll.set_array(value)
        coll.set_clim(*lim)
        ax.add_collection(coll)
    else:
        ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), facecolor="#9ecae1",
                                            edgecolor="#3182bd", **style))
    if arrows and grains:
        vel = snaps.velocity[k][idx[:grains], :2]
        scale = np.sqrt((snaps.velocity[k] ** 2).sum(axis=1).mean()) or 1.0
        ax.quiver(xy[:grains, 0], xy[:grains, 1], vel[:, 0] / scale, vel[:, 1] / scale, angles="xy",
                  scale_units="xy", scale=0.5, width=0.0015, color="k")
    ax.set_xlim(-margin, snaps.box[0] + margin)
    ax.set_ylim(-margin, (snaps.box[1] if top is None else top) + margin)
    if floor is not None:
        from matplotlib.patches import Rectangle

        a, omega = floor
        height = a * (1 - np.cos(omega * snaps.time[k]))
        ax.add_patch(Rectangle((0, -a), float(snaps.box[0]), height + a, color="0.45", zorder=2))
    if margin > 0:
        # The images, outside the box, under a white veil; the box's outline.
        from matplotlib.patches import PathPatch, Rectangle
        from matplotlib.path import Path as MPath

        lx, ly = float(snaps.box[0]), float(snaps.box[1])
        outer = [(-margin, -margin), (lx + margin, -margin), (lx + margin, ly + margin),
                 (-margin, ly + margin), (-margin, -margin)]
        inner = [(0, 0), (0, ly), (lx, ly), (lx, 0), (0, 0)]
        codes = [MPath.MOVETO] + [MPath.LINETO] * 3 + [MPath.CLOSEPOLY]
        veil = MPath(outer + inner, codes + codes)
        ax.add_patch(PathPatch(veil, facecolor="white", alpha=0.55, edgecolor="none", zorder=3))
        ax.add_patch(Rectangle((0, 0), lx, ly, fill=False, edgecolor="k", lw=0.8, zorder=4))
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    ax.set_title(title, fontsize="small")


def _colour_bar(fig, ax, colour):
    if colour == "speed":
        mappable = plt.cm.ScalarMappable(plt.Normalize(0.0, SPEED_MAX), "viridis")
        label = "|v| / rms speed"
    elif colour == "spin":
        mappable = plt.cm.ScalarMappable(plt.Normalize(-2.5, 2.5), "coolwarm")
        label = "omega / rms"
    else:
        return
    fig.colorbar(mappable, ax=ax, shrink=0.8, label=label)


def _gravity_view(snaps: io.Snapshots, params: dict):
    """Under gravity: the height the grains reach over the frames plus a tenth (at most the box's),
    and a vibrating floor's (amplitude, angular frequency) or None; elsewhere (None, None)."""
    if not params.get("gravity", 0) > 0 or snaps.position.shape[2] != 2:
        return None, None
    reach = float((snaps.position[:, :, 1] + np.asarray(snaps.radius, dtype=float)).max())
    top = min(1.1 * reach, float(snaps.box[1]))
    a = float(params.get("floor_amplitude", 0.0))
    return top, ((a, float(params["floor_omega"])) if a > 0 else None)


# Frame width in inches; the pixels are this times the dpi.
FRAME_INCHES = 5.0
# Default frame width in pixels: a laptop screen's half; a quick sweep's GIF stays near 2 MB
# (grains drawn as flat discs in a few colours compress well).
FRAME_PIXELS = 640


def movie(source, replica: Optional[int] = None, output=None, fps: float = 5.0,
          colour: Optional[str] = None, arrows: Optional[bool] = None, dpi: Optional[float] = None,
          max_frames: Optional[int] = None, mp4: Optional[bool] = None,
          size: int = FRAME_PIXELS) -> List[Path]:
    """Writes the movie of one replica; returns the files written.

    Frames are ``size`` pixels wide (default 640), or ``dpi`` pixels per inch of the 5-inch frame
    when it is given.

    ``source``: a sweep output directory (then ``replica`` is its index, by default ``pick_replica``)
    or a replica file. ``output``: the file to write (``.gif`` or ``.mp4``); by default
    ``OUT/movies/rKKKKK.gif``, with an ``.mp4`` beside it when ffmpeg is present (``mp4=False`` skips
    it). ``max_frames`` keeps that many snapshots evenly spread (first and last included).
    """
    source = Path(source)
    if source.is_dir():
        k = pick_replica(source) if replica is None else int(replica)
        path = source / "replicas" / f"r{k:05d}.h5"
        default_dir = source / "movies"
    else:
        path, default_dir = source, source.parent
        k = int(path.stem.lstrip("r") or 0) if path.stem.startswith("r") else 0
    snaps = io.read_snapshots(path)
    rep = io.read_replica(path)
    frames = np.arange(len(snaps.step))
    if len(frames) < 2:
        raise ValueError(f"{path}: {len(frames)} snapshot stored; a movie needs two or more "
                         "(set snapshots.every in the spec)")
    if max_frames is not None and len(frames) > max_frames:
        frames = np.unique(np.linspace(0, len(frames) - 1, max(max_frames, 2)).round().astype(int))
    colour = colour or default_colouring(snaps)
    if colour not in COLOURINGS:
        raise ValueError(f"colour = {colour!r}: one of {', '.join(COLOURINGS)}")
    if colour == "spin" and snaps.angular_velocity is None:
        raise ValueError(f"colour = 'spin': {path} holds smooth grains (no angular velocities)")
    arrows = colour != "speed" if arrows is None else arrows
    ratio = _temperature_ratio(rep, snaps.step)
    p = rep.params
    head = f"eps = {p['eps']:g}, N = {p['n']}, phi = {p['phi']:.3g}"
    if snaps.position.shape[2] == 3:
        head += ", slab |z - L/2| < sigma/2"
    top, floor = _gravity_view(snaps, p)
    if floor is not None:
        head = f"S = {p['shake_s']:g}, Gamma = {p['shake_gamma']:g}, N = {p['n']}: {p.get('shaken_state', '')}"

    outputs = [Path(output)] if output else [default_dir / f"r{k:05d}.gif"]
    if not output and (has_ffmpeg() if mp4 is None else mp4):
        outputs.append(default_dir / f"r{k:05d}.mp4")
    for o in outputs:
        if o.suffix not in (".gif", ".mp4"):
            raise ValueError(f"-o {o}: the movie is written as .gif or .mp4")
        if o.suffix == ".mp4" and not has_ffmpeg():
            raise ValueError(f"-o {o}: MP4 needs ffmpeg on the PATH (apt-get install ffmpeg); "
                             "write a .gif instead")

    dpi = dpi if dpi is not None else size / FRAME_INCHES
    fig, ax = plt.subplots(figsize=(FRAME_INCHES, 4.4 if colour in ("speed", "spin") else FRAME_INCHES),
                           layout="constrained")
    _colour_bar(fig, ax, colour)

    def update(j):
        f = frames[j]
        _draw(ax, snaps, f, colour, arrows,
              f"{head}\ntau = {snaps.tau[f]:.1f}   T/T0 = {ratio[f]:.3g}", top, floor)
        return []

    # The layout of the first frame holds for all (the same axes, colour bar and two-line title):
    # laid out once, not per frame, which was half of a movie's time.
    fig.set_dpi(dpi)
    update(0)
    fig.canvas.draw()
    fig.set_layout_engine("none")

    anim = animation.FuncAnimation(fig, update, frames=len(frames), blit=False)
    written = []
    for o in outputs:
        files.ensure_dir(o.parent)
        writer = (animation.PillowWriter(fps=fps) if o.suffix == ".gif"
                  else animation.FFMpegWriter(fps=fps, codec="libx264", extra_args=["-pix_fmt", "yuv420p"]))
        # A fresh temporary name, renamed over o: a planted link at either name is never written through.
        with files.replacing(o) as tmp:
            anim.save(tmp, writer=writer, dpi=dpi)
        written.append(o)
    plt.close(fig)
    return written
