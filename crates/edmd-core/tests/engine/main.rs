//! The engine's integration tests, one binary: physics against theory and independent oracles,
//! numerical stability, fuzzing. Long versions are `#[ignore]`d and run by `make stress` and
//! `make validate`.

mod collapse;
mod conservation;
mod deep_cooling;
mod equilibrium;
mod event_counts;
mod floor_contact;
mod fuzz;
mod gravity;
mod haff;
mod lees_edwards;
mod lees_edwards_rules;
mod mixture;
mod oracle;
mod overlaps;
mod persist;
mod ratio;
mod regress_round_off_contact;
mod rough;
mod rough_cooling;
mod shaken_bed;
mod shear_rheology;
mod single_ball;
mod single_collision;
mod stress;
mod viscoelastic;
mod white_noise;
