"""The movie command: one frame per stored snapshot (snapshots.at, every, per_decade, final), frame
size from the figure, GIF always and MP4 when ffmpeg is present; clear errors for what it cannot do."""

import json
import shutil
import subprocess

import edmd_analysis as ea
import numpy as np
import pytest
from conftest import run_edmd
from edmd_analysis import movie as movie_module
from edmd_analysis.__main__ import main
from PIL import Image

# 640 pixels wide by default: 5 x 4.4 inches at 128 dpi (speed colours with a colour bar).
FRAME = (640, 563)


@pytest.fixture(scope="session")
def grid_sweep(tmp_path_factory):
    """Disks with a linear and a logarithmic snapshot grid: tau 0, 1, 2, 3.16, 4, 6, 8, 10."""
    d = tmp_path_factory.mktemp("movie")
    spec = {"name": "movie", "seed": 5, "grid": {"eps": 0.8, "phi": 0.2, "n": 300, "seeds": 1},
            "stop": {"tau_max": 10}, "samples": {"every": 5, "per_decade": 0},
            "snapshots": {"every": 2, "per_decade": 2, "log_from": 1}}
    (d / "spec.json").write_text(json.dumps(spec))
    run_edmd("run", d / "spec.json", "-o", d / "out", "-q")
    return d / "out"


def frames(path):
    with Image.open(path) as im:
        return im.n_frames, im.size


def test_snapshot_grids_give_the_movie_its_frames(grid_sweep, tmp_path, capsys):
    snaps = ea.read_snapshots(grid_sweep / "replicas" / "r00000.h5")
    np.testing.assert_allclose(snaps.tau, [0, 1, 2, 10**0.5, 4, 6, 8, 10], atol=1 / 300)
    assert ea.snapshot_count(grid_sweep / "replicas" / "r00000.h5") == 8
    out = tmp_path / "m.gif"
    assert main(["movie", str(grid_sweep), "--replica", "0", "-o", str(out)]) == 0
    assert str(out) in capsys.readouterr().out
    assert frames(out) == (8, FRAME)
    assert main(["movie", str(grid_sweep), "-o", str(tmp_path / "few.gif"), "--max-frames", "3",
                 "--dpi", "40"]) == 0
    assert frames(tmp_path / "few.gif") == (3, (200, 176))


def test_default_output_and_mp4_when_ffmpeg_is_present(grid_sweep):
    written = movie_module.movie(grid_sweep)
    assert written[0] == grid_sweep / "movies" / "r00000.gif"
    assert frames(written[0])[0] == 8
    assert not list((grid_sweep / "movies").glob("*.part*")), "no temporary file is left"
    if not shutil.which("ffmpeg"):
        assert len(written) == 1
        pytest.skip("ffmpeg not on the PATH: MP4 not written (GIF checked)")
    assert written[1].suffix == ".mp4"
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0",
                            "-show_entries", "stream=nb_read_frames,width,height", "-of", "json",
                            str(written[1])], capture_output=True, text=True, check=True)
    stream = json.loads(probe.stdout)["streams"][0]
    assert int(stream["nb_read_frames"]) == 8
    assert (stream["width"], stream["height"]) == FRAME


def test_three_d_replicas_show_a_mid_plane_slab(sweep, tmp_path):
    # Replica 4 of the conftest sweep: spheres between walls, snapshots at tau 0, 5 and 20.
    out = tmp_path / "s.gif"
    movie_module.movie(sweep, replica=4, output=out, arrows=True)
    assert frames(out) == (3, FRAME)
    snaps = ea.read_snapshots(sweep / "replicas" / "r00004.h5")
    idx, _, cut = movie_module._visible(snaps, 0)
    assert 0 < len(idx) < len(snaps.radius) and (cut > 0).all() and (cut <= 2 * snaps.radius.max()).all()


def test_speed_colours_are_in_units_of_the_current_rms_speed(sweep):
    snaps = ea.read_snapshots(sweep / "replicas" / "r00000.h5")
    for k in range(len(snaps.step)):
        s = movie_module._speed(snaps, k)
        assert np.sqrt((s**2).mean()) == pytest.approx(1.0, rel=1e-12)


def test_movie_errors_name_the_problem(sweep, grid_sweep, tmp_path, capsys):
    assert main(["movie", str(grid_sweep), "-o", str(tmp_path / "m.avi")]) == 1
    assert ".gif or .mp4" in capsys.readouterr().err
    assert main(["movie", str(grid_sweep), "--colour", "spin", "-o", str(tmp_path / "m.gif")]) == 1
    assert "smooth grains" in capsys.readouterr().err
    assert main(["movie", str(grid_sweep), "--replica", "7"]) == 1
    assert "r00007.h5" in capsys.readouterr().err
    assert main(["movie", str(grid_sweep), "--fps", "0"]) == 1
    assert "--fps" in capsys.readouterr().err
    if not shutil.which("ffmpeg"):
        assert main(["movie", str(grid_sweep), "-o", str(tmp_path / "m.mp4")]) == 1
        assert "ffmpeg" in capsys.readouterr().err
    assert not list(tmp_path.glob("m.*")), "nothing written on error"
