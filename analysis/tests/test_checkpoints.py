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
