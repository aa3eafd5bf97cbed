"""`edmd refine` against the dense grid it saves: on the (eps, box) plane of disks at phi = 0.25, a
3 x 3 start refined twice finds, on every line of the start grid, the regime changes the 9 x 9 grid of
the same resolution shows, within one of its spacings, with at most 40 % of its replicas. The dense
grid's boundary is derived here from its own phase table. Both sweeps run the same replicas where
their points coincide (a replica's seed depends on its parameters, not its number), so the test
checks the bisection, not the noise of the classifier; 3 seeds per point make the labels of the
dense grid monotone along every line (with 1 seed the lines L = 28 and 33.3 flip between shearing
and clustering). Boxes of 14-56 diameters (N = 62-998) hold both boundaries, kinetic-shearing and
shearing-clustering, at a third less CPU time than 20-80. Also: boundary.json and the refined phase
table read as DataFrames, and the report draws the boundary (rendered in headless Chromium where
installed)."""

import json
import math
import re
import subprocess

import pytest
from conftest import run_edmd
from edmd_analysis import read_boundary, read_boundary_frame, read_phase_table
from edmd_analysis import report as report_module

START_EPS = [0.6, 0.8, 1.0]
START_BOX = [14.0, 28.0, 56.0]
ROUNDS = 2
CLASSES = ("kinetic", "shearing", "clustering")


def spec(name, eps, box):
    return {
        "name": name,
        "seed": 7,
        "grid": {"dim": 2, "boundary": "periodic", "eps": eps, "phi": 0.25, "box": box, "seeds": 3},
        "stop": {"tau_max": 800, "classified": True},
        "samples": {"every": 10, "per_decade": 10, "log_from": 0.1},
        "snapshots": {"final": True},
        "classify": {},
    }


def tidy(x):
    """Ten significant digits, as edmd rounds its midpoints."""
    return float(f"{x:.9e}")


def bisect(values, rounds, log):
    for _ in range(rounds):
        out = []
        for a, b in zip(values, values[1:]):
            out += [a, tidy(math.sqrt(a * b)) if log else tidy((a + b) / 2)]
        values = out + [values[-1]]
    return values


DENSE_EPS = bisect(START_EPS, ROUNDS, log=False)
DENSE_BOX = bisect(START_BOX, ROUNDS, log=True)
# One dense spacing: 0.05 in eps, a factor 2**(1/4) in the box side.
EPS_STEP = DENSE_EPS[1] - DENSE_EPS[0]
LOG_BOX_STEP = math.log(DENSE_BOX[1] / DENSE_BOX[0])


@pytest.fixture(scope="module")
def sweeps(tmp_path_factory):
    d = tmp_path_factory.mktemp("refine")
    for name, eps, box in (("coarse", START_EPS, START_BOX), ("dense", DENSE_EPS, DENSE_BOX)):
        (d / f"{name}.json").write_text(json.dumps(spec(name, eps, box)))
        run_edmd("run", d / f"{name}.json", "-o", d / name, "-q")
    run_edmd("refine", d / "coarse", "--rounds", ROUNDS, "--axes", "eps,box", "-q")
    return d / "coarse", d / "dense"


def labels(out):
    """(box, eps) -> the majority class of the point, from the phase table."""
    table = {}
    for row in json.loads((out / "phase.json").read_text()):
        fractions = {c: row[c] for c in CLASSES}
        table[(row["box_side"], row["eps"])] = max(fractions, key=fractions.get)
    return table


def crossings(table, axis, fixed):
    """The label changes along one line of `table`: (lower, upper, below, above)."""
    if axis == "eps":
        points = sorted((e, c) for (b, e), c in table.items() if b == fixed)
    else:
        points = sorted((b, c) for (b, e), c in table.items() if e == fixed)
    return [(p, q, cp, cq) for (p, cp), (q, cq) in zip(points, points[1:]) if cp != cq]


def distance(axis, a, b):
    """|a - b| in dense spacings."""
    if axis == "eps":
        return abs(a - b) / EPS_STEP
    return abs(math.log(a / b)) / LOG_BOX_STEP


def midpoint(axis, lower, upper):
    return (lower + upper) / 2 if axis == "eps" else math.sqrt(lower * upper)


def test_refined_boundary_matches_the_dense_grid(sweeps):
    coarse, dense = sweeps
    dense_labels, refined_labels = labels(dense), labels(coarse)
    boundary = read_boundary(coarse)
    dense_replicas = len(DENSE_EPS) * len(DENSE_BOX) * 3
    # Cost: at most 40 % of the dense grid, and the file's count is what ran.
    assert boundary["full_grid_replicas"] == dense_replicas
    assert boundary["replicas"] == len(list((coarse / "replicas").glob("*.h5")))
    assert boundary["replicas"] <= 0.4 * dense_replicas, boundary["replicas"]
    assert boundary["rounds"] == ROUNDS
    # Every refined point is a point of the dense grid, with the same label (same replicas).
    for key, label in refined_labels.items():
        assert key in dense_labels, f"refined point {key} is not on the dense grid"
        assert dense_labels[key] == label, key
    # On every line of the start grid, the regime changes of the dense grid, found.
    lines = [("eps", b) for b in START_BOX] + [("box", e) for e in START_EPS]
    found_any = 0
    for axis, fixed in lines:
        other = "box" if axis == "eps" else "eps"
        want = crossings(dense_labels, axis, fixed)
        got = [c for c in boundary["crossings"] if c["axis"] == axis and c["line"][other] == fixed]
        assert len(got) == len(want), f"{axis} at {other} = {fixed}: {got} vs dense {want}"
        for c, (lo, hi, below, above) in zip(got, want):
            assert (c["below"], c["above"]) == (below, above), (axis, fixed, c)
            assert distance(axis, c["at"], midpoint(axis, lo, hi)) <= 1.0, (axis, fixed, c, lo, hi)
            found_any += 1
    assert found_any >= 6, "the plane should hold both boundaries on several lines"
    # Every crossing the refinement reports (also on the coarser lines it opened) brackets a
    # change of the dense grid on the same line.
    for c in boundary["crossings"]:
        other = "box" if c["axis"] == "eps" else "eps"
        dense_line = crossings(dense_labels, c["axis"], c["line"][other])
        assert any(c["lower"] <= lo and hi <= c["upper"] for lo, hi, _, _ in dense_line), c


def test_boundary_and_refined_table_read_as_frames(sweeps):
    coarse, _ = sweeps
    frame = read_boundary_frame(coarse)
    boundary = read_boundary(coarse)
    assert len(frame) == len(boundary["crossings"])
    assert set(frame["axis"]) == {"eps", "box"}
    assert (frame["half_width"] > 0).all() and (frame["lower"] < frame["upper"]).all()
    assert {"regime_a", "regime_b", "below", "above", "at", "box", "eps"} <= set(frame.columns)
    table = read_phase_table(coarse)
    assert len(table) == boundary["replicas"] // 3
    spec_json = json.loads((coarse / "spec.json").read_text())
    assert len(spec_json["refinement"]["rounds"]) == ROUNDS


def test_report_draws_the_boundary(sweeps, tmp_path):
    coarse, _ = sweeps
    # The boundary is drawn from the whole phase table; two points' panels keep the page short.
    page = report_module.report(coarse, tmp_path / "rep", max_points=2, movies=False)
    text = page.read_text()
    assert 'src="phase-boundary.png"' in text
    assert report_module.title("phase-boundary.png") == "Phase boundary found by refinement"
    assert (page.parent / "phase-boundary.png").stat().st_size > 10_000


def test_boundary_figure_loads_in_chromium(sweeps, tmp_path):
    from test_report_page import browser

    exe = browser()
    coarse, _ = sweeps
    page = report_module.report(coarse, tmp_path / "rep", max_points=2, movies=False)
    text = page.read_text()
    probe = page.with_name("probe.html")
    probe.write_text(text.replace("</body>", """<script>window.addEventListener('load', () => {
      const i = document.querySelector('img[src="phase-boundary.png"]');
      document.body.setAttribute('data-probe', i.naturalWidth + 'x' + i.naturalHeight); });
      </script></body>"""))
    dom = subprocess.run([exe, "--headless", "--no-sandbox", "--disable-gpu", "--window-size=1280,900",
                          "--virtual-time-budget=10000", "--dump-dom", probe.as_uri()],
                         capture_output=True, text=True, timeout=120).stdout
    found = re.search(r'data-probe="(\d+)x(\d+)"', dom)
    assert found and int(found.group(1)) > 0, f"the boundary figure did not load in {exe}"
