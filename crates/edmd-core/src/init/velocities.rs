//! Initial velocities with zero total momentum and the exact target temperature.

use rand::Rng;
use rand_distr::StandardNormal;

use super::Velocities;
use crate::Vector;

/// Draws velocities, removes the centre-of-mass velocity and scales to temperature `t0` exactly.
/// Each particle's components have variance ∝ 1/m, so that every mass starts at one temperature
/// (equipartition); equal masses of 1 are drawn exactly as before masses entered.
pub fn draw_velocities<const D: usize>(
    masses: &[f64],
    dist: Velocities,
    t0: f64,
    rng: &mut impl Rng,
) -> Vec<Vector<D>> {
    let mut v: Vec<Vector<D>> = masses
        .iter()
        .map(|&m| {
            let scale = 1.0 / m.sqrt();
            Vector::<D>::from_fn(|_, _| match dist {
                Velocities::Uniform => rng.random::<f64>() * 2.0 - 1.0,
                Velocities::Maxwell => rng.sample::<f64, _>(StandardNormal),
            }) * scale
        })
        .collect();
    let mtot: f64 = masses.iter().sum();
    let vcm = v
        .iter()
        .zip(masses)
        .fold(Vector::<D>::zeros(), |acc, (v, m)| acc + v * *m)
        / mtot;
    let mut ke2 = 0.0;
    for (v, m) in v.iter_mut().zip(masses) {
        *v -= vcm;
        ke2 += m * v.norm_squared();
    }
    let t = ke2 / (D as f64 * masses.len() as f64);
    let s = (t0 / t).sqrt();
    for v in &mut v {
        *v *= s;
    }
    v
}
