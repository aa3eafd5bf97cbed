//! `edmd refine`: rounds that resume after SIGKILL to the same output, shards and `--plan` that
//! give what one process gives, a spec that reruns the refinement exactly, and refusals.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::common::{assert_same_output, edmd, listing, run, write};

/// The (ε, box) plane of disks at φ = 0.25 on a 3 × 3 grid; every replica runs to τ = 400. Boxes of
/// 10–40 diameters (N 32–509): the labels still change along both axes, so two rounds add points
/// (23 files against the start's 9), in a third of the time boxes of 20–80 took.
fn plane(name: &str) -> String {
    format!(
        r#"{{
  "name": "{name}",
  "seed": 11,
  "grid": {{ "eps": [0.6, 0.8, 1.0], "phi": 0.25, "box": [10, 20, 40] }},
  "stop": {{ "tau_max": 400 }},
  "samples": {{ "every": 10, "per_decade": 10, "log_from": 0.1 }},
  "snapshots": {{ "final": true }},
  "classify": {{}}
}}"#
    )
}

/// Runs `spec` into `dir/base` and copies it to each of `copies`.
fn base(dir: &Path, spec: &str, copies: &[&str]) {
    let s = write(dir, "s.json", spec);
    let b = dir.join("base");
    let o = run(&["run", s.to_str().unwrap(), "-o", b.to_str().unwrap(), "-q"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for c in copies {
        let st = std::process::Command::new("cp")
            .args(["-a", b.to_str().unwrap(), dir.join(c).to_str().unwrap()])
            .status()
            .unwrap();
        assert!(st.success());
    }
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn refine(out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec!["refine", out.to_str().unwrap(), "--rounds", "2", "-q"];
    args.extend_from_slice(extra);
    run(&args)
}

/// The refinement, its files and its spec agree between two outputs.
fn assert_same_refinement(a: &Path, b: &Path) {
    assert_same_output(a, b);
    // (summary.csv and summary.json carry wall-clock times; sweep.h5 was compared without them.)
    for f in ["spec.json", "boundary.json", "phase.json"] {
        assert_eq!(read(&a.join(f)), read(&b.join(f)), "{f} differs");
    }
}

/// SIGKILL during a refinement round, rerun: the output equals an uninterrupted refinement.
#[test]
fn killed_refinement_resumes_to_the_same_output() {
    let tmp = tempfile::tempdir().unwrap();
    base(tmp.path(), &plane("kill"), &["clean", "killed"]);
    let clean = tmp.path().join("clean");
    let o = refine(&clean, &["-j", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let clean_files = listing(&clean.join("replicas")).len();
    assert!(clean_files > 9, "the refinement added no replica");

    let killed = tmp.path().join("killed");
    let mut child = edmd()
        .args([
            "refine",
            killed.to_str().unwrap(),
            "--rounds",
            "2",
            "-j",
            "1",
            "-q",
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Kill once the first round has written a file of its own (its spec is then on disk).
    let replicas = killed.join("replicas");
    let deadline = Instant::now() + Duration::from_secs(120);
    while !replicas.join("r00009.h5").exists() {
        assert!(Instant::now() < deadline, "refinement made no progress");
        assert!(
            child.try_wait().unwrap().is_none(),
            "refinement ended before the kill"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let finished = listing(&replicas)
        .iter()
        .filter(|f| f.ends_with(".h5"))
        .count();
    assert!(
        finished < clean_files,
        "the refinement finished before the kill"
    );
    assert!(
        !killed.join("boundary.json").exists(),
        "boundary written by a killed round"
    );
    let o = refine(&killed, &["-j", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_same_refinement(&killed, &clean);
}

/// Shards of each round and `--plan` between them (what sweeps/slurm/refine.sh submits) give the
/// unsharded refinement; the spec written to OUT reruns it exactly with `edmd run`.
#[test]
fn sharded_rounds_and_a_rerun_of_the_spec_equal_the_refinement() {
    let tmp = tempfile::tempdir().unwrap();
    base(tmp.path(), &plane("shard"), &["whole", "sharded"]);
    let whole = tmp.path().join("whole");
    let o = refine(&whole, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let sharded = tmp.path().join("sharded");
    let s = sharded.to_str().unwrap();
    for round in 1..=2 {
        let o = run(&["refine", s, "--rounds", &round.to_string(), "--plan"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        for k in 0..3 {
            let o = run(&["refine", s, "--shard", &format!("{k}/3"), "-q"]);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        }
    }
    let o = run(&["refine", s, "--rounds", "2", "--plan"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_same_refinement(&sharded, &whole);

    // The spec written by the refinement reruns every replica: the same files.
    let rerun = tmp.path().join("rerun");
    let spec = whole.join("spec.json");
    let o = run(&[
        "run",
        spec.to_str().unwrap(),
        "-o",
        rerun.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_same_refinement(&rerun, &whole);
}

#[test]
fn refusals_name_the_problem() {
    let tmp = tempfile::tempdir().unwrap();
    base(tmp.path(), &plane("refuse"), &[]);
    let b = tmp.path().join("base");
    let o = refine(&b, &["--axes", "eps,temperature"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("unknown axis \"temperature\""));
    let o = refine(&b, &["--axes", "phi"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--axes phi: no grid of the spec"));
    let o = run(&["refine", b.to_str().unwrap(), "--shard", "0/2", "--plan"]);
    assert_eq!(
        o.status.code(),
        Some(64),
        "--shard with --plan is a usage error"
    );
    // Nothing was written by the refusals.
    assert!(!read(&b.join("spec.json")).contains("refinement"));

    let o = run(&[
        "refine",
        b.to_str().unwrap(),
        "--rounds",
        "1",
        "--axes",
        "eps",
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // Other axes than the first round's, and the original spec into the refined output: refused.
    let o = refine(&b, &["--axes", "box"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("was refined along eps"));
    let spec = tmp.path().join("s.json");
    let o = run(&[
        "run",
        spec.to_str().unwrap(),
        "-o",
        b.to_str().unwrap(),
        "-q",
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("holds a refinement of this sweep"));

    // A sweep without classification has no regimes to refine.
    let plain = plane("plain").replace(",\n  \"classify\": {}", "");
    let s = write(tmp.path(), "plain.json", &plain);
    let out = tmp.path().join("plain");
    let o = run(&[
        "run",
        s.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success());
    let o = refine(&out, &[]);
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no \"classify\" section"));
}
