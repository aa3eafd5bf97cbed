//! # edmd-sweep
//!
//! Ensembles of [`edmd_core`] simulations: a JSON sweep spec ([`spec`]) expands into replicas over a
//! grid of (D, boundary, remedy, N, φ or L, ε, seed); [`run`] runs them across cores with rayon, each
//! replica single-threaded and deterministic, writing one H5MD file per replica ([`h5md`]) under a
//! temporary name that is renamed when complete; [`output`] keeps the output directory and the sweep
//! index; [`summary`] aggregates the phase table. The `edmd` binary (crate `edmd-cli`) is the command-line
//! front end; this library has no command-line or terminal dependency (progress reaches the caller
//! through [`run::Progress`]).
#![warn(missing_docs)]

pub mod budget;
pub mod classify;
pub mod configuration;
pub mod domain;
mod error;
pub mod files;
pub mod h5md;
pub mod lock;
pub mod merge;
pub mod output;
pub mod record;
pub mod refine;
pub mod refine_rounds;
pub mod replica;
pub use replica::checkpoint;
pub mod run;
pub mod spec;
pub mod summary;

pub use error::SweepError;

/// The quick default sweep run by a bare `edmd run` (and `make run`).
pub const QUICK_SPEC: &str = include_str!("../../../sweeps/quick.json");
