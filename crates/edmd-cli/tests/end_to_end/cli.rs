//! End-to-end tests of the `edmd` binary: determinism across thread counts, resume after SIGKILL,
//! sharding and merge, the ready specs, and clear errors for bad input.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::{assert_same_output, dump, edmd, listing, run, small_spec, write};

/// Replica results do not depend on the number of threads.
#[test]
fn results_are_bit_identical_across_thread_counts() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("threads", &[0.9, 0.7], 256, 3, 20.0),
    );
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    for (dir, threads) in [(&a, "1"), (&b, "2")] {
        let o = run(&[
            "run",
            spec.to_str().unwrap(),
            "-o",
            dir.to_str().unwrap(),
            "-j",
            threads,
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    assert_eq!(listing(&a.join("replicas")).len(), 6);
    assert_same_output(&a, &b);
}

/// SIGKILL mid-sweep, rerun the same command: the output equals an uninterrupted run, and no file
/// under a final name is ever incomplete.
#[test]
fn killed_sweep_resumes_to_the_same_output() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("kill", &[0.95, 0.9, 0.85, 0.8, 0.75, 0.7], 512, 4, 200.0),
    );
    let spec = spec.to_str().unwrap();
    let killed = tmp.path().join("killed");
    let killed_s = killed.to_str().unwrap();
    let mut child = edmd()
        .args(["run", spec, "-o", killed_s, "-j", "2", "-q"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let replicas = killed.join("replicas");
    let deadline = Instant::now() + Duration::from_secs(120);
    let done = |d: &Path| listing(d).iter().filter(|f| f.ends_with(".h5")).count();
    while done(&replicas) < 4 {
        assert!(Instant::now() < deadline, "sweep made no progress");
        assert!(
            child.try_wait().unwrap().is_none(),
            "sweep ended before it could be killed"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let finished = done(&replicas);
    assert!(finished < 24, "the sweep finished before the kill");
    // Every file under a final name is complete: it opens and holds the final snapshot.
    for f in listing(&replicas).iter().filter(|f| f.ends_with(".h5")) {
        let d = dump(&replicas.join(f));
        assert!(
            d.contains_key("/particles/gas/position/value"),
            "{f} incomplete"
        );
        assert!(
            d.contains_key("/observables/temperature/value"),
            "{f} incomplete"
        );
    }
    assert!(
        !killed.join("sweep.h5").exists(),
        "index written by an incomplete sweep"
    );
    let o = run(&["run", spec, "-o", killed_s, "-j", "2"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(
        msg.contains(&format!("ran {} of 24 replicas", 24 - finished)),
        "resume reran finished replicas: {msg}"
    );
    assert!(
        listing(&replicas).iter().all(|f| f.ends_with(".h5")),
        "partial files left"
    );
    let clean = tmp.path().join("clean");
    let o = run(&["run", spec, "-o", clean.to_str().unwrap(), "-j", "2", "-q"]);
    assert!(o.status.success());
    assert_same_output(&killed, &clean);
}

/// Three shards merged give what one unsharded run gives, whether the shards write to separate
/// directories (merged with -o) or to one shared directory (indexed in place).
#[test]
fn shards_merge_to_the_unsharded_output() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("shards", &[0.9, 0.8], 256, 4, 15.0),
    );
    let spec = spec.to_str().unwrap();
    let whole = tmp.path().join("whole");
    assert!(run(&["run", spec, "-o", whole.to_str().unwrap(), "-q"])
        .status
        .success());
    let shared = tmp.path().join("shared");
    let mut parts = Vec::new();
    for k in 0..3 {
        let dir = tmp.path().join(format!("part{k}"));
        let shard = format!("{k}/3");
        let o = run(&[
            "run",
            spec,
            "-o",
            dir.to_str().unwrap(),
            "--shard",
            &shard,
            "-q",
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(
            !dir.join("sweep.h5").exists(),
            "a shard wrote the index of a partial sweep"
        );
        let o = run(&[
            "run",
            spec,
            "-o",
            shared.to_str().unwrap(),
            "--shard",
            &shard,
            "-q",
        ]);
        assert!(o.status.success());
        parts.push(dir);
    }
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge", "-o", merged.to_str().unwrap()];
    args.extend(parts.iter().map(|p| p.to_str().unwrap()));
    let o = run(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_same_output(&whole, &merged);
    // The last shard into the shared directory completed the sweep and built its index.
    assert_same_output(&whole, &shared);
    assert!(run(&["merge", shared.to_str().unwrap()]).status.success());
    assert_same_output(&whole, &shared);
    // Merging an incomplete set says which replicas are missing.
    let partial = tmp.path().join("partial");
    let o = run(&[
        "merge",
        "-o",
        partial.to_str().unwrap(),
        parts[0].to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing"));
}

/// Every ready spec in sweeps/ is valid.
#[test]
fn ready_specs_validate() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sweeps");
    let mut n = 0;
    for f in listing(&dir).iter().filter(|f| f.ends_with(".json")) {
        let p = dir.join(f);
        let o = run(&["validate-spec", p.to_str().unwrap()]);
        assert!(
            o.status.success(),
            "{f}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        n += 1;
    }
    assert!(
        n >= 3,
        "expected the ready specs quick, thesis, mcnamara-young"
    );
}

/// One bad-input case: the command fails with exit code 1 and one clear error line containing
/// `expect`, without panicking, and leaves no output behind.
fn assert_rejected(args: &[&str], expect: &str, out: &Path) {
    assert_output_rejected(run(args), args, expect, out);
}

/// [`assert_rejected`] of a command run in `dir` (the corpus names its configuration files
/// relative to itself).
fn assert_rejected_in(dir: &Path, args: &[&str], expect: &str, out: &Path) {
    let o = edmd()
        .current_dir(dir)
        .args(args)
        .output()
        .expect("edmd starts");
    assert_output_rejected(o, args, expect, out);
}

fn assert_output_rejected(o: std::process::Output, args: &[&str], expect: &str, out: &Path) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "{args:?}: not one line: {err}"
    );
    assert!(err.starts_with("error: "), "{err}");
    assert!(
        err.contains(expect),
        "{args:?}: {err:?} does not name {expect:?}"
    );
    assert!(!out.exists(), "{args:?} left {} behind", out.display());
}

/// Every spec of the shared corpus `tests/specs/bad/` (also read by pytest) is refused by `run` and
/// `validate-spec` with one line holding its `.expect` text, and nothing is written.
#[test]
fn bad_specs_are_rejected_with_one_clear_line() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/specs/bad");
    let mut cases: Vec<_> = std::fs::read_dir(&corpus)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    cases.sort();
    assert!(cases.len() >= 20, "corpus of {} cases", cases.len());
    for p in &cases {
        let expect = std::fs::read_to_string(p.with_extension("expect")).unwrap();
        let expect = expect.trim_end();
        let spec = p.to_str().unwrap();
        let o = out.to_str().unwrap();
        assert_rejected_in(&corpus, &["run", spec, "-o", o], expect, &out);
        assert_rejected_in(&corpus, &["validate-spec", spec], expect, &out);
    }
    let good = small_spec("bad", &[0.9], 64, 1, 1.0);
    let p = write(tmp.path(), "good.json", &good);
    let p = p.to_str().unwrap();
    let o = out.to_str().unwrap();
    assert_rejected(&["run", p, "-o", o, "--shard", "3/3"], "--shard 3/3", &out);
    assert_rejected(&["run", p, "-o", o, "-j", "0"], "--threads 0", &out);
    assert_rejected(
        &["run", "/nonexistent/spec.json", "-o", o],
        "cannot read spec",
        &out,
    );
    // Not a spec: read no further than 1 MiB, refused by size.
    assert_rejected(
        &["run", "/dev/zero", "-o", o],
        "/dev/zero: the file is larger than 1048576 bytes",
        &out,
    );
    let nowhere = Path::new("/dev/null/edmd-out");
    assert_rejected(
        &["run", p, "-o", nowhere.to_str().unwrap()],
        "cannot create output directory /dev/null/edmd-out",
        nowhere,
    );
}

/// An output directory of one spec is never mixed with another spec's replicas.
#[test]
fn output_of_a_different_spec_is_refused_unless_forced() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let a = write(tmp.path(), "a.json", &small_spec("a", &[0.9], 64, 1, 1.0));
    let b = write(tmp.path(), "b.json", &small_spec("a", &[0.8], 64, 1, 1.0));
    assert!(run(&["run", a.to_str().unwrap(), "-o", o, "-q"])
        .status
        .success());
    let before = dump(&out.join("replicas/r00000.h5"));
    let spec_before = std::fs::read_to_string(out.join("spec.json")).unwrap();
    let r = run(&["run", b.to_str().unwrap(), "-o", o, "-q"]);
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(
        err.contains("holds a different sweep") && err.contains("--force"),
        "{err}"
    );
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert_eq!(
        std::fs::read_to_string(out.join("spec.json")).unwrap(),
        spec_before
    );
    assert_eq!(
        dump(&out.join("replicas/r00000.h5")),
        before,
        "old output touched"
    );
    let r = run(&["run", b.to_str().unwrap(), "-o", o, "-q", "--force"]);
    assert!(r.status.success());
    assert_ne!(dump(&out.join("replicas/r00000.h5")), before);
}

/// A start no lattice reaches is refused before anything runs; a replica that collapses is recorded,
/// the sweep goes on and exits 2.
#[test]
fn unreachable_starts_are_refused_and_collapsed_replicas_recorded() {
    let tmp = tempfile::tempdir().unwrap();
    // phi = 0.905 is below close packing, but no lattice start of 64 disks reaches it: refused
    // before anything runs (it used to fail at run time), naming the replica and the limit.
    let bad = write(
        tmp.path(),
        "bad.json",
        r#"{"name": "problems", "grid": {"eps": 0.9, "phi": 0.905, "n": 64}, "stop": {"tau_max": 200}}"#,
    );
    let bad_out = tmp.path().join("bad-out");
    let o = run(&[
        "run",
        bad.to_str().unwrap(),
        "-o",
        bad_out.to_str().unwrap(),
        "-q",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("replica 0") && err.contains("at most 0.7854"),
        "{err}"
    );
    assert!(!bad_out.exists(), "nothing written for a refused spec");
    // 100 disks at phi = 0.6 and eps = 0.02 collapse near tau = 60.
    let spec = r#"{
  "name": "problems",
  "grid": [
    { "eps": 0.9, "phi": 0.3, "n": 64 },
    { "eps": 0.02, "phi": 0.6, "n": 100 }
  ],
  "stop": { "tau_max": 200 }
}"#;
    let p = write(tmp.path(), "p.json", spec);
    let out = tmp.path().join("out");
    let o = run(&[
        "run",
        p.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("collapsed: replica 1"), "{err}");
    let csv = std::fs::read_to_string(out.join("summary.csv")).unwrap();
    let status: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap())
        .collect();
    assert_eq!(status, ["done", "collapsed"]);
    let s = run(&["status", out.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&s.stdout);
    assert!(
        text.contains("1 done, 1 collapsed, 0 stalled, 0 failed"),
        "{text}"
    );
}

/// `edmd bench-replica` runs a replica's runner and its engine alone and prints their ratio; an
/// index outside the sweep is refused in one line.
#[test]
fn bench_replica_compares_the_runner_with_the_engine() {
    let tmp = tempfile::tempdir().unwrap();
    let p = write(tmp.path(), "s.json", &small_spec("b", &[0.9], 128, 1, 20.0));
    let p = p.to_str().unwrap();
    let o = run(&["bench-replica", p, "--rounds", "1", "--json"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let ratio: f64 = out
        .split("\"median_ratio\": ")
        .nth(1)
        .and_then(|x| x.trim().trim_end_matches('}').parse().ok())
        .unwrap_or_else(|| panic!("no ratio in {out}"));
    assert!(ratio > 0.1 && ratio < 10.0, "{out}");
    let bad = run(&["bench-replica", p, "--replica", "5"]);
    let err = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(1), "{err}");
    assert!(
        err.contains("--replica 5: the sweep has 1 replicas"),
        "{err}"
    );
}
