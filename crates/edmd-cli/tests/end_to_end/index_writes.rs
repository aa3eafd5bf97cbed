//! The index (`sweep.h5`) and the summaries when their writes fail: a file-size limit (`ulimit -f`,
//! with SIGXFSZ ignored so that writes fail with EFBIG as on a full disk) lets the replicas stand and
//! fails the index. Needs no root, unlike the tmpfs of `hardening`.

use std::path::Path;
use std::process::Command;

use crate::common::{dump, edmd, run, write};

/// `edmd args…` with files limited to `kib` KiB.
fn run_limited(kib: u64, args: &[&str]) -> std::process::Output {
    let program = edmd().get_program().to_owned();
    Command::new("bash")
        .arg("-c")
        .arg(format!("trap '' XFSZ; ulimit -f {kib}; exec \"$@\""))
        .arg("edmd")
        .arg(program)
        .args(args)
        .output()
        .unwrap()
}

/// Whether the index at `out` opens and holds `rows` replicas.
fn index_rows(out: &Path) -> Option<usize> {
    let file = hdf5::File::open(out.join("sweep.h5")).ok()?;
    let index = file.dataset("replicas/index").ok()?;
    Some(index.read_raw::<u64>().ok()?.len())
}

/// Hardening case 2: after a finished run, a rerun whose index cannot be written whole exits 1 with
/// one line naming `sweep.h5` and the system's reason, and leaves the previous index as it was;
/// without a previous index, none appears. A rerun with room then writes the same index as the
/// first run. (The index was closed with a group still open, so HDF5 deferred the close and lost
/// its error: exit 0 and a `sweep.h5` that h5py could not open.)
#[test]
fn an_index_that_cannot_be_written_whole_is_never_put_in_place() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = write(
        tmp.path(),
        "tiny.json",
        r#"{"name": "tiny", "grid": {"eps": [0.8, 0.9], "phi": 0.2, "n": 100, "seeds": 2},
            "stop": {"tau_max": 10}}"#,
    );
    let out = tmp.path().join("out");
    let args = [
        "run",
        spec.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ];
    assert!(run(&args).status.success());
    let first = dump(&out.join("sweep.h5"));
    assert_eq!(index_rows(&out), Some(4));

    let o = run_limited(2, &args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(
        err.contains("sweep.h5") && err.contains("File too large"),
        "{err}"
    );
    assert_eq!(index_rows(&out), Some(4), "the previous index was replaced");

    for name in ["sweep.h5", "summary.csv", "summary.json"] {
        std::fs::remove_file(out.join(name)).unwrap();
    }
    let o = run_limited(2, &args);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        !out.join("sweep.h5").exists(),
        "an index under its final name"
    );

    assert!(run(&args).status.success());
    assert_eq!(dump(&out.join("sweep.h5")), first);
}
