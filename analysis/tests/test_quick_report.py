"""The report of the default sweep (sweeps/quick.json, what `make run` draws): every figure with a
heading and a caption, and movies one can watch that stay small: at least 640 pixels wide, at most
3 MB each (measured: 2.1 MB at 640 pixels for 40 frames of 4096 disks)."""

import re

import pytest
from conftest import REPO, run_edmd
from edmd_analysis import report as report_module
from PIL import Image


@pytest.fixture(scope="session")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("quick") / "out"
    run_edmd("run", REPO / "sweeps" / "quick.json", "-o", out, "-q")
    return report_module.report(out, out / "report")


def test_quick_report_movies_are_watchable_and_small(quick_report):
    movies = sorted(quick_report.parent.glob("*.gif"))
    assert len(movies) == 3  # one per class: kinetic, shearing, clustering
    for m in movies:
        with Image.open(m) as im:
            assert im.size[0] >= 640, (m.name, im.size)
        assert m.stat().st_size <= 3 * 2**20, (m.name, m.stat().st_size)


def test_quick_report_figures_have_headings_and_captions(quick_report):
    text = quick_report.read_text()
    figures = re.findall(r"<figure><h3>(.*?)</h3><a href=\"(.*?)\">.*?<figcaption>(.*?)</figcaption>", text)
    assert len(figures) == len(list(quick_report.parent.glob("*.png"))) + 3
    for heading, name, caption in figures:
        assert " " in heading and heading != name, (heading, name)
        assert len(caption) > 20, (name, caption)
