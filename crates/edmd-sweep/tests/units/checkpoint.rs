//! A replica stopped by the interrupt flag (what a signal sets) at several moments and resumed from
//! its checkpoints ends with the outcome of an uninterrupted run, sample for sample and bit for bit:
//! 2D cells, 3D lists with walls, a sheared box of rough grains with the TC remedy. The resumed runs
//! start from their checkpoints, not from τ = 0.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use edmd_sweep::checkpoint::{read_header, Checkpoints};
use edmd_sweep::replica::{self, Outcome};
use edmd_sweep::spec::Spec;

/// The outcome of replica 0 of `spec` interrupted each time it passes one of `stops` (pair
/// collisions) and run again; returns it with the collisions each resumed run started from.
fn interrupted_at(spec: &Spec, stops: &[u64]) -> (Outcome, Vec<u64>) {
    let dir = tempfile::tempdir().unwrap();
    let r = &spec.replicas()[0];
    let mut started_from = Vec::new();
    for &stop in stops {
        let flag = AtomicBool::new(false);
        let ckpts = Checkpoints::new(spec, dir.path().to_path_buf(), &flag);
        let done = AtomicU64::new(0);
        let progress = |c: u64| {
            if done.fetch_add(c, Ordering::Relaxed) + c >= stop {
                flag.store(true, Ordering::Relaxed);
            }
        };
        let out = replica::run_with(spec, r, &progress, Some(&ckpts));
        assert!(
            out.is_none(),
            "the stop at {stop} collisions came after the end"
        );
        assert!(ckpts.notices.lock().unwrap().is_empty());
        started_from.push(ckpts.resumed_collisions());
        let header = read_header(&ckpts.path(r.index)).unwrap();
        assert!(header.collisions >= stop && header.reason == "signal");
    }
    let flag = AtomicBool::new(false);
    let ckpts = Checkpoints::new(spec, dir.path().to_path_buf(), &flag);
    let out = replica::run_with(spec, r, &|_| {}, Some(&ckpts)).expect("runs to the end");
    started_from.push(ckpts.resumed_collisions());
    (out, started_from)
}

fn same(a: &Outcome, b: &Outcome) {
    assert_eq!(a.status, b.status);
    assert_eq!(a.message, b.message);
    assert_eq!(a.collisions, b.collisions);
    assert_eq!(a.t0.to_bits(), b.t0.to_bits());
    assert_eq!(a.collapse, b.collapse);
    assert_eq!(a.snapshots, b.snapshots);
    // Series and verdicts hold NaN (the first compressibility, the Haff deviation before its
    // fit): compare them through Debug, which prints every bit that matters.
    assert_eq!(format!("{:?}", a.series), format!("{:?}", b.series));
    assert_eq!(
        format!("{:?}", a.classification),
        format!("{:?}", b.classification)
    );
    assert_eq!(format!("{:?}", a.bed), format!("{:?}", b.bed));
}

fn check(text: &str, stops: &[u64]) {
    let spec = Spec::from_json(text).unwrap();
    let whole = replica::run(&spec, &spec.replicas()[0], &|_| {});
    let (resumed, from) = interrupted_at(&spec, stops);
    same(&whole, &resumed);
    // The first run starts from nothing, every later one from the previous checkpoint.
    assert_eq!(from[0], 0);
    for (k, &c) in from[1..].iter().enumerate() {
        assert!(
            c >= stops[k],
            "run {} started from {c}, not from its checkpoint",
            k + 1
        );
    }
}

#[test]
fn a_cooling_gas_in_cells_resumes_bit_for_bit() {
    check(
        r#"{ "name": "c", "seed": 4, "grid": { "dim": 2, "eps": 0.8, "phi": 0.25, "n": 500 },
             "stop": { "tau_max": 120 }, "samples": { "every": 5, "per_decade": 5 },
             "snapshots": { "every": 40, "final": true }, "classify": {} }"#,
        &[7_000, 23_456, 40_000],
    );
}

#[test]
fn dense_spheres_in_lists_resume_bit_for_bit() {
    check(
        r#"{ "name": "l", "seed": 2, "grid": { "dim": 3, "boundary": "walls", "eps": 0.9,
             "phi": 0.45, "n": 600 },
             "stop": { "tau_max": 60 }, "samples": { "every": 3 }, "snapshots": { "final": true } }"#,
        &[5_000, 21_000],
    );
}

#[test]
fn sheared_rough_grains_with_tc_resume_bit_for_bit() {
    check(
        r#"{ "name": "s", "seed": 3, "grid": { "dim": 2, "boundary": "lees-edwards",
             "shear_rate": 0.05, "eps": 0.7, "beta": 0.5, "phi": 0.2, "n": 400,
             "remedy": { "kind": "tc", "tc": 0.0001 } },
             "stop": { "tau_max": 80 }, "samples": { "every": 2 }, "snapshots": { "every": 20 } }"#,
        &[3_000, 17_000],
    );
}

/// A shaken bed interrupted before and while its uniform-time meter runs (from τ 40 of 80): the
/// meter's sums travel in the checkpoint, and its time stops fall where they would have.
#[test]
fn a_shaken_bed_resumes_bit_for_bit() {
    let spec = Spec::from_json(SHAKEN).unwrap();
    let whole = replica::run(&spec, &spec.replicas()[0], &|_| {});
    assert!(whole.bed.as_ref().is_some_and(|b| b.samples > 100));
    check(SHAKEN, &[3_000, 9_000, 13_000]);
}

const SHAKEN: &str = r#"{ "name": "b", "seed": 5, "grid": { "dim": 2, "boundary": "channel",
    "eps": 0.9, "n": 200, "box": 100, "aspect": [0.5, 1], "gravity": 1, "wall_eps": 0.9,
    "remedy": { "kind": "tc", "tc": 0.001 }, "shake_s": 10, "shake_gamma": 4 },
    "stop": { "tau_max": 80 }, "samples": { "every": 10, "per_decade": 0 } }"#;

/// A checkpoint whose engine state cannot be used (cut short here; another build's layout in
/// practice) is not a failure: the replica starts over, says so, and ends as an uninterrupted run.
#[test]
fn an_unusable_engine_state_starts_the_replica_over() {
    let spec = Spec::from_json(
        r#"{ "name": "c", "seed": 4, "grid": { "dim": 2, "eps": 0.8, "phi": 0.25, "n": 300 },
             "stop": { "tau_max": 40 }, "samples": { "every": 5 } }"#,
    )
    .unwrap();
    let r = &spec.replicas()[0];
    let whole = replica::run(&spec, r, &|_| {});
    let dir = tempfile::tempdir().unwrap();
    let flag = AtomicBool::new(false);
    let ckpts = Checkpoints::new(&spec, dir.path().to_path_buf(), &flag);
    let stop = |c: u64| flag.store(c > 0, Ordering::Relaxed);
    assert!(replica::run_with(&spec, r, &stop, Some(&ckpts)).is_none());
    let path = ckpts.path(r.index);
    let mut bytes = std::fs::read(&path).unwrap();
    bytes.truncate(bytes.len() - 64);
    std::fs::write(&path, bytes).unwrap();
    let flag = AtomicBool::new(false);
    let ckpts = Checkpoints::new(&spec, dir.path().to_path_buf(), &flag);
    let out = replica::run_with(&spec, r, &|_| {}, Some(&ckpts)).expect("runs to the end");
    let notices = ckpts.notices.lock().unwrap().clone();
    assert!(
        notices.iter().any(|m| m.contains("starts over")),
        "{notices:?}"
    );
    same(&whole, &out);
}
