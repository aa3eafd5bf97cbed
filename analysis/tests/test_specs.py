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


BAD = [
    {"grid": {"eps": 0.9, "phi": 0.2, "n": 100, "epsilon": 1}},
    {"grid": {"eps": 1.5, "phi": 0.2, "n": 100}},
    {"grid": {"eps": 0.9, "phi": 0.95, "n": 100}},
    {"grid": {"eps": 0.9, "phi": 0.2, "n": 0}},
    {"grid": {"eps": [], "phi": 0.2, "n": 100}},
    {"grid": {"eps": 0.9, "phi": 0.2, "box": 30, "n": 100}},
    {"grid": {"eps": 0.9, "phi": 0.2, "n": 100, "remedy": {"kind": "tc"}}},
    {"stop": {"tau_max": 10, "when": "later"}},
    {"stop": {"tau_max": 10, "classified": True}},
    {"classify": {"grid": 0}},
    {"classify": {"thresholds": {"shear": 0.1}}},
]


@pytest.mark.parametrize("patch", BAD)
def test_schema_and_binary_reject_the_same_bad_specs(patch, tmp_path):
    spec = {"name": "bad", "grid": {"eps": 0.9, "phi": 0.2, "n": 100}, "stop": {"tau_max": 10}}
    spec.update(patch)
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate(spec, SCHEMA)
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(spec))
    r = run_edmd("validate-spec", p, check=False)
    assert r.returncode == 1 and r.stderr.startswith("error: invalid sweep spec"), r.stderr
