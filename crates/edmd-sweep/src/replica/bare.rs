//! The engine alone on a replica: the simulation the runner would build for it, run without
//! sampling, snapshots, classification or checkpoints, so that the runner's own cost can be measured
//! on the same trajectory (`edmd bench-replica`, docs/benchmarks.md).

use std::time::Instant;

use edmd_core::{
    Boundary, Channel, CollisionRule, Column, Container, EdmdError, LeesEdwards, Periodic, Stop,
    Walls,
};

use super::{rule, simulate::init_params};
use crate::spec::{BoundaryKind, Replica, Spec};

/// Builds replica `r` as the runner does and runs it to `collisions` pair collisions; returns the
/// collisions run and the seconds taken, building included (as the runner's `wall_s` includes it).
pub fn engine_only(spec: &Spec, r: &Replica, collisions: u64) -> Result<(u64, f64), EdmdError> {
    match r.dim {
        2 => scene::<2>(spec, r, collisions),
        3 => scene::<3>(spec, r, collisions),
        d => Err(EdmdError::invalid("dim", d, "dimension must be 2 or 3")),
    }
}

fn scene<const D: usize>(
    spec: &Spec,
    r: &Replica,
    collisions: u64,
) -> Result<(u64, f64), EdmdError> {
    match (r.boundary, r.gravity > 0.0) {
        (BoundaryKind::Periodic, _) => grains::<D, Periodic>(spec, r, collisions),
        (BoundaryKind::LeesEdwards, _) => grains::<D, LeesEdwards>(spec, r, collisions),
        (BoundaryKind::Walls, false) => grains::<D, Walls>(spec, r, collisions),
        (BoundaryKind::Channel, false) => grains::<D, Channel>(spec, r, collisions),
        (BoundaryKind::Walls, true) => grains::<D, Container>(spec, r, collisions),
        (BoundaryKind::Channel, true) => grains::<D, Column>(spec, r, collisions),
    }
}

fn grains<const D: usize, B: Boundary>(
    spec: &Spec,
    r: &Replica,
    collisions: u64,
) -> Result<(u64, f64), EdmdError> {
    let law = rule(spec, r)?;
    if r.rough() {
        timed::<D, B, _>(spec, r, law.rough(r.beta, r.inertia)?, collisions)
    } else {
        timed::<D, B, _>(spec, r, law, collisions)
    }
}

fn timed<const D: usize, B: Boundary, R: CollisionRule>(
    spec: &Spec,
    r: &Replica,
    rule: R,
    collisions: u64,
) -> Result<(u64, f64), EdmdError> {
    let start = Instant::now();
    let mut sim = init_params::<D>(spec, r)?.0.build::<B, R>(rule)?;
    sim.run(Stop::Tau(collisions as f64 / r.n as f64));
    Ok((
        sim.counters().pair_collisions,
        start.elapsed().as_secs_f64(),
    ))
}
