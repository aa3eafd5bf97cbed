"""The ready specs in sweeps/ follow docs/sweep-spec.schema.json, and the schema is as strict as the
binary (unknown fields and out-of-range values are rejected by both)."""

import json

import pytest
from conftest import REPO, run_edmd

jsonschema = pytest.importorskip("jsonschema")
SCHEMA = json.loads((REPO / "docs" / "sweep-spec.schema.json").read_text())
SPECS = sorted((REPO / "sweeps").glob("*.json"))


def test_schema_is_valid():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


@pytest.mark.parametrize("path", SPECS, ids=[p.name for p in SPECS])
def test_ready_spec_follows_schema(path):
    jsonschema.validate(json.loads(path.read_text()), SCHEMA)


BAD = sorted((REPO / "tests" / "specs" / "bad").glob("*.json"))


@pytest.mark.parametrize("path", BAD, ids=[p.stem for p in BAD])
def test_schema_and_binary_reject_the_same_bad_specs(path):
    """The shared corpus (tests/specs/README.md): the binary refuses every case with the expected
    message; the schema refuses every case but the cross-field ones, which it must accept."""
    expect = path.with_suffix(".expect").read_text().strip()
    r = run_edmd("validate-spec", path, check=False, cwd=path.parent)
    assert r.returncode == 1 and r.stderr.startswith("error: invalid sweep spec"), r.stderr
    assert expect in r.stderr, (expect, r.stderr)
    spec = json.loads(path.read_text())
    if path.stem.startswith("cross-"):
        jsonschema.validate(spec, SCHEMA)
    else:
        with pytest.raises(jsonschema.ValidationError):
            jsonschema.validate(spec, SCHEMA)


def test_corpus_is_not_empty():
    assert len(BAD) >= 20
