//! Particle state.

use crate::Vector;

/// The per-particle data the event loop reads for every neighbour, in one cache line (48 bytes in
/// 2D, 64 in 3D): the straight-line trajectory `r(t) = r0 + vel·t` in the simulation's local clock
/// (positions are never advanced between events; `r0` changes only when the velocity does), the
/// radius, and the link to the next member of the particle's cell (cell mode; in list mode the list
/// grid links through `NeighbourLists::links` and this field stays unused). In declaration order
/// (`repr(C)`): the four-wide list scan reads the fields by their offsets (`sim/neighbours/wide_scan.rs`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[repr(C)]
pub struct Particle<const D: usize> {
    /// Position extrapolated back to local time 0.
    pub r0: Vector<D>,
    /// Velocity.
    pub vel: Vector<D>,
    /// Radius.
    pub radius: f64,
    pub(crate) next_in_cell: u32,
    /// Collisions suffered; a partner's stored count that differs marks a stale candidate. Kept
    /// here, in the record a prediction reads anyway, rather than beside the event slot (in the
    /// padding of the record, so it costs no memory).
    pub(crate) counter: u32,
}

impl<const D: usize> Particle<D> {
    /// The straight-line part of the trajectory at local time `t`: the position itself except
    /// under gravity, whose fall along the last axis the scene adds (`sim/scene.rs`).
    #[inline(always)]
    pub fn at(&self, t: f64) -> Vector<D> {
        self.r0 + self.vel * t
    }

    /// A new velocity `v` from local time `t` on, through `pos`, the position at `t` (known to the
    /// caller, which has just used it): the trajectory's origin moves, and the collision counter
    /// advances so that predictions made against the old trajectory go stale.
    #[inline(always)]
    pub(crate) fn set_velocity(&mut self, pos: Vector<D>, v: Vector<D>, t: f64) {
        self.r0 = pos - v * t;
        self.vel = v;
        self.bump();
    }

    /// [`Self::set_velocity`] with the origin moved by the velocity's change, `r0 += (vel − v) t`:
    /// the same position to round-off, in the form wall contacts have always used (the two
    /// roundings differ in the last bit, and results stay bit-identical only with each kept).
    #[inline(always)]
    pub(crate) fn change_velocity(&mut self, v: Vector<D>, t: f64) {
        self.r0 += (self.vel - v) * t;
        self.vel = v;
        self.bump();
    }

    /// [`Self::change_velocity`] along one axis only.
    #[inline(always)]
    pub(crate) fn change_velocity_along(&mut self, axis: usize, v: f64, t: f64) {
        self.r0[axis] += (self.vel[axis] - v) * t;
        self.vel[axis] = v;
        self.bump();
    }

    /// Marks every prediction made against the present trajectory stale.
    #[inline(always)]
    pub(crate) fn bump(&mut self) {
        self.counter = self.counter.wrapping_add(1);
    }
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

// One particle record per cache line in 3D, and no larger than its constructor's record (the
// conversion in `Simulation::new` reuses that allocation).
const _: () = assert!(std::mem::size_of::<Particle<3>>() == 64);
// The four-wide 3D scan loads a record as [x y z vx | vy vz radius link] (`sim/neighbours/wide_scan.rs`).
const _: () = assert!(
    std::mem::offset_of!(Particle<3>, vel) == 24 && std::mem::offset_of!(Particle<3>, radius) == 48
);
const _: () = assert!(std::mem::size_of::<Particle<2>>() == std::mem::size_of::<ParticleInit<2>>());
