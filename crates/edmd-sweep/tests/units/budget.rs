//! Unit tests of `budget`.

use edmd_sweep::budget::*;
use edmd_sweep::spec::Spec;

fn spec(n: &str, extra: &str) -> Spec {
    Spec::from_json(&format!(
        r#"{{"name": "m", "grid": {{"eps": 0.9, "phi": 0.2, "n": {n}}}, "stop": {{"tau_max": 10}}{extra}}}"#
    ))
    .unwrap()
}

#[test]
fn a_replica_above_the_limit_names_n_and_the_estimate() {
    let s = spec("1000000000", "");
    let err = check_memory(&s, &s.replicas(), 1, MemoryLimit::new(Some(1 << 30)))
        .unwrap_err()
        .to_string();
    assert!(err.contains("grid.n = 1000000000"), "{err}");
    assert!(err.contains("GiB of memory"), "{err}");
    assert!(err.contains("--max-memory of 1.0 GiB"), "{err}");
}

#[test]
fn too_many_at_once_names_threads_and_how_many_fit() {
    let s = spec("[1000000, 1000001, 1000002, 1000003]", "");
    let one = replica_bytes(&s, &s.replicas()[0]).total();
    let limit = MemoryLimit::new(Some((2.5 * one) as u64));
    let err = check_memory(&s, &s.replicas(), 4, limit)
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("--threads 4: 4 replicas at once"), "{err}");
    assert!(err.contains("use --threads 2 or fewer"), "{err}");
    assert!(check_memory(&s, &s.replicas(), 2, limit).is_ok());
}

#[test]
fn snapshots_dominate_when_many_are_stored() {
    let at: Vec<String> = (0..5000).map(|k| (k as f64 * 0.002).to_string()).collect();
    let s = spec(
        "100000",
        &format!(r#", "snapshots": {{"at": [{}]}}"#, at.join(",")),
    );
    let err = check_memory(&s, &s.replicas(), 1, MemoryLimit::new(Some(1 << 30)))
        .unwrap_err()
        .to_string();
    assert!(err.contains("spec: snapshots.at = 5000 times"), "{err}");
}

#[test]
fn a_snapshot_grid_is_named_with_its_count() {
    let s = spec("100000", r#", "snapshots": {"every": 0.002}"#);
    assert_eq!(snapshots_per_replica(&s), 1 + 5001 + 1 + 1);
    let err = check_memory(&s, &s.replicas(), 1, MemoryLimit::new(Some(1 << 30)))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("spec: snapshots.every = 0.002 (5004 snapshots)"),
        "{err}"
    );
}

#[test]
fn bytes_print_in_binary_units() {
    assert_eq!(Bytes(512.0).to_string(), "512 B");
    assert_eq!(Bytes(1536.0).to_string(), "1.5 KiB");
    assert_eq!(Bytes(3.0 * (1u64 << 30) as f64).to_string(), "3.0 GiB");
}
