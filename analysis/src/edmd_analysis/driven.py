"""Gases heated by white noise (PHYSICS.md §8.1): the steady state of each replica and the figure
of temperature and kurtosis against restitution with the theory written into the files. Beds on a
vibrating floor are in :mod:`edmd_analysis.shaken`."""

import numpy as np

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
