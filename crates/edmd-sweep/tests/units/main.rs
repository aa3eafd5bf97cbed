//! Unit tests of the sweep library, built as one integration test so that `cargo test` does not
//! compile the library a second time as a test harness (docs/benchmarks.md).

mod bed_meter;
mod budget;
mod checkpoint;
mod classify;
mod domain;
mod files;
mod lock;
mod record;
mod refine;
mod replica_shear;
mod spec;
mod spec_dup_keys;
mod spec_species;
