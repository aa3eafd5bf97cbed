//! `edmd extend`: a finished sweep continued to a longer τ_max, bit-identical to a sweep run that
//! long from the start.
//!
//! Each replica that reached its τ_max kept its state there, before its last sample
//! (`rNNNNN.final`, [`super::checkpoint`]). Extending turns that state into a checkpoint of the
//! longer spec, heading for the first point of the longer schedule at or after the old τ_max, with
//! its snapshots read back from the replica's file; the run then goes on from it as from any
//! checkpoint. A replica that ended earlier (stopped, collapsed, stalled, failed) or kept no state
//! runs again from the start: it ends as it did, now with the longer spec in its file. So does a
//! shaken bed extended to less than twice its τ_max: its longer run records its uniform-time
//! samples from its own half-way point, which lies before the final state.

use std::sync::atomic::AtomicBool;

use super::checkpoint::{read, Checkpoints, Encoded};
use super::points::Points;
use crate::files::remove_stale;
use crate::h5md::read_snapshots;
use crate::output::OutDir;
use crate::spec::{Replica, Spec};
use crate::SweepError;

/// What [`prepare`] did with the replicas.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Prepared {
    /// Replicas that go on from their final state.
    pub from_final: usize,
    /// Replicas that run again from the start, and why (the first few reasons).
    pub from_start: usize,
    /// Why some replicas run from the start (one line per distinct reason).
    pub reasons: Vec<String>,
}

/// `old` with τ_max raised to `tau_max`.
pub fn extended(old: &Spec, tau_max: f64) -> Result<Spec, SweepError> {
    if !(tau_max > old.stop.tau_max && tau_max.is_finite()) {
        return Err(SweepError::Usage(format!(
            "--tau-max {tau_max}: must be finite and above the sweep's stop.tau_max = {}",
            old.stop.tau_max
        )));
    }
    let mut new = old.clone();
    new.stop.tau_max = tau_max;
    new.validate()?;
    Ok(new)
}

/// Makes every finished replica of `old` in `out` ready to go on under `new`: its final state
/// becomes a checkpoint of `new` and its file goes (a replica without a usable final state just
/// loses its file). Safe to repeat after a kill: a replica already converted has no file left.
pub fn prepare(out: &OutDir, old: &Spec, new: &Spec) -> Result<Prepared, SweepError> {
    let never = AtomicBool::new(false);
    let ckpts = Checkpoints::new(new, out.states_dir(), &never);
    let old_hash = old.hash();
    let mut done = Prepared::default();
    for r in new.replicas() {
        let file = out.replica_path(&r);
        if !file.exists() {
            continue;
        }
        let fin = out.final_state_path(&r);
        match convert(out, &r, &old_hash, new, &ckpts) {
            Ok(()) => done.from_final += 1,
            Err(why) => {
                done.from_start += 1;
                if !done.reasons.contains(&why) && done.reasons.len() < 5 {
                    done.reasons.push(why);
                }
            }
        }
        remove_stale(&file)?;
        remove_stale(&fin)?;
    }
    Ok(done)
}

/// Replica `r`'s final state under `old_hash`, as a checkpoint of `new`.
fn convert(
    out: &OutDir,
    r: &Replica,
    old_hash: &str,
    new: &Spec,
    ckpts: &Checkpoints,
) -> Result<(), String> {
    let fin = out.final_state_path(r);
    if !fin.exists() {
        return Err("no final state (the replica ended before tau_max, or kept none)".into());
    }
    let (header, mut saved) = read(&fin).map_err(|e| format!("{}: {e}", fin.display()))?;
    if header.spec_hash != old_hash || header.replica != r.index {
        return Err(format!("{}: of another spec or replica", fin.display()));
    }
    let runner = &mut saved.runner;
    runner.snapshots = read_snapshots(&out.replica_path(r), r, runner.snapshots_in_file)?;
    runner.snapshots_in_file = 0;
    let mut points = Points::new(new);
    runner.point = points
        .resume_at(runner.point)
        .ok_or("no point of the longer schedule after the final state")?;
    runner.next_snapshot = points.next_snapshot;
    if let Some(bed) = &mut runner.bed {
        // The longer run records its uniform-time samples from its own half-way point on.
        let window = Points::new(new).resume_at(0.5 * new.stop.tau_max);
        if window.is_some_and(|w| w < runner.point) {
            return Err(
                "a shaken bed whose longer run samples from before its final state (extend to \
                 twice tau_max or more to go on from it)"
                    .into(),
            );
        }
        bed.restart();
    }
    let state = Encoded::new(&saved.runner, saved.runner.wall_s, saved.engine);
    ckpts.save(r.index, header.tau, header.collisions, "extend", &state);
    match ckpts.notices.lock().expect("lock").pop() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
