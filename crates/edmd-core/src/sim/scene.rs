//! What differs between scenes, in one place: the nearest image across the periodic faces,
//! gravity's parabolic flight and the walls it meets, the wall contact itself (specular with a
//! restitution, or the thermal floor), where a grain is now and what moves with the clock's
//! rebase, and what each scene allows (neighbour lists, deep-cooling rescales, drift removal). The
//! sliding images of a sheared box are the other scene-specific file, `sim/shear.rs`; the event
//! loop asks these two and reads no scene flag itself.
//!
//! A new kind of wall (a floor that moves) is a new flight or contact here: the loop calls
//! [`Simulation::fall_exit`], [`Simulation::wall_ahead`] and [`Simulation::wall`] whatever the scene.

use super::{Aux, Simulation};
use super::{CellGrid, NONE};
use crate::calendar::Calendar;
use crate::predict::{fall_time, reach_time, rise_time};
use crate::{Boundary, CollisionRule, EdmdError, Particle, SimParams, Vector};

/// Whether scene `B` may run with neighbour lists: not under gravity, whose parabolas shells do not
/// bound.
#[inline(always)]
pub(crate) fn lists_possible<B: Boundary>() -> bool {
    !B::GRAVITY
}

/// Whether a list grid suits scene `B`: a sheared box needs four distinct columns across the
/// sliding faces (`sim/neighbours/shear_lists.rs`).
pub(super) fn list_grid_fits<const D: usize, B: Boundary>(grid: &CellGrid<D>) -> bool {
    !B::SHEARED || grid.n[0] >= 4
}

/// The checks of [`super::Simulation::new`] on the box and the parameters against scene `B`.
pub(crate) fn check_scene<const D: usize, B: Boundary>(
    n: usize,
    box_len: &Vector<D>,
    params: &SimParams,
) -> Result<(), EdmdError> {
    if n == 0 {
        return Err(EdmdError::invalid("N", 0, "need at least one particle"));
    }
    if n >= NONE as usize {
        return Err(EdmdError::invalid("N", n, "at most 2^32 − 2 particles"));
    }
    for a in 0..D {
        if !(box_len[a] > 0.0 && box_len[a].is_finite()) {
            return Err(EdmdError::invalid(
                crate::error::AXIS_NAMES[a],
                box_len[a],
                "box side must be positive and finite",
            ));
        }
    }
    params.validate()?;
    if params.gravity != 0.0 && !B::GRAVITY {
        return Err(EdmdError::invalid(
            "gravity",
            params.gravity,
            "this scene has no gravity: use a GravityAxes scene",
        ));
    }
    if params.shear_rate != 0.0 && !B::SHEARED {
        return Err(EdmdError::invalid(
            "shear_rate",
            params.shear_rate,
            "this scene is not sheared: use the LeesEdwards scene",
        ));
    }
    if params.floor_temperature > 0.0 && !B::is_wall(D - 1) {
        return Err(EdmdError::invalid(
            "floor_temperature",
            params.floor_temperature,
            "a thermal floor needs walls on the last axis",
        ));
    }
    if params.floor_amplitude > 0.0 {
        check_vibrating_floor::<D, B>(box_len, params)?;
    }
    if B::GRAVITY && !B::is_wall(D - 1) {
        return Err(EdmdError::invalid(
            "scene",
            B::NAME,
            "gravity needs walls (a floor) on the last axis",
        ));
    }
    Ok(())
}

/// A vibrating floor needs gravity, a top above its stroke, no thermal floor, and a wall contact
/// that can neither stop a grain on it nor let its bounces die away (PHYSICS.md §8.3).
fn check_vibrating_floor<const D: usize, B: Boundary>(
    box_len: &Vector<D>,
    params: &SimParams,
) -> Result<(), EdmdError> {
    let amplitude = params.floor_amplitude;
    let refuse = |reason| Err(EdmdError::invalid("floor_amplitude", amplitude, reason));
    if !B::GRAVITY || params.gravity <= 0.0 {
        return refuse("a vibrating floor needs a gravity scene with gravity > 0");
    }
    if params.floor_temperature > 0.0 {
        return refuse("a floor either vibrates or is thermal, not both");
    }
    if 2.0 * amplitude >= box_len[D - 1] {
        return refuse("the floor's stroke 2A must stay below the box's top");
    }
    if params.wall_epsilon == 0.0 {
        return Err(EdmdError::invalid(
            "wall_epsilon",
            0.0,
            "a vibrating floor needs a wall restitution > 0 (at 0 a grain rides it in contacts without end)",
        ));
    }
    if params.wall_epsilon < 1.0 && params.wall_threshold <= 0.0 {
        return Err(EdmdError::invalid(
            "wall_threshold",
            params.wall_threshold,
            "an inelastic vibrating floor needs a threshold > 0, below which contacts are elastic (else a resting grain's bounces die away in contacts without end)",
        ));
    }
    Ok(())
}

/// The image of `x` nearest to `y` across the periodic faces of a box of sides `box_len`.
#[inline(always)]
pub(super) fn image_near<const D: usize, B: Boundary>(
    box_len: &Vector<D>,
    half_box: &Vector<D>,
    x: &Vector<D>,
    y: &Vector<D>,
) -> Vector<D> {
    let mut r = *x;
    for a in 0..D {
        if !B::is_wall(a) {
            let d = x[a] - y[a];
            if d > half_box[a] {
                r[a] -= box_len[a];
            } else if d < -half_box[a] {
                r[a] += box_len[a];
            }
        }
    }
    r
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// The image of j nearest to i (at `x`, moving with `v`), found as the searches find it, so
    /// that a pair they predicted approaching is approaching here too: i's position moved to that
    /// image's frame, and i's velocity there (its own but across a sliding face).
    #[inline(always)]
    pub(super) fn pair_image(
        &self,
        x: &Vector<D>,
        v: &Vector<D>,
        y: &Vector<D>,
    ) -> (Vector<D>, Vector<D>) {
        if B::SHEARED {
            self.sheared_image_near(x, v, y)
        } else {
            (self.image_near(x, y), *v)
        }
    }

    /// `x` moved by a box length on each periodic axis where that brings it nearer to `y` (the
    /// minimum image of `x − y` is then the plain difference). `collide` and the neighbour-list
    /// search both take images this way, so that they agree to the last bit.
    #[inline(always)]
    pub(super) fn image_near(&self, x: &Vector<D>, y: &Vector<D>) -> Vector<D> {
        image_near::<D, B>(&self.box_len, &self.half_box, x, y)
    }

    /// True if the flight along `axis` is a parabola (gravity's last axis), which
    /// [`Self::fall_exit`] handles; the straight axes are the cell search's.
    #[inline(always)]
    pub(super) fn falls_along(&self, axis: usize) -> bool {
        B::GRAVITY && axis == D - 1
    }

    /// Cell mode: under gravity, the next crossing or wall contact along the last axis (in cell
    /// `c`); elsewhere none, `(∞, _)`.
    #[inline(always)]
    pub(super) fn fall_exit(&self, p: &Particle<D>, c: &[u16; D]) -> (f64, Aux) {
        if !B::GRAVITY {
            return (f64::INFINITY, Aux::Crossing { axis: 0, up: false });
        }
        // The last axis: a parabola, which may turn before the upper face and always falls.
        let a = D - 1;
        let g = self.params.gravity;
        let now = self.now;
        let x = p.r0[a] + p.vel[a] * now - 0.5 * g * now * now;
        let u = p.vel[a] - g * now;
        let top = c[a] as usize + 1 == self.grid.n[a];
        let axis = a as u8;
        let (up_target, up_code) = if top {
            (self.box_len[a] - p.radius, Aux::Wall { axis, up: true })
        } else {
            (
                (c[a] + 1) as f64 * self.grid.side[a],
                Aux::Crossing { axis, up: true },
            )
        };
        let (down_target, down_code) = if c[a] == 0 {
            (p.radius, Aux::Wall { axis, up: false })
        } else {
            (
                c[a] as f64 * self.grid.side[a],
                Aux::Crossing { axis, up: false },
            )
        };
        let t_up = rise_time(x, u, g, up_target);
        if self.vibration.reaches(c[a]) {
            return self.vibrating_fall_exit(p, c[a], (x, u), (t_up, up_code));
        }
        let t_down = fall_time(x, u, g, down_target);
        if t_up < t_down {
            (now + t_up, up_code)
        } else {
            (now + t_down, down_code)
        }
    }

    /// Time from now until `p`'s straight flight along `axis` (speed ≠ 0, upwards if `up`) touches
    /// the wall ahead: for cell mode at the box's edge cells and for list mode alike.
    #[inline(always)]
    pub(super) fn wall_ahead(&self, p: &Particle<D>, axis: usize, up: bool) -> f64 {
        let v = p.vel[axis];
        reach_time(p.r0[axis] + v * self.now, v, self.wall_target(p, axis, up))
    }

    /// Where `p`'s centre touches the upper (`up`) or lower wall normal to `axis`.
    #[inline(always)]
    fn wall_target(&self, p: &Particle<D>, axis: usize, up: bool) -> f64 {
        if up {
            self.box_len[axis] - p.radius
        } else {
            p.radius
        }
    }

    /// Specular reflection of particle `i` at a wall normal to `axis` (the upper one if `up`), with
    /// the wall's restitution; under gravity the floor may vibrate (`sim/vibrating_floor.rs`).
    #[inline]
    pub(super) fn wall(&mut self, i: usize, axis: usize, up: bool) {
        if B::GRAVITY && axis == D - 1 && !up && self.vibration.moves() {
            self.vibrating_floor_contact(i);
            return;
        }
        let now = self.now;
        let gravity = if B::GRAVITY && axis == D - 1 {
            self.params.gravity
        } else {
            0.0
        };
        // Normal speed at contact (the stored velocity is the one at local time 0 under gravity).
        let u = self.particles[i].vel[axis] - gravity * now;
        if self.params.floor_temperature > 0.0 && axis == D - 1 && u < 0.0 {
            self.thermal_floor(i, gravity);
            return;
        }
        let e = if u.abs() < self.params.wall_threshold {
            1.0
        } else {
            self.params.wall_epsilon
        };
        // r0 + v t is the non-gravitational part of the trajectory, kept continuous.
        self.particles[i].change_velocity_along(axis, -e * u + gravity * now, now);
        self.counters.wall_collisions += 1;
    }

    /// The thermal floor: particle `i`, hitting the wall at 0 of the last axis, leaves with a velocity
    /// drawn from the wall's flux-weighted Maxwellian at `floor_temperature` (in simulated units, so
    /// scaled like every velocity): normal speed √(−2 (T/m) ln U), Rayleigh-distributed, away from
    /// the wall; tangential components Gaussian of variance T/m.
    #[cold]
    fn thermal_floor(&mut self, i: usize, gravity: f64) {
        use rand::Rng;
        let now = self.now;
        let sd = (self.params.floor_temperature / self.meta[i].mass).sqrt() * self.scale;
        let mut v_new = Vector::<D>::zeros();
        for a in 0..D - 1 {
            v_new[a] = sd * self.rng.sample::<f64, _>(rand_distr::StandardNormal);
        }
        // 1 − U lies in (0, 1]: the logarithm is finite.
        let u: f64 = 1.0 - self.rng.random::<f64>();
        v_new[D - 1] = sd * (-2.0 * u.ln()).sqrt() + gravity * now;
        self.particles[i].change_velocity(v_new, now);
        self.counters.wall_collisions += 1;
    }

    /// A particle's velocity at the current time (the stored one is at local time 0 under gravity).
    #[inline(always)]
    pub(crate) fn velocity_now(&self, p: &Particle<D>) -> Vector<D> {
        let mut v = p.vel;
        if B::GRAVITY {
            v[D - 1] -= self.params.gravity * self.now;
        }
        if B::SHEARED && self.nl.is_some() {
            // List mode wraps lazily: a grain past a sliding face reports its image in the box.
            v[0] -= self.faces_passed(p) * self.shear.speed;
        }
        v
    }

    /// A particle's thermal velocity at the current time: [`Self::velocity_now`] less the imposed
    /// flow a (y − L_y/2) e_x in a sheared scene (the peculiar velocity, y taken where the
    /// trajectory is), the velocity itself elsewhere. Simulation units.
    #[inline(always)]
    pub(crate) fn thermal_velocity_now(&self, p: &Particle<D>) -> Vector<D> {
        if B::SHEARED {
            // The same for a grain and its images: no wrapping needed.
            let mut v = p.vel;
            let y = p.r0[1] + p.vel[1] * self.now;
            v[0] -= self.params.shear_rate * (y - self.half_box[1]);
            return v;
        }
        self.velocity_now(p)
    }

    /// Potential energy Σ m g h in the gravity field (0 without gravity).
    pub fn potential_energy(&self) -> f64 {
        if !B::GRAVITY {
            return 0.0;
        }
        let g = self.params.gravity;
        (0..self.len())
            .map(|s| self.meta[s].mass * g * self.position_of_slot(s)[D - 1])
            .sum()
    }

    pub(super) fn position_of_slot(&self, s: usize) -> Vector<D> {
        let p = &self.particles[s];
        let mut x = p.at(self.now);
        if B::GRAVITY {
            x[D - 1] -= 0.5 * self.params.gravity * self.now * self.now;
        }
        if B::SHEARED && self.nl.is_some() {
            let k = self.faces_passed(p);
            x[1] -= k * self.box_len[1];
            x[0] -= k * self.shear_delta();
        }
        for a in 0..D {
            if !B::is_wall(a) {
                x[a] = x[a].rem_euclid(self.box_len[a]);
            }
        }
        x
    }

    /// The trajectories' part of a clock rebase to local time `now`: origins (and, under gravity,
    /// the velocity at the origin) moved so that every grain is where it was.
    pub(super) fn rebase_trajectories(&mut self, now: f64) {
        self.vibration.rebase(now);
        let g = self.params.gravity;
        for p in &mut self.particles {
            p.r0 = p.at(now);
            if B::GRAVITY {
                p.r0[D - 1] -= 0.5 * g * now * now;
                p.vel[D - 1] -= g * now;
            }
        }
    }

    /// Whether a deeply cooled gas may have its velocities rescaled: not under gravity (the
    /// acceleration would have to be rescaled too), not under shear (the images' speed too; a
    /// sheared gas reaches a steady temperature instead of cooling without end), not with a
    /// thermostat (a driven gas is steady too).
    #[inline(always)]
    pub(super) fn may_rescale(&self) -> bool {
        !B::GRAVITY && !B::SHEARED && !self.thermostat.on()
    }

    /// Whether the scene conserves momentum, so that a drift may be removed: periodic on every
    /// axis, without gravity, without the sliding images' exchange of momentum, and without kicks
    /// (whose random walk of the total momentum is part of the model).
    #[inline(always)]
    pub(super) fn conserves_momentum(&self) -> bool {
        B::WALL_MASK == 0 && !B::GRAVITY && !B::SHEARED && !self.thermostat.on()
    }
}
