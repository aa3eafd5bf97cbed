//! Kinetic theory of hard disks and spheres: contact value of the pair correlation χ(φ), the Enskog
//! collision frequency and pressure (PHYSICS.md §1).

use std::f64::consts::PI;

/// Henderson (1975): χ = (1 − 7φ/16)/(1 − φ)² for hard disks (reliable for φ ≤ 0.35).
pub fn chi_henderson(phi: f64) -> f64 {
    (1.0 - 7.0 * phi / 16.0) / (1.0 - phi).powi(2)
}

/// Luding (2001) disk χ: Henderson minus φ³/(128(1 − φ)⁴); within 0.1 % of simulations to φ = 0.6.
pub fn chi_luding(phi: f64) -> f64 {
    chi_henderson(phi) - phi.powi(3) / (128.0 * (1.0 - phi).powi(4))
}

/// Carnahan–Starling χ = (1 − φ/2)/(1 − φ)³ for hard spheres.
pub fn chi_carnahan_starling(phi: f64) -> f64 {
    (1.0 - phi / 2.0) / (1.0 - phi).powi(3)
}

/// The reference χ of dimension `d`: Luding in 2D, Carnahan–Starling in 3D.
pub fn chi(d: usize, phi: f64) -> f64 {
    if d == 2 {
        chi_luding(phi)
    } else {
        chi_carnahan_starling(phi)
    }
}

/// Number density n from packing fraction φ and diameter σ.
pub fn number_density(d: usize, phi: f64, sigma: f64) -> f64 {
    if d == 2 {
        4.0 * phi / (PI * sigma * sigma)
    } else {
        6.0 * phi / (PI * sigma.powi(3))
    }
}

/// Enskog collision frequency per particle (collisions suffered per unit time):
/// 2D `ν = 2nσχ√(πT/m)`, 3D `ν = 4nσ²χ√(πT/m)`.
pub fn collision_frequency(
    d: usize,
    phi: f64,
    chi: f64,
    sigma: f64,
    temperature: f64,
    mass: f64,
) -> f64 {
    let n = number_density(d, phi, sigma);
    let pref = if d == 2 {
        2.0 * sigma
    } else {
        4.0 * sigma * sigma
    };
    pref * n * chi * (PI * temperature / mass).sqrt()
}

/// Enskog compressibility factor Z = p/(nT) = 1 + 2^{d−2}(1 + ε)φχ.
pub fn compressibility(d: usize, phi: f64, chi: f64, epsilon: f64) -> f64 {
    1.0 + 2f64.powi(d as i32 - 2) * (1.0 + epsilon) * phi * chi
}

/// χ inverted from a measured collision frequency (see [`collision_frequency`]).
pub fn chi_from_frequency(
    d: usize,
    phi: f64,
    nu: f64,
    sigma: f64,
    temperature: f64,
    mass: f64,
) -> f64 {
    nu / collision_frequency(d, phi, 1.0, sigma, temperature, mass)
}

/// χ inverted from a measured elastic compressibility factor Z.
pub fn chi_from_compressibility(d: usize, phi: f64, z: f64) -> f64 {
    (z - 1.0) / (2f64.powi(d as i32 - 1) * phi)
}

/// First Sonine coefficient of the homogeneous cooling state (van Noije & Ernst 1998):
/// `a₂ = 16(1−ε)(1−2ε²) / [9 + 24d + (8d − 41)ε + 30ε²(1−ε)]`.
pub fn a2(d: usize, epsilon: f64) -> f64 {
    let d = d as f64;
    16.0 * (1.0 - epsilon) * (1.0 - 2.0 * epsilon * epsilon)
        / (9.0 + 24.0 * d + (8.0 * d - 41.0) * epsilon + 30.0 * epsilon * epsilon * (1.0 - epsilon))
}

/// Haff decay rate per τ = C/N in the homogeneous cooling state, consistent first Sonine order
/// (PHYSICS.md §2.2): `T(τ) = T₀ exp(−k τ)` with `k = (2/d)(1−ε²)(1 + 3a₂/16)/(1 − a₂/16)`.
pub fn haff_rate(d: usize, epsilon: f64) -> f64 {
    let a = a2(d, epsilon);
    2.0 / d as f64 * (1.0 - epsilon * epsilon) * (1.0 + 3.0 * a / 16.0) / (1.0 - a / 16.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values from the table of PHYSICS.md §1.3.
    #[test]
    fn chi_matches_reference_table() {
        for (phi, h, l) in [
            (0.05, 1.08380, 1.08379),
            (0.25, 1.58333, 1.58295),
            (0.5, 3.12500, 3.10938),
            (0.6, 4.60937, 4.54346),
        ] {
            assert!((chi_henderson(phi) - h).abs() < 1e-5);
            assert!((chi_luding(phi) - l).abs() < 1e-5);
        }
    }

    /// PHYSICS.md §2.3: k per τ_C in 2D, and 3D values.
    #[test]
    fn haff_rate_matches_reference_table() {
        for (eps, k) in [
            (0.99, 0.01988),
            (0.9, 0.18873),
            (0.8, 0.35803),
            (0.6, 0.64620),
        ] {
            assert!(
                (haff_rate(2, eps) - k).abs() < 1e-5,
                "eps {eps}: {}",
                haff_rate(2, eps)
            );
        }
        for (eps, k) in [(0.9, 0.12621), (0.6, 0.42922)] {
            assert!(
                (haff_rate(3, eps) - k).abs() < 1e-5,
                "eps {eps}: {}",
                haff_rate(3, eps)
            );
        }
    }

    #[test]
    fn collision_frequency_matches_reference_table() {
        // σ = m = T = 1, χ_L: ν = 0.53284 at φ = 0.1 and 7.01711 at φ = 0.5.
        for (phi, nu) in [(0.1, 0.53284), (0.5, 7.01711)] {
            let got = collision_frequency(2, phi, chi_luding(phi), 1.0, 1.0, 1.0);
            assert!((got - nu).abs() < 1e-4, "{got}");
        }
        assert!((compressibility(2, 0.5, chi_luding(0.5), 1.0) - 4.1094).abs() < 1e-4);
    }
}
