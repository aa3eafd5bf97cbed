//! The white-noise thermostat against the theory of its steady state (PHYSICS.md §8.1): with kicks
//! of strength ξ₀² chosen so that the theory's T_s is 1, a dilute gas (φ 0.005, where the
//! mean-field theory holds: the density's correlations raise T by 1.3 % at φ 0.02 and 3.1 % at
//! 0.05, measured by `scan_interval_density_and_size`) holds a time-averaged temperature and a speed
//! kurtosis within their statistical errors of T_s and (d+2)/d·(1 + a₂), in 2D and 3D at α 0.9 and
//! 0.5 (a₂ within three standard errors and within 0.005); kicks of zero total momentum keep
//! the total momentum at zero while plain kicks let it random-walk.
//!
//! The statistical errors are batch means over 8 batches; T's tolerance is three of them plus
//! 0.005: the kicks' own bias, second order in ζΔt (0.05² here: below 0.3 %), and the residual
//! density effect at φ 0.005. Finite size: N = 1000 against 4000 in the scan; the conserving
//! kicks inject (N − 1)/N of the energy, which lowers T by ((N − 1)/N)^{2/3}: 0.07 % here.

use edmd_core::theory::{chi, collision_frequency, number_density, white_noise_a2};
use edmd_core::{ConstantRestitution, InitParams, Periodic, Rule, Stop};

struct Steady {
    temperature: f64,
    error: f64,
    kurtosis: f64,
    kurtosis_error: f64,
    momentum: f64,
}

/// Runs N grains at φ under kicks that the theory says hold T = 1, for `length` cooling times
/// 1/ζ after 5 to settle; the time-averaged T, its batch-means error, the mean kurtosis and the
/// largest |total momentum| over the samples.
fn steady<const D: usize>(alpha: f64, phi: f64, n: usize, length: f64, conserve: bool) -> Steady {
    steady_with::<D>(alpha, phi, n, length, conserve, 0.05)
}

fn steady_with<const D: usize>(
    alpha: f64,
    phi: f64,
    n: usize,
    length: f64,
    conserve: bool,
    kick: f64,
) -> Steady {
    let nu = collision_frequency(D, phi, chi(D, phi), 1.0, 1.0, 1.0);
    let zeta =
        (1.0 - alpha * alpha) * (1.0 + 3.0 * white_noise_a2(D, alpha) / 16.0) * nu / D as f64;
    assert!(number_density(D, phi, 1.0) > 0.0);
    let mut p = InitParams::<D>::with_packing(n, phi).unwrap();
    p.seed = 11;
    p.sim = Some(edmd_core::SimParams {
        white_noise: zeta, // m ξ₀² = ζ(T = 1) · 1
        kick_interval: kick / zeta,
        kick_conserves_momentum: conserve,
        ..p.default_sim_params()
    });
    let rule = Rule::new(ConstantRestitution::new(alpha).unwrap());
    let mut sim = p.build::<Periodic, _>(rule).unwrap();
    // Samples 0.37/ζ apart: not commensurate with the kicks, so their phases cover the interval.
    let (settle, step) = (5.0 / zeta, 0.37 / zeta);
    let count = (length / 0.37) as usize;
    let (mut t, mut k, mut p_max) = (Vec::new(), Vec::new(), 0.0f64);
    for i in 0..count {
        sim.run(Stop::Time(settle + i as f64 * step));
        let o = sim.observe();
        t.push(o.temperature);
        k.push(o.kurtosis);
        p_max = p_max.max(o.momentum.norm());
    }
    Steady {
        temperature: mean(&t),
        error: batch_error(&t),
        kurtosis: mean(&k),
        kurtosis_error: batch_error(&k),
        momentum: p_max,
    }
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// The standard error of the mean of a correlated series, from the means of 8 batches.
fn batch_error(v: &[f64]) -> f64 {
    let batches: Vec<f64> = v.chunks(v.len() / 8).take(8).map(mean).collect();
    let m = mean(&batches);
    (batches.iter().map(|b| (b - m).powi(2)).sum::<f64>() / 7.0 / 8.0).sqrt()
}

/// The steady state at φ 0.005, one α per dimension: T and the kurtosis (d+2)/d·(1 + a₂).
#[test]
fn the_steady_state_matches_the_theory() {
    check_steady_states(&[(2, 0.5), (3, 0.9)]);
}

/// Both α in both dimensions (`make validate`).
#[test]
#[ignore = "long validation run: make validate"]
fn the_steady_state_matches_the_theory_at_every_alpha() {
    check_steady_states(&[(2, 0.9), (2, 0.5), (3, 0.9), (3, 0.5)]);
}

fn check_steady_states(cases: &[(usize, f64)]) {
    for &(d, alpha) in cases {
        let s = if d == 2 {
            steady::<2>(alpha, 0.005, 1000, 150.0, true)
        } else {
            steady::<3>(alpha, 0.005, 1000, 150.0, true)
        };
        let a2 = white_noise_a2(d, alpha);
        let kurtosis = (d as f64 + 2.0) / d as f64 * (1.0 + a2);
        println!(
            "{d}D alpha {alpha}: T/T_s = {:.4} ± {:.4}, kurtosis {:.4} ± {:.4} (theory {kurtosis:.4}), |P| ≤ {:.1e}",
            s.temperature, s.error, s.kurtosis, s.kurtosis_error, s.momentum
        );
        let dev = s.temperature - 1.0;
        assert!(
            dev.abs() < 3.0 * s.error + 0.005,
            "{d}D alpha {alpha}: T/T_s − 1 = {dev:.4}"
        );
        // a₂ = d/(d+2) · kurtosis − 1, and its error likewise.
        let to_a2 = d as f64 / (d as f64 + 2.0);
        let (da2, error) = ((s.kurtosis - kurtosis) * to_a2, s.kurtosis_error * to_a2);
        assert!(
            da2.abs() < (3.0 * error).min(0.005),
            "{d}D alpha {alpha}: a2 off by {da2:.4} ± {error:.4}"
        );
        assert!(s.momentum < 1e-9, "conserving kicks: |P| = {}", s.momentum);
    }
}

#[test]
fn plain_kicks_let_the_momentum_random_walk() {
    let s = steady::<3>(0.8, 0.02, 300, 30.0, false);
    // After t, each component of P has the variance N m² ξ₀² t: far from zero.
    assert!(s.momentum > 1e-3, "|P| = {}", s.momentum);
}

/// The kicks' interval, the density and the system's size against the deviation from T_s (run by
/// hand; docs/benchmarks.md, "The white-noise thermostat").
#[test]
#[ignore]
fn scan_interval_density_and_size() {
    for (phi, n, kick) in [
        (0.005, 1000, 0.1),
        (0.005, 1000, 0.05),
        (0.005, 1000, 0.02),
        (0.005, 4000, 0.05),
        (0.02, 1000, 0.05),
        (0.05, 1000, 0.05),
    ] {
        let s = steady_with::<2>(0.5, phi, n, 300.0, true, kick);
        println!(
            "phi {phi} N {n} zeta dt {kick}: T/T_s {:.4} ± {:.4}, kurtosis {:.4} ± {:.4}",
            s.temperature, s.error, s.kurtosis, s.kurtosis_error
        );
    }
}
