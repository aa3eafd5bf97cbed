//! Homogeneous cooling of a mixture of smooth inelastic disks or spheres in the Maxwellian (first
//! order) approximation of Garzó & Dufty (1999), derived in PHYSICS.md §2.4: each species keeps its
//! own temperature T_i, and in the homogeneous cooling state all cool at one rate, which fixes the
//! ratios T_i/T_j. Contact values χ_ij of the pair correlation are 1 (dilute) or Enskog's.

use std::f64::consts::PI;

/// One species of a mixture: number fraction, diameter and mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Component {
    /// Number fraction x_i (the fractions sum to 1).
    pub fraction: f64,
    /// Diameter σ_i.
    pub diameter: f64,
    /// Mass m_i.
    pub mass: f64,
}

/// Contact values of the pair correlation χ_ij.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PairCorrelation {
    /// χ_ij = 1: the Boltzmann gas.
    Dilute,
    /// The Enskog χ_ij at packing fraction φ: Jenkins & Mancini (1987) for disks, Boublík,
    /// Mansoori, Carnahan, Starling & Leland (1971) for spheres; both reduce to the monodisperse χ of
    /// [`super::chi_henderson`] and [`super::chi_carnahan_starling`].
    Enskog(f64),
}

/// χ_ij of every pair.
pub fn pair_correlation(d: usize, species: &[Component], chi: PairCorrelation) -> Vec<Vec<f64>> {
    let k = species.len();
    let PairCorrelation::Enskog(phi) = chi else {
        return vec![vec![1.0; k]; k];
    };
    let moment = |p: i32| -> f64 {
        species
            .iter()
            .map(|s| s.fraction * s.diameter.powi(p))
            .sum()
    };
    let mut out = vec![vec![0.0; k]; k];
    for i in 0..k {
        for j in 0..k {
            let (si, sj) = (species[i].diameter, species[j].diameter);
            let sij = 0.5 * (si + sj);
            out[i][j] = if d == 2 {
                let y = si * sj * moment(1) / (sij * moment(2));
                1.0 / (1.0 - phi) + 9.0 / 16.0 * phi / (1.0 - phi).powi(2) * y
            } else {
                let y = si * sj * moment(2) / (sij * moment(3));
                1.0 / (1.0 - phi)
                    + 1.5 * phi / (1.0 - phi).powi(2) * y
                    + 0.5 * phi * phi / (1.0 - phi).powi(3) * y * y
            };
        }
    }
    out
}

/// Solid angle factor ∫_{ĝ·n>0} (ĝ·n) dn and mean speed factor ⟨|g|⟩/s of a Gaussian g of variance
/// s² per component: their product is the collision frequency per unit n χ σ^{d−1} s.
fn frequency_factor(d: usize) -> f64 {
    if d == 2 {
        2.0 * (PI / 2.0).sqrt()
    } else {
        PI * (8.0 / PI).sqrt()
    }
}

/// The cooling rates ζ_i = −d ln T_i/dt of every species at temperatures `t` (per unit number
/// density n = N/V): ζ_i = −(2/(d T_i)) Σ_j ν_ij ⟨ΔE_i⟩_ij with
/// `ν_ij = c_d x_j χ_ij σ_ij^{d−1} √(T_i/m_i + T_j/m_j)` and
/// `⟨ΔE_i⟩_ij = (1 + ε) μ_ji [(1 + ε)(m_j T_i + m_i T_j)/(m_i + m_j) − 2 T_i]`, μ_ji = m_j/(m_i + m_j).
pub fn cooling_rates(
    d: usize,
    eps: f64,
    species: &[Component],
    chi: &[Vec<f64>],
    t: &[f64],
) -> Vec<f64> {
    let c = frequency_factor(d);
    (0..species.len())
        .map(|i| {
            let si = &species[i];
            let mut de = 0.0;
            for (j, sj) in species.iter().enumerate() {
                let sigma = 0.5 * (si.diameter + sj.diameter);
                let nu = c
                    * sj.fraction
                    * chi[i][j]
                    * sigma.powi(d as i32 - 1)
                    * (t[i] / si.mass + t[j] / sj.mass).sqrt();
                let mu_ji = sj.mass / (si.mass + sj.mass);
                let mixed = (sj.mass * t[i] + si.mass * t[j]) / (si.mass + sj.mass);
                de += nu * (1.0 + eps) * mu_ji * ((1.0 + eps) * mixed - 2.0 * t[i]);
            }
            -2.0 / (d as f64 * t[i]) * de
        })
        .collect()
}

/// The homogeneous cooling state's temperature ratios T_i/T, with T = Σ x_i T_i the mixture's
/// temperature: the fixed point of the relaxation d ln T_i/ds = ζ̄ − ζ_i (ζ̄ = Σ x_i T_i ζ_i / T, the
/// mixture's rate), followed until every ζ_i agrees to 10⁻¹².
pub fn temperature_ratios(
    d: usize,
    eps: f64,
    species: &[Component],
    chi: PairCorrelation,
) -> Vec<f64> {
    let chi = pair_correlation(d, species, chi);
    let k = species.len();
    let mut theta = vec![1.0; k];
    for _ in 0..100_000 {
        let z = cooling_rates(d, eps, species, &chi, &theta);
        let mean = species
            .iter()
            .zip(&theta)
            .zip(&z)
            .map(|((s, th), z)| s.fraction * th * z)
            .sum::<f64>();
        let spread = z.iter().map(|z| (z - mean).abs()).fold(0.0, f64::max);
        if spread <= 1e-12 * mean.abs().max(f64::MIN_POSITIVE) {
            break;
        }
        // A step of a tenth of the slowest relaxation time keeps the iteration monotone.
        let h = 0.1 / z.iter().map(|z| z.abs()).fold(f64::MIN_POSITIVE, f64::max);
        for (th, z) in theta.iter_mut().zip(&z) {
            *th *= (h * (mean - z)).exp();
        }
        let total: f64 = species
            .iter()
            .zip(&theta)
            .map(|(s, th)| s.fraction * th)
            .sum();
        theta.iter_mut().for_each(|th| *th /= total);
    }
    theta
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pair(ratio: f64, mass_ratio: f64, x1: f64) -> [Component; 2] {
        [
            Component {
                fraction: x1,
                diameter: 1.0,
                mass: 1.0,
            },
            Component {
                fraction: 1.0 - x1,
                diameter: ratio,
                mass: mass_ratio,
            },
        ]
    }

    /// Equal species share one temperature, and their cooling rate is the monodisperse Maxwellian
    /// one, ζ = (1 − ε²) ν/d with ν = 2nσχ√(πT/m) (2D) or 4nσ²χ√(πT/m) (3D).
    #[test]
    fn identical_species_are_one_gas() {
        for d in [2, 3] {
            let s = pair(1.0, 1.0, 0.3);
            let th = temperature_ratios(d, 0.8, &s, PairCorrelation::Enskog(0.2));
            assert!((th[0] - 1.0).abs() < 1e-12 && (th[1] - 1.0).abs() < 1e-12);
            let chi = pair_correlation(d, &s, PairCorrelation::Enskog(0.2));
            assert!((chi[0][1] - super::super::chi_henderson(0.2)).abs() < 1e-12 || d == 3);
            if d == 3 {
                assert!((chi[0][1] - super::super::chi_carnahan_starling(0.2)).abs() < 1e-12);
            }
            let z = cooling_rates(d, 0.8, &s, &chi, &[1.0, 1.0]);
            let pref = if d == 2 { 2.0 } else { 4.0 };
            let nu = pref * chi[0][0] * PI.sqrt();
            assert!((z[0] / ((1.0 - 0.64) * nu / d as f64) - 1.0).abs() < 1e-12);
        }
    }

    /// Elastic mixtures have no cooling and equipartition: every ratio is 1 (ζ_i = 0 at T_i = T_j).
    #[test]
    fn elastic_mixtures_equipartition() {
        let s = pair(1.4, 1.96, 0.5);
        let chi = pair_correlation(2, &s, PairCorrelation::Dilute);
        let z = cooling_rates(2, 1.0, &s, &chi, &[1.0, 1.0]);
        assert!(z.iter().all(|z| z.abs() < 1e-14));
    }

    /// The heavier species is hotter in the cooling state, all the more for a larger mass ratio;
    /// the ratios solve ζ_1 = ζ_2 and average to 1.
    #[test]
    fn heavier_grains_are_hotter() {
        let mut last = 1.0;
        for m in [1.5, 2.0, 4.0, 8.0] {
            let s = pair(1.0, m, 0.5);
            let th = temperature_ratios(2, 0.8, &s, PairCorrelation::Dilute);
            let chi = pair_correlation(2, &s, PairCorrelation::Dilute);
            let z = cooling_rates(2, 0.8, &s, &chi, &th);
            assert!((z[0] / z[1] - 1.0).abs() < 1e-10);
            assert!((0.5 * th[0] + 0.5 * th[1] - 1.0).abs() < 1e-12);
            let light_over_heavy = th[0] / th[1];
            assert!(
                light_over_heavy < last,
                "mass ratio {m}: {light_over_heavy}"
            );
            last = light_over_heavy;
        }
    }
}
