"""The report writes only files of its own (hardening case 7), draws every shear rate (case 8), and
says in one line what is wrong with a damaged output."""

import json
import os
import shutil

import pytest
from conftest import run_edmd
from edmd_analysis import report as report_module
from edmd_analysis.__main__ import main


@pytest.fixture(scope="module")
def rates_sweep(tmp_path_factory):
    """A sheared gas over five shear rates from 1e-12 to 1000, two restitutions (10 points)."""
    d = tmp_path_factory.mktemp("rates")
    spec = {"name": "rates", "grid": {"boundary": "lees-edwards",
                                      "shear_rate": [1e-12, 0.05, 10, 100, 1000],
                                      "eps": [0.9, 0.7], "phi": 0.1, "n": 60},
            "stop": {"tau_max": 4}, "samples": {"every": 1, "per_decade": 0}, "classify": {}}
    (d / "spec.json").write_text(json.dumps(spec))
    run_edmd("run", d / "spec.json", "-o", d / "out", "-q")
    return d / "out"


def test_links_planted_in_the_report_are_replaced_not_written_through(sweep, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(sweep, out)
    (out / "report").mkdir()
    victims = {}
    for name in ("cooling-loglog.png", "index.html"):
        victim = tmp_path / f"victim-{name}"
        victim.write_text("not yours")
        (out / "report" / name).symlink_to(victim)
        victims[name] = victim
    assert main(["report", str(out), "--no-movies"]) == 0
    for name, victim in victims.items():
        assert victim.read_text() == "not yours", name
        assert not (out / "report" / name).is_symlink(), name
        assert (out / "report" / name).stat().st_size > 100, name
    leftovers = [p.name for p in (out / "report").iterdir() if ".part" in p.name]
    assert leftovers == []


@pytest.mark.parametrize("target", ["elsewhere", "missing"])
def test_a_report_directory_that_is_a_link_is_refused(sweep, tmp_path, capsys, target):
    out = tmp_path / "out"
    shutil.copytree(sweep, out)
    elsewhere = tmp_path / target
    if target == "elsewhere":
        elsewhere.mkdir()
    (out / "report").symlink_to(elsewhere)
    assert main(["report", str(out), "--no-movies"]) == 1
    err = capsys.readouterr().err
    assert "symbolic link" in err and "report" in err and err.count("\n") == 1, err
    assert not elsewhere.exists() or list(elsewhere.iterdir()) == []


def test_every_shear_rate_is_a_point_of_its_own(rates_sweep, tmp_path):
    index = report_module.io.read_index(rates_sweep)
    assert len(report_module._first_seed_per_point(index, 24)) == 10
    rows = json.loads((rates_sweep / "phase.json").read_text())
    assert sorted({r["shear_rate"] for r in rows}) == [1e-12, 0.05, 10, 100, 1000]
    assert report_module._x_axis(rows) == "shear_rate"
    page = report_module.report(rates_sweep, tmp_path / "r", movies=False)
    names = {p.name for p in page.parent.glob("snapshots-*.png")}
    assert len(names) == 10 and (page.parent / "phase-diagram.png").exists()


def test_damaged_json_files_are_named_in_one_line(sweep, tmp_path, capsys):
    out = tmp_path / "out"
    shutil.copytree(sweep, out)
    (out / "phase.json").write_text("{not json")
    assert main(["report", str(out), "-o", str(tmp_path / "r")]) == 1
    err = capsys.readouterr().err
    assert "phase.json" in err and err.count("\n") == 1, err
    with pytest.raises(ValueError, match="boundary.json: not a boundary file"):
        (out / "boundary.json").write_text(json.dumps({"crossings": []}))
        report_module.io.read_boundary(out)


def test_a_corrupt_replica_is_named_when_left_out(sweep, tmp_path, capsys):
    out = tmp_path / "out"
    shutil.copytree(sweep, out)
    victim = out / "replicas" / "r00001.h5"
    with open(victim, "r+b") as f:
        f.truncate(os.path.getsize(victim) // 2)
    assert main(["report", str(out), "-o", str(tmp_path / "r"), "--no-movies"]) == 0
    assert "r00001.h5: left out of the figures" in capsys.readouterr().err
