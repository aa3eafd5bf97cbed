"""The Python CLI answers bad input with one line and exit 1, never a traceback, and leaves nothing
behind; readers do not draw a replica file of another spec."""

import shutil

from edmd_analysis import io
from edmd_analysis.__main__ import main


def _one_line(capsys) -> str:
    err = capsys.readouterr().err
    assert "Traceback" not in err
    assert err.startswith("error: ") and err.count("\n") == 1, err
    return err


def test_report_of_a_file_is_one_line(sweep, capsys):
    assert main(["report", str(sweep / "sweep.h5"), "--no-movies"]) == 1
    assert "not a sweep output directory" in _one_line(capsys)


def test_report_into_a_path_under_a_file_is_one_line_and_leaves_nothing(sweep, tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["report", str(sweep), "-o", str(blocker / "report"), "--no-movies"]) == 1
    _one_line(capsys)
    assert blocker.read_text() == "x"


def test_a_failed_report_leaves_no_empty_directory(sweep, tmp_path, capsys):
    out = tmp_path / "out"
    shutil.copytree(sweep, out)
    (out / "phase.json").write_text("{not json")
    dest = out / "report"
    assert main(["report", str(out), "-o", str(dest), "--no-movies"]) == 1
    _one_line(capsys)
    assert not dest.exists()


def test_movie_dpi_must_be_positive(sweep, capsys):
    for dpi in ("0", "-5"):
        assert main(["movie", str(sweep), "--dpi", dpi]) == 1
        assert f"--dpi {dpi}: must be a positive" in _one_line(capsys)


def test_a_replica_of_another_spec_is_corrupt_not_drawn(sweep, classified_sweep, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(sweep, out)
    shutil.copy(classified_sweep / "replicas" / "r00000.h5", out / "replicas" / "r00000.h5")
    index = io.read_index(out)
    assert index["status"][0] == "corrupt"
    assert "different spec" in index["message"][0]
    assert all(s != "corrupt" for s in index["status"][1:])
    from edmd_analysis.report import _first_seed_per_point

    assert 0 not in _first_seed_per_point(index, 24)
