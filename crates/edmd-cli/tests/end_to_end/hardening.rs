//! End-to-end tests of what a sweep does when the world misbehaves: a disk that fills, replica files
//! corrupted after the fact, two runs into one output, command-line misuse and oversized values.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::{assert_same_output, dump, edmd, listing, run, small_spec, write};

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A tmpfs of `size` mounted at `dir` for the test's lifetime (needs root and a kernel that lets
/// this process mount; `None` otherwise).
struct Tmpfs<'a>(&'a Path);

impl<'a> Tmpfs<'a> {
    fn mount(dir: &'a Path, size: &str) -> Option<Tmpfs<'a>> {
        std::fs::create_dir_all(dir).ok()?;
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", &format!("size={size}"), "tmpfs"])
            .arg(dir)
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success());
        ok.then_some(Tmpfs(dir))
    }

    fn resize(&self, size: &str) {
        let s = Command::new("mount")
            .args(["-o", &format!("remount,size={size}")])
            .arg(self.0)
            .status()
            .unwrap();
        assert!(s.success(), "remount failed");
    }
}

/// Whether a file system is mounted at `dir` (by /proc/self/mounts).
fn mounted(dir: &Path) -> bool {
    let dir = std::fs::canonicalize(dir).unwrap_or_else(|_| dir.to_path_buf());
    std::fs::read_to_string("/proc/self/mounts")
        .unwrap_or_default()
        .lines()
        .any(|l| l.split(' ').nth(1) == Some(dir.to_str().unwrap_or_default()))
}

impl Drop for Tmpfs<'_> {
    /// Unmounts, detaching lazily when something still holds the file system (the memory is freed
    /// when the last holder lets go), and checks that the mount is gone: a test must not leave RAM
    /// mounted on the machine that ran it.
    fn drop(&mut self) {
        let umount = |lazy: bool| {
            let mut c = Command::new("umount");
            if lazy {
                c.arg("-l");
            }
            c.arg(self.0)
                .stderr(Stdio::null())
                .status()
                .is_ok_and(|s| s.success())
        };
        let _ = umount(false) || umount(true);
        if mounted(self.0) && !std::thread::panicking() {
            panic!("the test's tmpfs is still mounted at {}", self.0.display());
        }
    }
}

/// Every file under a final name in `replicas` is whole: it opens and holds its last temperature.
fn assert_final_files_whole(replicas: &Path) {
    for f in listing(replicas).iter().filter(|f| f.ends_with(".h5")) {
        let d = dump(&replicas.join(f));
        assert!(
            d.contains_key("/observables/temperature/value"),
            "{f} incomplete"
        );
    }
}

/// The disk fills while replicas are written: the run stops with one error line and exit 1, no file
/// under a final name is incomplete, `status` still reads the output, and once there is space the
/// same command finishes the sweep to the output of an uninterrupted run. (Without the flush, sync
/// and read-back before the rename, the replica being finished when space ran out was left as an
/// unreadable `rNNNNN.h5`, and `status` and the rerun failed on it.)
#[test]
fn a_full_disk_leaves_no_corrupt_final_file() {
    let tmp = tempfile::tempdir().unwrap();
    let mnt = tmp.path().join("small");
    let Some(fs) = Tmpfs::mount(&mnt, "300k") else {
        eprintln!(
            "skipped: cannot mount a tmpfs here (needs root); the disk-full case is untested"
        );
        return;
    };
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("full", &[0.95, 0.9, 0.85, 0.8, 0.75, 0.7], 400, 2, 20.0),
    );
    let spec = spec.to_str().unwrap();
    let out = mnt.join("out");
    let o = out.to_str().unwrap();
    let r = run(&["run", spec, "-o", o, "-q", "-j", "2"]);
    let err = stderr(&r);
    let replicas = out.join("replicas");
    let finished = listing(&replicas)
        .iter()
        .filter(|f| f.ends_with(".h5"))
        .count();
    assert!(finished < 12, "the disk did not fill ({finished} files)");
    assert_final_files_whole(&replicas);
    let s = run(&["status", o]);
    let text = String::from_utf8_lossy(&s.stdout);
    assert!(text.contains("0 corrupt"), "{text}{}", stderr(&s));
    assert_eq!(s.status.code(), Some(2), "{}", stderr(&s));
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");

    fs.resize("64m");
    let r = run(&["run", spec, "-o", o, "-q", "-j", "2"]);
    assert!(r.status.success(), "{}", stderr(&r));
    let reference = tmp.path().join("reference");
    let r = run(&["run", spec, "-o", reference.to_str().unwrap(), "-q"]);
    assert!(r.status.success(), "{}", stderr(&r));
    assert_same_output(&out, &reference);
    drop(fs);
    assert!(!mounted(&mnt), "tmpfs left mounted at {}", mnt.display());
}

/// Final files that are truncated, zeroed, random or of another spec are reported by `status` (exit
/// 2) and `summarize` (which still prints the table), then moved aside as `.corrupt` (bytes kept)
/// and redone by the rerun, which ends with the output of an uninterrupted run.
#[test]
fn corrupt_replica_files_are_reported_moved_aside_and_redone() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("corrupt", &[0.9, 0.8], 128, 3, 10.0),
    );
    let other = write(
        tmp.path(),
        "o.json",
        &small_spec("corrupt", &[0.7, 0.6], 128, 3, 10.0),
    );
    let (spec, other) = (spec.to_str().unwrap(), other.to_str().unwrap());
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    for (s, dir) in [(spec, &a), (other, &b)] {
        let r = run(&["run", s, "-o", dir.to_str().unwrap(), "-q"]);
        assert!(r.status.success(), "{}", stderr(&r));
    }
    let reference = tmp.path().join("reference");
    std::fs::create_dir(&reference).unwrap();
    let r = run(&["run", spec, "-o", reference.to_str().unwrap(), "-q"]);
    assert!(r.status.success());

    let rep = |k: usize| a.join("replicas").join(format!("r{k:05}.h5"));
    let whole = std::fs::read(rep(1)).unwrap();
    std::fs::write(rep(1), &whole[..whole.len() / 2]).unwrap(); // truncated
    std::fs::write(rep(2), vec![0u8; whole.len()]).unwrap(); // zeroed
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let random: Vec<u8> = (0..4096)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x as u8
        })
        .collect();
    std::fs::write(rep(3), &random).unwrap(); // not HDF5
    std::fs::copy(b.join("replicas/r00004.h5"), rep(4)).unwrap(); // another spec's
    let bad = [1, 2, 3, 4];
    let saved: Vec<Vec<u8>> = bad
        .iter()
        .map(|&k| std::fs::read(rep(k)).unwrap())
        .collect();

    let s = run(&["status", a.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&s.stdout);
    assert_eq!(s.status.code(), Some(2), "{text}");
    assert!(
        text.contains("2 done, 0 collapsed, 0 stalled, 0 failed, 4 corrupt"),
        "{text}"
    );
    for k in bad {
        assert!(text.contains(&format!("corrupt r{k:05}: ")), "{text}");
    }
    assert!(text.contains("different spec"), "{text}");

    let s = run(&["summarize", a.to_str().unwrap()]);
    assert!(s.status.success(), "{}", stderr(&s));
    let err = stderr(&s);
    assert_eq!(err.lines().count(), 4, "{err}");
    assert!(err.contains("corrupt: replicas/r00001.h5"), "{err}");

    let r = run(&["run", spec, "-o", a.to_str().unwrap(), "-q"]);
    let err = stderr(&r);
    assert!(r.status.success(), "{err}");
    for (k, bytes) in bad.iter().zip(&saved) {
        let aside = a.join("replicas").join(format!("r{k:05}.h5.corrupt"));
        assert!(
            err.contains(&format!("moved to {}", aside.display())),
            "{err}"
        );
        assert_eq!(&std::fs::read(&aside).unwrap(), bytes, "{k}: bytes kept");
        std::fs::remove_file(aside).unwrap();
    }
    assert_same_output(&a, &reference);
}

/// A second run (unsharded, the same shard, or a merge) into an output that a run holds is refused
/// with one line naming the holder's PID, exit 1, touching nothing; shards of one sweep run side by
/// side; once the holder is killed, the same command resumes. (Before the lock, two runs into one
/// output aborted with a failed rename or an HDF5 lock error in 12 of 12 trials.)
#[test]
fn a_second_run_into_a_held_output_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("lock", &[0.9, 0.8, 0.7, 0.6], 2000, 2, 2000.0),
    );
    let spec = spec.to_str().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let mut holder = edmd()
        .args(["run", spec, "-o", o, "-q", "-j", "1"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = holder.id();
    let deadline = Instant::now() + Duration::from_secs(60);
    let holds = |out: &Path| {
        std::fs::read_to_string(out.join(".lock")).is_ok_and(|t| t.trim() == pid.to_string())
            && out.join("spec.json").exists()
    };
    while !holds(&out) {
        assert!(
            Instant::now() < deadline,
            "the first run never took the lock"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    let spec_before = std::fs::read_to_string(out.join("spec.json")).unwrap();
    let files_before = listing(&out);
    let busy = format!("is in use by another edmd run (PID {pid})");
    let cases: [&[&str]; 3] = [
        &["run", spec, "-o", o, "-q"],
        &["run", spec, "-o", o, "-q", "--force"],
        &["merge", o],
    ];
    for args in cases {
        let r = run(args);
        let err = stderr(&r);
        assert_eq!(r.status.code(), Some(1), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(&busy), "{args:?}: {err}");
    }
    let r = run(&["run", spec, "-o", o, "-q", "--shard", "0/2"]);
    assert_eq!(r.status.code(), Some(1));
    assert!(stderr(&r).contains(&busy), "{}", stderr(&r));
    assert_eq!(
        std::fs::read_to_string(out.join("spec.json")).unwrap(),
        spec_before
    );
    assert_eq!(listing(&out), files_before, "the refused runs touched OUT");
    assert!(
        holder.try_wait().unwrap().is_none(),
        "the holder ended early"
    );
    holder.kill().unwrap();
    holder.wait().unwrap();

    // Two shards of one sweep hold the directory together; the same shard twice does not.
    let shard = |k: &str| {
        edmd()
            .args(["run", spec, "-o", o, "-q", "-j", "1", "--shard", k])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap()
    };
    let mut s0 = shard("0/2");
    let shard_lock = out.join(".lock.shard-0-of-2");
    while std::fs::read_to_string(&shard_lock).map_or(true, |t| t.trim() != s0.id().to_string()) {
        assert!(Instant::now() < deadline, "shard 0/2 never took its lock");
        std::thread::sleep(Duration::from_millis(5));
    }
    let mut s1 = shard("1/2");
    let again = run(&["run", spec, "-o", o, "-q", "--shard", "0/2"]);
    assert!(
        stderr(&again).contains(&format!("(shard 0/2, PID {})", s0.id())),
        "{}",
        stderr(&again)
    );
    std::thread::sleep(Duration::from_millis(300));
    assert!(s1.try_wait().unwrap().is_none(), "shard 1/2 was refused");
    for c in [&mut s0, &mut s1] {
        c.kill().unwrap();
        c.wait().unwrap();
    }
}

/// Usage errors exit 64 (not 2, which means "replicas failed"); --help exits 0; a thread count far
/// above the machine's is capped with a note instead of aborting; stale temporary files of killed
/// runs are removed; a `.part` left by a killed run is redone.
#[test]
fn command_line_misuse_and_leftovers() {
    for args in [
        &["run", "--no-such-option"][..],
        &["status"],
        &["frobnicate"],
        &["run", "-j", "many"],
    ] {
        let r = run(args);
        assert_eq!(r.status.code(), Some(64), "{args:?}: {}", stderr(&r));
    }
    let help = run(&["--help"]);
    assert_eq!(help.status.code(), Some(0));
    let text = String::from_utf8_lossy(&help.stdout);
    assert!(text.contains("64  usage error"), "{text}");

    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("misc", &[0.9], 64, 2, 2.0),
    );
    let spec = spec.to_str().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let r = run(&["run", spec, "-o", o, "-q", "--threads", "100000"]);
    let err = stderr(&r);
    assert!(r.status.success(), "{err}");
    assert!(
        err.contains("note: --threads 100000 is more than the"),
        "{err}"
    );

    // Leftovers of a killed run: a temporary index and a partial replica.
    std::fs::write(out.join("sweep.h5.tmp999999"), b"half an index").unwrap();
    std::fs::write(out.join("summary.csv.tmp424242"), b"half").unwrap();
    std::fs::remove_file(out.join("replicas/r00001.h5")).unwrap();
    std::fs::write(out.join("replicas/r00001.h5.part"), b"partial").unwrap();
    let r = run(&["run", spec, "-o", o, "-q"]);
    assert!(r.status.success(), "{}", stderr(&r));
    let names = listing(&out);
    assert!(!names.iter().any(|n| n.contains(".tmp")), "{names:?}");
    assert_eq!(
        listing(&out.join("replicas")),
        ["r00000.h5", "r00001.h5"],
        "the partial replica was not redone"
    );
    let s = run(&["status", o]);
    assert_eq!(s.status.code(), Some(0));

    // status exits 2 while replicas are missing.
    std::fs::remove_file(out.join("replicas/r00000.h5")).unwrap();
    let s = run(&["status", o]);
    assert_eq!(s.status.code(), Some(2));
}

/// Values that pass every field's own check but would exhaust the machine are refused before
/// anything is written, naming the field and the estimate; --max-memory lowers the limit.
#[test]
fn memory_estimates_refuse_oversized_runs_up_front() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "s.json",
        &small_spec("mem", &[0.9, 0.8, 0.7, 0.6], 200_000, 1, 1.0),
    );
    let spec = spec.to_str().unwrap();
    let out = tmp.path().join("out");
    let o = out.to_str().unwrap();
    let r = run(&["validate-spec", spec, "--max-memory", "16M"]);
    let err = stderr(&r);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.contains("grid.n = 200000: replica 0"), "{err}");
    assert!(err.contains("above the --max-memory of 16.0 MiB"), "{err}");
    // One replica (about 100 MB) fits in 150M, two or more at once do not.
    let r = run(&["run", spec, "-o", o, "-j", "4", "--max-memory", "150M"]);
    let err = stderr(&r);
    if std::thread::available_parallelism().map_or(1, |n| n.get()) >= 4 {
        assert!(err.contains("--threads 4: 4 replicas at once"), "{err}");
    } else {
        assert!(err.contains("replicas at once"), "{err}");
    }
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(!out.exists(), "a refused run wrote {}", out.display());
    let r = run(&["run", spec, "-o", o, "--max-memory", "lots"]);
    assert_eq!(r.status.code(), Some(64));
}
