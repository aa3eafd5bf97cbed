"""DataFrames: the index (one row per replica, summary.csv's columns and order), the phase table (one
row per grid point) and a replica's scalar observables, with the dtypes docs/output.md lists."""

import csv

import edmd_analysis as ea
import numpy as np
import pytest
from edmd_analysis import frames

pd = pytest.importorskip("pandas")


def test_index_frame_rows_columns_and_dtypes(sweep):
    index = ea.read_index(sweep)
    df = index.to_frame()
    assert len(df) == len(index) == 5
    with open(sweep / "summary.csv", newline="") as f:
        header = next(csv.reader(f))
    assert list(df.columns) == header, "the columns of summary.csv, in its order"
    assert df["index"].dtype == np.int64 and list(df["index"]) == list(range(5))
    for c in ("dim", "n", "seed_index"):
        assert df[c].dtype == np.int64, c
    for c in ("seed", "collisions"):
        assert df[c].dtype == np.uint64, c
    for c in ("eps", "phi", "box_side", "tau", "ln_temperature_ratio", "collapse_tau", "wall_s"):
        assert df[c].dtype == np.float64, c
    for c in frames.CATEGORIES:
        assert isinstance(df[c].dtype, pd.CategoricalDtype), c
    for c in ("file", "message", "species", "aspect"):
        assert isinstance(df[c].dtype, pd.StringDtype), c
    assert set(df["boundary"]) == {"periodic", "walls"}
    np.testing.assert_array_equal(df["eps"].to_numpy(), index["eps"])
    # The frame agrees with summary.csv value for value.
    csv_frame = pd.read_csv(sweep / "summary.csv")
    np.testing.assert_allclose(df["ln_temperature_ratio"], csv_frame["ln_temperature_ratio"])
    assert list(df["file"]) == list(csv_frame["file"])


def test_phase_table_frame(classified_sweep):
    df = ea.read_phase_table(classified_sweep)
    assert len(df) == 2  # eps 0.9 and 0.7
    assert list(df.columns[: len(frames.PHASE_COLUMNS)]) == list(frames.PHASE_COLUMNS)
    for c, dtype in frames.PHASE_COLUMNS.items():
        if dtype == "category":
            assert isinstance(df[c].dtype, pd.CategoricalDtype), c
        elif dtype == "string":
            assert isinstance(df[c].dtype, pd.StringDtype), c
        else:
            assert df[c].dtype == np.dtype(dtype), c
    fractions = df[["kinetic", "shearing", "clustering"]].sum(axis=1)
    np.testing.assert_allclose(fractions, 1.0)
    assert sorted(df["eps"]) == [0.7, 0.9]
    assert (df["seeds"] == 2).all()


def test_phase_table_missing_says_how_to_make_it(sweep, tmp_path):
    with pytest.raises(FileNotFoundError, match="edmd summarize"):
        ea.read_phase_table(tmp_path)


def test_replica_frame_holds_the_scalar_observables(sweep):
    rep = ea.read_replica(sweep / "replicas" / "r00000.h5")
    df = rep.to_frame()
    assert list(df.columns[:2]) == ["step", "time"]
    assert len(df) == len(rep.step)
    np.testing.assert_array_equal(df["ln_temperature"], rep.observables["ln_temperature"])
    assert "tau" in df and df["step"].dtype == np.int64
