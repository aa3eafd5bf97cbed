"""Driven gases: gases heated by white noise (PHYSICS.md §8.1), the steady state of each replica
and the figure of temperature and kurtosis against restitution with the theory written into the
files; beds on a vibrating floor (§8.4), their states in the plane of S and the number of layers F."""

import numpy as np
from matplotlib.ticker import NullFormatter

from . import io


def steady_white_noise(rep: io.Replica, last: float = 0.5) -> dict:
    """The time average over the last fraction ``last`` of a white-noise replica's samples: T/T_s
    and the speed kurtosis, with the theory's kurtosis (d+2)/d (1 + a2)."""
    p = rep.params
    d, t_s, a2 = int(p["dim"]), float(p["white_noise_theory_temperature"]), float(p["white_noise_theory_a2"])
    t = rep.observables["temperature"]
    k = rep.observables["kurtosis"]
    start = int(len(t) * (1 - last))
    return {"dim": d, "eps": float(p["eps"]), "t_ratio": float(np.mean(t[start:]) / t_s),
            "kurtosis": float(np.mean(k[start:])), "kurtosis_theory": (d + 2) / d * (1 + a2)}


def white_noise_steady_state(axes, reps, last: float = 0.5):
    """Two Axes: T/T_s against eps (the theory is 1), and the speed kurtosis against eps with the
    theory's (d+2)/d (1 + a2) of van Noije & Ernst; one series per dimension, the mean of the
    replicas of one eps."""
    states = [steady_white_noise(r, last) for r in reps]
    for dim in sorted({s["dim"] for s in states}):
        mine = [s for s in states if s["dim"] == dim]
        eps = sorted({s["eps"] for s in mine})

        def mean(key, mine=mine, eps=eps):
            return np.array([np.mean([s[key] for s in mine if s["eps"] == e]) for e in eps])

        axes[0].plot(eps, mean("t_ratio"), "o", label=f"{dim}D")
        line, = axes[1].plot(eps, mean("kurtosis"), "o", label=f"{dim}D simulation")
        axes[1].plot(eps, mean("kurtosis_theory"), "--", lw=1, color=line.get_color(), label=f"{dim}D theory")
    axes[0].axhline(1.0, color="k", lw=1, ls="--", label="theory")
    axes[0].set_ylabel("T / T_s")
    axes[1].set_ylabel("speed kurtosis <v^4>/<v^2>^2")
    for ax in axes:
        ax.set_xlabel("restitution eps")
        ax.legend(fontsize="small")


# The colours of a shaken bed's states (`parameters/shaken_state`, PHYSICS.md §8.4).
SHAKEN_COLOURS = {"solid": "#444444", "bouncing_bed": "#1f77b4", "undetermined": "#bbbbbb",
                  "leidenfrost": "#d62728", "gas": "#ff7f0e"}


def shaken_points(index) -> list:
    """The shaken replicas of an index that finished, as (S, F, Gamma, state): F = N d / W the
    layers of grains of diameter 1 over the floor's width W (the box side times the aspect's first
    side; the first sides' product in 3D, F = N d^2 / area)."""
    out = []
    for i in range(len(index)):
        if not index["shake_s"][i] > 0 or index["status"][i] != "done":
            continue
        dim = int(index["dim"][i])
        aspect = [float(a) for a in str(index["aspect"][i]).split("x")] if index["aspect"][i] else [1.0] * dim
        floor = float(np.prod([index["box_side"][i] * a for a in aspect[:dim - 1]]))
        out.append((float(index["shake_s"][i]), index["n"][i] / floor,
                    float(index["shake_gamma"][i]), str(index["shaken_state"][i])))
    return out


def shaken_states(ax, index) -> bool:
    """The (S, F) plane of a shaken-bed sweep, each replica a dot coloured by its state, one marker
    per Gamma (False where the index holds no finished shaken replica)."""
    points = shaken_points(index)
    if not points:
        return False
    markers = dict(zip(sorted({p[2] for p in points}), "osD^v<>"))
    for state, colour in SHAKEN_COLOURS.items():
        for gamma, marker in markers.items():
            mine = [p for p in points if p[3] == state and p[2] == gamma]
            if mine:
                label = state if len(markers) == 1 else f"{state}, Gamma={gamma:g}"
                ax.scatter([p[0] for p in mine], [p[1] for p in mine], c=colour, marker=marker,
                           s=40, label=label)
    ax.set_xscale("log")
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("shaking strength S = A^2 w^2 / (g d)")
    ax.set_ylabel("layers F = N d / W")
    ax.set_title("states of the shaken bed")
    ax.legend(fontsize=8)
    return True
