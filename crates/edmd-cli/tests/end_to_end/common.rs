//! Helpers of the end-to-end tests: running the `edmd` binary, and dumping HDF5 files into a
//! comparable map of every dataset and attribute.

#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use hdf5::types::{TypeDescriptor, VarLenUnicode};

/// The `edmd` binary under test: this build's, or the one named by `EDMD_UNDER_TEST` (to show that
/// a test fails on a build without the fix it covers).
pub fn edmd() -> Command {
    match std::env::var_os("EDMD_UNDER_TEST") {
        Some(bin) => Command::new(bin),
        None => Command::new(env!("CARGO_BIN_EXE_edmd")),
    }
}

/// Runs `edmd` with `args`, returning its output.
pub fn run(args: &[&str]) -> Output {
    edmd().args(args).output().expect("edmd starts")
}

/// A small sweep spec: 2D, N = `n` at φ = 0.25, the given ε values and seeds, to `tau`.
pub fn small_spec(name: &str, eps: &[f64], n: usize, seeds: u32, tau: f64) -> String {
    format!(
        r#"{{
  "name": "{name}",
  "seed": 7,
  "grid": {{ "eps": {eps:?}, "phi": 0.25, "n": {n}, "seeds": {seeds} }},
  "stop": {{ "tau_max": {tau} }},
  "samples": {{ "every": 5, "per_decade": 5 }},
  "snapshots": {{ "at": [0, 10], "final": true }}
}}"#
    )
}

/// The shape and the values of a float dataset of an HDF5 file.
pub fn read(path: &Path, dataset: &str) -> (Vec<usize>, Vec<f64>) {
    let file = hdf5::File::open(path).unwrap();
    let ds = file.dataset(dataset).unwrap();
    (ds.shape(), ds.read_raw::<f64>().unwrap())
}

/// Writes `spec` into `dir/<name>.json`, runs it into `dir/<name>` (quiet) and returns that output
/// directory; panics with edmd's stderr when the run fails.
pub fn run_spec(dir: &Path, name: &str, spec: &str) -> PathBuf {
    let p = write(dir, &format!("{name}.json"), spec);
    let out = dir.join(name);
    let o = run(&[
        "run",
        p.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "-q",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    out
}

/// Writes `text` into `dir/name` and returns the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).expect("write spec");
    p
}

fn read_values(c: &hdf5::Container) -> hdf5::Result<String> {
    Ok(match c.dtype()?.to_descriptor()? {
        TypeDescriptor::Float(_) => c
            .read_raw::<f64>()?
            .iter()
            .map(|x| format!("{:016x}", x.to_bits()))
            .collect::<Vec<_>>()
            .join(" "),
        TypeDescriptor::Integer(_) => format!("{:?}", c.read_raw::<i64>()?),
        TypeDescriptor::Unsigned(_) => format!("{:?}", c.read_raw::<u64>()?),
        TypeDescriptor::VarLenUnicode => c
            .read_raw::<VarLenUnicode>()?
            .iter()
            .map(|s| s.as_str().to_string())
            .collect::<Vec<_>>()
            .join("\u{1f}"),
        other => format!("<{other:?}>"),
    })
}

fn dump_attrs(loc: &hdf5::Location, path: &str, out: &mut BTreeMap<String, String>) {
    for name in loc.attr_names().expect("attribute names") {
        if name == "wall_s" || name == "resumes" {
            continue; // run-dependent by nature
        }
        let a = loc.attr(&name).expect("attribute");
        out.insert(
            format!("{path}@{name}"),
            read_values(&a).expect("attribute value"),
        );
    }
}

fn dump_group(g: &hdf5::Group, path: &str, out: &mut BTreeMap<String, String>) {
    dump_attrs(g, path, out);
    for name in g.member_names().expect("members") {
        let child = format!("{path}/{name}");
        if path == "/files" || (path.is_empty() && name == "files") {
            // External links of the index: record the names only.
            out.insert(child, "link".into());
            continue;
        }
        if let Ok(ds) = g.dataset(&name) {
            dump_attrs(&ds, &child, out);
            if child == "/replicas/wall_s" || child == "/replicas/resumes" {
                continue;
            }
            out.insert(
                child.clone(),
                format!("{:?} {}", ds.shape(), read_values(&ds).expect("dataset")),
            );
        } else {
            let sub = g.group(&name).expect("group");
            dump_group(&sub, &child, out);
        }
    }
}

/// Every dataset and attribute of an HDF5 file (floats bit-exact), except wall-clock times.
pub fn dump(path: &Path) -> BTreeMap<String, String> {
    let file = hdf5::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut out = BTreeMap::new();
    dump_group(&file, "", &mut out);
    out
}

/// File names in `dir`, sorted.
pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Asserts that two sweep outputs hold the same replica files (bit-identical data) and index.
pub fn assert_same_output(a: &Path, b: &Path) {
    let ra = listing(&a.join("replicas"));
    let rb = listing(&b.join("replicas"));
    assert_eq!(
        ra,
        rb,
        "replica files differ: {} vs {}",
        a.display(),
        b.display()
    );
    for f in &ra {
        let (da, db) = (
            dump(&a.join("replicas").join(f)),
            dump(&b.join("replicas").join(f)),
        );
        assert_eq!(
            da.keys().collect::<Vec<_>>(),
            db.keys().collect::<Vec<_>>(),
            "{f}: layout"
        );
        for (k, v) in &da {
            assert_eq!(v, &db[k], "{f}: {k} differs");
        }
    }
    assert_eq!(
        dump(&a.join("sweep.h5")),
        dump(&b.join("sweep.h5")),
        "sweep.h5 differs"
    );
    // The last two columns, wall_s and resumes, describe the run, not its result.
    let strip = |p: &Path| -> Vec<String> {
        std::fs::read_to_string(p)
            .expect("summary.csv")
            .lines()
            .map(|l| l.rsplitn(3, ',').last().unwrap_or(l).to_string())
            .collect()
    };
    assert_eq!(strip(&a.join("summary.csv")), strip(&b.join("summary.csv")));
}
