"""Plots of edmd output. Every function draws into a matplotlib Axes it is given and returns it, so
figures can be composed freely; none reads files (use edmd_analysis.io for that).

Theory curves come from the files: ``haff_temperature`` is written by the engine's theory module, and
the phase table's L/L_perp, L/L_par come from ``edmd summarize --format json``.
"""

from __future__ import annotations

from typing import Dict, Optional, Sequence

import numpy as np

CLASS_COLOURS = {
    "kinetic": "#2c7bb6",
    "shearing": "#fdae61",
    "clustering": "#d7191c",
    "collapsed": "#555555",
    "failed": "#bbbbbb",
}


def cooling(ax, rep, log_tau: bool = True, label: Optional[str] = None):
    """T/T0 against tau, with Haff's law (first Sonine order) when the file carries it.

    ``log_tau`` chooses the thesis's log-log form (figs. 7.1-7.4) or the semi-log form (fig. 8.1).
    The temperature is taken from ln T, so it stays finite however deep the cooling.
    """
    tau = rep.observables["tau"]
    ln_t = rep.observables["ln_temperature"]
    ratio = np.exp(ln_t - ln_t[0])
    keep = tau > 0 if log_tau else np.ones_like(tau, dtype=bool)
    ax.plot(tau[keep], ratio[keep], label=label or f"simulation, eps = {rep.params['eps']}")
    haff = rep.observables.get("haff_temperature")
    if haff is not None and np.isfinite(haff).any():
        ax.plot(tau[keep], haff[keep] / haff[0], "k--", lw=1, label="Haff's law")
    ax.set_yscale("log")
    # Haff's law may fall far below a gas that left it: keep the simulation in view.
    ax.set_ylim(bottom=max(ratio[keep].min() * 1e-2, 1e-300), top=2.0)
    if log_tau:
        ax.set_xscale("log")
    ax.set_xlabel("tau = collisions per particle")
    ax.set_ylabel("T / T0")
    ax.legend(frameon=False)
    return ax


def snapshot(ax, snaps, k: int = -1, arrows: bool = True, max_arrows: int = 4000):
    """Disks drawn to scale at snapshot ``k`` (2D), with velocity arrows (figs. 8.2-8.3, 8.7-8.11)."""
    from matplotlib.collections import EllipseCollection

    pos = snaps.position[k]
    if pos.shape[1] != 2:
        raise ValueError("snapshot() draws 2D states; project 3D states first")
    d = 2 * snaps.radius
    coll = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=pos,
                             offset_transform=ax.transData, facecolor="#9ecae1",
                             edgecolor="#3182bd", linewidth=0.3)
    ax.add_collection(coll)
    if arrows:
        vel = snaps.velocity[k]
        idx = np.arange(len(pos))[:max_arrows]
        scale = np.sqrt((vel**2).sum(axis=1).mean()) or 1.0
        ax.quiver(pos[idx, 0], pos[idx, 1], vel[idx, 0] / scale, vel[idx, 1] / scale,
                  angles="xy", scale_units="xy", scale=0.5, width=0.002, color="k")
    ax.set_xlim(0, snaps.box[0])
    ax.set_ylim(0, snaps.box[1])
    ax.set_aspect("equal")
    ax.set_title(f"tau = {snaps.tau[k]:.1f}")
    return ax


def velocity_histograms(ax, snaps, k: int = -1, component: int = 0, split_axis: int = 1, bins: int = 40):
    """Histograms of one velocity component over the whole box and over the two half-boxes split
    along ``split_axis`` (figs. 8.4-8.5, 8.12-8.13: v_x for y above and below the middle). A shear
    band shows as two shifted half-box histograms."""
    vel = snaps.velocity[k][:, component]
    pos = snaps.position[k][:, split_axis]
    mid = snaps.box[split_axis] / 2
    scale = np.sqrt((vel**2).mean()) or 1.0
    edges = np.linspace(-4, 4, bins + 1)
    names = "xyz"
    for data, label in ((vel, "whole box"), (vel[pos >= mid], f"{names[split_axis]} >= L/2"),
                        (vel[pos < mid], f"{names[split_axis]} < L/2")):
        ax.hist(data / scale, bins=edges, histtype="step", density=True, label=label)
    ax.set_xlabel(f"v_{names[component]} / rms")
    ax.set_ylabel("probability density")
    ax.legend(frameon=False)
    return ax


def order_parameters(ax, rep, thresholds: Optional[Dict[str, float]] = None):
    """Order parameters against tau (log scale) with their classification thresholds."""
    obs = rep.observables
    if "s_perp" not in obs:
        raise KeyError(f"{rep.path}: no order parameters (run the spec with a 'classify' section)")
    th = {"shear_s_perp": 20.0, "cluster_density": 0.15, "haff": 0.1}
    th.update(thresholds or {})
    tau = obs["tau"]
    d2 = obs["delta_rho2"] - obs["delta_rho2"][0]
    series = [("S_perp(k1) / 20", obs["s_perp"] / th["shear_s_perp"]),
              ("(delta rho^2 - initial) / 0.15", d2 / th["cluster_density"]),
              ("Delta H / 0.1", obs["haff_deviation"] / th["haff"]),
              ("f_flow / 0.1", obs["f_flow"] / 0.1)]
    for label, y in series:
        ax.plot(tau, y, label=label)
    ax.axhline(1.0, color="k", lw=0.8, ls=":")
    ax.set_yscale("symlog", linthresh=0.1)
    ax.set_xlabel("tau")
    ax.set_ylabel("order parameter / threshold")
    ax.legend(frameon=False, fontsize="small")
    return ax


def phase_diagram(ax, rows: Sequence[dict], x: str = "l_over_l_perp", size: float = 120.0):
    """The phase diagram from the phase table (``edmd summarize --format json``): eps against ``x``
    ('l_over_l_perp', 'phi', 'n' or 'box_side'), each point a pie of its class fractions, with the
    theory boundaries L = L_perp and L = L_par drawn when x is L/L_perp."""
    classes = ["kinetic", "shearing", "clustering"]
    for row in rows:
        fractions = np.array([row.get(c) or 0.0 for c in classes])
        if not np.isfinite(fractions).all() or fractions.sum() == 0:
            ax.scatter([row[x]], [row["eps"]], s=size / 4, c="#bbbbbb", marker="x")
            continue
        start = 0.0
        for c, f in zip(classes, fractions / fractions.sum()):
            if f <= 0:
                continue
            theta = np.linspace(2 * np.pi * start, 2 * np.pi * (start + f), 16)
            verts = np.column_stack([np.r_[0, np.cos(theta)], np.r_[0, np.sin(theta)]])
            ax.scatter([row[x]], [row["eps"]], marker=verts, s=size, c=CLASS_COLOURS[c], linewidths=0)
            start += f
    if x == "l_over_l_perp":
        ax.axvline(1.0, color="k", lw=1, ls="--", label="L = L_perp")
        ratio = [r["l_over_l_perp"] / r["l_over_l_par"] for r in rows if r["l_over_l_par"] > 0]
        eps = [r["eps"] for r in rows if r["l_over_l_par"] > 0]
        if ratio:
            order = np.argsort(eps)
            ax.plot(np.array(ratio)[order], np.array(eps)[order], "k:", lw=1, label="L = L_par")
        ax.set_xscale("log")
    for c in classes:
        ax.scatter([], [], c=CLASS_COLOURS[c], label=c)
    ax.set_xlabel({"l_over_l_perp": "L / L_perp", "phi": "phi", "n": "N", "box_side": "L"}.get(x, x))
    ax.set_ylabel("eps")
    ax.legend(frameon=False, fontsize="small")
    return ax
