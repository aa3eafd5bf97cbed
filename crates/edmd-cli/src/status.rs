//! `edmd status`: how far a sweep has got, and the checkpoints of its unfinished replicas.

use std::path::PathBuf;
use std::process::ExitCode;

use edmd_sweep::output::OutDir;
use edmd_sweep::record::{Record, Status};
use edmd_sweep::spec::Spec;

use crate::exit_for;

/// `edmd status`: the replicas by status, a run in progress, and why each failed one ended.
pub(crate) fn status_command(out: PathBuf) -> anyhow::Result<ExitCode> {
    let (dir, spec) = OutDir::open(&out)?;
    let records = dir.records(&spec);
    let partial = spec
        .replicas()
        .iter()
        .filter(|r| dir.part_path(r).exists())
        .count();
    let count = |s: Status| records.iter().filter(|r| r.status == s).count();
    println!(
        "{}: {} replicas: {} done, {} collapsed, {} stalled, {} failed, {} corrupt, {} in flight or partial, {} pending",
        spec.name,
        records.len(),
        count(Status::Done),
        count(Status::Collapsed),
        count(Status::Stalled),
        count(Status::Failed),
        count(Status::Corrupt),
        partial,
        count(Status::Missing).saturating_sub(partial)
    );
    if let Some(who) = edmd_sweep::lock::running(&out) {
        // A replica being simulated has no file yet: the pending ones include it.
        println!("  a run is in progress ({who}): its replicas being simulated now are among the pending");
    }
    for r in records.iter().filter(|r| {
        matches!(
            r.status,
            Status::Failed | Status::Collapsed | Status::Stalled | Status::Corrupt
        )
    }) {
        println!("  {} r{:05}: {}", r.status, r.index, r.message);
    }
    if count(Status::Corrupt) > 0 {
        println!("  (rerun `edmd run` with the same spec and -o: corrupt files are moved aside and redone)");
    }
    say_checkpoints(&dir, &spec, &records);
    Ok(exit_for(&records))
}

/// The checkpoints of unfinished replicas: how far each got and how old its checkpoint is.
fn say_checkpoints(dir: &OutDir, spec: &Spec, records: &[Record]) {
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64());
    let hash = spec.hash();
    for r in spec.replicas() {
        if records[r.index].status.has_file() {
            continue;
        }
        let path = dir.checkpoint_path(&r);
        if !path.exists() {
            continue;
        }
        match edmd_sweep::checkpoint::read_header(&path) {
            Ok(h) => println!(
                "  checkpoint r{:05}: tau {:.4} of {} ({:.0} %), {} pair collisions, written {} ago{}",
                r.index,
                h.tau,
                spec.stop.tau_max,
                100.0 * h.tau / spec.stop.tau_max,
                h.collisions,
                age(now - h.written),
                if h.spec_hash == hash { "" } else { " (of another spec: not used)" }
            ),
            Err(e) => println!("  checkpoint r{:05}: unreadable ({e}): the replica starts over", r.index),
        }
    }
}

/// An age in the unit that reads best.
fn age(seconds: f64) -> String {
    match seconds.max(0.0) {
        s if s < 120.0 => format!("{s:.0} s"),
        s if s < 7200.0 => format!("{:.0} min", s / 60.0),
        s if s < 172_800.0 => format!("{:.1} h", s / 3600.0),
        s => format!("{:.1} days", s / 86_400.0),
    }
}
