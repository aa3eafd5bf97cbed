//! The engine alone on a replica: the simulation the runner would build for it, behind the
//! object-safe [`Engine`], run without sampling, snapshots, classification or checkpoints. It
//! measures the runner's own cost on the same trajectory (`edmd bench-replica`, docs/benchmarks.md)
//! and is the Python module's `Simulation.from_spec`.

use std::time::Instant;

use edmd_core::{
    Boundary, Channel, CollisionRule, Column, Container, EdmdError, Engine, Law, LeesEdwards,
    Periodic, Remedy, Stop, Walls,
};

use super::{rule, setup::init_params};
use crate::spec::{BoundaryKind, Replica, Spec};

/// Builds replica `r` as the runner does and runs it to `collisions` pair collisions; returns the
/// collisions run and the seconds taken, building included (as the runner's `wall_s` includes it).
pub fn engine_only(spec: &Spec, r: &Replica, collisions: u64) -> Result<(u64, f64), EdmdError> {
    let start = Instant::now();
    let tau = collisions as f64 / r.n as f64;
    let run = match r.dim {
        2 => engine::<2>(spec, r).map(|mut e| (e.run(Stop::Tau(tau)), *e.counters())),
        3 => engine::<3>(spec, r).map(|mut e| (e.run(Stop::Tau(tau)), *e.counters())),
        d => Err(EdmdError::invalid("dim", d, "dimension must be 2 or 3")),
    };
    let (_, counters) = run?;
    Ok((counters.pair_collisions, start.elapsed().as_secs_f64()))
}

/// A replica's simulation in either dimension.
pub enum AnyEngine {
    /// A 2D replica.
    D2(Box<dyn Engine<2>>),
    /// A 3D replica.
    D3(Box<dyn Engine<3>>),
}

impl std::fmt::Debug for AnyEngine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (dim, n) = match self {
            AnyEngine::D2(e) => (2, e.len()),
            AnyEngine::D3(e) => (3, e.len()),
        };
        f.debug_struct("AnyEngine")
            .field("dim", &dim)
            .field("n", &n)
            .finish_non_exhaustive()
    }
}

/// Replica `r`'s simulation in its dimension. Not generic, so that a crate calling it (the Python
/// module) links the engine compiled here instead of compiling its own copy of every scene.
pub fn any_engine(spec: &Spec, r: &Replica) -> Result<AnyEngine, EdmdError> {
    match r.dim {
        2 => engine::<2>(spec, r).map(AnyEngine::D2),
        3 => engine::<3>(spec, r).map(AnyEngine::D3),
        d => Err(EdmdError::invalid("dim", d, "dimension must be 2 or 3")),
    }
}

/// The law and remedy replica `r` collides by, as the runner builds them (and checks them against
/// its scene): what a simulation built by [`any_engine`] takes to change its rule between runs.
pub fn law_and_remedy(spec: &Spec, r: &Replica) -> Result<(Law, Remedy), EdmdError> {
    let rule = rule(spec, r)?;
    Ok((*rule.law(), rule.remedy()))
}

/// Replica `r`'s simulation as the runner builds it: its scene as a type, its rule, its start
/// (placement or `init.from`, and the melt).
pub fn engine<const D: usize>(spec: &Spec, r: &Replica) -> Result<Box<dyn Engine<D>>, EdmdError> {
    match (r.boundary, r.gravity > 0.0) {
        (BoundaryKind::Periodic, _) => grains::<D, Periodic>(spec, r),
        (BoundaryKind::LeesEdwards, _) => grains::<D, LeesEdwards>(spec, r),
        (BoundaryKind::Walls, false) => grains::<D, Walls>(spec, r),
        (BoundaryKind::Channel, false) => grains::<D, Channel>(spec, r),
        (BoundaryKind::Walls, true) => grains::<D, Container>(spec, r),
        (BoundaryKind::Channel, true) => grains::<D, Column>(spec, r),
    }
}

fn grains<const D: usize, B: Boundary>(
    spec: &Spec,
    r: &Replica,
) -> Result<Box<dyn Engine<D>>, EdmdError> {
    let law = rule(spec, r)?;
    if r.rough() {
        built::<D, B, _>(spec, r, law.rough(r.beta, r.inertia)?)
    } else {
        built::<D, B, _>(spec, r, law)
    }
}

fn built<const D: usize, B: Boundary, R: CollisionRule + 'static>(
    spec: &Spec,
    r: &Replica,
    rule: R,
) -> Result<Box<dyn Engine<D>>, EdmdError> {
    Ok(Box::new(init_params::<D>(spec, r)?.0.build::<B, R>(rule)?))
}
