//! `edmd merge`: gathers the replica files of several shard outputs of one sweep into one output and
//! builds its index.

use std::fs;
use std::path::{Path, PathBuf};

use crate::output::OutDir;
use crate::record::Record;
use crate::SweepError;

/// Merges the sweep outputs `inputs` into `target` (which may be one of them) and writes the index.
/// Every input must hold the same spec. Returns the index records (missing replicas included).
pub fn merge(inputs: &[PathBuf], target: &Path) -> Result<Vec<Record>, SweepError> {
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
    let out = OutDir::prepare(target, &spec, false)?;
    let same = |a: &Path| fs::canonicalize(a).ok() == fs::canonicalize(out.root()).ok();
    for (dir, _) in &opened {
        if same(dir.root()) {
            continue;
        }
        for r in spec.replicas() {
            let src = dir.replica_path(&r);
            if !src.is_file() || out.is_done(&r) {
                continue;
            }
            let part = out.part_path(&r);
            fs::copy(&src, &part)
                .and_then(|_| fs::rename(&part, out.replica_path(&r)))
                .map_err(|e| {
                    let _ = fs::remove_file(&part);
                    SweepError::io("cannot copy", &src, e)
                })?;
        }
    }
    out.write_index(&spec)
}
