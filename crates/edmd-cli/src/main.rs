//! `edmd`: run sweeps of granular-gas simulations and summarise them.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use clap::{Parser, Subcommand, ValueEnum};

use refine::RefineArgs;

use edmd_sweep::budget::{check_memory, replica_bytes, snapshots_per_replica, Bytes, MemoryLimit};
use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::record::{Record, Status};
use edmd_sweep::run::{available_threads, run_sweep, RunOptions, RunReport};
use edmd_sweep::spec::{Replica, Shard, Spec, MAX_SPEC_BYTES};
use edmd_sweep::summary::{phase_table, render, Format};
use edmd_sweep::{merge, SweepError, QUICK_SPEC};

mod bar;
mod bench_replica;
mod extend;
mod interrupt;
mod refine;
mod size;
mod status;

use bar::Bar;
use size::parse_size;

/// Large arrays on cache-line boundaries: faster large 3D systems (edmd_core's `alloc` module).
#[global_allocator]
static ALLOC: edmd_core::LineAligned = edmd_core::LineAligned(std::alloc::System);

const EXAMPLES: &str = "\
Examples:
  edmd run                                   quick default sweep into edmd-out/quick, phase table
  edmd run sweeps/mcnamara-young.json -o my  the McNamara-Young box, all cores
  edmd run SPEC -o OUT --threads 2           at most two cores
  edmd run SPEC -o OUT --shard 3/8           the 4th of 8 shares (e.g. a Slurm array task)
  edmd merge -o OUT A B C                    gather shard outputs A, B, C into OUT, build the index
  edmd refine OUT --rounds 3 --axes eps,box  add replicas where neighbouring points' regimes differ
  edmd extend OUT --tau-max 1600             continue a finished sweep to a longer tau_max
  edmd status OUT                            how far a sweep has got
  edmd summarize OUT --format csv            the phase table as CSV
  edmd validate-spec SPEC                    check a spec without running it
  edmd spec-schema                           the JSON Schema of specs (for editors and validators)

Rerunning the same `edmd run` resumes a killed sweep: finished replicas are kept, those in flight go on
from their checkpoints (rNNNNN.ckpt: every 300 s, and at once on SIGTERM, SIGINT or SIGUSR1), corrupt
ones are moved aside as rNNNNN.h5.corrupt and redone. One run (or one shard) at a time holds OUT.

Exit status:
  0   success (status: every replica done)
  1   bad input (spec, arguments' values, memory estimate) or an I/O error; nothing was run
  2   the sweep ran but a replica failed, collapsed or stalled (ended before its stop);
      status/merge: replicas failed, collapsed, stalled, missing or corrupt
  64  usage error (unknown option, missing argument)
  75  run/refine stopped by SIGTERM, SIGINT or SIGUSR1; the replicas in flight saved checkpoints
      (run the same command again to go on)
Spec format: docs/sweep-spec.md.";

/// Exit status of a command-line usage error (BSD's EX_USAGE), distinct from 2 ("replicas failed").
const EXIT_USAGE: u8 = 64;

/// Event-driven molecular dynamics of granular gases: parameter sweeps over (eps, phi or L, N, seed).
#[derive(Debug, Parser)]
#[command(name = "edmd", version, about, after_help = EXAMPLES)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a sweep (or, with no SPEC, the embedded quick default sweep) and print its phase table.
    Run {
        /// Sweep spec (JSON); omitted: the quick default sweep (sweeps/quick.json).
        spec: Option<PathBuf>,
        /// Output directory [default: edmd-out/<spec name>].
        #[arg(short, long)]
        out: Option<PathBuf>,
        /// Worker threads [default: every core; at most the threads this process may use].
        #[arg(short = 'j', long)]
        threads: Option<usize>,
        /// Memory the run may use, e.g. 8G or 512M [default: the machine's or the cgroup's]; the run
        /// is refused up front when its estimate is above it.
        #[arg(long, value_name = "SIZE", value_parser = parse_size)]
        max_memory: Option<u64>,
        /// Run only share K of N (0-based): replicas whose index is K modulo N.
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Replace an output directory that holds a different sweep (deletes its files).
        #[arg(long)]
        force: bool,
        /// No progress bar (it is also off when stderr is not a terminal).
        #[arg(short, long)]
        quiet: bool,
        /// Format of the phase table printed at the end.
        #[arg(long, value_enum, default_value_t = FormatArg::Table)]
        format: FormatArg,
    },
    /// Refine a finished sweep's phase diagram: add the midpoints of neighbouring grid points whose
    /// regimes differ, run them, and repeat (docs/sweep-spec.md, "Refinement").
    Refine(RefineArgs),
    /// Continue a finished sweep to a longer stop.tau_max: bit-identical to a sweep run that long from
    /// the start (docs/output.md, "Extending a sweep").
    Extend(extend::ExtendArgs),
    /// Measure one replica's runner (sampling, classification, snapshots; no files) against the
    /// engine alone on the same trajectory, one thread, alternating rounds (docs/benchmarks.md).
    BenchReplica(bench_replica::BenchReplicaArgs),
    /// Show how many replicas of a sweep output are finished, failed, partial or pending.
    Status {
        /// Sweep output directory.
        out: PathBuf,
    },
    /// Gather shard outputs of one sweep into one directory and build its index.
    Merge {
        /// Shard output directories (all of the same spec).
        #[arg(required = true)]
        inputs: Vec<PathBuf>,
        /// Target directory [default: the first input, indexed in place].
        #[arg(short, long)]
        out: Option<PathBuf>,
    },
    /// Print the phase table of a sweep output: one row per grid point, aggregated over seeds.
    Summarize {
        /// Sweep output directory.
        out: PathBuf,
        /// Output format.
        #[arg(long, value_enum, default_value_t = FormatArg::Table)]
        format: FormatArg,
    },
    /// Check a sweep spec and print the size of its grid and its memory estimate, without running
    /// anything.
    ValidateSpec {
        /// Sweep spec (JSON).
        spec: PathBuf,
        /// Memory one replica may use, e.g. 8G [default: the machine's or the cgroup's].
        #[arg(long, value_name = "SIZE", value_parser = parse_size)]
        max_memory: Option<u64>,
    },
    /// Print the JSON Schema of sweep specs (the one in docs/sweep-spec.schema.json).
    SpecSchema,
}

/// Output format of a phase table (the library's [`Format`], as a command-line value).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum FormatArg {
    /// Aligned text for the terminal.
    Table,
    /// Comma-separated values with a header line.
    Csv,
    /// A JSON array of objects.
    Json,
}

impl From<FormatArg> for Format {
    fn from(f: FormatArg) -> Format {
        match f {
            FormatArg::Table => Format::Table,
            FormatArg::Csv => Format::Csv,
            FormatArg::Json => Format::Json,
        }
    }
}

/// Puts the spec's path before the message of a spec error, as `load_spec` does.
fn spec_error(path: Option<&Path>, e: SweepError) -> anyhow::Error {
    match (e, path) {
        (SweepError::Spec(m), Some(p)) => SweepError::Spec(format!("{}: {m}", p.display())).into(),
        (other, _) => other.into(),
    }
}

fn load_spec(path: Option<&Path>) -> anyhow::Result<Spec> {
    match path {
        None => Ok(Spec::from_json(QUICK_SPEC)?),
        Some(p) => {
            // At most MAX_SPEC_BYTES + 1 bytes are read: a wrong path (/dev/zero, a data file) is
            // refused by size instead of filling memory.
            let mut text = String::new();
            std::fs::File::open(p)
                .and_then(|f| f.take(MAX_SPEC_BYTES as u64 + 1).read_to_string(&mut text))
                .with_context(|| format!("cannot read spec {}", p.display()))?;
            Spec::from_json(&text).map_err(|e| spec_error(Some(p), e))
        }
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(EXIT_USAGE)
            } else {
                ExitCode::SUCCESS // --help, --version
            };
        }
    };
    match execute(cli.command) {
        Ok(code) => code,
        Err(e) if e.is::<interrupt::Interrupted>() => {
            eprintln!("{e}");
            ExitCode::from(interrupt::EXIT_INTERRUPTED)
        }
        Err(e) => {
            // One line: HDF5's messages carry line breaks of their own.
            let message = format!("{e:#}").replace(['\n', '\r'], " ");
            eprintln!("error: {message}");
            ExitCode::from(1)
        }
    }
}

fn execute(command: Command) -> anyhow::Result<ExitCode> {
    match command {
        Command::Run {
            spec,
            out,
            threads,
            max_memory,
            shard,
            force,
            quiet,
            format,
        } => run_command(spec, out, threads, max_memory, shard, force, quiet, format),
        Command::Refine(args) => refine::command(args),
        Command::Extend(args) => extend::command(args),
        Command::BenchReplica(args) => bench_replica::command(args),
        Command::Status { out } => status::status_command(out),
        Command::Merge { inputs, out } => merge_command(inputs, out),
        Command::Summarize { out, format } => summarize_command(out, format),
        Command::SpecSchema => {
            print!("{}", Spec::json_schema_text());
            Ok(ExitCode::SUCCESS)
        }
        Command::ValidateSpec { spec, max_memory } => validate_command(spec, max_memory),
    }
}

/// `edmd run`: the memory estimate first, then the sweep (or this shard of it), the phase table.
#[allow(clippy::too_many_arguments)]
fn run_command(
    spec: Option<PathBuf>,
    out: Option<PathBuf>,
    threads: Option<usize>,
    max_memory: Option<u64>,
    shard: Option<String>,
    force: bool,
    quiet: bool,
    format: FormatArg,
) -> anyhow::Result<ExitCode> {
    let spec_value = load_spec(spec.as_deref())?;
    let shard = shard.as_deref().map(Shard::parse).transpose()?;
    let threads = thread_count(threads)?;
    // The memory estimate is checked before anything is written.
    let mine: Vec<_> = spec_value
        .replicas()
        .into_iter()
        .filter(|r| shard.is_none_or(|s| s.contains(r.index)))
        .collect();
    check_memory(&spec_value, &mine, threads, MemoryLimit::new(max_memory))
        .map_err(|e| spec_error(spec.as_deref(), e))?;
    drop(mine);
    let root = out.unwrap_or_else(|| Path::new("edmd-out").join(&spec_value.name));
    let mode = shard.map_or(LockMode::Exclusive, LockMode::Shard);
    let dir = OutDir::prepare(&root, &spec_value, force, mode)?;
    let opts = RunOptions {
        threads: Some(threads),
        max_memory,
        shard,
        force,
        interrupt: Some(interrupt::on_signals()?),
    };
    let report = run_sweep(&spec_value, &dir, &opts, &Bar::new(quiet))?;
    say_ran(&spec_value, &report, shard, &root);
    if report.interrupted > 0 {
        return Err(interrupt::Interrupted::in_dir(report.interrupted, &dir).into());
    }
    match &report.records {
        Some(records) => print!(
            "{}",
            render(&phase_table(&spec_value, records), format.into())
        ),
        None => eprintln!(
            "other shards are still missing: once all have run, `edmd merge {}` builds the index",
            root.display()
        ),
    }
    Ok(say_problems(&report.problems))
}

/// `edmd merge`: the shards' files into one output and its index.
fn merge_command(inputs: Vec<PathBuf>, out: Option<PathBuf>) -> anyhow::Result<ExitCode> {
    let target = out.unwrap_or_else(|| inputs[0].clone());
    let report = merge::merge(&inputs, &target)?;
    for (path, why) in &report.skipped {
        eprintln!("corrupt: {} ({why}): not copied", path.display());
    }
    let records = report.records;
    let missing: Vec<usize> = records
        .iter()
        .filter(|r| !r.status.has_file())
        .map(|r| r.index)
        .collect();
    eprintln!(
        "merged {} of {} replicas into {}",
        records.len() - missing.len(),
        records.len(),
        target.display()
    );
    if missing.is_empty() {
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "error: {} replica(s) missing (indices {:?}); rerun the shards that hold them, then merge again",
            missing.len(),
            missing
        );
        Ok(ExitCode::from(2))
    }
}

/// `edmd summarize`: the phase table of an output, corrupt files named.
fn summarize_command(out: PathBuf, format: FormatArg) -> anyhow::Result<ExitCode> {
    let (dir, spec) = OutDir::open(&out)?;
    let records = dir.records(&spec);
    for r in records.iter().filter(|r| r.status == Status::Corrupt) {
        eprintln!(
            "corrupt: replicas/{} ({}); counted as missing (rerun `edmd run` to redo it)",
            r.file, r.message
        );
    }
    print!("{}", render(&phase_table(&spec, &records), format.into()));
    Ok(ExitCode::SUCCESS)
}

/// `edmd validate-spec`: the checks of a run without running, and what the spec would cost.
fn validate_command(spec: PathBuf, max_memory: Option<u64>) -> anyhow::Result<ExitCode> {
    let s = load_spec(Some(&spec))?;
    let replicas = s.replicas();
    // Collisions per particle: the elastic melt (at most 20 by default, for lattice starts)
    // and the run to tau_max.
    let melt = s.init.melt_tau.unwrap_or(20.0);
    let collisions: f64 = replicas
        .iter()
        .map(|r| r.n as f64 * (s.stop.tau_max + melt))
        .sum();
    // One replica must fit; how many fit at once is checked by `run` with its --threads.
    let estimate = check_memory(&s, &replicas, 1, MemoryLimit::new(max_memory))
        .map_err(|e| spec_error(Some(&spec), e))?;
    let all_cores =
        replicas
            .iter()
            .map(|r| replica_bytes(&s, r).total())
            .fold(Vec::new(), |mut v, b| {
                v.push(b);
                v
            });
    let mut sorted = all_cores;
    sorted.sort_by(|a, b| b.total_cmp(a));
    let at_once: f64 = sorted.iter().take(available_threads()).sum();
    println!(
        "{}: valid; {} replicas, at most {:.3e} pair collisions (tau_max = {}, melt {}); per replica at most {:.0} samples and {} snapshots; memory: about {} for the largest replica{}, {} for {} at once",
        spec.display(),
        replicas.len(),
        collisions,
        s.stop.tau_max,
        melt,
        s.samples_per_replica(),
        snapshots_per_replica(&s),
        Bytes(estimate.run_bytes),
        estimate
            .largest
            .as_ref()
            .map(|(r, _)| format!(" ({})", r.file_name()))
            .unwrap_or_default(),
        Bytes(at_once),
        available_threads().min(replicas.len()),
    );
    Ok(ExitCode::SUCCESS)
}

/// The worker threads: `--threads`, at most (and by default) what this process may use.
fn thread_count(threads: Option<usize>) -> anyhow::Result<usize> {
    let available = available_threads();
    Ok(match threads {
        Some(0) => bail!("--threads 0: need at least one thread"),
        Some(t) if t > available => {
            eprintln!(
                "note: --threads {t} is more than the {available} this process may use; using {available}"
            );
            available
        }
        Some(t) => t,
        None => available,
    })
}

/// The line a run ends with: what ran, how fast, where to.
fn say_ran(spec: &Spec, report: &RunReport, shard: Option<Shard>, root: &Path) {
    eprintln!(
        "{}: ran {} of {} replicas{}{} ({} pair collisions in {:.1} s, {:.3e} collisions/s) into {}",
        spec.name,
        report.ran - report.interrupted,
        report.in_shard,
        shard
            .map(|s| format!(" of shard {}/{}", s.k, s.n))
            .unwrap_or_default(),
        match report.resumed {
            0 => String::new(),
            k => format!(", {k} going on from their checkpoints"),
        },
        report.collisions,
        report.wall_s,
        report.collisions as f64 / report.wall_s.max(1e-9),
        root.display()
    );
    if report.ran > 0 {
        let (k, ckpt_s) = report.checkpoints;
        eprintln!(
            "time per replica summed: simulating {:.2} s, writing files {:.3} s ({:.2} % of the total){}",
            report.simulate_s,
            report.write_s,
            100.0 * report.write_s / (report.simulate_s + report.write_s).max(1e-12),
            match k {
                0 => String::new(),
                // Interrupted replicas' seconds are not in `simulate_s`: no share to give.
                k if report.interrupted > 0 => format!("; {k} checkpoints, {ckpt_s:.3} s"),
                k => format!(
                    "; {k} checkpoints, {ckpt_s:.3} s ({:.2} % of simulating)",
                    100.0 * ckpt_s / report.simulate_s.max(1e-12)
                ),
            }
        );
    }
}

/// Lists the replicas that failed, collapsed or stalled; 2 if any, else 0.
fn say_problems(problems: &[(Replica, Status, String)]) -> ExitCode {
    if problems.is_empty() {
        return ExitCode::SUCCESS;
    }
    for (r, status, message) in problems {
        eprintln!("{}: {r}: {message}", status.name());
    }
    eprintln!(
        "error: {} replica(s) failed, collapsed or stalled (listed above; their files record why)",
        problems.len()
    );
    ExitCode::from(2)
}

/// 0 when every replica is done, else 2 (failed, collapsed, stalled, missing or corrupt replicas).
fn exit_for(records: &[Record]) -> ExitCode {
    if records.iter().all(|r| r.status == Status::Done) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(2)
    }
}
