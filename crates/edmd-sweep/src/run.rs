//! Running a sweep: the replicas of a shard across a rayon pool, skipping finished ones, each replica
//! written atomically as soon as it ends; progress goes to the caller's [`Progress`].

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use rayon::prelude::*;

use crate::budget::{check_memory, MemoryLimit};
use crate::h5md::write_replica;
use crate::output::{OutDir, ReplicaState};
use crate::record::{Record, Status};
use crate::replica;
use crate::replica::checkpoint::Checkpoints;
use crate::spec::{Replica, Shard, Spec};
use crate::SweepError;

/// Options of `edmd run`.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Worker threads (default, and at most: the threads this process may use, see
    /// [`available_threads`]).
    pub threads: Option<usize>,
    /// Memory the run may use in bytes (default: the machine's, see [`crate::budget`]).
    pub max_memory: Option<u64>,
    /// Run only this share of the replicas.
    pub shard: Option<Shard>,
    /// Replace the output of a different spec.
    pub force: bool,
    /// Set (by a signal handler) to stop: every replica in flight writes its checkpoint and
    /// returns, none starts.
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// Where a run reports its progress (the CLI draws a bar from it). Every method has a default that
/// does nothing; calls come from the worker threads.
pub trait Progress: Sync {
    /// The run starts: `replicas` to run, about `collisions` pair collisions in all.
    fn start(&self, replicas: usize, collisions: u64) {
        let _ = (replicas, collisions);
    }
    /// `collisions` more pair collisions ran (a replica that ends early settles its estimate here).
    fn advance(&self, collisions: u64) {
        let _ = collisions;
    }
    /// A replica's file was written: `done` of the run's `replicas` are finished.
    fn replica_done(&self, done: usize, replicas: usize) {
        let _ = (done, replicas);
    }
    /// The run ended (also after an error).
    fn finish(&self) {}
    /// Something the user should know that does not stop the run (a corrupt file moved aside).
    fn notice(&self, message: &str) {
        let _ = message;
    }
}

/// The threads this process may use (its CPU affinity and cgroup quota, as the standard library
/// reads them; 1 when unknown).
pub fn available_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Reports nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Progress for Silent {}

/// What a run did.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// Replicas of this shard.
    pub in_shard: usize,
    /// Replicas run now (the others were finished before).
    pub ran: usize,
    /// Pair collisions run now (not those a checkpoint had already run).
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
    pub problems: Problems,
    /// Corrupt final files found and moved aside (their replicas were run again): (new path, why).
    pub set_aside: SetAside,
    /// Threads used.
    pub threads: usize,
    /// Replicas that went on from a checkpoint.
    pub resumed: usize,
    /// Checkpoints written, and the seconds they took (summed over the replicas).
    pub checkpoints: (u64, f64),
    /// Replicas left unfinished by an interrupt (those in flight with a checkpoint written).
    pub interrupted: usize,
}

/// Final files found unusable and moved aside: where each went, and why.
pub type SetAside = Vec<(PathBuf, String)>;

/// Replicas that did not end done: the replica, its status and its message.
pub type Problems = Vec<(Replica, Status, String)>;

/// Rough cost of a replica in pair collisions, for scheduling and the progress bar.
fn estimated_collisions(spec: &Spec, r: &Replica) -> u64 {
    (r.n as f64 * spec.stop.tau_max).ceil() as u64
}

/// The replicas of `mine` still to run: those without a final file. A partial file is a replica that
/// was in flight when a run died: redo it. A final file that cannot be used (a disk that filled, a
/// copy cut short) is moved aside (returned with the reason) and redone too.
fn unfinished<'a>(
    spec: &Spec,
    out: &OutDir,
    mine: &'a [Replica],
    progress: &dyn Progress,
) -> Result<(Vec<&'a Replica>, SetAside), SweepError> {
    let hash = spec.hash();
    remove_stale_checkpoint_tmp(out, mine)?;
    let mut set_aside = Vec::new();
    let mut todo: Vec<&Replica> = Vec::new();
    for r in mine {
        let part = out.part_path(r);
        crate::files::remove_stale(&part)?;
        match out.state(r, &hash) {
            // A run killed between the final file's rename and the checkpoint's removal.
            ReplicaState::Finished(_) => crate::files::remove_stale(&out.checkpoint_path(r))?,
            ReplicaState::Missing => todo.push(r),
            ReplicaState::Corrupt(reason) => {
                let to = out.set_aside(r)?;
                progress.notice(&format!(
                    "corrupt: {} ({reason}): moved to {} and run again",
                    out.replica_path(r).display(),
                    to.display()
                ));
                set_aside.push((to, reason));
                todo.push(r);
            }
        }
    }
    Ok((todo, set_aside))
}

/// Removes the temporary files of checkpoints that a killed run was writing for replicas of `mine`
/// (`rNNNNN.ckpt.tmpPID`); the lock keeps any other run off these replicas.
fn remove_stale_checkpoint_tmp(out: &OutDir, mine: &[Replica]) -> Result<(), SweepError> {
    let Ok(entries) = std::fs::read_dir(out.states_dir()) else {
        return Ok(());
    };
    let ours: std::collections::HashSet<usize> = mine.iter().map(|r| r.index).collect();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let index = name
            .split_once(".ckpt.tmp")
            .and_then(|(stem, pid)| pid.bytes().all(|b| b.is_ascii_digit()).then_some(stem))
            .and_then(|stem| stem.strip_prefix('r'))
            .and_then(|k| k.parse::<usize>().ok());
        if index.is_some_and(|k| ours.contains(&k)) {
            crate::files::remove_stale(&entry.path())?;
        }
    }
    Ok(())
}

/// The status of this shard's replicas (those run now and those finished before), read back from
/// the files, and those that did not end done; the index is written (and the records returned)
/// once every replica of the sweep has a whole file.
fn shard_records(
    spec: &Spec,
    out: &OutDir,
    mine: &[Replica],
) -> Result<(Option<Vec<Record>>, Problems), SweepError> {
    let records = out.records(spec);
    let problems = mine
        .iter()
        .filter_map(|r| {
            let rec = &records[r.index];
            matches!(
                rec.status,
                Status::Failed | Status::Collapsed | Status::Stalled | Status::Corrupt
            )
            .then(|| (r.clone(), rec.status, rec.message.clone()))
        })
        .collect();
    let complete = records.iter().all(|r| r.status.has_file());
    let records = if complete {
        out.write_index(spec, &records)?;
        Some(records)
    } else {
        None
    };
    Ok((records, problems))
}

/// What the replicas of a run did, summed across the pool's threads.
#[derive(Debug, Default)]
struct Tally {
    collisions: AtomicU64,
    simulate_ns: AtomicU64,
    write_ns: AtomicU64,
    done: AtomicU64,
    interrupted: AtomicU64,
    first_error: Mutex<Option<SweepError>>,
}

impl Tally {
    /// Runs replica `r` (from its checkpoint, if any) and writes its file, unless the run is being
    /// stopped by an error or a signal.
    fn run_one(
        &self,
        spec: &Spec,
        out: &OutDir,
        r: &Replica,
        ckpts: &Checkpoints,
        progress: &dyn Progress,
        n_todo: usize,
    ) {
        if self.first_error.lock().expect("lock").is_some() {
            return;
        }
        if ckpts.interrupted() {
            self.interrupted.fetch_add(1, Ordering::Relaxed);
            return;
        }
        let report = |c: u64| {
            self.collisions.fetch_add(c, Ordering::Relaxed);
            progress.advance(c);
        };
        let Some(outcome) = replica::run_with(spec, r, &report, Some(ckpts)) else {
            self.interrupted.fetch_add(1, Ordering::Relaxed);
            return;
        };
        // Settle the bar: the estimate becomes what the replica really ran.
        let est = estimated_collisions(spec, r);
        if outcome.collisions < est {
            progress.advance(est - outcome.collisions);
        }
        self.simulate_ns
            .fetch_add((outcome.wall_s * 1e9) as u64, Ordering::Relaxed);
        let t = Instant::now();
        let written = write_replica(&out.replica_path(r), spec, r, &outcome);
        self.write_ns
            .fetch_add(t.elapsed().as_nanos() as u64, Ordering::Relaxed);
        // The checkpoint goes once the final file is in place.
        if let Err(e) = written.and_then(|_| crate::files::remove_stale(&ckpts.path(r.index))) {
            self.first_error.lock().expect("lock").get_or_insert(e);
            return;
        }
        let k = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        progress.replica_done(k as usize, n_todo);
    }
}

/// Runs the replicas of `opts.shard` of `spec` into `out`.
pub fn run_sweep(
    spec: &Spec,
    out: &OutDir,
    opts: &RunOptions,
    progress: &dyn Progress,
) -> Result<RunReport, SweepError> {
    let start = Instant::now();
    let shard = opts.shard.unwrap_or(Shard { k: 0, n: 1 });
    let mine: Vec<Replica> = spec
        .replicas()
        .into_iter()
        .filter(|r| shard.contains(r.index))
        .collect();
    let (mut todo, set_aside) = unfinished(spec, out, &mine, progress)?;
    let threads = opts
        .threads
        .unwrap_or_else(available_threads)
        .clamp(1, available_threads());
    let owned: Vec<Replica> = todo.iter().map(|&r| r.clone()).collect();
    check_memory(spec, &owned, threads, MemoryLimit::new(opts.max_memory))?;
    // Longest first: the pool ends with short replicas and balances well.
    todo.sort_by_key(|r| std::cmp::Reverse(estimated_collisions(spec, r)));
    let total: u64 = todo.iter().map(|r| estimated_collisions(spec, r)).sum();

    let n_todo = todo.len();
    progress.start(n_todo, total);
    let never = Arc::new(AtomicBool::new(false));
    let interrupt = opts.interrupt.as_ref().unwrap_or(&never);
    let ckpts = Checkpoints::new(spec, out.states_dir(), interrupt);
    let tally = Tally::default();
    let work = || {
        // One replica per job: rayon would otherwise run runs of several replicas back to back on one
        // thread, and a run of slow ones at the end leaves the other threads idle.
        todo.par_iter()
            .with_max_len(1)
            .for_each(|r| tally.run_one(spec, out, r, &ckpts, progress, n_todo));
    };
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SweepError::Usage(format!("--threads {threads}: {e}")))?
        .install(work);
    progress.finish();
    for m in ckpts.notices.lock().expect("lock").iter() {
        progress.notice(m);
    }
    if let Some(e) = tally.first_error.into_inner().expect("lock") {
        return Err(e);
    }

    let (records, problems) = shard_records(spec, out, &mine)?;
    Ok(RunReport {
        in_shard: mine.len(),
        ran: n_todo,
        collisions: tally
            .collisions
            .load(Ordering::Relaxed)
            .saturating_sub(ckpts.resumed_collisions()),
        wall_s: start.elapsed().as_secs_f64(),
        simulate_s: tally.simulate_ns.load(Ordering::Relaxed) as f64 * 1e-9,
        write_s: tally.write_ns.load(Ordering::Relaxed) as f64 * 1e-9,
        records,
        problems,
        set_aside,
        threads,
        resumed: ckpts.resumed(),
        checkpoints: ckpts.written(),
        interrupted: tally.interrupted.load(Ordering::Relaxed) as usize,
    })
}
