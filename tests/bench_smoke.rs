//! Smoke run of `edmd-bench`: one small 2D case runs to the end and prints the line scripts parse.
//!
//! Part of `cargo test --workspace`, so the binary comes from the same test-profile build as every
//! other test (a separate `cargo run --bin edmd-bench` would build the dependencies again with other
//! features). It checks that the benchmark works, not how fast: measurements are `make bench`.

use std::process::Command;

#[test]
fn edmd_bench_runs_one_case_and_prints_its_summary_line() {
    let out = Command::new(env!("CARGO_BIN_EXE_edmd-bench"))
        .args(["--d", "2", "--n", "10000", "--phi", "0.3", "--repeats", "1"])
        .args(["--collisions-per-particle", "5"])
        .output()
        .expect("edmd-bench starts");
    let stdout = String::from_utf8_lossy(&out.stdout);
    eprintln!("{stdout}");
    assert!(
        out.status.success(),
        "edmd-bench failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let last = stdout.lines().last().expect("edmd-bench printed nothing");
    let value = |key: &str| -> f64 {
        let field = last
            .split_whitespace()
            .find_map(|f| f.strip_prefix(key))
            .unwrap_or_else(|| panic!("no `{key}` in the last line {last:?}"));
        field
            .parse()
            .unwrap_or_else(|e| panic!("`{key}{field}`: {e}"))
    };
    let rate = value("collisions_per_s=");
    let bytes = value("bytes_per_particle=");
    assert!(rate > 0.0 && rate.is_finite(), "collisions_per_s = {rate}");
    // Records, cells and calendar of the 2D engine: below the budget of 200 bytes per particle held
    // at N = 10^6 (docs/benchmarks.md; fixed costs weigh more at this N), above the 32 bytes of
    // positions and velocities alone.
    assert!(
        (32.0..200.0).contains(&bytes),
        "bytes_per_particle = {bytes}"
    );
}

#[test]
fn edmd_bench_refuses_a_bad_case_naming_the_field() {
    let out = Command::new(env!("CARGO_BIN_EXE_edmd-bench"))
        .args(["--d", "4", "--n", "100", "--phi", "0.3"])
        .output()
        .expect("edmd-bench starts");
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--d = 4"), "stderr: {stderr}");
}

/// `--cool-from` times a cooling gas and `--json` reports the events per collision by kind: each
/// collision is one event, and a 2D gas in cell mode crosses cells between collisions.
#[test]
fn edmd_bench_times_free_cooling_and_reports_events_by_kind() {
    let out = Command::new(env!("CARGO_BIN_EXE_edmd-bench"))
        .args(["--d", "2", "--n", "1000", "--phi", "0.25", "--eps", "0.9"])
        .args(["--cool-from", "5", "--collisions-per-particle", "5"])
        .args(["--repeats", "1", "--json"])
        .output()
        .expect("edmd-bench starts");
    assert!(
        out.status.success(),
        "edmd-bench failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    let last = stdout.lines().last().expect("edmd-bench printed nothing");
    let report: serde_json::Value = serde_json::from_str(last).expect("one JSON line");
    assert_eq!(report["cool_from"], 5.0, "{report}");
    assert_eq!(report["neighbours"], "cells", "{report}");
    let per = &report["events_per_collision"];
    let events = per["events"].as_f64().expect("events");
    let parts: f64 = ["stale", "crossings", "walls", "system"]
        .iter()
        .map(|k| per[k].as_f64().expect(k))
        .sum();
    // Every event is a pair collision or one of the kinds counted beside it.
    assert!((events - 1.0 - parts).abs() < 1e-3, "{per}");
    assert!(per["crossings"].as_f64().unwrap() > 0.0, "{per}");
}
