//! The homogeneous steady state of a gas heated by white noise (PHYSICS.md §8.1): the Sonine
//! coefficient a₂ of van Noije & Ernst and the temperature at which the collisions' cooling
//! balances the kicks' heating.

use std::f64::consts::PI;

/// First Sonine coefficient of the white-noise steady state (van Noije & Ernst 1998; Montanero &
/// Santos 2000): `a₂ = 16(1−α)(1−2α²) / [73 + 56d − 3α(35 + 8d) + 30α²(1−α)]`.
pub fn white_noise_a2(d: usize, alpha: f64) -> f64 {
    let d = d as f64;
    16.0 * (1.0 - alpha) * (1.0 - 2.0 * alpha * alpha)
        / (73.0 + 56.0 * d - 3.0 * alpha * (35.0 + 8.0 * d) + 30.0 * alpha * alpha * (1.0 - alpha))
}

/// The steady temperature `T_s` of grains of mass `m` and diameter `sigma` at number density `n`
/// and contact value `chi`, kicked with strength ξ₀² (velocity variance per component and unit
/// time): `m ξ₀² = ζ T` with the Enskog cooling rate `ζ = (1−α²)(1 + 3a₂/16) ν/d`, so
/// `T_s = m [ξ₀² / (c_d (1−α²)(1 + 3a₂/16) n σ^{d−1} χ)]^{2/3}`, `c₂ = √π`, `c₃ = 4√π/3`.
pub fn white_noise_temperature(
    d: usize,
    alpha: f64,
    n: f64,
    sigma: f64,
    chi: f64,
    mass: f64,
    strength: f64,
) -> f64 {
    let c = if d == 2 {
        PI.sqrt()
    } else {
        4.0 * PI.sqrt() / 3.0
    };
    let a2 = white_noise_a2(d, alpha);
    let rate =
        c * (1.0 - alpha * alpha) * (1.0 + 3.0 * a2 / 16.0) * n * sigma.powi(d as i32 - 1) * chi;
    mass * (strength / rate).powf(2.0 / 3.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table of PHYSICS.md §8.1.
    #[test]
    fn a2_matches_the_table() {
        for (d, alpha, want) in [
            (2, 0.9, -0.0199),
            (2, 0.7, 0.0012),
            (2, 0.5, 0.0356),
            (3, 0.9, -0.0118),
            (3, 0.7, 0.0008),
            (3, 0.5, 0.0256),
        ] {
            let a2 = white_noise_a2(d, alpha);
            assert!(
                (a2 - want).abs() < 6e-5,
                "d {d} alpha {alpha}: {a2} vs {want}"
            );
        }
    }

    /// Heating balances cooling at T_s: ζ(T_s) T_s = m ξ₀², with ζ from the collision frequency.
    #[test]
    fn the_steady_temperature_balances_the_energy() {
        for d in [2, 3] {
            let (alpha, phi, sigma, mass, strength) = (0.8, 0.1, 1.0, 2.0, 0.3);
            let chi = crate::theory::chi(d, phi);
            let n = crate::theory::number_density(d, phi, sigma);
            let t = white_noise_temperature(d, alpha, n, sigma, chi, mass, strength);
            let nu = crate::theory::collision_frequency(d, phi, chi, sigma, t, mass);
            let zeta = (1.0 - alpha * alpha) * (1.0 + 3.0 * white_noise_a2(d, alpha) / 16.0) * nu
                / d as f64;
            assert!((zeta * t / (mass * strength) - 1.0).abs() < 1e-12, "d {d}");
        }
    }
}
