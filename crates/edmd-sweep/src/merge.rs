//! `edmd merge`: gathers the replica files of several shard outputs of one sweep into one output and
//! builds its index.

use std::fs;
use std::path::{Path, PathBuf};

use crate::lock::LockMode;
use crate::output::{OutDir, ReplicaState};
use crate::record::Record;
use crate::SweepError;

/// What a merge did.
#[derive(Debug, Clone)]
pub struct MergeReport {
    /// The index records of the target (missing and corrupt replicas included).
    pub records: Vec<Record>,
    /// Input files that could not be used and were not copied: (path, why).
    pub skipped: Vec<(PathBuf, String)>,
}

/// Merges the sweep outputs `inputs` into `target` (which may be one of them) under the target's
/// exclusive lock, and writes the index (missing replicas listed as such). Every input must hold
/// the same spec; a corrupt input file is skipped (and reported), never copied.
pub fn merge(inputs: &[PathBuf], target: &Path) -> Result<MergeReport, SweepError> {
    let mut opened = Vec::new();
    for dir in inputs {
        opened.push(OutDir::open(dir)?);
    }
    let Some((_, spec)) = opened.first().cloned() else {
        return Err(SweepError::Usage(
            "merge: give at least one sweep output".into(),
        ));
    };
    for (dir, other) in &opened[1..] {
        if *other != spec {
            return Err(SweepError::Output(format!(
                "{} holds a different sweep than {} (their spec.json differ)",
                dir.root().display(),
                inputs[0].display()
            )));
        }
    }
    let out = OutDir::prepare(target, &spec, false, LockMode::Exclusive)?;
    let hash = spec.hash();
    let mut skipped = Vec::new();
    let same = |a: &Path| fs::canonicalize(a).ok() == fs::canonicalize(out.root()).ok();
    for (dir, _) in &opened {
        if same(dir.root()) {
            continue;
        }
        for r in spec.replicas() {
            let src = dir.replica_path(&r);
            if !src.exists() || out.replica_path(&r).exists() {
                continue;
            }
            if let ReplicaState::Corrupt(why) = dir.state(&r, &hash) {
                skipped.push((src, why));
                continue;
            }
            copy_replica(&src, &out.part_path(&r), &out.replica_path(&r))?;
            // The replica's state at tau_max goes with it, for `edmd extend`.
            let state = dir.final_state_path(&r);
            if state.exists() {
                fs::create_dir_all(out.states_dir())
                    .map_err(|e| SweepError::io("cannot create", &out.states_dir(), e))?;
                let dest = out.final_state_path(&r);
                copy_replica(&state, &crate::files::tmp_path(&dest), &dest)?;
            }
        }
    }
    // The index is written even with replicas missing: it lists them, and a later merge rewrites it.
    let records = out.records(&spec);
    out.write_index(&spec, &records)?;
    Ok(MergeReport { records, skipped })
}

/// Copies a replica file to `part` (created fresh, never through a link), syncs it, renames it to
/// `dest` and syncs the directory: a merge killed at any moment leaves `dest` whole or absent, as a
/// run does.
fn copy_replica(src: &Path, part: &Path, dest: &Path) -> Result<(), SweepError> {
    let copied = crate::files::create_fresh(part).and_then(|mut to| {
        fs::File::open(src)
            .and_then(|mut from| std::io::copy(&mut from, &mut to))
            .and_then(|_| to.sync_all())
            .and_then(|_| fs::rename(part, dest))
            .map_err(|e| SweepError::io("cannot copy", src, e))
    });
    if copied.is_err() {
        let _ = fs::remove_file(part);
    }
    copied?;
    if let Some(dir) = dest.parent() {
        fs::File::open(dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| SweepError::io("cannot sync", dir, e))?;
    }
    Ok(())
}
