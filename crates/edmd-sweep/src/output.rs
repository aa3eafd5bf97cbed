//! The output directory of a sweep and its index.
//!
//! ```text
//! OUT/spec.json          the canonical spec (every default filled in); guards against mixing specs
//! OUT/replicas/rNNNNN.h5 one H5MD file per finished replica (written as .h5.part, then renamed)
//! OUT/states/rNNNNN.ckpt a running replica's checkpoint; rNNNNN.final a finished one's state at τ_max
//! OUT/sweep.h5           index: one column per parameter / result, external links to the replicas
//! OUT/summary.csv        the same table as CSV
//! OUT/summary.json       the same table as JSON
//! OUT/phase.json         the phase table (one row per grid point, with theory's L/L⊥, L/L∥)
//! OUT/boundary.json      a refined sweep's regime boundaries ([`crate::refine`])
//! OUT/.lock              the advisory lock of runs and merges ([`crate::lock`])
//! ```

use std::fs;
use std::path::{Path, PathBuf};
use std::sync::Arc;

pub(crate) use crate::files::tmp_path;
pub use crate::files::{write_atomic, write_atomic_parts};
use crate::h5md::{attr_i64, attr_str, check_file, SCHEMA_VERSION};
use crate::lock::{lock, LockMode, OutLock};
use crate::record::{Record, Status};
use crate::spec::{Replica, Spec};
use crate::summary::{phase_table, render, Format};
use crate::SweepError;

/// An output directory holding (part of) one sweep.
#[derive(Debug, Clone)]
pub struct OutDir {
    root: PathBuf,
    /// Held from [`OutDir::prepare`] until the last clone is dropped.
    _lock: Option<Arc<OutLock>>,
}

/// What the final file of a replica holds.
#[derive(Debug, Clone)]
pub enum ReplicaState {
    /// No file under the final name.
    Missing,
    /// A whole file, and its record.
    Finished(Box<Record>),
    /// A file that cannot be used, and why (not HDF5, truncated, another schema or spec, …).
    Corrupt(String),
}

/// Syncs the directory `dir`, so that a rename into it survives a crash.
fn sync_dir(dir: &Path) -> Result<(), SweepError> {
    fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(|e| SweepError::io("cannot sync", dir, e))
}

/// Whether `root` holds an edmd sweep's spec.
fn out_spec_exists(root: &Path) -> bool {
    root.join("spec.json").exists()
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
            "boundary.json",
            "report",
            ".lock",
        ]
        .iter()
        .any(|p| name.starts_with(p))
            || name.ends_with(".log")
    };
    for entry in fs::read_dir(root).map_err(|e| SweepError::io("cannot read", root, e))? {
        let entry = entry.map_err(|e| SweepError::io("cannot read", root, e))?;
        if !ours(&entry.file_name().to_string_lossy()) {
            return Ok(true);
        }
    }
    Ok(false)
}

impl OutDir {
    /// Opens `root` for running `spec`: creates it if needed, takes its lock in `mode` (refusing when
    /// another run holds it, before anything is read or written), refuses an output of another spec
    /// unless `force` (which then deletes the old sweep's files), removes the temporary files of
    /// killed runs (when alone in the directory), and records the spec.
    pub fn prepare(
        root: &Path,
        spec: &Spec,
        force: bool,
        mode: LockMode,
    ) -> Result<OutDir, SweepError> {
        if root.exists() && !root.is_dir() {
            return Err(SweepError::Output(format!(
                "output {} exists and is not a directory",
                root.display()
            )));
        }
        let existed = root.exists();
        if !existed {
            fs::create_dir_all(root)
                .map_err(|e| SweepError::io("cannot create output directory", root, e))?;
        }
        // A new directory holds no foreign files; an existing one is checked before the lock file
        // is created in it.
        if existed && !force && !out_spec_exists(root) && has_foreign_files(root)? {
            return Err(SweepError::Output(format!(
                "output {} is not empty and holds no edmd sweep; choose a new or empty directory, or pass --force",
                root.display()
            )));
        }
        let held = lock(root, mode)?;
        let out = OutDir {
            root: root.to_path_buf(),
            _lock: Some(Arc::new(held)),
        };
        let spec_path = out.spec_path();
        if existed {
            if spec_path.exists() {
                let old = fs::read_to_string(&spec_path)
                    .map_err(|e| SweepError::io("cannot read", &spec_path, e))?;
                let old = Spec::from_json(&old).ok();
                let same = old.as_ref().is_some_and(|s| s == spec);
                if !same {
                    let refined = old
                        .as_ref()
                        .is_some_and(|s| s.refinement.is_some() && s.base() == spec.base());
                    if refined && !force {
                        return Err(SweepError::Output(format!(
                            "output {} holds a refinement of this sweep (edmd refine); resume it with `edmd refine {}`, or rerun it with `edmd run {}`",
                            root.display(),
                            root.display(),
                            spec_path.display()
                        )));
                    }
                    if !force {
                        return Err(SweepError::Output(format!(
                            "output {} holds a different sweep (see its spec.json); choose another -o or pass --force to delete it",
                            root.display()
                        )));
                    }
                    out.remove_sweep_files()?;
                }
            }
            if mode == LockMode::Exclusive {
                out.remove_stale_tmp_files()?;
            }
        }
        let replicas = out.replicas_dir();
        fs::create_dir_all(&replicas)
            .map_err(|e| SweepError::io("cannot create output directory", &replicas, e))?;
        write_atomic(&spec_path, spec.canonical_json().as_bytes())?;
        Ok(out)
    }

    /// Opens an existing sweep output and reads its spec.
    pub fn open(root: &Path) -> Result<(OutDir, Spec), SweepError> {
        let out = OutDir {
            root: root.to_path_buf(),
            _lock: None,
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

    /// Removes `NAME.tmpPID` files left by killed runs (only called while holding the lock alone).
    fn remove_stale_tmp_files(&self) -> Result<(), SweepError> {
        let entries =
            fs::read_dir(&self.root).map_err(|e| SweepError::io("cannot read", &self.root, e))?;
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let stale = name
                .rsplit_once(".tmp")
                .is_some_and(|(_, pid)| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()));
            if stale {
                let p = entry.path();
                fs::remove_file(&p).map_err(|e| SweepError::io("cannot remove", &p, e))?;
            }
        }
        Ok(())
    }

    fn remove_sweep_files(&self) -> Result<(), SweepError> {
        for name in [
            "sweep.h5",
            "summary.csv",
            "summary.json",
            "phase.json",
            "boundary.json",
            "spec.json",
        ] {
            let p = self.root.join(name);
            if p.exists() {
                fs::remove_file(&p).map_err(|e| SweepError::io("cannot remove", &p, e))?;
            }
        }
        for dir in [self.replicas_dir(), self.states_dir()] {
            if dir.exists() {
                fs::remove_dir_all(&dir).map_err(|e| SweepError::io("cannot remove", &dir, e))?;
            }
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

    /// `OUT/states`: the checkpoints of replicas in flight and the final states of finished ones.
    pub fn states_dir(&self) -> PathBuf {
        self.root.join("states")
    }

    /// A running replica's checkpoint (`states/rNNNNN.ckpt`, removed once its final file is in place).
    pub fn checkpoint_path(&self, r: &Replica) -> PathBuf {
        crate::replica::checkpoint::file_in(&self.states_dir(), r.index)
    }

    /// A finished replica's state at τ_max (`states/rNNNNN.final`), from which `edmd extend` goes on.
    pub fn final_state_path(&self, r: &Replica) -> PathBuf {
        crate::replica::checkpoint::final_in(&self.states_dir(), r.index)
    }

    /// Temporary path of a replica's file while it is written.
    pub fn part_path(&self, r: &Replica) -> PathBuf {
        self.replica_path(r).with_extension("h5.part")
    }

    /// Where a corrupt replica file is moved: `rNNNNN.h5.corrupt`, or `.corrupt.K` when taken.
    pub fn corrupt_path(&self, r: &Replica) -> PathBuf {
        let base = self.replica_path(r).with_extension("h5.corrupt");
        let mut p = base.clone();
        let mut k = 1;
        while p.exists() {
            let mut name = base.file_name().unwrap_or_default().to_os_string();
            name.push(format!(".{k}"));
            p = base.with_file_name(name);
            k += 1;
        }
        p
    }

    /// What the final file of replica `r` holds (`hash`: the spec's hash).
    pub fn state(&self, r: &Replica, hash: &str) -> ReplicaState {
        let p = self.replica_path(r);
        if !p.exists() {
            return ReplicaState::Missing;
        }
        match check_file(&p, hash, r.index) {
            Ok(rec) => ReplicaState::Finished(Box::new(rec)),
            Err(reason) => ReplicaState::Corrupt(reason),
        }
    }

    /// Moves the corrupt final file of `r` aside (never deleting it); returns where it went.
    pub fn set_aside(&self, r: &Replica) -> Result<PathBuf, SweepError> {
        let from = self.replica_path(r);
        let to = self.corrupt_path(r);
        fs::rename(&from, &to).map_err(|e| SweepError::io("cannot move aside", &from, e))?;
        Ok(to)
    }

    /// The records of every replica of `spec`: read from whole files, [`Status::Missing`] without
    /// one, [`Status::Corrupt`] (with the reason as the message) for a file that cannot be used.
    pub fn records(&self, spec: &Spec) -> Vec<Record> {
        let hash = spec.hash();
        spec.replicas()
            .iter()
            .map(|r| match self.state(r, &hash) {
                ReplicaState::Finished(rec) => *rec,
                ReplicaState::Missing => Record::missing(r),
                ReplicaState::Corrupt(reason) => Record {
                    status: Status::Corrupt,
                    message: reason,
                    file: r.file_name(),
                    ..Record::missing(r)
                },
            })
            .collect()
    }

    /// Builds `sweep.h5`, `summary.csv`, `summary.json` and `phase.json` from `records` (those of
    /// [`OutDir::records`]).
    pub fn write_index(&self, spec: &Spec, records: &[Record]) -> Result<(), SweepError> {
        let index = self.root.join("sweep.h5");
        let tmp = tmp_path(&index);
        crate::files::create_fresh(&tmp)?;
        // Written, closed, synced and read back whole before it replaces the previous index.
        let written = write_index_h5(&tmp, spec, records)
            .map_err(|e| SweepError::hdf5(&index, e))
            .and_then(|_| {
                fs::File::open(&tmp)
                    .and_then(|f| f.sync_all())
                    .map_err(|e| SweepError::io("cannot sync", &tmp, e))
            })
            .and_then(|_| {
                check_index(&tmp, spec, records).map_err(|reason| {
                    SweepError::Output(format!(
                        "{}: written but unreadable: {reason}",
                        index.display()
                    ))
                })
            })
            .and_then(|_| {
                fs::rename(&tmp, &index).map_err(|e| SweepError::io("cannot write", &index, e))
            })
            .and_then(|_| sync_dir(&self.root));
        if let Err(e) = written {
            let _ = fs::remove_file(&tmp);
            return Err(e);
        }
        write_atomic(
            &self.root.join("summary.csv"),
            Record::to_csv(records).as_bytes(),
        )?;
        let json = serde_json::to_string_pretty(records).expect("records serialise");
        write_atomic(&self.root.join("summary.json"), json.as_bytes())?;
        let table = phase_table(spec, records);
        let phase = render(&table, Format::Json);
        write_atomic(&self.root.join("phase.json"), phase.as_bytes())?;
        if let Some(r) = &spec.refinement {
            let file = crate::refine::boundary_file(spec, records, &r.axes);
            let json = serde_json::to_string_pretty(&file).expect("a boundary serialises") + "\n";
            write_atomic(&self.root.join("boundary.json"), json.as_bytes())?;
        }
        Ok(())
    }

    /// Replaces `OUT/spec.json` by `spec` (a refinement's next round); only while holding the lock
    /// alone.
    pub fn set_spec(&self, spec: &Spec) -> Result<(), SweepError> {
        write_atomic(&self.spec_path(), spec.canonical_json().as_bytes())
    }
}

/// Writes the index into `path`, closing every group before the file, so that flush and close
/// report the last writes' errors (a close with objects still open is deferred by HDF5, and its
/// errors are lost).
fn write_index_h5(path: &Path, spec: &Spec, records: &[Record]) -> hdf5::Result<()> {
    let file = hdf5::File::create(path)?;
    fill_index(&file, spec, records)?;
    file.flush()?;
    file.close()
}

fn fill_index(file: &hdf5::File, spec: &Spec, records: &[Record]) -> hdf5::Result<()> {
    attr_i64(file, "schema_version", SCHEMA_VERSION)?;
    attr_str(file, "sweep_name", &spec.name)?;
    attr_str(file, "spec", &spec.canonical_json())?;
    attr_str(file, "spec_hash", &spec.hash())?;
    Record::write_columns(&file.create_group("replicas")?, records)?;
    let links = file.create_group("files")?;
    for r in records.iter().filter(|r| r.status.has_file()) {
        let stem = r.file.trim_end_matches(".h5");
        links.link_external(&format!("replicas/{}", r.file), "/", stem)?;
    }
    Ok(())
}

/// Reads a written index back whole: its spec hash, and every replica's row and link.
fn check_index(path: &Path, spec: &Spec, records: &[Record]) -> Result<(), String> {
    let check = || -> hdf5::Result<Option<String>> {
        let file = hdf5::File::open(path)?;
        let hash: hdf5::types::VarLenUnicode = file.attr("spec_hash")?.read_scalar()?;
        if hash.as_str() != spec.hash() {
            return Ok(Some("its spec hash does not read back".into()));
        }
        let index = file.dataset("replicas/index")?.read_raw::<u64>()?;
        if index.len() != records.len() {
            return Ok(Some(format!(
                "{} rows read back of {}",
                index.len(),
                records.len()
            )));
        }
        let links = file.group("files")?.member_names()?.len();
        let expected = records.iter().filter(|r| r.status.has_file()).count();
        if links != expected {
            return Ok(Some(format!("{links} links read back of {expected}")));
        }
        Ok(None)
    };
    match check() {
        Ok(None) => Ok(()),
        Ok(Some(reason)) => Err(reason),
        Err(e) => Err(e.to_string()),
    }
}
