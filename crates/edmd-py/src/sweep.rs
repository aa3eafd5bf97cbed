//! `edmd.run_sweep`: a sweep run as `edmd run` runs it, writing the same files; the phase table
//! comes back as JSON for the Python side to turn into a DataFrame.

use std::path::PathBuf;

use edmd_sweep::lock::LockMode;
use edmd_sweep::output::OutDir;
use edmd_sweep::run::{run_sweep, RunOptions, Silent};
use edmd_sweep::spec::Spec;
use edmd_sweep::summary::{phase_table, render, Format};
use pyo3::prelude::*;

use crate::value_error;

/// Runs the sweep `spec` (JSON text) into `out` with `threads` worker threads (every core if
/// None); returns the phase table as JSON text (`[]` while other shards are missing).
#[pyfunction]
#[pyo3(signature = (spec, out, threads = None, force = false))]
pub fn run_sweep_json(
    py: Python<'_>,
    spec: &str,
    out: PathBuf,
    threads: Option<usize>,
    force: bool,
) -> PyResult<String> {
    let spec = Spec::from_json(spec).map_err(value_error)?;
    let dir = OutDir::prepare(&out, &spec, force, LockMode::Exclusive).map_err(value_error)?;
    let opts = RunOptions {
        threads,
        force,
        ..RunOptions::default()
    };
    let report = py
        .detach(|| run_sweep(&spec, &dir, &opts, &Silent))
        .map_err(value_error)?;
    Ok(match &report.records {
        Some(records) => render(&phase_table(&spec, records), Format::Json),
        None => "[]".into(),
    })
}
