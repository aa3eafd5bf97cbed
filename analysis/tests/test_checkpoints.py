"""Checkpoints end to end (scripts/kill-resume.py, short): a sweep of 2D cells, 3D lists, a sheared
box, rough grains with the TC remedy and rough spheres, killed with SIGKILL and stopped with SIGTERM,
SIGINT and SIGUSR1 (exit status 75), then run again, ends bit-identical to an uninterrupted run,
with replicas going on from their checkpoints. The full version (10 SIGKILL trials) is in
`make stress`."""

import importlib.util

from conftest import REPO, edmd_binary

spec = importlib.util.spec_from_file_location("kill_resume", REPO / "scripts" / "kill-resume.py")
kill_resume = importlib.util.module_from_spec(spec)
spec.loader.exec_module(kill_resume)


def test_killed_and_signalled_runs_resume_bit_identical(capsys):
    rc = kill_resume.main(["--edmd", str(edmd_binary()), "--trials", "1", "--signals", "3",
                           "--kills", "2", "--tau-max", "300", "--seed", "3"])
    out = capsys.readouterr().out
    assert rc == 0, out
    assert "4 of 4 trials bit-identical" in out
    resumed = [int(line.split("checkpoints")[1].split(":")[0]) for line in out.splitlines()
               if line.startswith("trial")]
    assert sum(resumed) > 0, out


def test_status_and_python_read_a_checkpoint(tmp_path):
    """A run stopped by SIGTERM leaves checkpoints whose headers `edmd status` and
    `edmd_analysis.checkpoints` report: τ reached, collisions, age."""
    import json
    import signal
    import subprocess
    import time

    import edmd_analysis
    from conftest import run_edmd

    spec = dict(kill_resume.SPEC, checkpoint={"every_s": 0, "every_tau": 1})
    (tmp_path / "spec.json").write_text(json.dumps(spec))
    p = subprocess.Popen([str(edmd_binary()), "run", str(tmp_path / "spec.json"), "-o", str(tmp_path / "o"), "-q"],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    time.sleep(1.5)
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate()
    assert p.returncode == kill_resume.EXIT_INTERRUPTED, err
    rows = edmd_analysis.checkpoints(tmp_path / "o")
    assert rows and all("error" not in r for r in rows), rows
    for r in rows:
        assert 0 < r["tau"] < spec["stop"]["tau_max"] and r["collisions"] > 0 and r["reason"] == "signal"
        assert 0 <= r["age_s"] < 60
    status = run_edmd("status", tmp_path / "o", check=False).stdout
    for r in rows:
        assert f"checkpoint r{r['replica']:05d}: tau {r['tau']:.4f}" in status, status


def test_a_signalled_refinement_resumes_bit_identical(tmp_path, capsys):
    """`edmd refine` stopped by SIGINT and SIGUSR1 exits 75 naming the checkpoints it left; rerun, it ends equal
    to an uninterrupted refinement."""
    import json
    import re
    import shutil
    import signal
    import subprocess

    from conftest import run_edmd

    spec = {"name": "rf", "seed": 5, "grid": {"eps": [0.6, 1.0], "phi": 0.25, "box": [40, 80, 160]},
            "stop": {"tau_max": 300}, "samples": {"every": 5, "per_decade": 0}, "classify": {},
            "checkpoint": {"every_s": 0, "every_tau": 10}}
    (tmp_path / "rf.json").write_text(json.dumps(spec))
    run_edmd("run", tmp_path / "rf.json", "-o", tmp_path / "a", "-q")
    shutil.copytree(tmp_path / "a", tmp_path / "b")
    run_edmd("refine", tmp_path / "a", "--rounds", "2", "-q")
    stopped, went_on = 0, False
    for sig, after in ((signal.SIGINT, 1.5), (signal.SIGUSR1, 0.8)):
        p = subprocess.Popen([str(edmd_binary()), "refine", str(tmp_path / "b"), "--rounds", "2", "-q"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        try:
            p.wait(timeout=after)
        except subprocess.TimeoutExpired:
            p.send_signal(sig)
        _, err = p.communicate()
        if p.returncode == 0:
            break
        assert p.returncode == kill_resume.EXIT_INTERRUPTED and "interrupted:" in err, err
        # A signal between two replicas or two rounds leaves nothing in flight to save: the message
        # counts the checkpoints there are, and they are on disk.
        saved = int(re.search(r"(\d+) checkpoint\(s\) to go on from", err).group(1))
        assert len(list((tmp_path / "b" / "states").glob("*.ckpt"))) == saved, err
        stopped += 1
        went_on = went_on or saved > 0
    assert stopped > 0, "the refinement ended before any signal"
    run_edmd("refine", tmp_path / "b", "--rounds", "2", "-q")
    assert kill_resume.load_compare().main(str(tmp_path / "a"), str(tmp_path / "b")) == 0, capsys.readouterr().out
    # What differs is recorded as a fact of the run: which replicas went on from a checkpoint.
    import edmd_analysis
    assert not edmd_analysis.read_index(tmp_path / "a")["resumes"].any()
    assert edmd_analysis.read_index(tmp_path / "b")["resumes"].any() == went_on
