//! Equilibrium hard disks and spheres against kinetic theory (PHYSICS.md §1): the contact value χ
//! inverted from the collision rate and from the collision virial must agree with Luding's χ (2D,
//! within 0.3 %) and Carnahan–Starling (3D, within 0.5 %). The 3D case at φ = 0.45 runs on neighbour
//! lists, all others on cell crossings.
//!
//! CI runs N = 4000 for τ = 1000 after 50 of equilibration; the ignored `*_full` tests (run by
//! `make validate`) run N = 10^4 for τ = 2000. The statistical error is estimated from 10 blocks and
//! printed; each test also requires it to be small enough (< 1/3 of the tolerance) for the
//! comparison to mean something.

use edmd_core::theory::{chi, chi_from_compressibility, chi_from_frequency};
use edmd_core::{Elastic, InitParams, Periodic, Stop, VirialMeter};

struct Estimate {
    mean: f64,
    se: f64,
}

fn estimate(values: &[f64]) -> Estimate {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    Estimate {
        mean,
        se: (var / n).sqrt(),
    }
}

fn check<const D: usize>(phi: f64, tolerance: f64, full: bool) {
    let (n, tau) = if full {
        (10_000, 2000.0)
    } else {
        (4000, 1000.0)
    };
    let mut p = InitParams::<D>::with_packing(n, phi).unwrap();
    p.seed = 42;
    let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
    // The default neighbour strategy: lists for dense spheres, cell crossings elsewhere.
    assert_eq!(sim.uses_neighbour_lists(), D == 3 && phi >= 0.38);
    sim.run(Stop::Tau(50.0));
    let blocks = 10;
    let (mut from_nu, mut from_z) = (Vec::new(), Vec::new());
    for _ in 0..blocks {
        let meter = VirialMeter::start(&sim);
        sim.run(Stop::Tau(sim.tau() + tau / blocks as f64));
        let r = meter.read(&sim);
        from_nu.push(chi_from_frequency(
            D,
            phi,
            r.nu,
            1.0,
            sim.temperature(),
            1.0,
        ));
        from_z.push(chi_from_compressibility(D, phi, r.z));
    }
    let reference = chi(D, phi);
    for (label, values) in [("collision rate", &from_nu), ("virial", &from_z)] {
        let e = estimate(values);
        let dev = e.mean / reference - 1.0;
        println!(
            "D = {D}, phi = {phi}, N = {n}, tau = {tau}: chi from {label} = {:.5} ± {:.5}, reference {reference:.5}, deviation {:+.3} %",
            e.mean,
            e.se,
            100.0 * dev
        );
        assert!(
            e.se / reference < tolerance / 3.0,
            "statistical error too large for the test: {:e}",
            e.se
        );
        assert!(
            dev.abs() < tolerance,
            "chi from {label} deviates by {:.3} % (tolerance {} %)",
            100.0 * dev,
            100.0 * tolerance
        );
    }
}

#[test]
fn disks_phi_0_10() {
    check::<2>(0.10, 0.003, false);
}

#[test]
#[ignore = "long validation run: make validate"]
fn disks_phi_0_10_full() {
    check::<2>(0.10, 0.003, true);
}

#[test]
fn disks_phi_0_25() {
    check::<2>(0.25, 0.003, false);
}

#[test]
#[ignore = "long validation run: make validate"]
fn disks_phi_0_25_full() {
    check::<2>(0.25, 0.003, true);
}

#[test]
fn disks_phi_0_50() {
    check::<2>(0.50, 0.003, false);
}

#[test]
#[ignore = "long validation run: make validate"]
fn disks_phi_0_50_full() {
    check::<2>(0.50, 0.003, true);
}

#[test]
fn spheres_phi_0_20() {
    check::<3>(0.20, 0.005, false);
}

#[test]
#[ignore = "long validation run: make validate"]
fn spheres_phi_0_20_full() {
    check::<3>(0.20, 0.005, true);
}

#[test]
fn spheres_phi_0_35() {
    check::<3>(0.35, 0.005, false);
}

#[test]
#[ignore = "long validation run: make validate"]
fn spheres_phi_0_35_full() {
    check::<3>(0.35, 0.005, true);
}

/// φ = 0.45 runs on neighbour lists (the default there), the other cases on cell crossings.
#[test]
fn spheres_phi_0_45_neighbour_lists() {
    check::<3>(0.45, 0.005, false);
}

#[test]
#[ignore = "long validation run: make validate"]
fn spheres_phi_0_45_neighbour_lists_full() {
    check::<3>(0.45, 0.005, true);
}
