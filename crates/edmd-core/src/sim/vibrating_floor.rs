//! A floor that vibrates under gravity (PHYSICS.md §8.3): z_w(t) = A + A sin(ωt + φ), so that in
//! the box's coordinates it moves between 0 and 2A and starts at its lowest point (φ = −π/2 at
//! time 0, at rest). Its contact with a grain's parabolic flight is the exact first root of
//! [`crate::floor`]; a contact reflects the grain in the floor's frame with the wall's
//! restitution, elastically below `wall_threshold` (the treatment of grains that would come to
//! rest on the floor, §8.3: they keep bouncing with a speed about the threshold relative to it).
//!
//! Only cells whose lower face lies below the floor's top plus the largest radius can hold a grain
//! that touches it; [`VibratingFloor::cells`] counts those layers, 0 for a floor that stands still,
//! so that a static scene takes the static formula, bit for bit.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::{Aux, Simulation};
use crate::calendar::Calendar;
use crate::floor::{Flight, Floor};
use crate::predict::fall_time;
use crate::{Boundary, CollisionRule, Particle};

/// The vibrating floor's motion and the cell layers it can reach.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct VibratingFloor {
    /// Amplitude A (0: the floor stands still at 0).
    pub amplitude: f64,
    /// Angular frequency ω.
    pub omega: f64,
    /// Phase φ at local time 0, in [0, 2π): moved on and reduced at every clock rebase, so that
    /// sin(ωt + φ) keeps its precision however long the run.
    pub phase: f64,
    /// Layers of cells, from the bottom, in which a grain can touch the floor (0 when it is still).
    pub cells: u16,
}

impl VibratingFloor {
    /// A floor of amplitude `amplitude` and angular frequency `omega` at its lowest point at time
    /// 0, reaching grains of radius up to `max_radius` in cells of height `cell_side`.
    pub fn new(amplitude: f64, omega: f64, max_radius: f64, cell_side: f64) -> Self {
        if amplitude <= 0.0 {
            return VibratingFloor::default();
        }
        let reach = 2.0 * amplitude + max_radius;
        VibratingFloor {
            amplitude,
            omega,
            phase: 1.5 * PI,
            cells: ((reach / cell_side).floor() as u64 + 1).min(u16::MAX as u64) as u16,
        }
    }

    /// Whether a grain in cell layer `c` (from the bottom) may touch the floor.
    #[inline(always)]
    pub fn reaches(&self, c: u16) -> bool {
        c < self.cells
    }

    /// Whether the floor moves.
    #[inline(always)]
    pub fn moves(&self) -> bool {
        self.amplitude > 0.0
    }

    /// The floor as [`crate::floor`] describes it (height about its mean A) from local time `now`
    /// on, as at time 0.
    pub fn at(&self, now: f64) -> Floor {
        Floor {
            amplitude: self.amplitude,
            omega: self.omega,
            phase: self.phase + self.omega * now,
        }
    }

    /// The floor's height in the box at local time `now`.
    pub fn height(&self, now: f64) -> f64 {
        self.amplitude + self.at(now).height(0.0)
    }

    /// Time from `now` until a grain whose lowest point is at `z_low` in the box, with vertical
    /// speed `u`, meets the floor, within `horizon` (∞ if not).
    pub fn contact(&self, z_low: f64, u: f64, g: f64, now: f64, horizon: f64) -> f64 {
        let floor = self.at(now);
        let floor_now = floor.height(0.0);
        let z0 = z_low - self.amplitude;
        if z0 < floor_now {
            // Below by round-off (just after a contact): touching now, so approaching means the
            // contact is now, and receding means the flight starts on the floor.
            if u - floor.speed(0.0) < 0.0 {
                return 0.0;
            }
        }
        let flight = Flight {
            z0: z0.max(floor_now),
            v0: u,
            g,
        };
        flight
            .first_contact(&floor, horizon)
            .unwrap_or(f64::INFINITY)
    }

    /// Moves the phase to local time `now`, which becomes time 0.
    pub fn rebase(&mut self, now: f64) {
        if self.moves() {
            self.phase = (self.phase + self.omega * now).rem_euclid(2.0 * PI);
        }
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Under gravity, in a cell layer the vibrating floor reaches: the grain's next event along
    /// the last axis, the earliest of rising out of the cell (`up`, found by the caller), falling
    /// into the cell below, and meeting the floor. `x` and `u` are the grain's height and vertical
    /// speed now.
    #[inline(never)]
    pub(super) fn vibrating_fall_exit(
        &self,
        p: &Particle<D>,
        layer: u16,
        (x, u): (f64, f64),
        up: (f64, Aux),
    ) -> (f64, Aux) {
        let a = D - 1;
        let g = self.params.gravity;
        let t_cross = if layer == 0 {
            f64::INFINITY
        } else {
            fall_time(x, u, g, layer as f64 * self.grid.side[a])
        };
        let horizon = up.0.min(t_cross);
        let t_floor = self
            .vibration
            .contact(x - p.radius, u, g, self.now, horizon);
        let axis = a as u8;
        let (t, code) = if t_floor.is_finite() && t_floor <= horizon {
            (t_floor, Aux::Wall { axis, up: false })
        } else if t_cross < up.0 {
            (t_cross, Aux::Crossing { axis, up: false })
        } else {
            up
        };
        (self.now + t, code)
    }

    /// Grain `i` meets the vibrating floor: its vertical velocity is reflected in the floor's
    /// frame with the wall's restitution (elastic below `wall_threshold`), and the kinetic energy
    /// it gains is added to [`super::Counters::floor_work`].
    #[cold]
    pub(super) fn vibrating_floor_contact(&mut self, i: usize) {
        let a = D - 1;
        let now = self.now;
        let g = self.params.gravity;
        let floor_speed = self.vibration.at(now).speed(0.0);
        let u = self.particles[i].vel[a] - g * now;
        let relative = u - floor_speed;
        let e = if relative.abs() < self.params.wall_threshold {
            1.0
        } else {
            self.params.wall_epsilon
        };
        let u_new = floor_speed - e * relative;
        self.particles[i].change_velocity_along(a, u_new + g * now, now);
        self.counters.wall_collisions += 1;
        self.counters.floor_work += 0.5 * self.meta[i].mass * (u_new * u_new - u * u);
    }

    /// The vibrating floor's height in the box now (0 for a floor that stands still).
    pub fn floor_height(&self) -> f64 {
        if self.vibration.moves() {
            self.vibration.height(self.now)
        } else {
            0.0
        }
    }

    /// The vibrating floor's vertical speed now (0 for a floor that stands still).
    pub fn floor_speed(&self) -> f64 {
        if self.vibration.moves() {
            self.vibration.at(self.now).speed(0.0)
        } else {
            0.0
        }
    }
}
