"""Every plotting function draws real data from a generated sweep into an Axes and saves a PNG."""

import json

import matplotlib

matplotlib.use("Agg")
import edmd_analysis as ea  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from edmd_analysis import plots  # noqa: E402


def save(ax, tmp_path, name):
    path = tmp_path / f"{name}.png"
    ax.figure.savefig(path, dpi=60)
    plt.close(ax.figure)
    assert path.stat().st_size > 1000
    return path


@pytest.mark.parametrize("log_tau", [True, False])
def test_cooling_draws_simulation_and_haff(sweep, tmp_path, log_tau):
    rep = ea.read_replica(sweep / "replicas" / "r00000.h5")
    ax = plots.cooling(plt.figure().gca(), rep, log_tau=log_tau)
    lines = ax.get_lines()
    assert len(lines) == 2  # simulation and Haff's law
    sim_y, haff_y = lines[0].get_ydata(), lines[1].get_ydata()
    assert sim_y[-1] < 1 and haff_y[-1] < 1
    # Early on (tau <= 5) the simulation follows Haff's law closely.
    x = lines[0].get_xdata()
    early = x <= 5
    np.testing.assert_allclose(sim_y[early], haff_y[early], rtol=0.1)
    save(ax, tmp_path, f"cooling-{log_tau}")


def test_snapshot_draws_every_disk_and_arrows(sweep, tmp_path):
    snaps = ea.read_snapshots(sweep / "replicas" / "r00000.h5")
    ax = plots.snapshot(plt.figure().gca(), snaps, k=0)
    assert len(ax.collections[0].get_offsets()) == 200
    assert ax.get_xlim() == (0, snaps.box[0])
    save(ax, tmp_path, "snapshot")
    with pytest.raises(ValueError, match="2D"):
        plots.snapshot(plt.figure().gca(), ea.read_snapshots(sweep / "replicas" / "r00004.h5"))


def test_velocity_histograms_split_the_box(sweep, tmp_path):
    snaps = ea.read_snapshots(sweep / "replicas" / "r00001.h5")
    ax = plots.velocity_histograms(plt.figure().gca(), snaps)
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["whole box", "y >= L/2", "y < L/2"]
    save(ax, tmp_path, "histograms")


def test_order_parameters_and_phase_diagram(classified_sweep, tmp_path):
    rep = ea.read_replica(classified_sweep / "replicas" / "r00000.h5")
    ax = plots.order_parameters(plt.figure().gca(), rep)
    assert len(ax.get_lines()) == 5  # four series and the threshold line
    save(ax, tmp_path, "order")
    rows = json.loads((classified_sweep / "phase.json").read_text())
    assert {r["eps"] for r in rows} == {0.9, 0.7}
    ax = plots.phase_diagram(plt.figure().gca(), rows)
    assert ax.get_xlabel() == "L / L_perp"
    save(ax, tmp_path, "phase")
    ax = plots.phase_diagram(plt.figure().gca(), rows, x="phi")
    assert ax.get_xlabel() == "phi"
    plt.close("all")


def test_order_parameters_need_classification(sweep):
    rep = ea.read_replica(sweep / "replicas" / "r00000.h5")
    with pytest.raises(KeyError, match="classify"):
        plots.order_parameters(plt.figure().gca(), rep)
    plt.close("all")
