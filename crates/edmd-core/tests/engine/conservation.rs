//! Elastic hard disks conserve energy exactly up to round-off, and (in periodic boxes) momentum.
//! Tolerances from the engine's specification: |ΔE/E| < 1e-10 over 10^7 collisions of N = 10^4
//! disks at φ = 0.3, and |P| < 1e-12 Σ|p|.

use edmd_core::{Boundary, Elastic, InitParams, Periodic, Stop, Walls};

fn drift<B: Boundary>(collisions: u64) -> (f64, f64, f64) {
    let mut p = InitParams::<2>::with_packing(10_000, 0.3).unwrap();
    p.seed = 3;
    let mut sim = p.build::<B, _>(Elastic).unwrap();
    let start = sim.observe();
    sim.run(Stop::Tau(collisions as f64 / 10_000.0));
    let end = sim.observe();
    assert!(end.pair_collisions >= collisions);
    let de = ((end.kinetic_energy - start.kinetic_energy) / start.kinetic_energy).abs();
    let dp = (end.momentum - start.momentum).norm() / end.momentum_scale;
    let overlap = sim.deepest_overlap().unwrap().2;
    (de, dp, overlap)
}

#[test]
fn energy_and_momentum_over_ten_million_collisions_periodic() {
    let (de, dp, overlap) = drift::<Periodic>(10_000_000);
    println!("periodic: |dE/E| = {de:.3e}, |dP|/sum|p| = {dp:.3e}, deepest overlap {overlap:.2e}");
    assert!(de < 1e-10, "energy drift {de:e}");
    assert!(dp < 1e-12, "momentum drift {dp:e}");
    assert!(overlap < 1e-9);
}

#[test]
fn energy_over_ten_million_collisions_with_walls() {
    let (de, _, overlap) = drift::<Walls>(10_000_000);
    println!("walls: |dE/E| = {de:.3e}, deepest overlap {overlap:.2e}");
    assert!(de < 1e-10, "energy drift {de:e}");
    assert!(overlap < 1e-9);
}

/// Neighbour lists (the default for dense 3D packings) conserve as exactly as cell crossings.
#[test]
fn neighbour_lists_conserve_energy_and_momentum() {
    fn run<B: Boundary>(label: &str) {
        let mut p = InitParams::<3>::with_packing(4000, 0.45).unwrap();
        p.seed = 9;
        let mut sim = p.build::<B, _>(Elastic).unwrap();
        assert!(sim.uses_neighbour_lists());
        let start = sim.observe();
        sim.run(Stop::Tau(500.0));
        let end = sim.observe();
        let de = ((end.kinetic_energy - start.kinetic_energy) / start.kinetic_energy).abs();
        let dp = (end.momentum - start.momentum).norm() / end.momentum_scale;
        let overlap = sim.deepest_overlap().unwrap().2;
        println!(
            "{label}: 2e6 collisions, {:.2} shell exits per collision, |dE/E| = {de:.3e}, |dP|/sum|p| = {dp:.3e}, deepest overlap {overlap:.2e}",
            sim.counters().crossings as f64 / sim.counters().pair_collisions as f64
        );
        assert!(de < 1e-10, "{label}: energy drift {de:e}");
        assert!(overlap < 1e-9, "{label}: overlap {overlap:e}");
        if !B::is_wall(0) {
            assert!(dp < 1e-12, "{label}: momentum drift {dp:e}");
        }
    }
    run::<Periodic>("3D periodic phi 0.45, neighbour lists");
    run::<Walls>("3D walls phi 0.45, neighbour lists");
}

/// Inelastic collisions conserve momentum too, and never create energy.
#[test]
fn inelastic_collisions_conserve_momentum_and_lose_energy() {
    let mut p = InitParams::<3>::with_packing(2000, 0.2).unwrap();
    p.seed = 5;
    let mut sim = p
        .build::<Periodic, _>(edmd_core::Rule::new(
            edmd_core::ConstantRestitution::new(0.8).unwrap(),
        ))
        .unwrap();
    let mut last = sim.kinetic_energy();
    for _ in 0..50 {
        sim.run(Stop::Events(4000));
        let o = sim.observe();
        assert!(
            o.kinetic_energy <= last,
            "energy grew: {} > {last}",
            o.kinetic_energy
        );
        assert!(
            o.momentum.norm() < 1e-12 * o.momentum_scale,
            "momentum {:e}",
            o.momentum.norm()
        );
        last = o.kinetic_energy;
    }
}
