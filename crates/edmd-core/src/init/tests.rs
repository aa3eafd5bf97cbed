//! Initial states: densities, limits, momenta and temperatures.

use super::*;
use crate::{Periodic, Walls};

#[test]
fn random_start_has_exact_temperature_and_no_momentum() {
    let mut p = InitParams::<2>::with_packing(500, 0.2).unwrap();
    p.velocities = Velocities::Uniform;
    p.temperature = 1.0 / 3.0;
    let sim = p.build::<Periodic, _>(Elastic).unwrap();
    let o = sim.observe();
    assert!((o.temperature - 1.0 / 3.0).abs() < 1e-14);
    assert!(o.momentum.norm() < 1e-13 * o.momentum_scale);
    assert!(sim.deepest_overlap().unwrap().2 < 0.0);
}

#[test]
fn lattice_reaches_dense_states() {
    for (phi, walls) in [(0.7, false), (0.7, true)] {
        let mut p = InitParams::<2>::with_packing(400, phi).unwrap();
        p.melt_tau = Some(0.0);
        let sim = if walls {
            p.build::<Walls, _>(Elastic).map(|s| s.deepest_overlap())
        } else {
            p.build::<Periodic, _>(Elastic).map(|s| s.deepest_overlap())
        };
        assert!(sim.unwrap().unwrap().2 <= 1e-12, "phi {phi} walls {walls}");
    }
    let mut p = InitParams::<3>::with_packing(1000, 0.5).unwrap();
    p.melt_tau = Some(0.0);
    assert!(
        p.build::<Periodic, _>(Elastic)
            .unwrap()
            .deepest_overlap()
            .unwrap()
            .2
            <= 1e-12
    );
}

#[test]
fn too_dense_is_an_error_naming_the_limit() {
    let mut p = InitParams::<2>::with_packing(400, 0.6).unwrap();
    p.placement = Placement::Random;
    let e = p.build::<Periodic, _>(Elastic).unwrap_err();
    assert!(
        matches!(
            e,
            EdmdError::TooDense {
                method: "random",
                ..
            }
        ),
        "{e}"
    );
    let p = InitParams::<2>::with_packing(400, 0.95).unwrap();
    let e = p.build::<Periodic, _>(Elastic).unwrap_err().to_string();
    assert!(e.contains("lattice") && e.contains("0.9500"), "{e}");
}

#[test]
fn bad_parameters_name_the_field() {
    let e = InitParams::<2>::with_packing(0, 0.2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("N = 0"), "{e}");
    let e = InitParams::<2>::with_packing(10, 1.2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("phi = 1.2"), "{e}");
    let mut p = InitParams::<2>::with_packing(10, 0.1).unwrap();
    p.radius = -1.0;
    let e = p.build::<Periodic, _>(Elastic).unwrap_err().to_string();
    assert!(e.contains("radius = -1"), "{e}");
    let p = InitParams::<2>::in_box(10, Vector::<2>::new(2.5, 10.0));
    let e = p.build::<Periodic, _>(Elastic).unwrap_err().to_string();
    assert!(e.contains("Lx = 2.5"), "{e}");
}

/// Unequal masses start at one temperature: each species' m⟨v²⟩/d matches T0 to its statistical
/// error (√(2/(d N_k)) = 1 % for 10^4 disks each; tolerance 5 %, i.e. 5 standard errors).
#[test]
fn unequal_masses_start_in_equipartition() {
    let n = 20_000;
    let side = (n as f64 * unit_volume::<2>(0.5) / 0.05).sqrt();
    let mut p = InitParams::<2>::in_box(n, Vector::<2>::repeat(side));
    p.masses = Some((0..n).map(|i| if i < n / 2 { 1.0 } else { 4.0 }).collect());
    p.seed = 5;
    let sim = p.build::<Periodic, _>(Elastic).unwrap();
    let (v, m) = (sim.velocities(), sim.masses());
    let mut e = [0.0; 2];
    for (i, (v, m)) in v.iter().zip(&m).enumerate() {
        e[usize::from(i >= n / 2)] += m * v.norm_squared();
    }
    for e in e {
        let t = e / (2.0 * (n / 2) as f64);
        assert!((t - 1.0).abs() < 0.05, "species temperature {t}");
    }
}

#[test]
fn large_list_mode_systems_get_the_wider_skin_and_others_keep_theirs() {
    let skin = |n: usize, phi: f64| {
        InitParams::<3>::with_packing(n, phi)
            .unwrap()
            .default_sim_params()
            .neighbour_skin
    };
    let small = skin(LARGE_LIST_N - 1, 0.45);
    assert_eq!(small, SimParams::for_density::<3>(0.45).neighbour_skin);
    assert!(small > 0.0 && small < LARGE_LIST_SKIN);
    assert_eq!(skin(LARGE_LIST_N, 0.45), LARGE_LIST_SKIN);
    // Cell mode (a dilute gas) stays in cell mode at any size.
    assert_eq!(skin(LARGE_LIST_N, 0.1), 0.0);
}
