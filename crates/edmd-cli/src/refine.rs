//! `edmd refine`: rounds of run, plan and a longer spec (docs/sweep-spec.md, "Refinement").

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::bail;
use clap::Args;

use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::record::Record;
use edmd_sweep::refine;
use edmd_sweep::refine_rounds::{self, End, Limits};
use edmd_sweep::run::{RunOptions, RunReport};
use edmd_sweep::spec::{RefineAxis, Shard, Spec};
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
    /// Axes to bisect, e.g. eps,box (of eps, phi, box, n, beta, shake_s) [default: those the grid varies,
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
    let (_, spec) = OutDir::open(&a.out)?;
    if spec.classify.is_none() {
        bail!(
            "refine: {} has no \"classify\" section: its replicas carry no regime to refine",
            a.out.join("spec.json").display()
        );
    }
    let asked = asked_axes(a.axes.as_deref())?;
    let axes = refine::choose_axes(&spec, asked.as_deref())?;
    let shard = a.shard.as_deref().map(Shard::parse).transpose()?;
    let threads = thread_count(a.threads)?;
    let limits = Limits {
        rounds: a.rounds,
        budget: a.budget,
    };
    let mode = shard.map_or(LockMode::Exclusive, LockMode::Shard);
    let dir = OutDir::prepare(&a.out, &spec, false, mode)?;
    if a.plan {
        return plan_only(&a, &dir, spec, &axes, limits);
    }
    let opts = RunOptions {
        threads: Some(threads),
        max_memory: a.max_memory,
        shard,
        force: false,
        interrupt: Some(crate::interrupt::on_signals()?),
    };
    let log = Printed { out: &a.out, shard };
    let refined =
        refine_rounds::refine(&dir, spec, &axes, limits, &opts, &Bar::new(a.quiet), &log)?;
    match refined.end {
        End::Interrupted(k) => {
            return Err(crate::interrupt::Interrupted::in_dir(k, &dir).into())
        }
        End::ShardDone => eprintln!(
            "refine: this shard's replicas are finished; `edmd refine {} --plan` plans the next round once every shard has run",
            a.out.display()
        ),
        End::Finished(records) => say_finished(&a, &refined.spec, &records, &axes),
    }
    Ok(say_problems(&refined.problems))
}

/// The refinement's lines on stderr, as `edmd run` prints its own.
struct Printed<'a> {
    out: &'a Path,
    shard: Option<Shard>,
}

impl refine_rounds::Log for Printed<'_> {
    fn ran(&self, spec: &Spec, report: &RunReport) {
        say_ran(spec, report, self.shard, self.out);
    }
    fn say(&self, line: &str) {
        eprintln!("{line}");
    }
}

/// `--plan`: the index of the finished round (every replica must be finished), then the next
/// round's points into the spec, or the end of the refinement.
fn plan_only(
    a: &RefineArgs,
    dir: &OutDir,
    mut spec: Spec,
    axes: &[RefineAxis],
    limits: Limits,
) -> anyhow::Result<ExitCode> {
    let records = dir.records(&spec);
    let missing = records.iter().filter(|r| !r.status.has_file()).count();
    if missing > 0 {
        bail!(
            "refine --plan: {missing} replica(s) of {} are not finished; run them first (edmd refine {} --shard K/N, or without --shard)",
            a.out.display(),
            a.out.display()
        );
    }
    dir.write_index(&spec, &records)?;
    let log = Printed {
        out: &a.out,
        shard: None,
    };
    if let Some(next) = refine_rounds::next_round(&spec, &records, axes, limits, &log)? {
        dir.set_spec(&next)?;
        eprintln!("{}", refine_rounds::round_line(&next, limits));
        return Ok(ExitCode::SUCCESS);
    }
    let records = refine_rounds::finish(dir, &mut spec, axes)?;
    say_finished(a, &spec, &records, axes);
    Ok(ExitCode::SUCCESS)
}

/// The phase table of the refined sweep, and what it cost against the full grid.
fn say_finished(a: &RefineArgs, spec: &Spec, records: &[Record], axes: &[RefineAxis]) {
    print!("{}", render(&phase_table(spec, records), a.format.into()));
    eprintln!("{}", refine_rounds::cost_line(spec, records, axes, &a.out));
}
