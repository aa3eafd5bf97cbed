//! An elastic gas at rest under gravity (PHYSICS.md §1.4): hydrostatic balance dp/dz = −m g n with the
//! local equation of state p = n T Z(φ), Z = 1 + 2^{d−1} φ χ(φ) (Enskog, local density), so
//!
//! ```text
//! dφ/dz = −φ / (ℓ · d(φZ)/dφ),      ℓ = T/(m g)
//! ```
//!
//! which is the barometric φ₀ e^{−z/ℓ} when φ → 0; denser layers decay more slowly.

//!
//! Integrated once and for all: with g(φ) = d(φZ)/dφ, dz = −ℓ g(φ) dφ/φ, so the potential
//! H(φ) = ln φ + G(φ), G(φ) = ∫₀^φ (g − 1)/p dp = 2^{d−1} (φ χ(φ) + ∫₀^φ χ), falls by exactly z/ℓ
//! along the column. A profile is one root of H per height, and the column's mean is the pressure
//! difference ℓ [φZ]: the cost is set by the heights asked for, whatever ℓ (a column compressed to
//! ℓ = 10⁻¹⁸ costs what one of ℓ = 10 does).

use super::chi;

/// d(φ Z(φ))/dφ of the reference equation of state in `d` dimensions (central difference).
fn d_phi_z(d: usize, phi: f64) -> f64 {
    let f = |p: f64| p * (1.0 + 2f64.powi(d as i32 - 1) * p * chi(d, p));
    let h = 1e-7 * phi.max(1e-3);
    (f(phi + h) - f(phi - h)) / (2.0 * h)
}

/// φ Z(φ), the pressure in units of T/(grain volume).
fn phi_z(d: usize, phi: f64) -> f64 {
    phi * (1.0 + 2f64.powi(d as i32 - 1) * phi * chi(d, phi))
}

/// The densest floor the theory describes in `d` dimensions: in 2D below 0.867, where Luding's φZ
/// peaks and would stop rising with the pressure; in 3D hexagonal close packing, 0.74.
pub fn barometric_phi_max(d: usize) -> f64 {
    if d == 2 {
        0.85
    } else {
        0.74
    }
}

/// Eight-point Gauss–Legendre nodes on [−1, 1] (positive half) and their weights.
const GAUSS_NODES: [f64; 4] = [
    0.183_434_642_495_649_8,
    0.525_532_409_916_329,
    0.796_666_477_413_626_7,
    0.960_289_856_497_536_3,
];
const GAUSS_WEIGHTS: [f64; 4] = [
    0.362_683_783_378_362,
    0.313_706_645_877_887_3,
    0.222_381_034_453_374_5,
    0.101_228_536_290_376_3,
];

/// ∫₀^φ χ(p) dp by Gauss–Legendre on panels of at most 0.02 (χ is smooth well inside its pole at 1).
fn chi_integral(d: usize, phi: f64) -> f64 {
    let panels = (phi / 0.02).ceil().max(1.0) as usize;
    let width = phi / panels as f64;
    (0..panels)
        .map(|k| {
            let mid = (k as f64 + 0.5) * width;
            let half = 0.5 * width;
            GAUSS_NODES
                .iter()
                .zip(GAUSS_WEIGHTS)
                .map(|(x, w)| w * (chi(d, mid - half * x) + chi(d, mid + half * x)))
                .sum::<f64>()
                * half
        })
        .sum()
}

/// G(φ) = ∫₀^φ (d(pZ)/dp − 1)/p dp, the dense part of the barometric potential (0 at φ = 0).
fn dense_potential(d: usize, phi: f64) -> f64 {
    if phi <= 0.0 {
        return 0.0;
    }
    2f64.powi(d as i32 - 1) * (phi * chi(d, phi) + chi_integral(d, phi))
}

/// The φ at which H(φ) = ln φ + G(φ) equals `target`, with 0 < φ ≤ `phi_top` where
/// H(φ_top) ≥ target: Newton on y = ln φ (H' = d(φZ)/dφ ≥ 1), kept inside the bracket
/// [target − G(φ_top), min(target, ln φ_top)] by bisection. 0 where e^target underflows.
fn invert_potential(d: usize, target: f64, phi_top: f64) -> f64 {
    let (mut lo, mut hi) = (
        target - dense_potential(d, phi_top),
        target.min(phi_top.ln()),
    );
    if hi < f64::MIN_POSITIVE.ln() {
        return 0.0;
    }
    let mut y = lo.max(hi - dense_potential(d, hi.exp()));
    for _ in 0..200 {
        let phi = y.exp();
        let f = y + dense_potential(d, phi) - target;
        if f > 0.0 {
            hi = y;
        } else {
            lo = y;
        }
        let mut next = y - f / d_phi_z(d, phi);
        if !(lo..=hi).contains(&next) {
            next = 0.5 * (lo + hi);
        }
        if (next - y).abs() <= 1e-14 * y.abs().max(1.0) || hi - lo <= 1e-14 * y.abs().max(1.0) {
            return next.exp();
        }
        y = next;
    }
    y.exp()
}

/// The packing fraction at heights `z` (≥ 0) above the floor where it is `phi_floor`, for the decay
/// length ℓ = T/(m g): the root of H(φ) = H(φ_floor) − z/ℓ at each height.
pub fn barometric_profile(d: usize, ell: f64, phi_floor: f64, z: &[f64]) -> Vec<f64> {
    let top = phi_floor.ln() + dense_potential(d, phi_floor);
    z.iter()
        .map(|&z| {
            if z <= 0.0 {
                phi_floor
            } else {
                invert_potential(d, top - z / ell, phi_floor)
            }
        })
        .collect()
}

/// The floor's packing fraction of a column whose mean packing fraction over heights `[z0, z1]` is
/// `mean`, from the weight of the layer: ∫ φ dz = ℓ (φZ(φ(z0)) − φZ(φ(z1))), bisected on the floor.
/// None when even a floor at [`barometric_phi_max`] holds less (a column pressed onto its floor,
/// which the fluid's equation of state does not describe).
pub fn barometric_floor(d: usize, ell: f64, mean: f64, z0: f64, z1: f64) -> Option<f64> {
    let average = |floor: f64| {
        let phi = barometric_profile(d, ell, floor, &[z0, z1]);
        ell * (phi_z(d, phi[0]) - phi_z(d, phi[1])) / (z1 - z0)
    };
    let top = barometric_phi_max(d);
    if !(mean > 0.0 && ell > 0.0 && z1 > z0) || average(top) < mean {
        return None;
    }
    let (mut lo, mut hi) = (0.0, top);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if average(mid) < mean {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo <= 1e-15 * hi {
            break;
        }
    }
    Some(0.5 * (lo + hi))
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
        let floor = barometric_floor(2, 1.0, 0.05, 0.0, 4.0).unwrap();
        // Simpson's mean of the profile over [0, 4] (error ~h⁴).
        let z: Vec<f64> = (0..=4000).map(|k| 4.0 * k as f64 / 4000.0).collect();
        let prof = barometric_profile(2, 1.0, floor, &z);
        let simpson: f64 = prof
            .iter()
            .enumerate()
            .map(|(k, p)| {
                p * if k == 0 || k == 4000 {
                    1.0
                } else {
                    [2.0, 4.0][k % 2]
                }
            })
            .sum::<f64>()
            / (3.0 * 4000.0);
        assert!((simpson / 0.05 - 1.0).abs() < 1e-9, "{simpson}");
    }

    /// The profile by the potential agrees with the hydrostatic equation integrated step by step
    /// (fourth-order Runge–Kutta, steps of ℓ/2000) to 10⁻⁹, dilute and dense, 2D and 3D.
    #[test]
    fn the_potential_solves_the_hydrostatic_equation() {
        for (d, floor) in [(2, 0.6), (2, 0.05), (3, 0.4), (3, 1e-4)] {
            let z = [0.1, 0.7, 2.0, 5.0];
            let p = barometric_profile(d, 1.3, floor, &z);
            let rate = |phi: f64| -phi / (1.3 * d_phi_z(d, phi));
            let (mut at, mut phi) = (0.0, floor);
            for (target, got) in z.iter().zip(p) {
                let steps = ((target - at) / (1.3 / 2000.0)).ceil() as usize;
                let h = (target - at) / steps as f64;
                for _ in 0..steps {
                    let k1 = rate(phi);
                    let k2 = rate(phi + 0.5 * h * k1);
                    let k3 = rate(phi + 0.5 * h * k2);
                    let k4 = rate(phi + h * k3);
                    phi += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                }
                at = *target;
                assert!(
                    (got / phi - 1.0).abs() < 1e-9,
                    "d {d}, z {target}: {got} against {phi}"
                );
            }
        }
    }

    /// A column compressed far below a grain (ℓ = 10⁻¹⁸, hardening case 3) costs what any other
    /// does: its profile underflows to 0 above the floor, and no fluid floor holds its mean.
    #[test]
    fn a_collapsed_column_costs_no_more_than_any() {
        let start = std::time::Instant::now();
        let z: Vec<f64> = (0..4000).map(|k| k as f64 * 0.01).collect();
        let p = barometric_profile(2, 1e-18, 0.5, &z);
        assert_eq!(p[0], 0.5);
        assert!(p[1..].iter().all(|&x| x == 0.0));
        assert_eq!(barometric_floor(2, 1e-18, 0.05, 0.0, 40.0), None);
        assert!(barometric_floor(2, 10.0, 0.05, 0.0, 40.0).is_some());
        assert!(start.elapsed().as_secs_f64() < 5.0);
    }
}
