//! Fuzzing of spec fields through the binary: a small valid spec with one or two fields replaced by
//! hostile values (huge, negative, zero, fractional where an integer belongs, wrong types, empty and
//! nested lists, long strings). `validate-spec` must answer every one with exit 0, or exit 1 and one
//! `error:` line; a spec it accepts whose estimated cost is small must also run (exit 0 or 2, never a
//! panic or an abort; a run past two minutes fails too, since the estimate called it cheap). The
//! specific cases found by hand (a box of 1e100, 4e9 seeds, …) are in `tests/specs/bad/`. `PROPTEST_CASES` sets the number of cases (default 64 here: each case starts
//! the binary).

use proptest::prelude::*;
use serde_json::{json, Value};

use std::io::Read;
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

use crate::common::{edmd, run, write};

/// Runs `edmd args`, killing it after `limit_s` seconds (a spec the estimate calls cheap must be).
fn run_for(args: &[&str], limit_s: u64) -> Output {
    let mut child = edmd()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("edmd starts");
    let deadline = Instant::now() + Duration::from_secs(limit_s);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if Instant::now() > deadline {
            child.kill().expect("kill");
            panic!("edmd {args:?} ran past {limit_s} s although its estimate was small");
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let (mut stdout, mut stderr) = (Vec::new(), Vec::new());
    child
        .stdout
        .take()
        .expect("stdout")
        .read_to_end(&mut stdout)
        .expect("read");
    child
        .stderr
        .take()
        .expect("stderr")
        .read_to_end(&mut stderr)
        .expect("read");
    Output {
        status,
        stdout,
        stderr,
    }
}

/// Every field a spec has, as a JSON pointer into the base spec.
const FIELDS: &[&str] = &[
    "/name",
    "/description",
    "/seed",
    "/grid/dim",
    "/grid/boundary",
    "/grid/eps",
    "/grid/phi",
    "/grid/box",
    "/grid/n",
    "/grid/seeds",
    "/grid/remedy",
    "/grid/remedy/tc",
    "/rule",
    "/rule/delta",
    "/init/velocities",
    "/init/melt_tau",
    "/stop/tau_max",
    "/stop/temperature_ratio",
    "/stop/classified",
    "/samples/every",
    "/samples/per_decade",
    "/samples/log_from",
    "/snapshots/at",
    "/snapshots/every",
    "/snapshots/per_decade",
    "/snapshots/log_from",
    "/snapshots/final",
    "/output/compression",
    "/output/author",
    "/classify/grid",
    "/classify/thresholds/haff",
];

/// The base spec; `density` picks how the box is given: n with phi, n with box, or phi with box.
fn base(density: usize) -> Value {
    let grid = match density {
        0 => json!({ "eps": 0.9, "phi": 0.25, "n": 64, "remedy": { "kind": "tc", "tc": 0.001 } }),
        1 => json!({ "eps": 0.9, "box": 16, "n": 64, "remedy": { "kind": "tc", "tc": 0.001 } }),
        _ => json!({ "eps": 0.9, "phi": 0.25, "box": 16, "remedy": { "kind": "tc", "tc": 0.001 } }),
    };
    json!({
        "name": "fuzz",
        "grid": grid,
        "rule": { "kind": "threshold", "delta": 0.01 },
        "init": { "melt_tau": 0 },
        "stop": { "tau_max": 2, "temperature_ratio": 0.5 },
        "samples": { "every": 1, "per_decade": 5 },
        "snapshots": { "at": [0] },
        "output": { "compression": 1 },
        "classify": { "grid": 4, "thresholds": { "haff": 0.1 } }
    })
}

fn hostile() -> impl Strategy<Value = Value> {
    let numbers = prop_oneof![
        Just(json!(0)),
        Just(json!(-1)),
        Just(json!(1)),
        Just(json!(2)),
        Just(json!(0.5)),
        Just(json!(-0.0)),
        Just(json!(1e-300)),
        Just(json!(1e300)),
        Just(json!(-1e300)),
        Just(json!(4294967296u64)),
        Just(json!(18446744073709551615u64)),
        Just(json!(i64::MIN)),
        Just(json!(1e9)),
        Just(json!(1e100)),
        (-1e12f64..1e12).prop_map(|x| json!(x)),
        (0u64..100_000).prop_map(|x| json!(x)),
    ];
    let others = prop_oneof![
        Just(json!(null)),
        Just(json!(true)),
        Just(json!("")),
        Just(json!("../x")),
        Just(json!("a".repeat(5000))),
        Just(json!([])),
        Just(json!([[]])),
        Just(json!({})),
        Just(json!({ "kind": "none" })),
        Just(json!({ "kind": "nope" })),
        Just(json!("walls")),
        Just(json!("uniform")),
        Just(json!(REMOVE)),
    ];
    let leaf = prop_oneof![3 => numbers, 1 => others];
    leaf.prop_recursive(2, 8, 4, |inner| {
        prop::collection::vec(inner, 0..4).prop_map(Value::Array)
    })
}

/// The value that removes a field instead of setting it.
const REMOVE: &str = "<remove the field>";

fn set(spec: &mut Value, pointer: &str, v: Value) {
    let (parent, key) = pointer.rsplit_once('/').expect("a pointer");
    if let Some(Value::Object(map)) = spec.pointer_mut(parent) {
        if v == json!(REMOVE) {
            map.remove(key);
        } else {
            map.insert(key.to_string(), v);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|c| c.parse().ok()).unwrap_or(64),
        ..ProptestConfig::default()
    })]

    #[test]
    fn no_spec_panics_the_binary(
        density in 0..3usize,
        edits in prop::collection::vec((0..FIELDS.len(), hostile()), 1..3)
    ) {
        let mut spec = base(density);
        for (field, value) in &edits {
            set(&mut spec, FIELDS[*field], value.clone());
        }
        let tmp = tempfile::tempdir().unwrap();
        let text = serde_json::to_string_pretty(&spec).unwrap();
        let path = write(tmp.path(), "s.json", &text);
        let path = path.to_str().unwrap();
        let o = run(&["validate-spec", path]);
        let err = String::from_utf8_lossy(&o.stderr);
        let out = String::from_utf8_lossy(&o.stdout);
        prop_assert!(!err.contains("panicked"), "{text}\n{err}");
        match o.status.code() {
            Some(0) => prop_assert!(out.contains(": valid;"), "{text}\n{out}"),
            Some(1) => {
                prop_assert_eq!(err.trim_end().lines().count(), 1, "{}\n{}", text, err);
                prop_assert!(err.starts_with("error: "), "{text}\n{err}");
            }
            code => prop_assert!(false, "exit {code:?} for\n{text}\n{err}"),
        }
        // A valid spec whose cost is small runs: exit 0 (done) or 2 (failed or collapsed).
        let collisions: f64 = out
            .split("at most ")
            .nth(1)
            .and_then(|r| r.split(' ').next())
            .and_then(|x| x.parse().ok())
            .unwrap_or(f64::INFINITY);
        if o.status.code() == Some(0) && collisions < 2e5 {
            let dir = tmp.path().join("out");
            let r = run_for(&["run", path, "-o", dir.to_str().unwrap(), "-q", "-j", "1"], 120);
            let err = String::from_utf8_lossy(&r.stderr);
            prop_assert!(!err.contains("panicked"), "{text}\n{err}");
            prop_assert!(matches!(r.status.code(), Some(0) | Some(2)), "exit {:?} for\n{}\n{}", r.status.code(), text, err);
        }
    }
}
