//! Observables: temperature, energy, momentum and the collision virial.
//!
//! Temperature is `T = m⟨v²⟩/d` (the variance of one velocity component for unit mass); in a sheared
//! scene every observable here is taken with the peculiar velocities V = v − a (y − L_y/2) e_x. The pressure
//! comes from the collision virial: `p V = N T + (1/(d Δt)) Σ r_ij·Δp_i`, so the compressibility
//! factor is `Z = 1 + Σ r_ij·Δp_i / (d N T Δt)`; for elastic hard disks `Z = 1 + 2φχ`
//! (spheres: `1 + 4φχ`).

use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule, Engine, Simulation, Vector};

/// A snapshot of the bulk observables.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observables<const D: usize> {
    /// Physical time.
    pub time: f64,
    /// Pair collisions per particle, C/N.
    pub tau: f64,
    /// Pair collisions C.
    pub pair_collisions: u64,
    /// Wall collisions.
    pub wall_collisions: u64,
    /// Total kinetic energy Σ m v²/2.
    pub kinetic_energy: f64,
    /// Granular temperature m⟨v²⟩/d.
    pub temperature: f64,
    /// ln of the temperature, finite however deep the cooling.
    pub ln_temperature: f64,
    /// Total momentum.
    pub momentum: Vector<D>,
    /// Σ m|v|, the scale against which momentum conservation is judged.
    pub momentum_scale: f64,
    /// Speed kurtosis ⟨v⁴⟩/⟨v²⟩² (2 for a 2D Maxwellian, 5/3 in 3D).
    pub kurtosis: f64,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Kinetic energy in the simulation's (deep-cooling-scaled) units.
    fn simulated_kinetic_energy(&self) -> f64 {
        self.particles
            .iter()
            .zip(&self.meta)
            .map(|(p, m)| 0.5 * m.mass * self.thermal_velocity_now(p).norm_squared())
            .sum()
    }

    /// Temperature in the simulation's (deep-cooling-scaled) units.
    pub(crate) fn simulated_temperature(&self) -> f64 {
        2.0 * self.simulated_kinetic_energy() / (D as f64 * self.len() as f64)
    }

    /// Total kinetic energy (physical units; underflows to 0 below ~1e-308, see
    /// [`Self::ln_temperature`]).
    pub fn kinetic_energy(&self) -> f64 {
        self.simulated_kinetic_energy() * self.inv_scale * self.inv_scale
    }

    /// Granular temperature `T = Σ m v² / (d N)` (physical units).
    pub fn temperature(&self) -> f64 {
        self.simulated_temperature() * self.inv_scale * self.inv_scale
    }

    /// ln T in physical units, finite however deep the cooling.
    pub fn ln_temperature(&self) -> f64 {
        self.simulated_temperature().ln() - 2.0 * self.ln_scale
    }

    /// ln of the deep-cooling factor: simulated velocities are the physical ones times its exponential.
    pub fn ln_velocity_scale(&self) -> f64 {
        self.ln_scale
    }

    /// All bulk observables at the current time.
    pub fn observe(&self) -> Observables<D> {
        let mut momentum = Vector::<D>::zeros();
        let (mut scale, mut ke, mut v2, mut v4) = (0.0, 0.0, 0.0, 0.0);
        for (p, m) in self.particles.iter().zip(self.meta.iter().map(|m| m.mass)) {
            let v = self.thermal_velocity_now(p);
            let s2 = v.norm_squared();
            momentum += v * m;
            scale += m * s2.sqrt();
            ke += 0.5 * m * s2;
            v2 += s2;
            v4 += s2 * s2;
        }
        let n = self.len() as f64;
        let s = self.inv_scale;
        Observables {
            time: self.time(),
            tau: self.tau(),
            pair_collisions: self.counters.pair_collisions,
            wall_collisions: self.counters.wall_collisions,
            kinetic_energy: ke * s * s,
            temperature: 2.0 * ke / (D as f64 * n) * s * s,
            ln_temperature: (2.0 * ke / (D as f64 * n)).ln() - 2.0 * self.ln_scale,
            momentum: momentum * s,
            momentum_scale: scale * s,
            kurtosis: if v2 > 0.0 {
                (v4 / n) / (v2 / n).powi(2)
            } else {
                f64::NAN
            },
        }
    }
}

/// Measures pressure and collision frequency over an interval of a stationary (elastic) run.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub struct VirialMeter {
    time: f64,
    virial: f64,
    collisions: u64,
}

/// What a [`VirialMeter`] measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VirialReading {
    /// Compressibility factor Z = pV/(NT).
    pub z: f64,
    /// Collision frequency per particle ν = 2C/(N Δt).
    pub nu: f64,
    /// Interval length.
    pub duration: f64,
}

impl VirialMeter {
    /// Starts measuring now.
    pub fn start<const D: usize, E: Engine<D> + ?Sized>(sim: &E) -> Self {
        VirialMeter {
            time: sim.time(),
            virial: sim.counters().virial,
            collisions: sim.counters().pair_collisions,
        }
    }

    /// Reads Z and ν since the start, with the current temperature.
    pub fn read<const D: usize, E: Engine<D> + ?Sized>(&self, sim: &E) -> VirialReading {
        let dt = sim.time() - self.time;
        let n = sim.len() as f64;
        let t = sim.temperature();
        let c = sim.counters();
        VirialReading {
            z: 1.0 + (c.virial - self.virial) / (D as f64 * n * t * dt),
            nu: 2.0 * (c.pair_collisions - self.collisions) as f64 / (n * dt),
            duration: dt,
        }
    }
}

/// Decay rate −d ln T/dτ from samples `(τ, ln T)`: minus the least-squares slope. NaN with fewer
/// than two distinct τ or slices of different lengths.
pub fn decay_rate(tau: &[f64], ln_t: &[f64]) -> f64 {
    if tau.len() != ln_t.len() {
        return f64::NAN;
    }
    let n = tau.len() as f64;
    let (mx, my) = (tau.iter().sum::<f64>() / n, ln_t.iter().sum::<f64>() / n);
    let sxy: f64 = tau.iter().zip(ln_t).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = tau.iter().map(|x| (x - mx).powi(2)).sum();
    -sxy / sxx
}

#[cfg(test)]
mod tests {
    #[test]
    fn decay_rate_of_an_exponential_with_noise_free_samples() {
        // ln T = 3 − 0.25 τ, sampled unevenly: the rate is 0.25 to round-off.
        let tau = [5.0, 6.5, 9.0, 20.0, 40.0];
        let ln_t: Vec<f64> = tau.iter().map(|t| 3.0 - 0.25 * t).collect();
        assert!((super::decay_rate(&tau, &ln_t) - 0.25).abs() < 1e-14);
        // By hand: τ̄ = ȳ = 1.5, Σ(τ−τ̄)(y−ȳ) = −1, Σ(τ−τ̄)² = 5, so the rate is 1/5.
        let ln_t = [2.0, 1.0, 2.0, 1.0];
        assert!((super::decay_rate(&[0.0, 1.0, 2.0, 3.0], &ln_t) - 0.2).abs() < 1e-15);
        assert!(super::decay_rate(&[1.0], &[1.0]).is_nan());
        assert!(super::decay_rate(&[1.0, 2.0], &[1.0]).is_nan());
    }
}
