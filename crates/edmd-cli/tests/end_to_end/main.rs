//! End-to-end tests of the `edmd` binary, one module per subject, in one test crate: one build and
//! one link instead of seven (the fresh test build of a 2-core machine; docs/benchmarks.md).
//!
//! * `cli`: determinism across thread counts, resume after SIGKILL, sharding and merge, the ready
//!   specs, clear errors for bad input.
//! * `early_end`: runs that must not end `done` by mistake; no file written through a symbolic link.
//! * `hardening`: a disk that fills, files corrupted after the fact, two runs into one output,
//!   misuse and oversized values.
//! * `index_writes`: an index that cannot be written whole is never put in place.
//! * `refine`: rounds that resume after SIGKILL, shards and `--plan`, refusals.
//! * `refine_points`: points known by their parameters; axes named once; rounds of at least 1.
//! * `scenes`: rough grains, mixtures, gravity with a thermal floor, wall restitution, boxes.
//! * `shaken`: a bed on a vibrating floor from a spec: its parameters, observables and grains.
//! * `sheared`: the sheared gas from a spec: files, steady state, bad specs, resume.
//! * `spec_fuzz`: hostile spec fields get exit 0 or 1 with one line, never a panic.
//!
//! `cargo test -p edmd-cli --test end_to_end MODULE::` runs one subject.

mod common;

mod cli;
mod early_end;
mod hardening;
mod index_writes;
mod refine;
mod refine_points;
mod scenes;
mod shaken;
mod sheared;
mod spec_fuzz;
