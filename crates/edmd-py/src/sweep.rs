//! `edmd.run_sweep` and `edmd.refine`: a sweep run as `edmd run` runs it and refined as `edmd
//! refine` refines it, writing the same files; the phase table comes back as JSON for the Python
//! side to turn into a DataFrame. The work runs on a thread of its own while the caller's thread
//! reports progress to a Python callback and watches for Ctrl-C, which stops the replicas in
//! flight with their checkpoints written, as a signal stops the command.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;

use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::refine;
use edmd_sweep::refine_rounds::{self, End, Limits};
use edmd_sweep::run::{run_sweep, Progress, RunOptions};
use edmd_sweep::spec::{RefineAxis, Shard, Spec};
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
    check_threads(threads)?;
    let mode = shard.map_or(LockMode::Exclusive, LockMode::Shard);
    let dir = OutDir::prepare(&out, &spec, force, mode).map_err(value_error)?;
    let mut opts = RunOptions {
        threads,
        force,
        shard,
        ..RunOptions::default()
    };
    let report = watched(py, progress.as_ref(), &mut opts, |opts, tally| {
        run_sweep(&spec, &dir, opts, tally)
    })?;
    Ok(match &report.records {
        Some(records) => render(&phase_table(&spec, records), Format::Json),
        None => "[]".into(),
    })
}

/// Refines the classified sweep in `out` (of `edmd run` or `run_sweep`) as `edmd refine` does, to
/// `rounds` rounds in all, adding at most `budget` replicas, bisecting `axes` (names as
/// `--axes` takes them); progress and Ctrl-C as [`run_sweep_json`]. Returns the refined sweep's
/// phase table as JSON text.
#[pyfunction]
#[pyo3(signature = (out, rounds = 3, budget = None, axes = None, threads = None, progress = None))]
pub fn refine_json(
    py: Python<'_>,
    out: PathBuf,
    rounds: usize,
    budget: Option<usize>,
    axes: Option<Vec<String>>,
    threads: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    check_threads(threads)?;
    if rounds == 0 || budget == Some(0) {
        return Err(value_error("rounds and budget must be at least 1"));
    }
    let (_, spec) = OutDir::open(&out).map_err(value_error)?;
    if spec.classify.is_none() {
        return Err(value_error(format!(
            "refine: {} has no \"classify\" section: its replicas carry no regime to refine",
            out.join("spec.json").display()
        )));
    }
    let asked = axes.map(|names| names.iter().map(|n| axis(n)).collect::<PyResult<Vec<_>>>());
    let axes = refine::choose_axes(&spec, asked.transpose()?.as_deref()).map_err(value_error)?;
    let dir = OutDir::prepare(&out, &spec, false, LockMode::Exclusive).map_err(value_error)?;
    let limits = Limits { rounds, budget };
    let mut opts = RunOptions {
        threads,
        ..RunOptions::default()
    };
    let refined = watched(py, progress.as_ref(), &mut opts, |opts, tally| {
        refine_rounds::refine(&dir, spec, &axes, limits, opts, tally, &ToStderr)
    })?;
    match refined.end {
        End::Finished(records) => Ok(render(&phase_table(&refined.spec, &records), Format::Json)),
        End::ShardDone => Ok("[]".into()),
        End::Interrupted(k) => Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(format!(
            "{k} replica(s) unfinished, checkpointed"
        ))),
    }
}

fn axis(name: &str) -> PyResult<RefineAxis> {
    RefineAxis::parse(name).ok_or_else(|| {
        value_error(format!(
            "axes: unknown axis {name:?} (axes: eps, phi, box, n, beta)"
        ))
    })
}

fn check_threads(threads: Option<usize>) -> PyResult<()> {
    match threads {
        Some(0) => Err(value_error("threads = 0: a run needs at least one thread")),
        _ => Ok(()),
    }
}

/// The refinement's own lines, on Python's stderr (a notebook shows them).
struct ToStderr;

impl refine_rounds::Log for ToStderr {
    fn say(&self, line: &str) {
        Python::attach(|py| {
            let _ = py
                .import("sys")
                .and_then(|sys| sys.getattr("stderr"))
                .and_then(|err| err.call_method1("write", (format!("{line}\n"),)));
        });
    }
}

/// Runs `job` on a thread of its own with the GIL released, while this thread hands the progress
/// to `progress` and looks for Ctrl-C a few times a second; Ctrl-C (or an exception in the
/// callback) sets the run's interrupt, waits for the job to checkpoint and return, and is raised.
fn watched<T: Send>(
    py: Python<'_>,
    progress: Option<&Py<PyAny>>,
    opts: &mut RunOptions,
    job: impl FnOnce(&RunOptions, &Tally) -> Result<T, edmd_sweep::SweepError> + Send,
) -> PyResult<T> {
    let interrupt = Arc::new(AtomicBool::new(false));
    opts.interrupt = Some(interrupt.clone());
    let tally = Tally::default();
    let mut stopped_by = None;
    let opts = &*opts;
    let result = py.detach(|| {
        std::thread::scope(|s| {
            let worker = s.spawn(|| job(opts, &tally));
            while !worker.is_finished() {
                std::thread::sleep(TICK);
                if stopped_by.is_none() {
                    if let Err(e) = Python::attach(|py| tell(py, progress, &tally)) {
                        interrupt.store(true, Ordering::Relaxed);
                        stopped_by = Some(e);
                    }
                }
            }
            worker.join().expect("the sweep does not panic")
        })
    });
    let value = result.map_err(value_error)?;
    tell(py, progress, &tally)?;
    match stopped_by {
        Some(e) => Err(e),
        None => Ok(value),
    }
}

/// Hands the progress to the callback and looks for Ctrl-C.
fn tell(py: Python<'_>, progress: Option<&Py<PyAny>>, tally: &Tally) -> PyResult<()> {
    py.check_signals()?;
    if let Some(f) = progress {
        f.call1(py, tally.read())?;
    }
    Ok(())
}
