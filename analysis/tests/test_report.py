"""The report command writes every figure type and an index.html with the phase table."""

import pytest
from edmd_analysis import report as report_module
from edmd_analysis.__main__ import main


def test_report_of_a_classified_sweep(classified_sweep, tmp_path):
    page = report_module.report(classified_sweep, tmp_path / "rep")
    names = sorted(p.name for p in (tmp_path / "rep").glob("*.png"))
    for expected in ("cooling-loglog.png", "cooling-semilog.png", "velocity-histograms.png",
                     "order-parameters.png", "phase-diagram.png"):
        assert expected in names
    assert any(n.startswith("snapshots-r") for n in names)
    text = page.read_text()
    assert "pytest-classified" in text and "<table>" in text
    for name in names:
        assert f'src="{name}"' in text
    assert text.count("<tr>") == 1 + 2  # header and two grid points (eps 0.9 and 0.7)


def test_every_figure_has_a_heading_and_a_caption_and_movies_are_watchable(classified_sweep, tmp_path):
    """Each figure on the page has a heading that is not its file name and a caption; the movies
    are at least 640 pixels wide and at most 3 MB."""
    import re

    from PIL import Image

    page = report_module.report(classified_sweep, tmp_path / "rep")
    text = page.read_text()
    figures = re.findall(r"<figure><h3>(.*?)</h3><a href=\"(.*?)\">.*?<figcaption>(.*?)</figcaption>", text)
    files = sorted(p.name for p in (tmp_path / "rep").iterdir() if p.suffix in (".png", ".gif"))
    assert sorted(f for _, f, _ in figures) == files
    for heading, name, caption in figures:
        assert " " in heading and not heading.endswith((".png", ".gif")), (heading, name)
        assert len(caption) > 20, (name, caption)
    movies = [p for p in (tmp_path / "rep").glob("*.gif")]
    assert movies
    for m in movies:
        with Image.open(m) as im:
            assert im.size[0] >= 640, (m.name, im.size)
        assert m.stat().st_size <= 3 * 2**20, (m.name, m.stat().st_size)


def test_report_cli(sweep, partial_sweep, tmp_path, capsys):
    assert main(["report", str(sweep), "-o", str(tmp_path / "r")]) == 0
    assert "report:" in capsys.readouterr().out
    # 3D replicas get no snapshot panels; unclassified sweeps no order parameters.
    names = {p.name for p in (tmp_path / "r").glob("*.png")}
    assert "order-parameters.png" not in names and "cooling-loglog.png" in names
    assert main(["report", str(partial_sweep)]) == 1
    assert "incomplete" in capsys.readouterr().err


def test_report_needs_a_sweep(tmp_path):
    with pytest.raises(FileNotFoundError):
        report_module.report(tmp_path, tmp_path / "r")


def test_figures_drawn_in_parallel_are_those_drawn_one_at_a_time(sweep, tmp_path):
    one = report_module.report(sweep, tmp_path / "one", movies=False, jobs=1).parent
    two = report_module.report(sweep, tmp_path / "two", movies=False, jobs=2).parent
    names = sorted(p.name for p in one.iterdir())
    assert names == sorted(p.name for p in two.iterdir()) and "cooling-loglog.png" in names
    for name in names:
        assert (one / name).read_bytes() == (two / name).read_bytes(), name


def test_report_jobs_must_be_positive(sweep, tmp_path, capsys):
    assert main(["report", str(sweep), "-o", str(tmp_path / "r"), "--jobs", "0"]) == 1
    assert "--jobs 0" in capsys.readouterr().err
    assert not (tmp_path / "r").exists()
