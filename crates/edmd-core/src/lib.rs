//! # edmd-core
//!
//! An event-driven molecular dynamics (EDMD) engine for smooth hard disks (`D = 2`) and spheres
//! (`D = 3`), written once for both dimensions with `nalgebra::SVector<f64, D>`.
//!
//! * **Events**: pair collisions, cell crossings and wall contacts; one pending event per particle,
//!   stale events detected by per-particle collision counters ([`sim`]).
//! * **Calendar**: O(1) amortised bucket queue after G. Paul, J. Comput. Phys. 221, 615 (2007)
//!   ([`PaulCalendar`]); a `BinaryHeap` version ([`HeapCalendar`]) is the oracle and baseline.
//! * **Cells**: a grid with side ≥ the largest diameter; a crossing searches only the newly adjacent
//!   cells ([`CellGrid`]). Dense 3D packings use neighbour lists with a skin instead ([`nlist`],
//!   [`SimParams::neighbour_skin`]).
//! * **Scenes**: periodic, walled, or mixed per axis, each a zero-sized type ([`Boundary`]).
//! * **Numerics**: cancellation-free contact roots, no event ever in the past, overlapping-and-
//!   approaching pairs collide at once, and the clock is rebased every few N events.
//!
//! Units: lengths in the user's units (σ = 1 by default), masses per particle, `T = m⟨v²⟩/d`,
//! τ = C/N pair collisions per particle. No I/O, no threads.
//!
//! ```
//! use edmd_core::{ConstantRestitution, InitParams, Periodic, Stop};
//! let params = InitParams::<2>::with_packing(1000, 0.25).unwrap();
//! let mut sim = params.build::<Periodic, _>(ConstantRestitution::new(0.9).unwrap()).unwrap();
//! sim.run(Stop::Tau(5.0));
//! assert!(sim.temperature() < 1.0);
//! ```
#![warn(missing_docs)]

mod alloc;
pub mod boundary;
pub mod caches;
pub mod calendar;
pub mod collide;
pub mod error;
pub mod floor;
pub mod geometry;
pub mod init;
pub mod observe;
pub mod order;
pub mod predict;
mod prefetch;
pub mod schedule;
pub mod sim;
pub mod state;
pub mod theory;

/// A D-dimensional `f64` vector.
pub type Vector<const D: usize> = nalgebra::SVector<f64, D>;

pub use alloc::LineAligned;
pub use boundary::{
    Axes, Boundary, Channel, Column, Container, GravityAxes, LeesEdwards, Periodic, Walls,
};
pub use calendar::{Calendar, Entry, HasEntry, HeapCalendar, PaulCalendar, Standalone};
pub use collide::{
    CollisionRule, ConstantRestitution, Elastic, Grain, LastCollision, Law, Remedy, Rough, Rule,
    Smooth, Spin, ThesisRestitution, ThresholdRestitution, Viscoelastic,
};
pub use error::EdmdError;
pub use init::{InitParams, Placement, Velocities};
pub use observe::{decay_rate, Observables, VirialMeter, VirialReading};
pub use order::{order_parameters, OrderParameters};
pub use schedule::Schedule;
pub use sim::neighbours::CellGrid;
pub use sim::{
    Collapse, CollapseReason, Counters, Engine, EventKind, RunEnd, SimParams, Simulation, Stop,
    STATE_VERSION,
};
pub use state::{Particle, ParticleInit};
