//! `edmd` for Python: the engine in-process ([`Simulation`]) and sweeps from a notebook
//! ([`run_sweep`]), over the public API of edmd-core and edmd-sweep; nothing of the engine is
//! written twice here. The Python package around it (`python/edmd/`) adds the DataFrame and the
//! type hints.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

mod chunks;
mod configuration;
mod simulation;
mod stress;
mod sweep;

pub use simulation::Simulation;

/// An edmd error as Python's `ValueError`, with the one line the command prints.
pub(crate) fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// The native part of the `edmd` package.
#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<Simulation>()?;
    m.add_function(wrap_pyfunction!(sweep::run_sweep_json, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::refine_json, m)?)?;
    Ok(())
}
