//! Controls on the velocity scale: deep-cooling rescale, drift removal, and explicit scaling.

use super::Simulation;
use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule, Vector};

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Deep cooling: if the simulated temperature fell below `rescale_below` of the reference, scales
    /// every velocity back up to it and records the factor, so that T/T0 = 1e-300 and beyond is
    /// reached without underflow. The caller predicts all events again.
    pub(super) fn rescale_if_cold(&mut self) -> bool {
        if self.params.rescale_below <= 0.0 || !self.may_rescale() {
            return false;
        }
        let sim_t = self.simulated_temperature();
        if self.t_ref == 0.0 {
            self.t_ref = sim_t;
            return false;
        }
        if !(sim_t > 0.0) || sim_t >= self.params.rescale_below * self.t_ref {
            return false;
        }
        let factor = (self.t_ref / sim_t).sqrt();
        self.scale_motion(factor);
        self.epoch /= factor;
        self.ln_scale += factor.ln();
        self.inv_scale = (-self.ln_scale).exp();
        self.scale = self.ln_scale.exp();
        // The monitor's clock check compares simulated times; restart it in the new units.
        self.monitor.restart_clock_check();
        self.counters.rescales += 1;
        true
    }

    /// Periodic scenes conserve momentum exactly, so the round-off residual of the initial zero
    /// momentum (≈ 1e-16 of the initial velocity scale) never decays, while free cooling shrinks the
    /// thermal velocities: below T/T0 ≈ 1e-32 the whole gas would drift with that residual, cooling
    /// would stop and cell crossings would swamp the collisions. A uniform velocity changes no relative
    /// motion, so once the drift carries more than 1e-12 of the kinetic energy it is removed (a
    /// Galilean boost; events are predicted again). Walls and gravity break the symmetry: never there.
    pub(super) fn remove_drift_if_large(&mut self) -> bool {
        if !self.conserves_momentum() {
            return false;
        }
        let (mut p, mut mass, mut twice_ke) = (Vector::<D>::zeros(), 0.0, 0.0);
        for (q, m) in self.particles.iter().zip(&self.meta) {
            p += q.vel * m.mass;
            mass += m.mass;
            twice_ke += m.mass * q.vel.norm_squared();
        }
        let drift = p / mass;
        if !(mass * drift.norm_squared() > 1e-12 * twice_ke) {
            return false;
        }
        self.rebase_clock();
        for q in &mut self.particles {
            q.vel -= drift;
        }
        self.invalidate_events();
        true
    }

    /// Scales every spin by `factor` (rough rules only).
    fn scale_spins(&mut self, factor: f64) {
        if R::ROUGH {
            for st in &mut self.rule_state {
                let w = R::spin(st);
                R::set_spin(st, [w[0] * factor, w[1] * factor, w[2] * factor]);
            }
        }
    }

    /// Scales every velocity (in a sheared scene, every peculiar velocity) by `factor` and predicts
    /// all events again (e.g. to set a temperature).
    pub fn scale_velocities(&mut self, factor: f64) {
        self.scale_motion(factor);
        self.restart_events();
    }

    /// Rebases the clock, scales every velocity and spin by `factor` and marks every pending event
    /// stale (the caller predicts them again).
    fn scale_motion(&mut self, factor: f64) {
        self.rebase_clock();
        self.scale_thermal_velocities(factor);
        self.scale_spins(factor);
        self.invalidate_events();
    }

    /// Marks every particle's pending events stale: each particle counts one more collision.
    fn invalidate_events(&mut self) {
        for p in &mut self.particles {
            p.bump();
        }
    }
}
