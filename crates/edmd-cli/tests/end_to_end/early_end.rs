//! Runs that must not end `done` by mistake, and output files that must never be written through
//! a symbolic link. Each test fails on a build without its fix (`EDMD_UNDER_TEST=OLD_BINARY`).

use std::path::Path;

use crate::common::{edmd, run, write};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The status and the message of every replica, from `summary.json`.
fn statuses(out: &Path) -> Vec<(String, String)> {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let rows: Vec<serde_json::Value> = serde_json::from_str(&text).expect("summary.json parses");
    rows.iter()
        .map(|r| {
            (
                r["status"].as_str().unwrap().to_string(),
                r["message"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// A planted `OUT/.lock` (and shard lock) pointing at a file of the user's: the run refuses with one
/// line naming the link, exit 1, and the target is untouched; `merge` likewise.
#[test]
fn a_symlinked_lock_is_refused_and_its_target_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &crate::common::small_spec("lock", &[0.9], 64, 1, 2.0),
    );
    let precious = tmp.path().join("precious.txt");
    let keep = "a file the user cares about\n";
    for lock in [".lock", ".lock.shard-0-of-2"] {
        std::fs::write(&precious, keep).unwrap();
        let out = tmp.path().join(format!("out{lock}"));
        std::fs::create_dir_all(&out).unwrap();
        std::os::unix::fs::symlink(&precious, out.join(lock)).unwrap();
        let mut args = vec![
            "run",
            spec.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ];
        if lock.contains("shard") {
            args.extend(["--shard", "0/2"]);
        }
        let o = run(&args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{lock}: {e}");
        assert!(
            e.contains("is a symbolic link") && e.contains(lock),
            "{lock}: {e}"
        );
        assert_eq!(e.trim().lines().count(), 1, "{lock}: one line: {e}");
        assert_eq!(std::fs::read_to_string(&precious).unwrap(), keep, "{lock}");
    }
    // merge into an output whose lock is a link.
    let a = tmp.path().join("a");
    let o = run(&[
        "run",
        spec.to_str().unwrap(),
        "-o",
        a.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let b = tmp.path().join("b");
    std::fs::create_dir_all(&b).unwrap();
    std::os::unix::fs::symlink(&precious, b.join(".lock")).unwrap();
    let o = run(&["merge", a.to_str().unwrap(), "-o", b.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("is a symbolic link"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&precious).unwrap(), keep);
}

/// A planted `.h5.part` that links elsewhere, in the output of a run and in the target of a merge,
/// is replaced, never written through: both succeed and the link's target is untouched.
#[test]
fn planted_links_under_our_temporary_names_are_not_followed() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &crate::common::small_spec("parts", &[0.9], 64, 1, 2.0),
    );
    let precious = tmp.path().join("precious.txt");
    std::fs::write(&precious, "keep\n").unwrap();
    let plant = |out: &Path| {
        std::fs::create_dir_all(out.join("replicas")).unwrap();
        std::os::unix::fs::symlink(&precious, out.join("replicas/r00000.h5.part")).unwrap();
    };
    let a = tmp.path().join("a");
    plant(&a);
    let o = run(&[
        "run",
        spec.to_str().unwrap(),
        "-o",
        a.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&precious).unwrap(), "keep\n");
    let b = tmp.path().join("b");
    plant(&b);
    let o = run(&["merge", a.to_str().unwrap(), "-o", b.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&precious).unwrap(), "keep\n");
    assert!(b.join("replicas/r00000.h5").is_file());
    assert!(!crate::common::listing(&b.join("replicas"))
        .iter()
        .any(|f| f.ends_with(".part")));
}

/// A column on a floor that takes all the energy of a bounce (`wall_eps` 0, gravity 1): the grains
/// bounce ever lower and pair collisions cease long before τ = 50. The run must not say `done`: it
/// ends `stalled` with the wall-collision cascade named, exit 2.
#[test]
fn a_column_on_a_dissipating_floor_stalls_and_says_so() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "col.json",
        r#"{"name": "col", "seed": 1,
            "grid": {"dim": 2, "boundary": "walls", "eps": 0.9, "phi": 0.1, "n": 64,
                     "wall_eps": 0, "gravity": 1},
            "stop": {"tau_max": 50}, "samples": {"every": 5, "per_decade": 0}}"#,
    );
    let out = tmp.path().join("out");
    let o = run(&[
        "run",
        spec.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let rows = statuses(&out);
    assert_eq!(rows.len(), 1);
    let (status, message) = &rows[0];
    assert_eq!(status, "stalled", "{message}");
    assert!(message.contains("wall-collision cascade"), "{message}");
    assert!(message.contains("wall_eps = 0"), "{message}");
    let phase = std::fs::read_to_string(out.join("phase.json")).unwrap();
    assert!(phase.contains("\"stalled\": 1"), "{phase}");
    let status = edmd()
        .args(["status", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&status.stdout).contains("1 stalled"));
}

/// A mixture of masses 1 and 10⁶ whose light grains get caught between heavy ones: the clock stops
/// at τ ≈ 70.75, less than 10 τ before the end of a run to τ 85. The sliding clock check sees the
/// stall there exactly as in a run to τ 200: `collapsed (ClockStalled)` at the same τ (a check
/// every 10 N collisions missed it at τ 85 and found it at τ 90.004 in the longer run).
#[test]
fn a_clock_stall_in_the_last_window_is_seen() {
    let tmp = tempfile::tempdir().unwrap();
    let mut seen = Vec::new();
    for tau in [85, 200] {
        let spec = write(
            tmp.path(),
            &format!("mix{tau}.json"),
            &format!(
                r#"{{"name": "mix", "seed": 1,
                "grid": {{"dim": 2, "eps": 0.9, "phi": 0.1, "n": 256,
                         "species": [{{"fraction": 0.5, "diameter": 1, "mass": 1}},
                                     {{"fraction": 0.5, "diameter": 1, "mass": 1e6}}]}},
                "stop": {{"tau_max": {tau}}}, "samples": {{"every": 1, "per_decade": 0}}}}"#
            ),
        );
        let out = tmp.path().join(format!("out{tau}"));
        let o = run(&[
            "run",
            spec.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "-q",
        ]);
        assert_eq!(o.status.code(), Some(2), "tau_max {tau}: {}", stderr(&o));
        let (status, message) = statuses(&out).remove(0);
        assert_eq!(status, "collapsed", "tau_max {tau}: {message}");
        assert!(message.contains("ClockStalled"), "tau_max {tau}: {message}");
        seen.push(message);
    }
    assert_eq!(
        seen[0], seen[1],
        "the stall is found where it is, whatever the stop"
    );
}

/// With N = 3 and 50 log samples per decade from τ 0.01, many schedule points fall on one pair
/// collision. Each collision is sampled once: the steps rise strictly, and the compressibility is
/// NaN only at the first sample (before that, repeated samples read the virial over no time: NaN).
#[test]
fn schedule_points_on_one_collision_give_one_sample() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "few.json",
        r#"{"name": "few", "seed": 2,
            "grid": {"dim": 2, "eps": 0.9, "phi": 0.1, "n": 3},
            "stop": {"tau_max": 20},
            "samples": {"every": 1, "per_decade": 50, "log_from": 0.01},
            "snapshots": {"at": [0.01, 0.011, 5], "final": true}}"#,
    );
    let out = tmp.path().join("out");
    let o = run(&[
        "run",
        spec.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.code().is_some_and(|c| c <= 2), "{}", stderr(&o));
    let f = hdf5::File::open(out.join("replicas/r00000.h5")).unwrap();
    let step: Vec<i64> = f
        .dataset("observables/compressibility/step")
        .unwrap()
        .read_raw()
        .unwrap();
    let z: Vec<f64> = f
        .dataset("observables/compressibility/value")
        .unwrap()
        .read_raw()
        .unwrap();
    assert!(step.len() > 10, "{step:?}");
    assert!(
        step.windows(2).all(|w| w[0] < w[1]),
        "repeated samples: {step:?}"
    );
    assert!(z[0].is_nan());
    let nan: Vec<usize> = (1..z.len()).filter(|&k| z[k].is_nan()).collect();
    assert!(nan.is_empty(), "NaN at samples {nan:?} of {}", z.len());
    let snap: Vec<i64> = f
        .dataset("particles/gas/position/step")
        .unwrap()
        .read_raw()
        .unwrap();
    assert!(
        snap.windows(2).all(|w| w[0] < w[1]),
        "repeated snapshots: {snap:?}"
    );
}
