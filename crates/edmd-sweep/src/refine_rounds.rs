//! A refinement in this process, round after round: run the sweep as it stands, plan the pairs
//! that differ, extend the spec, until the rounds, the budget or the differing pairs run out
//! (`edmd refine`, and `edmd.refine` from Python). The caller says how to report.

use std::path::Path;

use crate::output::OutDir;
use crate::record::Record;
use crate::refine::{full_grid_replicas, plan, points, refinement_replicas, rounds, with_round};
use crate::run::{run_sweep, Problems, Progress, RunOptions, RunReport};
use crate::spec::{RefineAxis, Refinement, Spec};
use crate::SweepError;

/// How far a refinement may go.
#[derive(Debug, Clone, Copy)]
pub struct Limits {
    /// Rounds in all (a rerun continues to this many).
    pub rounds: usize,
    /// Replicas the refinement may add in all.
    pub budget: Option<usize>,
}

/// Where a refinement tells how it goes. Both methods default to saying nothing.
pub trait Log {
    /// A run of the sweep as it stands ended with `report`.
    fn ran(&self, spec: &Spec, report: &RunReport) {
        let _ = (spec, report);
    }
    /// A line of the refinement's own (a round planned, why it ends).
    fn say(&self, line: &str) {
        let _ = line;
    }
}

/// How a refinement call ended.
#[derive(Debug)]
pub enum End {
    /// Every round ran: the records of the whole refined sweep (index and boundary written).
    Finished(Vec<Record>),
    /// A shard's replicas ran; planning waits for the others (`edmd refine --plan`).
    ShardDone,
    /// Stopped by the run's interrupt: this many replicas left checkpoints or did not start.
    Interrupted(usize),
}

/// What a refinement call did.
#[derive(Debug)]
pub struct Refined {
    /// The spec as it stands (with every round planned so far).
    pub spec: Spec,
    /// How it ended.
    pub end: End,
    /// Replicas that failed, collapsed or stalled on the way.
    pub problems: Problems,
}

/// Runs `spec`'s refinement in `dir` to its end (or this shard's share of the current round).
pub fn refine(
    dir: &OutDir,
    mut spec: Spec,
    axes: &[RefineAxis],
    limits: Limits,
    opts: &RunOptions,
    progress: &dyn Progress,
    log: &dyn Log,
) -> Result<Refined, SweepError> {
    let mut problems = Problems::new();
    loop {
        let report = run_sweep(&spec, dir, opts, progress)?;
        log.ran(&spec, &report);
        if report.interrupted > 0 {
            let end = End::Interrupted(report.interrupted);
            return Ok(Refined {
                spec,
                end,
                problems,
            });
        }
        problems.extend(report.problems.iter().cloned());
        let records = match report.records {
            Some(records) if opts.shard.is_none() => records,
            _ => {
                return Ok(Refined {
                    spec,
                    end: End::ShardDone,
                    problems,
                })
            }
        };
        match next_round(&spec, &records, axes, limits, log)? {
            Some(next) => {
                dir.set_spec(&next)?;
                log.say(&round_line(&next, limits));
                spec = next;
            }
            None => {
                let records = finish(dir, &mut spec, axes)?;
                let end = End::Finished(records);
                return Ok(Refined {
                    spec,
                    end,
                    problems,
                });
            }
        }
    }
}

/// The spec with the next round's points, or None when the refinement ends here (the rounds
/// done, the budget spent, or no neighbouring points differ; the last two said to `log`).
pub fn next_round(
    spec: &Spec,
    records: &[Record],
    axes: &[RefineAxis],
    limits: Limits,
    log: &dyn Log,
) -> Result<Option<Spec>, SweepError> {
    let done = rounds(spec);
    if done >= limits.rounds {
        return Ok(None);
    }
    let budget = limits.budget.unwrap_or(usize::MAX);
    let left = budget.saturating_sub(refinement_replicas(spec));
    let round = plan(&points(spec, records), axes, left);
    if round.is_empty() {
        let seeds = spec.grids().iter().map(|g| g.seeds as usize).min();
        let why = if left < seeds.unwrap_or(1) {
            format!("the budget of {budget} replicas is spent")
        } else {
            "no pair of neighbouring points differs".to_string()
        };
        log.say(&format!(
            "refine: {why}; the refinement ends after {done} round(s)"
        ));
        return Ok(None);
    }
    let next = with_round(spec, axes, round);
    next.validate()?;
    Ok(Some(next))
}

/// "refine: round k of n: …", for the round `spec` has just gained.
pub fn round_line(spec: &Spec, limits: Limits) -> String {
    let round = spec
        .refinement
        .as_ref()
        .and_then(|r| r.rounds.last())
        .expect("a round was just planned");
    let added: usize = round.iter().map(|g| g.seeds as usize).sum();
    format!(
        "refine: round {} of {}: {} point(s), {added} replica(s)",
        rounds(spec),
        limits.rounds,
        round.len()
    )
}

/// The end of a refinement: the spec records it (also when no round was needed), the index and
/// boundary are written; the records of the whole refined sweep.
pub fn finish(
    dir: &OutDir,
    spec: &mut Spec,
    axes: &[RefineAxis],
) -> Result<Vec<Record>, SweepError> {
    let records = dir.records(spec);
    if spec.refinement.is_none() {
        spec.refinement = Some(Refinement {
            axes: axes.to_vec(),
            rounds: Vec::new(),
        });
        dir.set_spec(spec)?;
    }
    dir.write_index(spec, &records)?;
    Ok(records)
}

/// "refine: k round(s), …": what the refinement cost against the full grid of its resolution.
pub fn cost_line(spec: &Spec, records: &[Record], axes: &[RefineAxis], root: &Path) -> String {
    let spent = refinement_replicas(spec);
    let full = full_grid_replicas(spec, axes, rounds(spec));
    format!(
        "refine: {} round(s), {} replicas in all ({} added); the full grid of the same resolution holds {} ({:.0} %); boundary in {}",
        rounds(spec),
        records.len(),
        spent,
        full,
        100.0 * records.len() as f64 / full.max(1) as f64,
        root.join("boundary.json").display()
    )
}
