//! The energy a vibrating floor puts into a gas resting on it (PHYSICS.md §8.3).
//!
//! An elastic floor moving with speed u sends a grain that meets it with vertical speed v < u
//! back with 2u − v: it gains 2m(u² − uv). Grains meet it at the rate n (u − v) f(v) per unit
//! area. With the floor's phase uniform at the contacts and the gas at the floor of density n₀
//! and vertical velocity distribution f, the power per unit area is
//! P = 2 m n₀ ⟨u I(u)⟩ with I(u) = ∫_{v<u} (u − v)² f(v) dv, the average over the phase. For a
//! Maxwellian of variance s² = T_z/m, I(u) = (u² + s²) Φ(u/s) + u s φ(u/s); with ⟨u⟩ = ⟨u³⟩ = 0,
//! ⟨u I(u)⟩ = ⟨u²⟩ I'(0) + O((Aω)⁴) = (Aω)²/2 · 2sφ(0), so P = 2 m n₀ (Aω)² √(T_z/(2π m)):
//! twice the mass times (Aω)² times the grains' flux onto the floor. A dilute gas in
//! hydrostatic balance has n₀ T_z = M g / area (the weight on the floor), so the whole floor
//! puts in P = M g (Aω)² √(2m/(π T_z)): the weight times (Aω)² times a function of the
//! near-floor temperature (McNamara & Luding, PRE 58, 813 (1998)).

use std::f64::consts::{PI, SQRT_2};

/// The floor's power into a dilute gas of weight `weight` (M g, in the floor's area) whose grains
/// of mass `mass` have the vertical temperature `t_z` at the floor, for a floor of speed
/// amplitude `a_omega` (Aω): the Maxwellian average over the phase, to every order in Aω/√(T_z/m).
pub fn floor_power(weight: f64, mass: f64, t_z: f64, a_omega: f64) -> f64 {
    let s = (t_z / mass).sqrt();
    let n0 = weight / t_z; // n₀ per unit floor area, times the area
    let incoming = |u: f64| {
        let x = u / s;
        let cdf = 0.5 * libm::erfc(-x / SQRT_2);
        let pdf = (-0.5 * x * x).exp() / (2.0 * PI).sqrt();
        (u * u + s * s) * cdf + u * s * pdf
    };
    // The trapezoidal rule over a period converges geometrically for a smooth periodic integrand.
    const PHASES: usize = 256;
    let mean = (0..PHASES)
        .map(|k| {
            let u = a_omega * (2.0 * PI * k as f64 / PHASES as f64).cos();
            u * incoming(u)
        })
        .sum::<f64>()
        / PHASES as f64;
    2.0 * mass * n0 * mean
}

/// [`floor_power`] to leading order in Aω: M g (Aω)² √(2m/(π T_z)).
pub fn floor_power_leading(weight: f64, mass: f64, t_z: f64, a_omega: f64) -> f64 {
    weight * a_omega * a_omega * (2.0 * mass / (PI * t_z)).sqrt()
}

/// The temperature of a dilute 2D bed of disks (diameter `sigma`, mass `mass`, restitution
/// `alpha`, `layers` grains per unit floor length) on an elastic floor of speed amplitude
/// `a_omega`, if it were isothermal (PHYSICS.md §8.3): the floor's power to leading order equals
/// the Haff losses of the barometric column, T = 2√2 m (Aω)² / (π k σ ν), k the Haff rate per
/// τ. It does not depend on g, which sets only the column's height T/(m g).
pub fn dilute_bed_temperature(sigma: f64, mass: f64, alpha: f64, layers: f64, a_omega: f64) -> f64 {
    let k = super::haff_rate(2, alpha);
    2.0 * SQRT_2 * mass * a_omega * a_omega / (PI * k * sigma * layers)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The isothermal bed's balance, term by term: the leading-order power against the Haff
    /// losses of the barometric column, k n² σ √(π T/m) T summed over heights (n₀² ℓ/2).
    #[test]
    fn the_bed_temperature_balances_power_and_losses() {
        let (sigma, mass, alpha, layers, a_omega, g) = (1.0, 2.0, 0.95, 4.0, 0.3, 0.1);
        let t = dilute_bed_temperature(sigma, mass, alpha, layers, a_omega);
        let ell = t / (mass * g);
        let n0 = layers / ell;
        let k = crate::theory::haff_rate(2, alpha);
        let losses = k * sigma * (PI * t / mass).sqrt() * t * n0 * n0 * ell / 2.0;
        let power = floor_power_leading(layers * mass * g, mass, t, a_omega);
        assert!((losses / power - 1.0).abs() < 1e-12, "{losses} {power}");
    }

    #[test]
    fn the_full_power_tends_to_the_leading_order() {
        for r in [1e-3, 1e-2, 0.1, 0.3] {
            let (full, lead) = (
                floor_power(2.0, 1.5, 0.7, r),
                floor_power_leading(2.0, 1.5, 0.7, r),
            );
            println!("Aω {r}: full/leading {:.6}", full / lead);
            // The next order is relative (Aω)²/s² times a number of order one.
            assert!(
                (full / lead - 1.0).abs() < 2.0 * r * r / (0.7 / 1.5),
                "{full} {lead}"
            );
        }
    }
}
