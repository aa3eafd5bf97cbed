"""analysis/examples/tutorial.ipynb is stored without outputs and runs from top to bottom (nbclient,
in a fresh directory, with the `edmd` module the other tests use): the in-process part cools a gas,
changes its ε and reads its order parameters; every figure cell draws, the movie is written, and
the h5py cell finds the homogeneous gas on Haff's law."""

import os
import re

import pytest
from conftest import REPO

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

NOTEBOOK = REPO / "analysis" / "examples" / "tutorial.ipynb"


def test_the_notebook_is_stored_without_outputs():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code
    for c in code:
        assert c.outputs == [] and c.execution_count is None, c.source[:60]


def test_the_notebook_runs(tmp_path):
    if not os.environ.get("EDMD_TEST_MODULE"):
        pytest.importorskip("edmd", reason="the notebook drives the module `make python-module` builds")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) >= 5, "in-process cooling and look; cooling, phase diagram and snapshot figures"
    assert any("image/gif" in o.get("data", {}) for o in outputs), "the movie is shown"
    assert (tmp_path / "tutorial-out" / "sweep.h5").exists()
    assert (tmp_path / "tutorial.gif").stat().st_size > 0
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "T/T0 at tau = 30:" in text and "delta_rho2:" in text, "the in-process part ran"
    low, high = map(float, re.search(r"T / T_Haff over tau <= 10: ([\d.]+) \.\.\. ([\d.]+)", text).groups())
    # N = 1024 homogeneous disks follow Haff's law to the ~1 % of their temperature fluctuations.
    assert 0.97 < low <= high < 1.03, (low, high)
