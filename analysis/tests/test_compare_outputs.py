"""scripts/compare-outputs.py, on which the project's bit-identity claims rest, compares both ways:
an object, attribute, replica or index row present on one side only is a difference, whichever side
is A; a directory that is not there is one line, not a traceback."""

import importlib.util
import json
import shutil
from pathlib import Path

import h5py

REPO = Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("compare_outputs", REPO / "scripts" / "compare-outputs.py")
compare_outputs = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare_outputs)


def _both_ways(a, b):
    return compare_outputs.main(str(a), str(b)), compare_outputs.main(str(b), str(a))


def test_equal_outputs_pass(sweep, tmp_path, capsys):
    b = tmp_path / "b"
    shutil.copytree(sweep, b)
    assert _both_ways(sweep, b) == (0, 0)
    assert "index equal: sweep.h5, summary.csv, summary.json, phase.json, spec.json" in capsys.readouterr().out


def test_a_dataset_or_attribute_on_one_side_only_differs(sweep, tmp_path, capsys):
    b = tmp_path / "b"
    shutil.copytree(sweep, b)
    first = sorted((b / "replicas").glob("*.h5"))[0]
    with h5py.File(first, "a") as f:
        f.create_dataset("extra", data=[1.0])
    assert _both_ways(sweep, b) == (1, 1)
    assert "extra only in B" in capsys.readouterr().out
    shutil.rmtree(b)
    shutil.copytree(sweep, b)
    with h5py.File(sorted((b / "replicas").glob("*.h5"))[0], "a") as f:
        f.attrs["extra"] = 1
    assert _both_ways(sweep, b) == (1, 1)


def test_index_files_are_compared(sweep, tmp_path, capsys):
    b = tmp_path / "b"
    shutil.copytree(sweep, b)
    rows = json.loads((b / "phase.json").read_text())
    rows[0]["done"] += 1
    (b / "phase.json").write_text(json.dumps(rows))
    assert _both_ways(sweep, b) == (1, 1)
    assert "phase.json differs" in capsys.readouterr().out
    (b / "phase.json").unlink()
    assert _both_ways(sweep, b) == (1, 1)


def test_a_missing_directory_is_one_line(tmp_path, capsys):
    assert compare_outputs.main(str(tmp_path / "nowhere"), str(tmp_path)) == 2
    assert "is not a sweep output directory" in capsys.readouterr().err


def test_an_ignored_column_may_exist_on_one_side_only(sweep, tmp_path, capsys):
    """`--ignore-attr NAME` skips an index column that one build writes and the other does not (a
    new column of summary.csv and sweep.h5), and nothing else: another extra dataset still differs."""
    b = tmp_path / "b"
    shutil.copytree(sweep, b)
    with h5py.File(b / "sweep.h5", "a") as f:
        f["replicas"].create_dataset("new_column", data=[0.0] * len(f["replicas/index"]))
    ignored = compare_outputs.RUN_ATTRIBUTES | {"new_column"}
    assert compare_outputs.main(str(sweep), str(b), ignored) == 0
    assert compare_outputs.main(str(b), str(sweep), ignored) == 0
    assert _both_ways(sweep, b) == (1, 1)
    assert "new_column only in B" in capsys.readouterr().out
