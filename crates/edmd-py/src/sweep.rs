//! `edmd.run_sweep`: a sweep run as `edmd run` runs it, writing the same files; the phase table
//! comes back as JSON for the Python side to turn into a DataFrame. The sweep runs on a thread of
//! its own while the caller's thread reports progress to a Python callback and watches for Ctrl-C,
//! which stops the replicas in flight with their checkpoints written, as a signal stops `edmd run`.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::run::{run_sweep, Progress, RunOptions, RunReport};
use edmd_sweep::spec::{Shard, Spec};
use edmd_sweep::summary::{phase_table, render, Format};
use pyo3::prelude::*;

use crate::value_error;

/// How often the callback hears of the run.
const TICK: Duration = Duration::from_millis(200);

/// The run's progress, counted by its worker threads.
#[derive(Debug, Default)]
struct Tally {
    collisions: AtomicU64,
    total: AtomicU64,
    replicas: AtomicU64,
    done: AtomicU64,
}

impl Progress for Tally {
    fn start(&self, replicas: usize, collisions: u64) {
        self.replicas.store(replicas as u64, Ordering::Relaxed);
        self.total.store(collisions, Ordering::Relaxed);
    }
    fn advance(&self, collisions: u64) {
        self.collisions.fetch_add(collisions, Ordering::Relaxed);
    }
    fn replica_done(&self, done: usize, _replicas: usize) {
        self.done.store(done as u64, Ordering::Relaxed);
    }
}

impl Tally {
    /// (collisions run, collisions planned, replicas finished, replicas to run).
    fn read(&self) -> (u64, u64, u64, u64) {
        let get = |a: &AtomicU64| a.load(Ordering::Relaxed);
        (
            get(&self.collisions),
            get(&self.total),
            get(&self.done),
            get(&self.replicas),
        )
    }
}

/// Runs the sweep `spec` (JSON text) into `out` with `threads` worker threads (every core if
/// None), or only share `shard` ("K/N"); `progress(collisions, total, replicas_done, replicas)` is
/// called a few times a second. Returns the phase table as JSON text (`[]` while other shards are
/// missing). Ctrl-C stops the run with checkpoints written and raises KeyboardInterrupt; running
/// it again goes on from them.
#[pyfunction]
#[pyo3(signature = (spec, out, threads = None, force = false, shard = None, progress = None))]
pub fn run_sweep_json(
    py: Python<'_>,
    spec: &str,
    out: PathBuf,
    threads: Option<usize>,
    force: bool,
    shard: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let spec = Spec::from_json(spec).map_err(value_error)?;
    let shard = shard.map(Shard::parse).transpose().map_err(value_error)?;
    if threads == Some(0) {
        return Err(value_error("threads = 0: a run needs at least one thread"));
    }
    let mode = shard.map_or(LockMode::Exclusive, LockMode::Shard);
    let dir = OutDir::prepare(&out, &spec, force, mode).map_err(value_error)?;
    let interrupt = Arc::new(AtomicBool::new(false));
    let opts = RunOptions {
        threads,
        force,
        shard,
        interrupt: Some(interrupt.clone()),
        ..RunOptions::default()
    };
    let tally = Tally::default();
    let mut stopped_by = None;
    let report = py.detach(|| {
        std::thread::scope(|s| {
            let worker = s.spawn(|| run_sweep(&spec, &dir, &opts, &tally));
            while !worker.is_finished() {
                std::thread::sleep(TICK);
                if stopped_by.is_none() {
                    if let Err(e) = Python::attach(|py| tell(py, progress.as_ref(), &tally)) {
                        interrupt.store(true, Ordering::Relaxed);
                        stopped_by = Some(e);
                    }
                }
            }
            worker.join().expect("the sweep does not panic")
        })
    });
    let report: RunReport = report.map_err(value_error)?;
    Python::attach(|py| tell(py, progress.as_ref(), &tally))?;
    if let Some(e) = stopped_by {
        return Err(e);
    }
    Ok(match &report.records {
        Some(records) => render(&phase_table(&spec, records), Format::Json),
        None => "[]".into(),
    })
}

/// Hands the progress to the callback and looks for Ctrl-C.
fn tell(py: Python<'_>, progress: Option<&Py<PyAny>>, tally: &Tally) -> PyResult<()> {
    py.check_signals()?;
    if let Some(f) = progress {
        f.call1(py, tally.read())?;
    }
    Ok(())
}
