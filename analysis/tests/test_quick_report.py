"""The report of the default sweep (sweeps/quick.json, what `make run` draws): every figure with a
heading and a caption, and movies one can watch that stay small: at least 640 pixels wide, at most
3 MB each (measured on the whole sweep: 2.1 MB at 640 pixels). The report's movies show the first
replica of each class, which in the quick sweep are N = 1024 disks at eps 0.99 (kinetic), 0.95
(shearing) and 0.7 (clustering): the test runs those three grid points with one seed (the same
frames and disks, a thirtieth of the sweep's collisions). A movie of 4096 disks is 3.5 MB."""

import json
import re

import pytest
from conftest import REPO, run_edmd
from edmd_analysis import report as report_module
from PIL import Image


@pytest.fixture(scope="session")
def quick_report(tmp_path_factory):
    d = tmp_path_factory.mktemp("quick")
    spec = json.loads((REPO / "sweeps" / "quick.json").read_text())
    spec["grid"].update({"n": 1024, "eps": [0.99, 0.95, 0.7], "seeds": 1})
    (d / "spec.json").write_text(json.dumps(spec))
    run_edmd("run", d / "spec.json", "-o", d / "out", "-q")
    return report_module.report(d / "out", d / "out" / "report")


def test_quick_report_movies_are_watchable_and_small(quick_report):
    movies = sorted(quick_report.parent.glob("*.gif"))
    assert [m.name.split("-")[1] for m in movies] == ["clustering", "kinetic", "shearing"]
    for m in movies:
        with Image.open(m) as im:
            assert im.size[0] >= 640, (m.name, im.size)
        assert m.stat().st_size <= 3 * 2**20, (m.name, m.stat().st_size)


def test_quick_report_figures_have_headings_and_captions(quick_report):
    text = quick_report.read_text()
    figures = re.findall(r"<figure><h3>(.*?)</h3><a href=\"(.*?)\">.*?<figcaption>(.*?)</figcaption>", text)
    assert len(figures) == len(list(quick_report.parent.glob("*.png"))) + len(list(quick_report.parent.glob("*.gif")))
    for heading, name, caption in figures:
        assert " " in heading and heading != name, (heading, name)
        assert len(caption) > 20, (name, caption)
