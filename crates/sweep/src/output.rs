//! The output directory of a sweep and its index.
//!
//! ```text
//! OUT/spec.json          the canonical spec (every default filled in); guards against mixing specs
//! OUT/replicas/rNNNNN.h5 one H5MD file per finished replica (written as .h5.part, then renamed)
//! OUT/sweep.h5           index: one column per parameter / result, external links to the replicas
//! OUT/summary.csv        the same table as CSV
//! OUT/summary.json       the same table as JSON
//! OUT/phase.json         the phase table (one row per grid point, with theory's L/L⊥, L/L∥)
//! ```

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use hdf5::types::VarLenUnicode;

use crate::h5md::{attr_i64, attr_str, read_record, Record, SCHEMA_VERSION};
use crate::spec::{Replica, Spec};
use crate::SweepError;

/// An output directory holding (part of) one sweep.
#[derive(Debug, Clone)]
pub struct OutDir {
    root: PathBuf,
}

fn io_err(what: &str, path: &Path, e: std::io::Error) -> SweepError {
    SweepError::Output(format!("{what} {}: {e}", path.display()))
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so that a
/// reader never sees a half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), SweepError> {
    let tmp = tmp_path(path);
    let result = fs::File::create(&tmp)
        .and_then(|mut f| f.write_all(bytes).and_then(|_| f.sync_all()))
        .and_then(|_| fs::rename(&tmp, path));
    result.map_err(|e| {
        let _ = fs::remove_file(&tmp);
        io_err("cannot write", path, e)
    })
}

/// A temporary name beside `path`, unique to this process.
fn tmp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(format!(".tmp{}", std::process::id()));
    path.with_file_name(name)
}

/// Whether `root` holds files that no edmd run (or a shard starting at the same moment, or a Slurm
/// log) would have put there.
fn has_foreign_files(root: &Path) -> Result<bool, SweepError> {
    let ours = |name: &str| {
        [
            "spec.json",
            "replicas",
            "sweep.h5",
            "summary.",
            "phase.json",
            "report",
        ]
        .iter()
        .any(|p| name.starts_with(p))
            || name.ends_with(".log")
    };
    for entry in fs::read_dir(root).map_err(|e| io_err("cannot read", root, e))? {
        let entry = entry.map_err(|e| io_err("cannot read", root, e))?;
        if !ours(&entry.file_name().to_string_lossy()) {
            return Ok(true);
        }
    }
    Ok(false)
}

impl OutDir {
    /// Opens `root` for running `spec`: creates it if needed, refuses an output of another spec
    /// unless `force` (which then deletes the old sweep's files), and records the spec.
    pub fn prepare(root: &Path, spec: &Spec, force: bool) -> Result<OutDir, SweepError> {
        let out = OutDir {
            root: root.to_path_buf(),
        };
        let spec_path = out.spec_path();
        if root.exists() {
            if !root.is_dir() {
                return Err(SweepError::Output(format!(
                    "output {} exists and is not a directory",
                    root.display()
                )));
            }
            if spec_path.exists() {
                let old = fs::read_to_string(&spec_path)
                    .map_err(|e| io_err("cannot read", &spec_path, e))?;
                let same = Spec::from_json(&old).map(|s| s == *spec).unwrap_or(false);
                if !same {
                    if !force {
                        return Err(SweepError::Output(format!(
                            "output {} holds a different sweep (see its spec.json); choose another -o or pass --force to delete it",
                            root.display()
                        )));
                    }
                    out.remove_sweep_files()?;
                }
            } else if !force && has_foreign_files(root)? {
                return Err(SweepError::Output(format!(
                    "output {} is not empty and holds no edmd sweep; choose a new or empty directory, or pass --force",
                    root.display()
                )));
            }
        } else {
            fs::create_dir_all(root)
                .map_err(|e| io_err("cannot create output directory", root, e))?;
        }
        let replicas = out.replicas_dir();
        fs::create_dir_all(&replicas)
            .map_err(|e| io_err("cannot create output directory", &replicas, e))?;
        write_atomic(&spec_path, spec.canonical_json().as_bytes())?;
        Ok(out)
    }

    /// Opens an existing sweep output and reads its spec.
    pub fn open(root: &Path) -> Result<(OutDir, Spec), SweepError> {
        let out = OutDir {
            root: root.to_path_buf(),
        };
        let spec_path = out.spec_path();
        let text = fs::read_to_string(&spec_path).map_err(|e| {
            SweepError::Output(format!(
                "{} is not an edmd sweep output (cannot read {}: {e})",
                root.display(),
                spec_path.display()
            ))
        })?;
        let spec = Spec::from_json(&text)
            .map_err(|e| SweepError::Output(format!("{}: {e}", spec_path.display())))?;
        Ok((out, spec))
    }

    fn remove_sweep_files(&self) -> Result<(), SweepError> {
        for name in [
            "sweep.h5",
            "summary.csv",
            "summary.json",
            "phase.json",
            "spec.json",
        ] {
            let p = self.root.join(name);
            if p.exists() {
                fs::remove_file(&p).map_err(|e| io_err("cannot remove", &p, e))?;
            }
        }
        let dir = self.replicas_dir();
        if dir.exists() {
            fs::remove_dir_all(&dir).map_err(|e| io_err("cannot remove", &dir, e))?;
        }
        Ok(())
    }

    /// The directory.
    pub fn root(&self) -> &Path {
        &self.root
    }

    /// `OUT/spec.json`.
    pub fn spec_path(&self) -> PathBuf {
        self.root.join("spec.json")
    }

    /// `OUT/replicas`.
    pub fn replicas_dir(&self) -> PathBuf {
        self.root.join("replicas")
    }

    /// Final path of a replica's file.
    pub fn replica_path(&self, r: &Replica) -> PathBuf {
        self.replicas_dir().join(r.file_name())
    }

    /// Temporary path of a replica's file while it is written.
    pub fn part_path(&self, r: &Replica) -> PathBuf {
        self.replica_path(r).with_extension("h5.part")
    }

    /// Whether a replica's file is complete.
    pub fn is_done(&self, r: &Replica) -> bool {
        self.replica_path(r).is_file()
    }

    /// Reads the records of every replica of `spec` (missing ones included).
    pub fn records(&self, spec: &Spec) -> Result<Vec<Record>, SweepError> {
        let hash = spec.hash();
        spec.replicas()
            .iter()
            .map(|r| {
                let p = self.replica_path(r);
                if p.is_file() {
                    read_record(&p, &hash)
                } else {
                    Ok(Record::missing(r))
                }
            })
            .collect()
    }

    /// Builds `sweep.h5`, `summary.csv` and `summary.json` from the replica files on disk.
    pub fn write_index(&self, spec: &Spec) -> Result<Vec<Record>, SweepError> {
        let records = self.records(spec)?;
        let index = self.root.join("sweep.h5");
        let tmp = tmp_path(&index);
        let written = write_index_h5(&tmp, spec, &records)
            .map_err(|e| SweepError::Output(format!("{}: {e}", tmp.display())))
            .and_then(|_| fs::rename(&tmp, &index).map_err(|e| io_err("cannot write", &index, e)));
        if let Err(e) = written {
            let _ = fs::remove_file(&tmp);
            return Err(e);
        }
        write_atomic(&self.root.join("summary.csv"), to_csv(&records).as_bytes())?;
        let json = serde_json::to_string_pretty(&records).expect("records serialise");
        write_atomic(&self.root.join("summary.json"), json.as_bytes())?;
        let table = crate::summary::phase_table(spec, &records);
        let phase = crate::summary::render(&table, crate::summary::Format::Json);
        write_atomic(&self.root.join("phase.json"), phase.as_bytes())?;
        Ok(records)
    }
}

fn column<T: hdf5::H5Type + Clone>(
    g: &hdf5::Group,
    name: &str,
    values: Vec<T>,
) -> hdf5::Result<()> {
    g.new_dataset_builder()
        .with_data(&ndarray::Array1::from(values))
        .create(name)?;
    Ok(())
}

fn write_index_h5(path: &Path, spec: &Spec, records: &[Record]) -> hdf5::Result<()> {
    let file = hdf5::File::create(path)?;
    attr_i64(&file, "schema_version", SCHEMA_VERSION)?;
    attr_str(&file, "sweep_name", &spec.name)?;
    attr_str(&file, "spec", &spec.canonical_json())?;
    attr_str(&file, "spec_hash", &spec.hash())?;
    let g = file.create_group("replicas")?;
    let s = |f: fn(&Record) -> &str| -> Vec<VarLenUnicode> {
        records
            .iter()
            .map(|r| f(r).replace('\0', " ").parse().expect("no NUL"))
            .collect()
    };
    column(
        &g,
        "index",
        records.iter().map(|r| r.index as i64).collect(),
    )?;
    column(&g, "file", s(|r| &r.file))?;
    column(&g, "status", s(|r| &r.status))?;
    column(&g, "message", s(|r| &r.message))?;
    column(&g, "dim", records.iter().map(|r| r.dim as i64).collect())?;
    column(&g, "boundary", s(|r| &r.boundary))?;
    column(&g, "eps", records.iter().map(|r| r.eps).collect())?;
    column(&g, "phi", records.iter().map(|r| r.phi).collect())?;
    column(&g, "box_side", records.iter().map(|r| r.box_side).collect())?;
    column(&g, "n", records.iter().map(|r| r.n as i64).collect())?;
    column(
        &g,
        "seed_index",
        records.iter().map(|r| r.seed_index as i64).collect(),
    )?;
    column(&g, "seed", records.iter().map(|r| r.seed).collect())?;
    column(&g, "remedy", s(|r| &r.remedy))?;
    column(&g, "tau", records.iter().map(|r| r.tau).collect())?;
    column(&g, "time", records.iter().map(|r| r.time).collect())?;
    column(
        &g,
        "ln_temperature_ratio",
        records.iter().map(|r| r.ln_temperature_ratio).collect(),
    )?;
    column(
        &g,
        "collisions",
        records.iter().map(|r| r.collisions).collect(),
    )?;
    column(
        &g,
        "collapse_tau",
        records.iter().map(|r| r.collapse_tau).collect(),
    )?;
    column(&g, "wall_s", records.iter().map(|r| r.wall_s).collect())?;
    column(&g, "class", s(|r| &r.class))?;
    column(
        &g,
        "shear_onset_tau",
        records.iter().map(|r| r.shear_onset_tau).collect(),
    )?;
    column(
        &g,
        "cluster_onset_tau",
        records.iter().map(|r| r.cluster_onset_tau).collect(),
    )?;
    column(&g, "f_flow", records.iter().map(|r| r.f_flow).collect())?;
    column(&g, "s_perp", records.iter().map(|r| r.s_perp).collect())?;
    column(
        &g,
        "delta_rho2",
        records.iter().map(|r| r.delta_rho2).collect(),
    )?;
    let links = file.create_group("files")?;
    for r in records.iter().filter(|r| !r.file.is_empty()) {
        let stem = r.file.trim_end_matches(".h5");
        links.link_external(&format!("replicas/{}", r.file), "/", stem)?;
    }
    file.close()
}

/// Column names of `summary.csv`, in order.
pub const CSV_COLUMNS: [&str; 25] = [
    "index",
    "file",
    "status",
    "message",
    "dim",
    "boundary",
    "eps",
    "phi",
    "box_side",
    "n",
    "seed_index",
    "seed",
    "remedy",
    "tau",
    "time",
    "ln_temperature_ratio",
    "collisions",
    "collapse_tau",
    "class",
    "shear_onset_tau",
    "cluster_onset_tau",
    "f_flow",
    "s_perp",
    "delta_rho2",
    "wall_s",
];

/// Quotes a CSV field when needed.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn to_csv(records: &[Record]) -> String {
    let mut out = CSV_COLUMNS.join(",");
    out.push('\n');
    for r in records {
        let row = [
            r.index.to_string(),
            csv_field(&r.file),
            r.status.clone(),
            csv_field(&r.message),
            r.dim.to_string(),
            r.boundary.clone(),
            r.eps.to_string(),
            r.phi.to_string(),
            r.box_side.to_string(),
            r.n.to_string(),
            r.seed_index.to_string(),
            r.seed.to_string(),
            csv_field(&r.remedy),
            r.tau.to_string(),
            r.time.to_string(),
            r.ln_temperature_ratio.to_string(),
            r.collisions.to_string(),
            r.collapse_tau.to_string(),
            r.class.clone(),
            r.shear_onset_tau.to_string(),
            r.cluster_onset_tau.to_string(),
            r.f_flow.to_string(),
            r.s_perp.to_string(),
            r.delta_rho2.to_string(),
            r.wall_s.to_string(),
        ];
        out.push_str(&row.join(","));
        out.push('\n');
    }
    out
}
