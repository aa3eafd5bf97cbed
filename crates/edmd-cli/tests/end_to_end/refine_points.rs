//! `edmd refine` knows a point by its parameters alone (hardening cases 4 and 6): not by the seeds
//! a grid runs it with, nor by whether a default is written out; axes are named once, and rounds and
//! budgets are at least 1.

use std::path::Path;

use crate::common::{run, run_spec};

/// Runs `spec` into `dir/name` (exit 0), then refines it `rounds` rounds; returns the refinement's
/// output.
fn refined(dir: &Path, name: &str, spec: &str, rounds: &str) -> std::process::Output {
    let out = run_spec(dir, name, spec);
    run(&["refine", out.to_str().unwrap(), "--rounds", rounds, "-q"])
}

/// Case 4a: two grids that differ only in their seeds. The first's midpoint in ε is the second's
/// point, which a key with the seeds in it did not recognise: it was planned again, and every rerun
/// failed with "the same grid point as replica 4". Case 4b: a β axis holding −1, stored without its
/// `beta` key (the default), planned again in round 2. Both now run their rounds, and a rerun
/// adds nothing.
#[test]
fn points_are_known_by_their_parameters_not_their_seeds_or_defaults() {
    let tmp = tempfile::tempdir().unwrap();
    let stop = r#""classify": {}, "stop": {"tau_max": 200, "classified": true}"#;
    let seeds = format!(
        r#"{{"name": "seeds", "grid": [{{"eps": [0.7, 0.98], "phi": 0.25, "box": 40, "seeds": 2}},
            {{"eps": 0.84, "phi": 0.25, "box": 40, "seeds": 3}}], {stop}}}"#
    );
    let beta = format!(
        r#"{{"name": "beta", "grid": {{"eps": [0.7, 0.98], "beta": [-1, 1], "box": [20, 40],
            "phi": 0.25}}, {stop}}}"#
    );
    for (name, spec) in [("seeds", seeds), ("beta", beta)] {
        let o = refined(tmp.path(), name, &spec, "2");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{name}: {err}");
        assert!(err.contains("round 2 of 2"), "{name}: {err}");
        let out = tmp.path().join(name);
        let again = run(&["refine", out.to_str().unwrap(), "--rounds", "2", "-q"]);
        assert!(
            again.status.success(),
            "{name}: rerun: {}",
            String::from_utf8_lossy(&again.stderr)
        );
        let boundary = std::fs::read_to_string(out.join("boundary.json")).unwrap();
        let file: serde_json::Value = serde_json::from_str(&boundary).unwrap();
        let crossings = file["crossings"].as_array().unwrap();
        let mut keys: Vec<String> = crossings.iter().map(|c| c.to_string()).collect();
        keys.sort();
        keys.dedup();
        assert_eq!(
            keys.len(),
            crossings.len(),
            "{name}: a crossing listed twice"
        );
    }
}

/// Case 6 and its neighbours: `--axes eps,eps,box` (each crossing listed twice, the full grid
/// counted as 270 replicas instead of 90, and a later `--axes eps,box` refused), `--rounds 0` and
/// `--budget 0` (exit 0, yet a refinement written into spec.json) are refused with one line and
/// leave spec.json as it was.
#[test]
fn axes_named_twice_and_empty_rounds_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = r#"{"name": "twice", "grid": {"eps": [0.7, 0.98], "phi": 0.25, "box": [20, 40]},
        "classify": {}, "stop": {"tau_max": 50}}"#;
    let out = run_spec(tmp.path(), "twice", spec);
    let before = std::fs::read_to_string(out.join("spec.json")).unwrap();
    let o = out.to_str().unwrap();
    for (args, says) in [
        (vec!["--axes", "eps,eps,box"], "eps is named more than once"),
        (vec!["--rounds", "0"], "must be at least 1"),
        (vec!["--budget", "0"], "must be at least 1"),
    ] {
        let mut all = vec!["refine", o, "-q"];
        all.extend_from_slice(&args);
        let r = run(&all);
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(!r.status.success(), "{args:?} accepted");
        assert!(err.contains(says), "{args:?}: {err}");
        let after = std::fs::read_to_string(out.join("spec.json")).unwrap();
        assert_eq!(after, before, "{args:?} changed spec.json");
    }
}
