//! An elastic gas at rest under gravity (PHYSICS.md §1.4): hydrostatic balance dp/dz = −m g n with the
//! local equation of state p = n T Z(φ), Z = 1 + 2^{d−1} φ χ(φ) (Enskog, local density), so
//!
//! ```text
//! dφ/dz = −φ / (ℓ · d(φZ)/dφ),      ℓ = T/(m g)
//! ```
//!
//! which is the barometric φ₀ e^{−z/ℓ} when φ → 0; denser layers decay more slowly.

use super::chi;

/// d(φ Z(φ))/dφ of the reference equation of state in `d` dimensions (central difference).
fn d_phi_z(d: usize, phi: f64) -> f64 {
    let f = |p: f64| p * (1.0 + 2f64.powi(d as i32 - 1) * p * chi(d, p));
    let h = 1e-7 * phi.max(1e-3);
    (f(phi + h) - f(phi - h)) / (2.0 * h)
}

/// The packing fraction at heights `z` (sorted, ≥ 0) above the floor where it is `phi_floor`, for the
/// decay length ℓ = T/(m g): the hydrostatic equation integrated by fourth-order Runge–Kutta in
/// steps of at most ℓ/2000.
pub fn barometric_profile(d: usize, ell: f64, phi_floor: f64, z: &[f64]) -> Vec<f64> {
    let rate = |phi: f64| -phi / (ell * d_phi_z(d, phi));
    let (mut at, mut phi) = (0.0, phi_floor);
    z.iter()
        .map(|&target| {
            let steps = ((target - at) / (ell / 2000.0)).ceil().max(1.0) as usize;
            let h = (target - at) / steps as f64;
            for _ in 0..steps {
                let k1 = rate(phi);
                let k2 = rate(phi + 0.5 * h * k1);
                let k3 = rate(phi + 0.5 * h * k2);
                let k4 = rate(phi + h * k3);
                phi += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            at = target;
            phi
        })
        .collect()
}

/// The floor's packing fraction of a column whose mean packing fraction over heights `[z0, z1]` is
/// `mean` (bisection on the monotone map; the profile is integrated on 4000 points).
pub fn barometric_floor(d: usize, ell: f64, mean: f64, z0: f64, z1: f64) -> f64 {
    let z: Vec<f64> = (0..=4000)
        .map(|k| z0 + (z1 - z0) * k as f64 / 4000.0)
        .collect();
    let average = |floor: f64| {
        let p = barometric_profile(d, ell, floor, &z);
        // Trapezoids.
        let sum: f64 = p.windows(2).map(|w| 0.5 * (w[0] + w[1])).sum();
        sum / 4000.0
    };
    let (mut lo, mut hi) = (0.0, 0.9);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if average(mid) < mean {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Dilute columns are barometric: φ(z)/φ₀ = e^{−z/ℓ} to 10⁻⁶ where φ₀ = 10⁻⁸.
    #[test]
    fn dilute_columns_are_barometric() {
        let z = [0.5, 1.0, 3.0, 7.5];
        let p = barometric_profile(2, 2.0, 1e-8, &z);
        for (z, p) in z.iter().zip(p) {
            assert!((p / 1e-8 / (-z / 2.0f64).exp() - 1.0).abs() < 1e-6);
        }
    }

    /// Dense layers decay more slowly: the local decay length is ℓ·d(φZ)/dφ, 1 + 4φχ + … in 2D.
    #[test]
    fn dense_layers_decay_slower() {
        let p = barometric_profile(2, 1.0, 0.3, &[1e-3]);
        let local = -1e-3 / (p[0] / 0.3).ln();
        assert!((local / d_phi_z(2, 0.3) - 1.0).abs() < 1e-3, "{local}");
        assert!(local > 2.0);
        let floor = barometric_floor(2, 1.0, 0.05, 0.0, 4.0);
        let z: Vec<f64> = (0..=4000).map(|k| 4.0 * k as f64 / 4000.0).collect();
        let prof = barometric_profile(2, 1.0, floor, &z);
        let mean: f64 = prof.windows(2).map(|w| 0.5 * (w[0] + w[1])).sum::<f64>() / 4000.0;
        assert!((mean / 0.05 - 1.0).abs() < 1e-9);
    }
}
