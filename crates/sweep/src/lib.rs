//! # edmd-sweep
//!
//! Ensembles of [`edmd_core`] simulations: a JSON sweep spec ([`spec`]) expands into replicas over a
//! grid of (D, boundary, remedy, N, φ or L, ε, seed); [`run`] runs them across cores with rayon, each
//! replica single-threaded and deterministic, writing one H5MD file per replica ([`h5md`]) under a
//! temporary name that is renamed when complete; [`output`] keeps the output directory and the sweep
//! index; [`summary`] aggregates the phase table. The `edmd` binary is the command-line front end.
#![warn(missing_docs)]

pub mod classify;
pub mod h5md;
pub mod merge;
pub mod output;
pub mod replica;
pub mod run;
pub mod spec;
pub mod summary;

use thiserror::Error;

/// Everything that can go wrong in a sweep. Messages name the field, value or path at fault.
#[derive(Debug, Error)]
pub enum SweepError {
    /// The sweep spec is malformed or holds a value out of its domain.
    #[error("invalid sweep spec: {0}")]
    Spec(String),
    /// A command-line argument is wrong.
    #[error("{0}")]
    Usage(String),
    /// Reading or writing the output failed.
    #[error("{0}")]
    Output(String),
}

/// The quick default sweep run by a bare `edmd run` (and `make run`).
pub const QUICK_SPEC: &str = include_str!("../../../sweeps/quick.json");
