//! `edmd extend OUT --tau-max T`: a finished sweep continued to a longer τ_max, bit-identical to a
//! sweep run that long from the start (docs/output.md, "Extending a sweep").

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::bail;
use clap::Args;

use edmd_sweep::budget::{check_memory, MemoryLimit};
use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::replica::extend::{extended, prepare};
use edmd_sweep::run::{run_sweep, RunOptions};
use edmd_sweep::summary::{phase_table, render};

use crate::bar::Bar;
use crate::size::parse_size;
use crate::{interrupt, say_problems, say_ran, thread_count, FormatArg};

/// Arguments of `edmd extend`.
#[derive(Debug, Args)]
pub struct ExtendArgs {
    /// Output directory of a finished sweep.
    pub out: PathBuf,
    /// The new stop.tau_max, above the sweep's.
    #[arg(long, value_name = "T")]
    pub tau_max: f64,
    /// Worker threads [default: every core].
    #[arg(short = 'j', long)]
    pub threads: Option<usize>,
    /// Memory the run may use, e.g. 8G [default: the machine's or the cgroup's].
    #[arg(long, value_name = "SIZE", value_parser = parse_size)]
    pub max_memory: Option<u64>,
    /// No progress bar.
    #[arg(short, long)]
    pub quiet: bool,
    /// Format of the phase table printed at the end.
    #[arg(long, value_enum, default_value_t = FormatArg::Table)]
    pub format: FormatArg,
}

/// Converts every replica's final state into a checkpoint of the longer spec, records that spec,
/// and runs the sweep on from there.
pub fn command(a: ExtendArgs) -> anyhow::Result<ExitCode> {
    let (_, old) = OutDir::open(&a.out)?;
    let threads = thread_count(a.threads)?;
    // A rerun after a kill finds spec.json already extended: go on with it.
    let (old, new) = if old.stop.tau_max == a.tau_max {
        (None, old)
    } else {
        let new = extended(&old, a.tau_max)?;
        (Some(old), new)
    };
    check_memory(
        &new,
        &new.replicas(),
        threads,
        MemoryLimit::new(a.max_memory),
    )?;
    let dir = OutDir::prepare(
        &a.out,
        old.as_ref().unwrap_or(&new),
        false,
        LockMode::Exclusive,
    )?;
    if let Some(old) = &old {
        let records = dir.records(old);
        let missing = records.iter().filter(|r| !r.status.has_file()).count();
        if missing > 0 {
            bail!(
                "{missing} replica(s) of {} are not finished: finish the sweep first (edmd run with its spec and -o {})",
                a.out.display(),
                a.out.display()
            );
        }
        let done = prepare(&dir, old, &new)?;
        eprintln!(
            "extend: tau_max {} -> {}: {} replicas go on from their final state, {} run again from the start",
            old.stop.tau_max, new.stop.tau_max, done.from_final, done.from_start
        );
        for why in &done.reasons {
            eprintln!("  from the start: {why}");
        }
        dir.set_spec(&new)?;
    }
    let opts = RunOptions {
        threads: Some(threads),
        max_memory: a.max_memory,
        shard: None,
        force: false,
        interrupt: Some(interrupt::on_signals()?),
    };
    let report = run_sweep(&new, &dir, &opts, &Bar::new(a.quiet))?;
    say_ran(&new, &report, None, &a.out);
    if report.interrupted > 0 {
        return Err(interrupt::Interrupted::in_dir(report.interrupted, &dir).into());
    }
    if let Some(records) = &report.records {
        print!("{}", render(&phase_table(&new, records), a.format.into()));
    }
    Ok(say_problems(&report.problems))
}
