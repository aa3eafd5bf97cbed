//! Particle state.

use crate::Vector;

/// The per-particle data the event loop reads for every neighbour: position and velocity at the
/// particle's own time `t` (positions are advanced lazily), and its radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Particle<const D: usize> {
    /// Position at time `t`.
    pub pos: Vector<D>,
    /// Velocity.
    pub vel: Vector<D>,
    /// Time of the last update (local clock of the simulation).
    pub t: f64,
    /// Radius.
    pub radius: f64,
}

/// A particle as given to a constructor: position, velocity, radius, mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleInit<const D: usize> {
    /// Position inside the box.
    pub pos: Vector<D>,
    /// Velocity.
    pub vel: Vector<D>,
    /// Radius (> 0).
    pub radius: f64,
    /// Mass (> 0).
    pub mass: f64,
}
