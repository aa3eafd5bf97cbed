//! The white-noise thermostat (PHYSICS.md §8.1): every grain's velocity receives independent
//! Gaussian kicks, dv = ξ₀ dW per component, applied to all grains at once every `Δt` as a system
//! event. Global kicks at fixed intervals rather than per-grain kicks at Poisson times: the kick's
//! first-order bias on T cancels over an interval, where per-grain kicks bias the velocity
//! distribution's Sonine coefficient by (ζ/λ) unless their rate λ is tens of collision frequencies;
//! each kick renews every prediction, so one kick costs about as much as N/2 collisions.

use rand::Rng;
use rand_distr::StandardNormal;

use super::Simulation;
use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule, Vector};

/// The kicks' settings and clock.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct Thermostat {
    /// ξ₀²: the variance of a velocity component's kicks per unit (physical) time; 0 for none.
    pub strength: f64,
    /// Δt between kicks, physical time.
    pub interval: f64,
    /// Kicks of zero total momentum (the mass-weighted mean kick removed).
    pub conserve_momentum: bool,
    /// The next kick, in local simulated time (∞ without a thermostat).
    pub next: f64,
}

impl Default for Thermostat {
    fn default() -> Self {
        Thermostat {
            strength: 0.0,
            interval: f64::INFINITY,
            conserve_momentum: false,
            next: f64::INFINITY,
        }
    }
}

impl Thermostat {
    /// A thermostat of strength ξ₀² kicking every `interval` from time 0 (none if the strength is 0).
    pub fn new(strength: f64, interval: f64, conserve_momentum: bool) -> Self {
        if strength > 0.0 {
            Thermostat {
                strength,
                interval,
                conserve_momentum,
                next: interval,
            }
        } else {
            Thermostat::default()
        }
    }

    /// Whether grains are kicked.
    pub fn on(&self) -> bool {
        self.strength > 0.0
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Kicks every grain's velocity now and predicts every event again; the next kick is due one
    /// interval later (in simulated time, which is the physical time over the velocity scale).
    pub(super) fn kick(&mut self) {
        self.rebase_clock();
        let t = &self.thermostat;
        let sd = self.scale * (t.strength * t.interval).sqrt();
        let conserve = t.conserve_momentum;
        let kicks: Vec<Vector<D>> = (0..self.particles.len())
            .map(|_| Vector::<D>::from_fn(|_, _| sd * self.rng.sample::<f64, _>(StandardNormal)))
            .collect();
        let mean = if conserve {
            let n = self.particles.len();
            let total: f64 = self.meta[..n].iter().map(|m| m.mass).sum();
            let p: Vector<D> = kicks
                .iter()
                .zip(&self.meta[..n])
                .map(|(k, m)| k * m.mass)
                .sum();
            p / total
        } else {
            Vector::<D>::zeros()
        };
        // After the rebase every trajectory starts now: the origin stays, the velocity changes.
        for (p, k) in self.particles.iter_mut().zip(&kicks) {
            p.vel += k - mean;
            p.bump();
        }
        self.thermostat.next = self.thermostat.interval / self.scale;
        self.restart_events();
    }
}
