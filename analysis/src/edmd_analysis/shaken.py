"""Beds on a vibrating floor (PHYSICS.md §8.3-8.4): their states in the plane of S and the number of
layers F, their height profiles per state, and the mean flow of the most convective one, from the
uniform-time samples each shaken replica keeps in its file (`/bed`, docs/output.md)."""

import numpy as np
from matplotlib.ticker import NullFormatter

from . import io

# The colours of a shaken bed's states (`parameters/shaken_state`, PHYSICS.md §8.4).
SHAKEN_COLOURS = {"solid": "#444444", "bouncing_bed": "#1f77b4", "undulations": "#17becf",
                  "undetermined": "#bbbbbb", "leidenfrost": "#d62728", "convection": "#2ca02c",
                  "gas": "#ff7f0e"}

# Bins less dense than this fraction of a bed's densest are left out of its temperature and flow.
SPARSE = 0.01

# The states a report shows as movies, where a replica in them has two snapshots or more.
MOVIE_STATES = ("undulations", "leidenfrost", "convection")


def shaken_points(index) -> list:
    """The shaken replicas of an index that finished, as (S, F, Gamma, state, beta): F = N d / W
    the layers of grains of diameter 1 over the floor's width W (the box side times the aspect's
    first side; the first sides' product in 3D, F = N d^2 / area); beta = -1 for smooth grains."""
    out = []
    for i in range(len(index)):
        if not index["shake_s"][i] > 0 or index["status"][i] != "done":
            continue
        dim = int(index["dim"][i])
        aspect = [float(a) for a in str(index["aspect"][i]).split("x")] if index["aspect"][i] else [1.0] * dim
        floor = float(np.prod([index["box_side"][i] * a for a in aspect[:dim - 1]]))
        out.append((float(index["shake_s"][i]), index["n"][i] / floor, float(index["shake_gamma"][i]),
                    str(index["shaken_state"][i]), float(index["beta"][i])))
    return out


def shaken_states(ax, index, beta=None) -> bool:
    """The states of a shaken-bed sweep (of the grains with tangential restitution ``beta`` if
    given), each replica a dot coloured by its state: in the (S, F) plane with one marker per Gamma,
    or in the (S, Gamma) plane where F does not vary (False where there is no finished shaken
    replica)."""
    points = [p for p in shaken_points(index) if beta is None or p[4] == beta]
    if not points:
        return False
    by_gamma = len({p[1] for p in points}) == 1 and len({p[2] for p in points}) > 1
    y, other = (2, 1) if by_gamma else (1, 2)
    markers = dict(zip(sorted({p[other] for p in points}), "osD^v<>"))
    name = "F" if by_gamma else "Gamma"
    for state, colour in SHAKEN_COLOURS.items():
        for value, marker in markers.items():
            mine = [p for p in points if p[3] == state and p[other] == value]
            if mine:
                label = state if len(markers) == 1 else f"{state}, {name}={value:g}"
                ax.scatter([p[0] for p in mine], [p[y] for p in mine], c=colour, marker=marker,
                           s=40, label=label)
    ax.set_xscale("log")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("shaking strength S = A^2 w^2 / (g d)")
    ax.set_ylabel("shaking acceleration Gamma = A w^2 / g" if by_gamma else "layers F = N d / W")
    ax.set_title("states of the shaken bed" + ("" if beta is None else f", beta = {beta:g}"))
    ax.legend(fontsize=8)
    return True


def profiles(axes, reps) -> bool:
    """Two Axes: the time-averaged packing fraction and granular temperature against height, one
    line per replica coloured by its state (False where no replica has uniform-time samples)."""
    reps = [r for r in reps if r.bed and "shaken_state" in r.params]
    if not reps:
        return False
    seen = set()
    for rep in reps:
        state = str(rep.params["shaken_state"])
        label = None if state in seen else state
        seen.add(state)
        colour = SHAKEN_COLOURS.get(state, "k")
        height, packing = rep.bed["height"], rep.bed["packing"]
        axes[0].plot(packing, height, color=colour, lw=1, alpha=0.8, label=label)
        # The temperature where a bin saw enough grains to have one.
        seen_enough = packing >= SPARSE * packing.max()
        axes[1].plot(np.where(seen_enough, rep.bed["temperature"], np.nan), height, color=colour,
                     lw=1, alpha=0.8)
    top = max(_top(r) for r in reps)
    for ax in axes:
        ax.set_ylim(0, top)
        ax.set_ylabel("height z / d")
    axes[0].set_xlabel("packing fraction")
    axes[1].set_xlabel("granular temperature T / (m g d)")
    axes[1].set_xscale("log")
    axes[0].legend(fontsize=8)
    return True


def _top(rep) -> float:
    """The height below which 99.9 % of a bed's grains were seen, plus a margin of 5 %."""
    packing = rep.bed["packing"]
    share = np.cumsum(packing) / max(packing.sum(), 1e-300)
    return 1.05 * float(rep.bed["height"][min(np.searchsorted(share, 0.999), len(share) - 1)])


def most_convective(reps):
    """The replica with the largest convection amplitude (None where none has one)."""
    reps = [r for r in reps if r.bed and np.isfinite(r.params.get("shaken_convection", np.nan))]
    return max(reps, key=lambda r: r.params["shaken_convection"], default=None)


def flow(ax, rep) -> None:
    """The time-averaged vertical velocity of replica ``rep`` over the box (red up, blue down), in
    sqrt(g d), in the rows at least SPARSE as dense as the densest; the colour scale ends at the
    99th percentile of its magnitude."""
    field = rep.bed["vertical_velocity"]
    height, packing = rep.bed["height"], rep.bed["packing"]
    width = float(rep.params["box_sides"][0])
    rows = np.nonzero(packing >= SPARSE * packing.max())[0]
    rows = np.arange(rows.min(), rows.max() + 1)
    shown = np.where(np.isfinite(field[rows]), field[rows], 0.0)
    scale = max(float(np.percentile(np.abs(shown), 99)), 1e-12)
    step = height[1] - height[0]
    image = ax.imshow(shown, origin="lower", aspect="auto", cmap="RdBu_r", vmin=-scale, vmax=scale,
                      extent=(0, width, float(height[rows[0]] - step / 2), float(height[rows[-1]] + step / 2)))
    ax.figure.colorbar(image, ax=ax, label="mean v_z / sqrt(g d)")
    p = rep.params
    ax.set_title(f"S={p['shake_s']:g}, N={int(p['n'])}: {p['shaken_state']}, convection "
                 f"{p['shaken_convection']:.2f} (noise {p['shaken_convection_noise']:.2f}), "
                 f"mode {int(p['shaken_convection_mode'])}", fontsize=9)
    ax.set_xlabel("x / d")
    ax.set_ylabel("height z / d")


def read(index) -> list:
    """The finished shaken replicas of an index, read."""
    return [io.read_replica(index.replica_path(i)) for i in range(len(index))
            if index["shake_s"][i] > 0 and index["status"][i] == "done"]
