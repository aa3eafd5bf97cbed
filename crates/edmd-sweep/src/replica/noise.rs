//! A replica heated by white noise (PHYSICS.md §8.1): the steady state its kicks sustain, and the
//! interval between the kicks chosen from it.

use edmd_core::theory::{chi, number_density, white_noise_a2, white_noise_temperature};

use crate::spec::{Replica, RuleSpec, Spec};

/// ζΔt, the fraction of the steady cooling time between two kicks: the kicks' bias on T is of
/// second order in it (below 0.3 % here), and each kick costs about N/2 collisions' work
/// (docs/benchmarks.md, "The white-noise thermostat").
pub const KICKS_PER_COOLING_TIME: f64 = 20.0;

/// The steady temperature the theory gives for replica `r` (grains of σ = 1, m = 1 at its φ and
/// ε), and its cooling rate ζ_s = m ξ₀² / T_s.
pub fn steady_state(r: &Replica) -> (f64, f64) {
    let phi = r.phi();
    let t = white_noise_temperature(
        r.dim,
        r.eps,
        number_density(r.dim, phi, 1.0),
        1.0,
        chi(r.dim, phi),
        1.0,
        r.white_noise,
    );
    (t, r.white_noise / t)
}

/// Δt between kicks: 1/20 of the steady cooling time 1/ζ_s (of the elastic gas's collision time
/// where ε = 1, which has no steady state: it heats without end).
pub fn kick_interval(r: &Replica) -> f64 {
    let (_, zeta) = steady_state(r);
    if zeta.is_finite() && zeta > 0.0 {
        1.0 / (KICKS_PER_COOLING_TIME * zeta)
    } else {
        // ε = 1: the collision time at T = 1 (ν of the dilute gas, σ = m = 1).
        let nu = edmd_core::theory::collision_frequency(
            r.dim,
            r.phi(),
            chi(r.dim, r.phi()),
            1.0,
            1.0,
            1.0,
        );
        0.05 / nu
    }
}

/// The theory's steady temperature and Sonine coefficient a₂ where it applies (smooth grains of
/// one species, constant restitution below 1), else None.
pub fn white_noise_theory(spec: &Spec, r: &Replica) -> Option<(f64, f64)> {
    let applies = r.white_noise > 0.0
        && r.eps < 1.0
        && !r.rough()
        && r.species.is_none()
        && matches!(spec.rule, RuleSpec::Constant {});
    applies.then(|| (steady_state(r).0, white_noise_a2(r.dim, r.eps)))
}
