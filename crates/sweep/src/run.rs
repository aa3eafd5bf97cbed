//! Running a sweep: the replicas of a shard across a rayon pool, skipping finished ones, with a
//! progress bar, each replica written atomically as soon as it ends.

use std::fs;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rayon::prelude::*;

use crate::h5md::{write_replica, Record};
use crate::output::OutDir;
use crate::replica::{self, Status};
use crate::spec::{Replica, Shard, Spec};
use crate::SweepError;

/// Options of `edmd run`.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Worker threads (default: every core).
    pub threads: Option<usize>,
    /// Run only this share of the replicas.
    pub shard: Option<Shard>,
    /// Replace the output of a different spec.
    pub force: bool,
    /// No progress bar.
    pub quiet: bool,
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// Replicas of this shard.
    pub in_shard: usize,
    /// Replicas run now (the others were finished before).
    pub ran: usize,
    /// Pair collisions run now.
    pub collisions: u64,
    /// Wall-clock seconds.
    pub wall_s: f64,
    /// Seconds spent simulating, summed over the replicas run now.
    pub simulate_s: f64,
    /// Seconds spent writing replica files, summed over the replicas run now.
    pub write_s: f64,
    /// The index records of the whole sweep, when every replica is finished (else `None`).
    pub records: Option<Vec<Record>>,
    /// Replicas of this shard that failed or collapsed: (replica, status, message).
    pub problems: Vec<(Replica, Status, String)>,
}

/// Rough cost of a replica in pair collisions, for scheduling and the progress bar.
fn estimated_collisions(spec: &Spec, r: &Replica) -> u64 {
    (r.n as f64 * spec.stop.tau_max).ceil() as u64
}

/// Runs the replicas of `opts.shard` of `spec` into `out`.
pub fn run_sweep(spec: &Spec, out: &OutDir, opts: &RunOptions) -> Result<RunReport, SweepError> {
    let start = Instant::now();
    let shard = opts.shard.unwrap_or(Shard { k: 0, n: 1 });
    let mine: Vec<Replica> = spec
        .replicas()
        .into_iter()
        .filter(|r| shard.contains(r.index))
        .collect();
    // A partial file is a replica that was in flight when a run died: redo it.
    for r in &mine {
        let part = out.part_path(r);
        if part.exists() {
            fs::remove_file(&part).map_err(|e| {
                SweepError::Output(format!("cannot remove {}: {e}", part.display()))
            })?;
        }
    }
    let mut todo: Vec<&Replica> = mine.iter().filter(|r| !out.is_done(r)).collect();
    // Longest first: the pool ends with short replicas and balances well.
    todo.sort_by_key(|r| std::cmp::Reverse(estimated_collisions(spec, r)));
    let total: u64 = todo.iter().map(|r| estimated_collisions(spec, r)).sum();

    let bar = if opts.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::with_draw_target(Some(total.max(1)), ProgressDrawTarget::stderr())
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {msg} | {human_per_sec} collisions/s | ETA {eta}",
        )
        .expect("valid template"),
    );
    let n_todo = todo.len();
    let done_count = AtomicU64::new(0);
    bar.set_message(format!("0/{n_todo} replicas"));
    let collisions = AtomicU64::new(0);
    let simulate_ns = AtomicU64::new(0);
    let write_ns = AtomicU64::new(0);
    let first_error: Mutex<Option<SweepError>> = Mutex::new(None);

    let work = || {
        // One replica per job: rayon would otherwise run runs of several replicas back to back on one
        // thread, and a run of slow ones at the end leaves the other threads idle.
        todo.par_iter().with_max_len(1).for_each(|r| {
            if first_error.lock().expect("lock").is_some() {
                return;
            }
            let progress = |c: u64| {
                collisions.fetch_add(c, Ordering::Relaxed);
                bar.inc(c);
            };
            let outcome = replica::run(spec, r, &progress);
            // Settle the bar: the estimate becomes what the replica really ran.
            let est = estimated_collisions(spec, r);
            if outcome.collisions < est {
                bar.inc(est - outcome.collisions);
            }
            simulate_ns.fetch_add((outcome.wall_s * 1e9) as u64, Ordering::Relaxed);
            let t = Instant::now();
            let written = write_replica(&out.replica_path(r), spec, r, &outcome);
            write_ns.fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
            if let Err(e) = written {
                first_error.lock().expect("lock").get_or_insert(e);
                return;
            }
            let k = done_count.fetch_add(1, Ordering::Relaxed) + 1;
            bar.set_message(format!("{k}/{n_todo} replicas"));
        });
    };
    match opts.threads {
        Some(t) => rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .map_err(|e| SweepError::Usage(format!("--threads {t}: {e}")))?
            .install(work),
        None => work(),
    }
    bar.finish_and_clear();
    if let Some(e) = first_error.into_inner().expect("lock") {
        return Err(e);
    }

    // Status of this shard's replicas (those run now and those finished before).
    let hash = spec.hash();
    let mut problems = Vec::new();
    for r in &mine {
        let rec = crate::h5md::read_record(&out.replica_path(r), &hash)?;
        let status = Status::parse(&rec.status).unwrap_or(Status::Failed);
        if status != Status::Done {
            problems.push((r.clone(), status, rec.message));
        }
    }
    let complete = spec.replicas().iter().all(|r| out.is_done(r));
    let records = if complete {
        Some(out.write_index(spec)?)
    } else {
        None
    };
    Ok(RunReport {
        in_shard: mine.len(),
        ran: n_todo,
        collisions: collisions.load(Ordering::Relaxed),
        wall_s: start.elapsed().as_secs_f64(),
        simulate_s: simulate_ns.load(Ordering::Relaxed) as f64 * 1e-9,
        write_s: write_ns.load(Ordering::Relaxed) as f64 * 1e-9,
        records,
        problems,
    })
}
