"""Plots of edmd output. Every function draws into a matplotlib Axes it is given and returns it, so
figures can be composed freely; none reads files (use edmd_analysis.io for that).

Theory curves come from the files: ``haff_temperature``, ``rotational_ratio_theory``, the parameters
``rotational_ratio_sonine`` and ``species_temperature_theory`` and the ``theory`` profile of
``density_profile`` are written by the engine's theory module (docs/PHYSICS.md), and the phase
table's L/L_perp, L/L_par come from ``edmd summarize --format json``.
"""

from __future__ import annotations

from typing import Dict, Optional, Sequence

import numpy as np

# Species colours (a mixture's species in order).
SPECIES_COLOURS = ["#9ecae1", "#fdae6b", "#a1d99b", "#bcbddc", "#fdd0a2", "#c7e9c0"]
SPECIES_EDGES = ["#3182bd", "#e6550d", "#31a354", "#756bb1", "#d94801", "#238b45"]

CLASS_COLOURS = {
    "kinetic": "#2c7bb6",
    "shearing": "#fdae61",
    "clustering": "#d7191c",
    "collapsed": "#555555",
    "stalled": "#8c6d31",
    "failed": "#bbbbbb",
    "homogeneous": "#1a9641",
    "inhomogeneous": "#7b3294",
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


def snapshot_colouring(snaps) -> str:
    """How ``snapshot`` colours grains by default: 'species' for a mixture, 'spin' for rough grains,
    'plain' otherwise."""
    if snaps.species is not None and len(np.unique(snaps.species)) > 1:
        return "species"
    if snaps.angular_velocity is not None:
        return "spin"
    return "plain"


def snapshot(ax, snaps, k: int = -1, arrows: bool = True, max_arrows: int = 4000,
             colour: Optional[str] = None):
    """Disks drawn to scale at snapshot ``k`` (2D), with velocity arrows (figs. 8.2-8.3, 8.7-8.11).

    ``colour``: 'species' (one colour per species of a mixture, with a legend), 'spin' (the angular
    velocity omega of rough disks, blue to red, in units of its rms at that instant, with a colour
    bar), 'plain'; by default what ``snapshot_colouring`` picks. Returns the Axes."""
    from matplotlib.collections import EllipseCollection

    pos = snaps.position[k]
    if pos.shape[1] != 2:
        raise ValueError("snapshot() draws 2D states; project 3D states first")
    colour = colour or snapshot_colouring(snaps)
    d = 2 * snaps.radius
    style = dict(units="xy", offsets=pos, offset_transform=ax.transData, linewidth=0.3)
    if colour == "species":
        sp = np.asarray(snaps.species)
        face = [SPECIES_COLOURS[s % len(SPECIES_COLOURS)] for s in sp]
        edge = [SPECIES_EDGES[s % len(SPECIES_EDGES)] for s in sp]
        ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), facecolor=face, edgecolor=edge,
                                            **style))
        for s in np.unique(sp):
            ax.scatter([], [], c=SPECIES_COLOURS[s % len(SPECIES_COLOURS)],
                       edgecolors=SPECIES_EDGES[s % len(SPECIES_EDGES)],
                       label=f"species {s} (sigma = {d[sp == s][0]:g})")
        ax.legend(loc="upper right", fontsize="x-small", framealpha=0.8)
    elif colour == "spin":
        if snaps.angular_velocity is None:
            raise ValueError("colour='spin' needs rough grains (no angular velocities stored)")
        omega = snaps.angular_velocity[k][:, 0]
        scale = np.sqrt((omega**2).mean()) or 1.0
        coll = EllipseCollection(d, d, np.zeros_like(d), cmap="coolwarm", edgecolor="#444444",
                                 **style)
        coll.set_array(omega / scale)
        coll.set_clim(-2.5, 2.5)
        ax.add_collection(coll)
        ax.figure.colorbar(coll, ax=ax, shrink=0.7, label="omega / rms")
    else:
        ax.add_collection(EllipseCollection(d, d, np.zeros_like(d), facecolor="#9ecae1",
                                            edgecolor="#3182bd", **style))
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


def _ratio_axes(ax, ylabel: str):
    """A ratio against tau: linear up to tau = 1 (the transient), logarithmic beyond."""
    ax.set_xscale("symlog", linthresh=1.0)
    ax.set_xlim(left=0)
    ax.set_xlabel("tau")
    ax.set_ylabel(ylabel)
    ax.legend(frameon=False, fontsize="small")
    return ax


def rotational_ratio(ax, rep):
    """T_rot/T_tr of rough grains against tau, with the two-temperature theory from the same start
    (Maxwellian, transient included) and the stationary ratio of its Sonine correction (PHYSICS.md
    6.6-6.7)."""
    obs = rep.observables
    if "rotational_temperature" not in obs:
        raise KeyError(f"{rep.path}: no rotational temperature (smooth grains)")
    tau = obs["tau"]
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = obs["rotational_temperature"] / obs["temperature"]
    ax.plot(tau, ratio, label="simulation")
    if "rotational_ratio_theory" in obs:
        ax.plot(tau, obs["rotational_ratio_theory"], "k--", lw=1, label="two-temperature (Maxwellian)")
    sonine = rep.params.get("rotational_ratio_sonine")
    if sonine is not None and np.isfinite(sonine):
        ax.axhline(sonine, color="k", ls=":", lw=1, label=f"Sonine stationary {sonine:.3f}")
    return _ratio_axes(ax, "T_rot / T_tr")


def species_temperatures(ax, rep):
    """Each species' temperature over the last species' against tau, with Garzo and Dufty's
    homogeneous-cooling ratios (parameters/species_temperature_theory, Maxwellian with Enskog chi_ij;
    PHYSICS.md 2.4) as dashed lines. They hold while the gas is homogeneous; clusters part the
    species further."""
    obs = rep.observables
    if "species_temperature" not in obs:
        raise KeyError(f"{rep.path}: no species temperatures (one species)")
    tau, ts = obs["tau"], np.asarray(obs["species_temperature"])
    theory = np.asarray(rep.params.get("species_temperature_theory", []), dtype=float)
    ref = ts.shape[1] - 1
    for k in range(ref):
        line, = ax.plot(tau, ts[:, k] / ts[:, ref], label=f"T_{k} / T_{ref}")
        if theory.size == ts.shape[1] and np.isfinite(theory).all():
            ax.axhline(theory[k] / theory[ref], color=line.get_color(), ls="--", lw=1,
                       label=f"Garzo-Dufty {theory[k] / theory[ref]:.3f}")
    return _ratio_axes(ax, "temperature ratio")


def density_profile(ax, rep, last: float = 0.5):
    """The number density along the gravity axis, averaged over the last ``last`` of the samples,
    with the barometric profile (hydrostatic, local Enskog; PHYSICS.md 1.4) where the file has it
    (elastic columns)."""
    obs = rep.observables
    if "density_profile" not in obs:
        raise KeyError(f"{rep.path}: no density profile (no gravity)")
    prof = np.asarray(obs["density_profile"])
    z = rep.profile_position
    mean = prof[int(len(prof) * (1 - last)):].mean(axis=0)
    ax.plot(z, mean, "o", ms=3, label=f"simulation (last {100 * last:.0f} % of samples)")
    if rep.profile_theory is not None:
        ax.plot(z, rep.profile_theory, "k--", lw=1,
                label=f"barometric, T = {rep.profile_theory_temperature:.3g}")
    ax.set_yscale("log")
    ax.set_xlabel("height")
    ax.set_ylabel("number density")
    ax.legend(frameon=False, fontsize="small")
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
        if len(data) == 0:  # a settled column leaves its upper half empty
            continue
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


def _pie(ax, x, y, fractions, classes, size):
    """A pie of class fractions at (x, y), one wedge per class in CLASS_COLOURS."""
    start = 0.0
    for c, f in zip(classes, fractions / fractions.sum()):
        if f <= 0:
            continue
        theta = np.linspace(2 * np.pi * start, 2 * np.pi * (start + f), 16)
        verts = np.column_stack([np.r_[0, np.cos(theta)], np.r_[0, np.sin(theta)]])
        ax.scatter([x], [y], marker=verts, s=size, c=CLASS_COLOURS[c], linewidths=0)
        start += f


def phase_diagram(ax, rows: Sequence[dict], x: str = "l_over_l_perp", size: float = 120.0,
                  y: str = "eps"):
    """The phase diagram from the phase table (``edmd summarize --format json``): ``y`` ('eps',
    'beta' or 'species') against ``x`` ('l_over_l_perp', 'phi', 'n', 'box_side' or 'shear_rate'), each point a pie
    of its class fractions, with the theory boundaries L = L_perp and L = L_par drawn when x is
    L/L_perp and y is eps. Rows without class fractions (not_applicable scenes) are left out. A
    sheared sweep's rows carry the classes homogeneous and inhomogeneous instead (no theory lines)."""
    classes = ["kinetic", "shearing", "clustering"]
    if any(r.get("homogeneous") is not None for r in rows):
        classes = ["homogeneous", "inhomogeneous"]
    rows = [r for r in rows if any(r.get(c) is not None for c in classes)]
    labels = sorted({str(r[y]) for r in rows}) if rows and isinstance(rows[0][y], str) else None

    def y_of(row):
        return labels.index(str(row[y])) if labels is not None else row[y]

    if x == "shear_rate":
        rows = [dict(r, shear_rate=r.get("shear_rate", 0.0)) for r in rows]
    for row in rows:
        fractions = np.array([row.get(c) or 0.0 for c in classes])
        if not np.isfinite(fractions).all() or fractions.sum() == 0:
            ax.scatter([row[x]], [y_of(row)], s=size / 4, c="#bbbbbb", marker="x")
            continue
        _pie(ax, row[x], y_of(row), fractions, classes, size)
    if x == "l_over_l_perp" and classes[0] == "kinetic":
        if y == "eps":
            ax.axvline(1.0, color="k", lw=1, ls="--", label="L = L_perp")
            ratio = [r["l_over_l_perp"] / r["l_over_l_par"] for r in rows if r["l_over_l_par"] > 0]
            eps = [r["eps"] for r in rows if r["l_over_l_par"] > 0]
            if ratio:
                order = np.argsort(eps)
                ax.plot(np.array(ratio)[order], np.array(eps)[order], "k:", lw=1, label="L = L_par")
        ax.set_xscale("log")
    if labels is not None:
        ax.set_yticks(range(len(labels)), labels, fontsize="x-small")
        ax.set_ylim(-0.5, len(labels) - 0.5)
    for c in classes:
        ax.scatter([], [], c=CLASS_COLOURS[c], label=c)
    if x in ("box_side", "n", "shear_rate") and rows and min(r[x] for r in rows) > 0 \
            and max(r[x] for r in rows) > 4 * min(r[x] for r in rows):
        ax.set_xscale("log")
    ax.set_xlabel({"l_over_l_perp": "L / L_perp", "phi": "phi", "n": "N", "box_side": "L",
                   "shear_rate": "shear rate a"}.get(x, x))
    ax.set_ylabel(y)
    ax.legend(frameon=False, fontsize="small")
    return ax


# A refinement axis (boundary.json) and the phase table's column of the same quantity.
REFINE_COLUMNS = {"eps": "eps", "box": "box_side", "phi": "phi", "n": "n", "beta": "beta"}


def boundary_axes(rows: Sequence[dict], boundary: dict):
    """The axes (x, y) of a refined phase diagram: eps upwards when it is refined or varies, the
    other refined axis across (else the box, N or phi, whichever varies)."""
    axes = list(boundary["axes"])
    y = "eps" if "eps" in axes or len({r["eps"] for r in rows}) > 1 else axes[0]
    x = next((a for a in axes if a != y), None)
    if x is None:
        x = next((a for a in ("box", "n", "phi") if len({r[REFINE_COLUMNS[a]] for r in rows}) > 1), "box")
    return x, y


def boundary_diagram(ax, rows: Sequence[dict], boundary: dict, refined=(), size: float = 110.0):
    """A refined phase diagram (``edmd refine``): every point of the phase table as a pie of its
    classes (the points the refinement added smaller; ``refined`` holds their (x, y) values), each
    regime change of ``boundary`` (OUT/boundary.json) as its estimate with the bracketing pair as
    error bar, and, when the plane is (box, eps) of a periodic box, the linear theory's lines
    L = L_perp and L = L_par (the classifier's theory, PHYSICS.md 3). The title counts the replicas
    against the full grid of the same resolution."""
    x, y = boundary_axes(rows, boundary)
    xc, yc = REFINE_COLUMNS[x], REFINE_COLUMNS[y]
    classes = ["kinetic", "shearing", "clustering"]
    if any(r.get("homogeneous") is not None for r in rows):
        classes = ["homogeneous", "inhomogeneous"]
    refined = {(float(a), float(b)) for a, b in refined}
    for row in rows:
        fractions = np.array([row.get(c) or 0.0 for c in classes])
        if not np.isfinite(fractions).all() or fractions.sum() == 0:
            continue
        s = size * (0.4 if (float(row[xc]), float(row[yc])) in refined else 1.0)
        _pie(ax, row[xc], row[yc], fractions, classes, s)
    pairs = sorted({tuple(c["regimes"]) for c in boundary["crossings"]})
    markers = "oDs^v"
    for k, pair in enumerate(pairs):
        label = f"boundary {pair[0]} | {pair[1]}"
        for c in boundary["crossings"]:
            if tuple(c["regimes"]) != pair:
                continue
            if c["axis"] == y and x in c["line"]:
                px, py = float(c["line"][x]), c["at"]
                err = dict(yerr=[[c["at"] - c["lower"]], [c["upper"] - c["at"]]])
            elif c["axis"] == x and y in c["line"]:
                px, py = c["at"], float(c["line"][y])
                err = dict(xerr=[[c["at"] - c["lower"]], [c["upper"] - c["at"]]])
            else:
                continue
            ax.errorbar([px], [py], fmt=markers[k % len(markers)], ms=4, color="k", mfc="w",
                        capsize=2, lw=0.8, label=label, **err)
            label = None
    if (x, y) == ("box", "eps") and all(r["boundary"] == "periodic" for r in rows):
        lo, hi = min(r["box_side"] for r in rows), max(r["box_side"] for r in rows)
        for key, style, name in (("l_over_l_perp", "--", "L = L_perp (theory)"),
                                 ("l_over_l_par", ":", "L = L_par (theory)")):
            by_eps = {}
            for r in rows:
                if r.get(key) and r[key] > 0:
                    by_eps.setdefault(r["eps"], []).append(r["box_side"] / r[key])
            eps = sorted(e for e in by_eps if lo / 2 <= np.median(by_eps[e]) <= 2 * hi)
            if eps:
                ax.plot([np.median(by_eps[e]) for e in eps], eps, "k" + style, lw=1, label=name)
        ax.set_xlim(lo / 1.15, hi * 1.15)
    if x in ("box", "n"):
        from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

        ax.set_xscale("log")
        ax.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
    for c in classes:
        ax.scatter([], [], c=CLASS_COLOURS[c], label=c)
    full = boundary["full_grid_replicas"]
    ax.set_title(f"{boundary['replicas']} replicas ({boundary['refinement_replicas']} added in "
                 f"{boundary['rounds']} rounds); the full grid of this resolution: {full} "
                 f"({100 * boundary['replicas'] / max(full, 1):.0f} %)", fontsize="small")
    ax.set_xlabel({"box": "L (diameters)", "n": "N", "phi": "phi", "eps": "eps", "beta": "beta"}[x])
    ax.set_ylabel(y)
    ax.legend(frameon=False, fontsize="x-small", loc="best")
    return ax


def steady_shear(rep, last: float = 0.5) -> dict:
    """The steady state of a sheared replica (Lees-Edwards), averaged over the last ``last`` of its
    samples: temperature ``t``, reduced pressure tensor ``p_star`` (D x D, P/(nT)), reduced shear
    rate ``a_star`` = a/nu0(T) and viscosity ``eta_star`` = -P*_xy/a*, and the theory's values
    (``*_theory``: the Enskog gas with the anisotropic-Gaussian closure, PHYSICS.md 7.2; NaN where
    it does not apply). nu0 is the one of the theory, recovered from the file's theory temperature:
    nu0(T) = a / (a*_th sqrt(T_th/T))."""
    obs, p = rep.observables, rep.params
    if "pressure_tensor" not in obs:
        raise KeyError(f"{rep.path}: no pressure tensor (not a sheared replica)")
    start = int(len(rep.step) * (1 - last))
    tensor = np.asarray(obs["pressure_tensor"])[start:]
    tensor = tensor[np.all(np.isfinite(tensor), axis=(1, 2))]
    t = float(np.mean(obs["temperature"][start:]))
    volume = float(np.prod(p["box_sides"]))
    density = float(p["n"]) / volume
    p_star = tensor.mean(axis=0) / (density * t)
    a = float(p["shear_rate"])
    a_th, t_th = float(p["shear_theory_reduced_rate"]), float(p["shear_theory_temperature"])
    a_star = a_th * np.sqrt(t_th / t) if np.isfinite(a_th) else np.nan
    return {
        "eps": float(p["eps"]), "dim": int(p["dim"]), "shear_rate": a, "t": t, "p_star": p_star,
        "a_star": a_star, "eta_star": -p_star[0, 1] / a_star if a_star else np.nan,
        "a_star_theory": a_th, "eta_star_theory": float(p["shear_theory_viscosity"]),
        "pxx_theory": float(p["shear_theory_pxx"]), "pyy_theory": float(p["shear_theory_pyy"]),
        "pzz_theory": float(p.get("shear_theory_pzz", p["shear_theory_pyy"])),
    }


def shear_rheology(axes, reps, last: float = 0.5):
    """The steady sheared gas against restitution, one row of ``axes`` (three Axes: a*, eta*,
    normal stresses) per dimension present: simulation (points, the mean of the replicas of one
    eps) against kinetic theory (lines: the Enskog gas with the anisotropic-Gaussian closure,
    PHYSICS.md 7.2)."""
    states = [steady_shear(r, last) for r in reps]
    dims = sorted({s["dim"] for s in states})
    axes = np.atleast_2d(axes)
    for row, dim in zip(axes, dims):
        mine = [s for s in states if s["dim"] == dim]
        eps = sorted({s["eps"] for s in mine})

        def mean(key, i=None, j=None, mine=mine, eps=eps):
            out = []
            for e in eps:
                vals = [s[key] if i is None else s[key][i, j] for s in mine if s["eps"] == e]
                out.append(np.mean(vals))
            return np.array(out)

        for ax, key, label in ((row[0], "a_star", "a* = a / nu0"), (row[1], "eta_star", "eta* = -P*_xy / a*")):
            ax.plot(eps, mean(key), "o", label="simulation")
            ax.plot(eps, mean(key + "_theory"), "k--", lw=1, label="kinetic theory")
            ax.set_ylabel(label)
        names = "xyz"
        for i in range(dim):
            line, = row[2].plot(eps, mean("p_star", i, i), "o", label=f"P*_{names[i]}{names[i]}")
            th = mean(("pxx_theory", "pyy_theory", "pzz_theory")[i])
            row[2].plot(eps, th, "--", lw=1, color=line.get_color())
        row[2].set_ylabel("P_ii / (n T)")
        for ax in row:
            ax.set_xlabel("restitution eps")
            ax.set_title(f"{dim}D", fontsize="small")
            ax.legend(frameon=False, fontsize="small")
    return axes


def stream_profile(ax, rep, last: float = 0.5):
    """The stream velocity u_x(y) of a sheared replica, averaged over the last ``last`` of its samples,
    against the imposed flow a (y - L_y/2); on a second axis the density along y over its mean (flat
    in a homogeneous flow, banded otherwise)."""
    obs = rep.observables
    if "velocity_profile" not in obs:
        raise KeyError(f"{rep.path}: no velocity profile (not a sheared replica)")
    start = int(len(rep.step) * (1 - last))
    u = np.nanmean(np.asarray(obs["velocity_profile"])[start:], axis=0)
    rho = np.asarray(obs["density_profile_y"])[start:].mean(axis=0)
    y = rep.positions["velocity_profile"]
    a, ly = float(rep.params["shear_rate"]), float(rep.params["box_sides"][1])
    ax.plot(y, u, "o", ms=3, label="simulation")
    ax.plot(y, a * (y - ly / 2), "k--", lw=1, label="a (y - L_y/2)")
    ax.set_xlabel("y")
    ax.set_ylabel("u_x")
    twin = ax.twinx()
    twin.plot(y, rho / rho.mean(), color="#d95f0e", lw=1, label="density / mean")
    twin.set_ylabel("n(y) / mean", color="#d95f0e")
    ax.legend(frameon=False, fontsize="small", loc="upper left")
    return ax
