//! Homogeneous cooling state against kinetic theory (PHYSICS.md §2.2–2.3): in periodic boxes of half
//! the shear-critical size L⊥ (so that the state stays homogeneous), the decay rate −d ln T/dτ
//! fitted over τ ∈ [5, 40] matches the Haff rate within 2 % (4 % at ε = 0.6), averaged over seeds, and
//! the speed kurtosis matches (d+2)/d·(1 + a₂) within 0.02.
//!
//! The Haff rate of N particles with zero total momentum is k(ε)·N/(N − 1), exactly: their
//! temperature m⟨v²⟩/d averages over N particles, but only d(N − 1) degrees of freedom are free, so
//! pairs meet with ⟨g²⟩ = 2⟨v²⟩·N/(N − 1) and each collision removes that much more energy. Below L⊥
//! at φ = 0.25 the box holds 12–460 disks (ε = 0.6–0.99), where the factor is 0.2–9 %. Measured with
//! `examples/haff_finite_size.rs` (ε = 0.8, φ = 0.25, 10⁵–2·10⁵ particle runs per size): boxes of
//! 0.3–0.4 L⊥ (N = 9, 15) give k·N/(N − 1) to −0.24 %; larger boxes fall below it as the stable but
//! enhanced shear modes hold more of the kinetic energy (−1.0 % at L⊥/2, −7.9 % at 0.9 L⊥).

use edmd_core::theory::{a2, critical_sizes, haff_rate, Transport};
use edmd_core::{decay_rate, ConstantRestitution, InitParams, Periodic, Schedule, Stop, Vector};

/// Mean over seeds of the least-squares slope of ln T(τ) on τ ∈ [5, 40], and the mean kurtosis
/// over the same window.
fn decay<const D: usize>(eps: f64, phi: f64, n: usize, seeds: u64) -> (f64, f64, f64) {
    let (mut slopes, mut kurt) = (Vec::new(), Vec::new());
    for seed in 0..seeds {
        let side = (n as f64 * edmd_core::init::unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
        let mut p = InitParams::<D>::in_box(n, Vector::<D>::repeat(side));
        p.seed = 1000 + seed;
        p.melt_tau = Some(5.0);
        let mut sim = p
            .build::<Periodic, _>(edmd_core::Rule::new(ConstantRestitution::new(eps).unwrap()))
            .unwrap();
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        sim.run_sampled(Stop::Tau(40.0), &Schedule::every(1.0), |s| {
            if s.tau() >= 5.0 {
                let o = s.observe();
                xs.push(o.tau);
                ys.push(o.temperature.ln());
                kurt.push(o.kurtosis);
            }
        });
        slopes.push(decay_rate(&xs, &ys));
    }
    let m = slopes.iter().sum::<f64>() / slopes.len() as f64;
    let se = (slopes.iter().map(|s| (s - m).powi(2)).sum::<f64>()
        / (slopes.len() as f64 - 1.0)
        / slopes.len() as f64)
        .sqrt();
    (m, se, kurt.iter().sum::<f64>() / kurt.len() as f64)
}

/// Box side L⊥/2 (Enskog), where the transverse modes are only mildly enhanced (S⊥ ≈ 4/3), or the
/// side holding 2000 particles if smaller; ~8·10^4 particles over all seeds.
fn check<const D: usize>(eps: f64, phi: f64, tolerance: f64) {
    let (l_perp, _) = critical_sizes(D, eps, phi, 1.0, Transport::Enskog);
    let side = 0.5 * l_perp;
    let n = ((phi * side.powi(D as i32) / edmd_core::init::unit_volume::<D>(0.5)).round() as usize)
        .min(2000);
    assert!(n >= 8, "box too small for a gas: N = {n}");
    let seeds = (80_000 / n).clamp(4, 2000) as u64;
    let (k, se, kurtosis) = decay::<D>(eps, phi, n, seeds);
    let theory = haff_rate(D, eps) * n as f64 / (n as f64 - 1.0);
    let dev = k / theory - 1.0;
    println!(
        "D = {D}, eps = {eps}, phi = {phi}: N = {n} x {seeds} seeds, fitted k = {k:.5} ± {se:.5}, theory k N/(N-1) = {theory:.5} ({:+.2} %; {:+.2} % against k), kurtosis {kurtosis:.4} (theory {:.4})",
        100.0 * dev,
        100.0 * (k / haff_rate(D, eps) - 1.0),
        (D as f64 + 2.0) / D as f64 * (1.0 + a2(D, eps))
    );
    assert!(
        se / theory < tolerance / 3.0,
        "statistical error too large: {se}"
    );
    assert!(
        dev.abs() < tolerance,
        "decay rate off by {:.2} %",
        100.0 * dev
    );
    // The kurtosis of a snapshot of N speeds is biased at O(1/N) (it cannot exceed N, and the
    // speeds share a fixed energy); it is compared from N = 100 on (PHYSICS.md §2.2).
    let kurtosis_theory = (D as f64 + 2.0) / D as f64 * (1.0 + a2(D, eps));
    if n >= 100 {
        assert!(
            (kurtosis - kurtosis_theory).abs() < 0.02,
            "kurtosis {kurtosis} vs {kurtosis_theory}"
        );
    }
}

#[test]
fn disks_dilute() {
    check::<2>(0.9, 0.05, 0.02);
    check::<2>(0.6, 0.05, 0.04);
}

/// The dilute disks at ε 0.99 and 0.8 besides (`make validate`).
#[test]
#[ignore = "long validation run: make validate"]
fn disks_dilute_at_every_eps() {
    check::<2>(0.99, 0.05, 0.02);
    check::<2>(0.8, 0.05, 0.02);
}

#[test]
fn disks_dense() {
    check::<2>(0.99, 0.25, 0.02);
    check::<2>(0.9, 0.25, 0.02);
    check::<2>(0.8, 0.25, 0.02);
    check::<2>(0.6, 0.25, 0.04);
}

#[test]
fn spheres_eps_0_9() {
    check::<3>(0.9, 0.1, 0.02);
}

/// The homogeneous cooling state's speed kurtosis at ε = 0.9 with N = 500 disks (φ = 0.05, box
/// 0.7 L⊥): within 0.02 of 2(1 + a₂), averaged over τ ∈ [5, 40] and 40 seeds.
#[test]
fn kurtosis_eps_0_9_n_500() {
    let (eps, phi, n) = (0.9, 0.05, 500);
    let (l_perp, _) = critical_sizes(2, eps, phi, 1.0, Transport::Enskog);
    let side = (n as f64 * edmd_core::init::unit_volume::<2>(0.5) / phi).sqrt();
    assert!(side < l_perp, "box {side} not below L_perp {l_perp}");
    let (_, _, kurtosis) = decay::<2>(eps, phi, n, 40);
    let theory = 2.0 * (1.0 + a2(2, eps));
    println!(
        "N = {n}, eps = {eps}: kurtosis {kurtosis:.4}, theory {theory:.4} (box {:.2} L_perp)",
        side / l_perp
    );
    assert!((kurtosis - theory).abs() < 0.02);
}
