//! `edmd refine`: rounds of run, plan and a longer spec (docs/sweep-spec.md, "Refinement").

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use clap::Args;

use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::run::{run_sweep, RunOptions};
use edmd_sweep::spec::{RefineAxis, Refinement, Shard};
use edmd_sweep::summary::{phase_table, render};

use crate::bar::Bar;
use crate::size::parse_size;
use crate::{say_problems, say_ran, thread_count, FormatArg};

/// The options of `edmd refine`.
#[derive(Debug, Args)]
pub struct RefineArgs {
    /// Sweep output directory (of `edmd run`; its spec.json records the refinement).
    pub out: PathBuf,
    /// Rounds in all, at least 1 (a rerun continues to this many).
    #[arg(long, default_value_t = 3, value_parser = at_least_one)]
    pub rounds: usize,
    /// Replicas the refinement may add in all, at least 1 [default: no limit].
    #[arg(long, value_name = "R", value_parser = at_least_one)]
    pub budget: Option<usize>,
    /// Axes to bisect, e.g. eps,box (of eps, phi, box, n, beta) [default: those the grid varies,
    /// or those of an earlier round].
    #[arg(long, value_name = "AXES")]
    pub axes: Option<String>,
    /// Worker threads [default: every core; at most the threads this process may use].
    #[arg(short = 'j', long)]
    pub threads: Option<usize>,
    /// Memory the run may use, e.g. 8G or 512M [default: the machine's or the cgroup's].
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub max_memory: Option<u64>,
    /// Run only share K of N (0-based) of the replicas planned and not finished; plans nothing
    /// (a Slurm array task; `--plan` plans the next round).
    #[arg(long, value_name = "K/N", conflicts_with = "plan")]
    pub shard: Option<String>,
    /// Run nothing: build the index of a complete refinement and plan its next round (after the
    /// shards of a round; see sweeps/slurm/refine.sh).
    #[arg(long)]
    pub plan: bool,
    /// No progress bar (it is also off when stderr is not a terminal).
    #[arg(short, long)]
    pub quiet: bool,
    /// Format of the phase table printed at the end.
    #[arg(long, value_enum, default_value_t = FormatArg::Table)]
    pub format: FormatArg,
}

/// A count that must be at least 1 (`--rounds 0` would record a refinement without running one).
fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("must be at least 1".into()),
        Ok(n) => Ok(n),
        Err(_) => Err("expected a whole number of at least 1".into()),
    }
}

/// The axes of `--axes` (None when not given).
fn asked_axes(axes: Option<&str>) -> anyhow::Result<Option<Vec<RefineAxis>>> {
    axes.map(|list| {
        list.split(',')
            .map(|name| {
                RefineAxis::parse(name).ok_or_else(|| {
                    anyhow::anyhow!(
                        "--axes {list}: unknown axis {name:?} (axes: eps, phi, box, n, beta)"
                    )
                })
            })
            .collect::<anyhow::Result<Vec<_>>>()
    })
    .transpose()
}

/// `edmd refine`: rounds of run, plan, extend the spec, until the rounds, the budget or the pairs
/// that differ run out; with `--shard` only this share's unfinished replicas, with `--plan` only the
/// index and the next round's points.
pub fn command(a: RefineArgs) -> anyhow::Result<ExitCode> {
    let (_, mut spec) = OutDir::open(&a.out)?;
    if spec.classify.is_none() {
        bail!(
            "refine: {} has no \"classify\" section: its replicas carry no regime to refine",
            a.out.join("spec.json").display()
        );
    }
    let asked = asked_axes(a.axes.as_deref())?;
    let axes = edmd_sweep::refine::choose_axes(&spec, asked.as_deref())?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let threads = thread_count(a.threads)?;
    let budget = a.budget.unwrap_or(usize::MAX);
    let mode = shard.map_or(LockMode::Exclusive, LockMode::Shard);
    let dir = OutDir::prepare(&a.out, &spec, false, mode)?;
    let opts = RunOptions {
        threads: Some(threads),
        max_memory: a.max_memory,
        shard,
        force: false,
        interrupt: Some(crate::interrupt::on_signals()?),
    };
    let mut problems = Vec::new();
    loop {
        let Some(records) = round_records(&a, &dir, &spec, &opts, &mut problems)? else {
            return Ok(say_problems(&problems));
        };
        let done = edmd_sweep::refine::rounds(&spec);
        if done >= a.rounds {
            break;
        }
        let left = budget.saturating_sub(edmd_sweep::refine::refinement_replicas(&spec));
        let round =
            edmd_sweep::refine::plan(&edmd_sweep::refine::points(&spec, &records), &axes, left);
        if round.is_empty() {
            let seeds = spec.grids().iter().map(|g| g.seeds as usize).min();
            let why = if left < seeds.unwrap_or(1) {
                format!("the budget of {budget} replicas is spent")
            } else {
                "no pair of neighbouring points differs".to_string()
            };
            eprintln!("refine: {why}; the refinement ends after {done} round(s)");
            break;
        }
        let added: usize = round.iter().map(|g| g.seeds as usize).sum();
        let points = round.len();
        spec = edmd_sweep::refine::with_round(&spec, &axes, round);
        spec.validate()?;
        dir.set_spec(&spec)?;
        eprintln!(
            "refine: round {} of {}: {points} point(s), {added} replica(s)",
            done + 1,
            a.rounds
        );
        if a.plan {
            return Ok(ExitCode::SUCCESS);
        }
    }
    finish(&a, &dir, &mut spec, &axes)?;
    Ok(say_problems(&problems))
}

/// The records of the sweep as it stands: with `--plan` those on disk (every replica must be
/// finished), else after running its unfinished replicas. None when only this shard's are done.
fn round_records(
    a: &RefineArgs,
    dir: &OutDir,
    spec: &edmd_sweep::spec::Spec,
    opts: &RunOptions,
    problems: &mut Vec<(
        edmd_sweep::spec::Replica,
        edmd_sweep::record::Status,
        String,
    )>,
) -> anyhow::Result<Option<Vec<edmd_sweep::record::Record>>> {
    if a.plan {
        let records = dir.records(spec);
        let missing = records.iter().filter(|r| !r.status.has_file()).count();
        if missing > 0 {
            bail!(
                "refine --plan: {missing} replica(s) of {} are not finished; run them first (edmd refine {} --shard K/N, or without --shard)",
                a.out.display(),
                a.out.display()
            );
        }
        dir.write_index(spec, &records)?;
        return Ok(Some(records));
    }
    let report = run_sweep(spec, dir, opts, &Bar::new(a.quiet))?;
    say_ran(spec, &report, opts.shard, &a.out);
    if report.interrupted > 0 {
        return Err(crate::interrupt::Interrupted(report.interrupted).into());
    }
    problems.extend(report.problems.iter().cloned());
    match report.records {
        Some(records) if opts.shard.is_none() => Ok(Some(records)),
        _ => {
            eprintln!(
                "refine: this shard's replicas are finished; `edmd refine {} --plan` plans the next round once every shard has run",
                a.out.display()
            );
            Ok(None)
        }
    }
}

/// The end of a refinement: the index and boundary, the phase table, and what it cost against the
/// full grid of the same resolution.
fn finish(
    a: &RefineArgs,
    dir: &OutDir,
    spec: &mut edmd_sweep::spec::Spec,
    axes: &[RefineAxis],
) -> anyhow::Result<()> {
    let records = dir.records(spec);
    if spec.refinement.is_none() {
        // No round was needed: the spec still records the refinement (and boundary.json is written).
        spec.refinement = Some(Refinement {
            axes: axes.to_vec(),
            rounds: Vec::new(),
        });
        dir.set_spec(spec)?;
    }
    dir.write_index(spec, &records)?;
    print!("{}", render(&phase_table(spec, &records), a.format.into()));
    let spent = edmd_sweep::refine::refinement_replicas(spec);
    let full = edmd_sweep::refine::full_grid_replicas(spec, axes, edmd_sweep::refine::rounds(spec));
    eprintln!(
        "refine: {} round(s), {} replicas in all ({} added); the full grid of the same resolution holds {} ({:.0} %); boundary in {}",
        edmd_sweep::refine::rounds(spec),
        records.len(),
        spent,
        full,
        100.0 * records.len() as f64 / full.max(1) as f64,
        a.out.join("boundary.json").display()
    );
    Ok(())
}
