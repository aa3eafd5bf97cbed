//! What theory says about a replica's scene, written beside the measurement so that figures and users
//! compare against the files alone: species temperatures of mixtures (PHYSICS.md §2.4), the
//! rotational-to-translational ratio of rough grains (§6.6–6.7), the barometric profile of an elastic
//! column (§1.4) and the steady uniform shear flow (§7.1).

use std::collections::HashMap;
use std::sync::Mutex;

use edmd_core::theory::{
    barometric_floor, barometric_profile, temperature_ratios, Component, EnskogShear,
    PairCorrelation, RoughCooling, RoughSonine, ShearSteadyState,
};

use super::Series;
use crate::spec::{Replica, RuleSpec, Spec};

/// Garzó & Dufty's T_k/T of each species of a mixture in the homogeneous cooling state (Maxwellian,
/// Enskog χ_ij at the replica's φ; PHYSICS.md §2.4), T the mixture's temperature; NaN where it does not
/// apply (rough grains, or a rule other than constant restitution).
pub fn species_temperature_theory(spec: &Spec, r: &Replica) -> Vec<f64> {
    let Some(m) = &r.species else {
        return Vec::new();
    };
    if r.rough() || !matches!(spec.rule, RuleSpec::Constant {}) {
        return vec![f64::NAN; m.len()];
    }
    let counts = r.species_counts();
    let components: Vec<Component> = m
        .iter()
        .zip(&counts)
        .map(|(s, &c)| Component {
            fraction: c as f64 / r.n as f64,
            diameter: s.diameter,
            mass: s.mass_in(r.dim),
        })
        .collect();
    temperature_ratios(r.dim, r.eps, &components, PairCorrelation::Enskog(r.phi()))
}

/// Quadrature samples of the Sonine theory in files: its error is 0.2–0.5 % of R/T here (PHYSICS.md
/// §6.7 gives 0.1–0.35 % at 2²¹), at about a second per grid point, computed once per point.
const SONINE_SAMPLES: usize = 1 << 20;

/// The two-temperature theory of a rough replica's free cooling: the Maxwellian theory and the
/// stationary R/T of its Sonine correction, both for the replica's N; None unless the grains are
/// rough, of one species, with constant restitution, and cool freely (no gravity or floor).
pub fn rotational_ratio_theory(spec: &Spec, r: &Replica) -> Option<(RoughCooling, f64)> {
    if !r.rough()
        || r.species.is_some()
        || r.driven_or_stratified()
        || !matches!(spec.rule, RuleSpec::Constant {})
    {
        return None;
    }
    let maxwell = RoughCooling::new(r.dim, r.eps, r.beta, r.inertia).with_particles(r.n);
    // Replicas of one grid point share the (deterministic) Sonine solution.
    static CACHE: Mutex<Option<HashMap<[u64; 5], f64>>> = Mutex::new(None);
    let key = [
        r.dim as u64,
        r.eps.to_bits(),
        r.beta.to_bits(),
        r.inertia.to_bits(),
        r.n as u64,
    ];
    let cached = CACHE
        .lock()
        .ok()
        .and_then(|c| c.as_ref().and_then(|m| m.get(&key).copied()));
    let sonine = cached.unwrap_or_else(|| {
        let ratio = RoughSonine::new(r.dim, r.eps, r.beta, r.inertia)
            .with_particles(r.n)
            .with_samples(SONINE_SAMPLES, 1)
            .solve()
            .ratio;
        if let Ok(mut c) = CACHE.lock() {
            c.get_or_insert_with(HashMap::new).insert(key, ratio);
        }
        ratio
    });
    Some((maxwell, sonine))
}

/// The barometric profile of an elastic column with the replica's N at its measured temperature.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileTheory {
    /// The temperature used: the mean T over the second half of the samples.
    pub temperature: f64,
    /// Number density per bin (the bins of `observables/density_profile`), the local-Enskog
    /// hydrostatic profile averaged over each bin (centres live in [σ/2, H − σ/2]).
    pub density: Vec<f64>,
}

/// Sub-points per bin of the bin averages.
const SUB_POINTS: usize = 8;

/// The barometric profile of an elastic (ε = 1, elastic walls) column of one species under gravity;
/// None for any other scene (an inelastic column is not isothermal) and for a column denser at its
/// floor than the fluid's equation of state reaches ([`edmd_core::theory::barometric_phi_max`]).
pub fn density_profile_theory(r: &Replica, s: &Series, bins: usize) -> Option<ProfileTheory> {
    if r.gravity <= 0.0 || r.eps != 1.0 || r.wall_eps != 1.0 || r.species.is_some() || bins == 0 {
        return None;
    }
    let half = &s.temperature[s.temperature.len() / 2..];
    if half.is_empty() {
        return None;
    }
    let temperature = half.iter().sum::<f64>() / half.len() as f64;
    let d = r.dim;
    let sides = r.sides();
    let height = sides[d - 1];
    let grain = r.grain_volume() / r.n as f64;
    let cross: f64 = sides[..d - 1].iter().product();
    // Centres live in [1/2, H − 1/2] (σ = 1, m = 1): φ over that layer.
    let layer = height - 1.0;
    let mean = r.grain_volume() / (cross * layer);
    let ell = temperature / r.gravity;
    // None for a column pressed onto its floor (ℓ far below a grain), which no fluid describes.
    let floor = barometric_floor(d, ell, mean, 0.0, layer)?;
    let width = height / bins as f64;
    let points: Vec<f64> = (0..bins * SUB_POINTS)
        .map(|k| (k as f64 + 0.5) * width / SUB_POINTS as f64)
        .collect();
    let inside: Vec<f64> = points
        .iter()
        .map(|&z| (z - 0.5).clamp(0.0, layer))
        .collect();
    let phi = barometric_profile(d, ell, floor, &inside);
    let density = (0..bins)
        .map(|b| {
            let sum: f64 = (0..SUB_POINTS)
                .map(|k| {
                    let i = b * SUB_POINTS + k;
                    if (0.5..=height - 0.5).contains(&points[i]) {
                        phi[i] / grain
                    } else {
                        0.0
                    }
                })
                .sum();
            sum / SUB_POINTS as f64
        })
        .collect();
    Some(ProfileTheory {
        temperature,
        density,
    })
}

/// The kinetic theory of a sheared replica's steady flow (the Enskog gas at its φ with the
/// anisotropic-Maxwellian closure, PHYSICS.md §7.2), and the temperature its shear rate sustains;
/// None unless the grains are smooth, of one species, with constant restitution below 1 and a
/// shear rate above 0.
pub fn shear_theory(spec: &Spec, r: &Replica) -> Option<(ShearSteadyState, f64)> {
    let applies = r.sheared()
        && r.shear_rate > 0.0
        && r.eps < 1.0
        && !r.rough()
        && r.species.is_none()
        && matches!(spec.rule, RuleSpec::Constant {});
    if !applies {
        return None;
    }
    let flow = EnskogShear::new(r.dim, r.eps, r.phi()).solve()?;
    Some((flow, flow.steady_temperature(r.shear_rate)))
}
