//! Stress tests of numerical stability: where the engine could break, run it there and check that it
//! does not. Each case prints one `stress:` line with its figures (collected in docs/benchmarks.md).
//!
//! `cargo test` runs short versions (CI); the ignored `*_full` tests (`make stress`) run the full sizes:
//! 10^8 elastic collisions, deep cooling to T/T0 = 1e-1000, N = 4096 collapse cases, N = 10^7 disks.

use std::time::Instant;

use edmd_core::{
    Boundary, CollisionRule, ConstantRestitution, Elastic, InitParams, Periodic, Rule, RunEnd,
    SimParams, Simulation, Stop, ThresholdRestitution, Vector,
};

/// The size of a stress case: the short version runs in `cargo test`, the full one is `#[ignore]`d
/// and run by `make stress` (`cargo test -- --ignored stress::`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Size {
    Short,
    Full,
}

/// Declares the short test `$name` and the ignored full-size test `$name_full` of one case.
macro_rules! sized {
    ($name:ident, $full:ident, $case:ident) => {
        #[test]
        fn $name() {
            $case(Size::Short);
        }
        #[test]
        #[ignore = "full size: make stress"]
        fn $full() {
            $case(Size::Full);
        }
    };
}

/// Total kinetic energy from the physical velocities.
fn kinetic<const D: usize, B: Boundary, R: CollisionRule>(sim: &Simulation<D, B, R>) -> f64 {
    sim.velocities()
        .iter()
        .zip(sim.masses())
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .sum()
}

fn deepest<const D: usize, B: Boundary, R: CollisionRule>(sim: &Simulation<D, B, R>) -> f64 {
    sim.deepest_overlap().map_or(0.0, |o| o.2)
}

sized!(
    elastic_energy_drift_over_many_collisions,
    elastic_energy_drift_over_many_collisions_full,
    elastic_energy_drift_over_many_collisions_case
);

/// Elastic disks, N = 10^4, φ = 0.3: 10^8 collisions (10^6 in CI), energy drift reported.
fn elastic_energy_drift_over_many_collisions_case(size: Size) {
    let collisions: u64 = if size == Size::Full {
        100_000_000
    } else {
        1_000_000
    };
    let mut p = InitParams::<2>::with_packing(10_000, 0.3).unwrap();
    p.seed = 11;
    let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
    let o0 = sim.observe();
    let start = Instant::now();
    // In chunks of 10^6 collisions, checking overlaps every chunk.
    let mut worst: f64 = 0.0;
    while sim.counters().pair_collisions < collisions {
        sim.run(Stop::Tau(sim.tau() + 100.0));
        worst = worst.max(deepest(&sim));
    }
    let secs = start.elapsed().as_secs_f64();
    let o1 = sim.observe();
    let de = (o1.kinetic_energy - o0.kinetic_energy).abs() / o0.kinetic_energy;
    let dp = (o1.momentum - o0.momentum).norm() / o1.momentum_scale;
    println!(
        "stress: elastic drift: {} collisions, |dE/E| = {de:.2e}, |dP|/sum|p| = {dp:.2e}, deepest overlap {worst:.1e} sigma, {:.2} M collisions/s",
        o1.pair_collisions,
        o1.pair_collisions as f64 / secs / 1e6
    );
    assert!(de < 1e-10, "energy drift {de:e}");
    assert!(dp < 1e-12, "momentum drift {dp:e}");
    assert!(worst < 1e-9, "overlap {worst:e}");
}

sized!(
    deep_cooling_below_1e_minus_300,
    deep_cooling_below_1e_minus_300_full,
    deep_cooling_below_1e_minus_300_case
);

/// Deep cooling: 66 disks at φ = 0.25 in a periodic box of 0.59 L⊥ (homogeneous), ε = 0.9, until
/// T/T0 < 1e-300 (1e-1000 in the full version). ln T must stay finite and never rise, the collision
/// rate per τ must not stall, and the final ln T must follow Haff's exponential within 2 %.
fn deep_cooling_below_1e_minus_300_case(size: Size) {
    let target_log10 = if size == Size::Full { -1000.0 } else { -300.0 };
    let mut p = InitParams::<2>::in_box(66, Vector::<2>::repeat(14.4));
    p.seed = 5;
    let mut sim = p
        .build::<Periodic, _>(Rule::new(ConstantRestitution::new(0.9).unwrap()))
        .unwrap();
    let ln0 = sim.ln_temperature();
    let start = Instant::now();
    let mut last = ln0;
    let mut worst: f64 = 0.0;
    let mut ln_t = ln0;
    while (ln_t - ln0) / std::f64::consts::LN_10 > target_log10 {
        assert!(
            sim.tau() < 40_000.0,
            "did not cool: ln T/T0 = {}",
            ln_t - ln0
        );
        let c0 = sim.counters().events;
        sim.run(Stop::Tau(sim.tau() + 10.0));
        let events = sim.counters().events - c0;
        // 10 τ of 66 disks is 660 collisions; a stalled run would need millions of events.
        assert!(events < 100_000, "stalled: {events} events for 10 tau");
        ln_t = sim.ln_temperature();
        assert!(ln_t.is_finite(), "ln T = {ln_t}");
        assert!(ln_t <= last + 1e-12, "ln T rose from {last} to {ln_t}");
        last = ln_t;
        worst = worst.max(deepest(&sim));
    }
    let log10 = (ln_t - ln0) / std::f64::consts::LN_10;
    // Haff per τ (PHYSICS §2.2): T(τ) = T0 e^{−k τ}; finite N and fluctuations give a few 0.1 %.
    let k = edmd_core::theory::haff_rate(2, 0.9);
    let haff_log10 = -k * sim.tau() / std::f64::consts::LN_10;
    println!(
        "stress: deep cooling: log10(T/T0) = {log10:.1} at tau {:.0} (Haff {haff_log10:.1}), time e^{:.1}, deepest overlap {worst:.1e} sigma, {:.2} s",
        sim.tau(),
        sim.ln_time(),
        start.elapsed().as_secs_f64()
    );
    assert!((log10 / haff_log10 - 1.0).abs() < 0.02);
    assert!(worst < 1e-9);
}

/// How a dense inelastic run ended: end, τ, log10(T/T0), busiest particle's collisions over the
/// mean, deepest overlap, seconds.
type DenseRun = (RunEnd, f64, f64, f64, f64, f64);

/// Runs a strongly inelastic dense gas to `tau` and returns how it ended, with figures.
fn dense_inelastic<R: CollisionRule>(n: usize, rule: R, tau: f64) -> DenseRun {
    let mut p = InitParams::<2>::with_packing(n, 0.5).unwrap();
    p.seed = 7;
    let mut sim = p.build::<Periodic, _>(rule).unwrap();
    let e0 = kinetic(&sim);
    let start = Instant::now();
    let mut end = RunEnd::Reached;
    let mut last = e0;
    while sim.tau() < tau {
        end = sim.run(Stop::Tau((sim.tau() + 25.0).min(tau)));
        let e = kinetic(&sim);
        assert!(e <= last * (1.0 + 1e-12), "energy created: {e} > {last}");
        last = e;
        if end != RunEnd::Reached {
            break;
        }
    }
    let o = sim.observe();
    assert!(o.momentum.norm() < 1e-10 * o.momentum_scale);
    let log10 = (sim.ln_temperature() - 1f64.ln()) / std::f64::consts::LN_10;
    // Collisions of the busiest particle over the mean (2τ): ≫ 1 where collisions crowd into
    // collapsing clusters and τ stops measuring the gas's age.
    let busiest = *sim.collision_counts().iter().max().unwrap() as f64 / (2.0 * sim.tau());
    (
        end,
        sim.tau(),
        log10,
        busiest,
        deepest(&sim),
        start.elapsed().as_secs_f64(),
    )
}

sized!(
    strongly_inelastic_dense_gas_with_and_without_remedies,
    strongly_inelastic_dense_gas_with_and_without_remedies_full,
    strongly_inelastic_dense_gas_with_and_without_remedies_case
);

/// ε = 0.1–0.3 at φ = 0.5: without a remedy the run ends (collapse detected, or the target reached)
/// in bounded time; with the TC model, the velocity threshold and the thesis's combination
/// (threshold + rotation) every run reaches the target τ. Never an overlap.
fn strongly_inelastic_dense_gas_with_and_without_remedies_case(size: Size) {
    let (n, tau) = if size == Size::Full {
        (4096, 500.0)
    } else {
        (1024, 100.0)
    };
    // Mean free time at φ = 0.5, T0 = 1: 1/ν ≈ 0.14; remedies act on the scale of 1e-4 of it.
    let tc = 1.4e-5;
    let delta = 1e-4;
    for eps in [0.1, 0.2, 0.3] {
        let c = Rule::new(ConstantRestitution::new(eps).unwrap());
        let cases: [(&str, DenseRun); 4] = [
            ("none", dense_inelastic(n, c, tau)),
            ("TC", dense_inelastic(n, c.with_tc(tc).unwrap(), tau)),
            (
                "threshold",
                dense_inelastic(
                    n,
                    Rule::new(ThresholdRestitution::new(eps, 1.0, delta).unwrap()),
                    tau,
                ),
            ),
            (
                "threshold+rotation",
                dense_inelastic(
                    n,
                    Rule::new(ThresholdRestitution::new(eps, 1.0, delta).unwrap())
                        .with_rotation(10f64.to_radians())
                        .unwrap(),
                    tau,
                ),
            ),
        ];
        for (name, (end, t, log10, busiest, overlap, secs)) in cases {
            println!(
                "stress: eps {eps} phi 0.5 N {n} remedy {name}: {end:?} at tau {t:.1}, log10(T/T0) = {log10:.1}, busiest particle {busiest:.0}x the mean collisions, deepest overlap {overlap:.1e} sigma, {secs:.2} s"
            );
            assert!(overlap < 1e-9, "{name}: overlap {overlap:e}");
            assert!(secs < 120.0, "{name}: {secs} s");
            if name == "none" {
                assert!(matches!(end, RunEnd::Reached | RunEnd::Collapsed));
            } else {
                assert_eq!(end, RunEnd::Reached, "{name} at eps {eps}");
            }
        }
    }
}

sized!(
    near_crystal_elastic_disks,
    near_crystal_elastic_disks_full,
    near_crystal_elastic_disks_case
);

/// Elastic disks at φ = 0.72, near the crystal (hexagonal close packing 0.9069, freezing ≈ 0.70):
/// energy exact, no overlap, finite pressure.
fn near_crystal_elastic_disks_case(size: Size) {
    let (n, tau) = if size == Size::Full {
        (10_000, 1000.0)
    } else {
        (1024, 100.0)
    };
    let mut p = InitParams::<2>::with_packing(n, 0.72).unwrap();
    p.seed = 2;
    let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
    let o0 = sim.observe();
    let start = Instant::now();
    let mut worst: f64 = 0.0;
    let meter = edmd_core::VirialMeter::start(&sim);
    while sim.tau() < tau {
        sim.run(Stop::Tau(sim.tau() + 10.0));
        worst = worst.max(deepest(&sim));
    }
    let reading = meter.read(&sim);
    let secs = start.elapsed().as_secs_f64();
    let o1 = sim.observe();
    let de = (o1.kinetic_energy - o0.kinetic_energy).abs() / o0.kinetic_energy;
    println!(
        "stress: near crystal phi 0.72 N {n}: {} collisions, |dE/E| = {de:.1e}, Z = pV/(NT) = {:.2}, deepest overlap {worst:.1e} sigma, {:.2} M collisions/s",
        o1.pair_collisions,
        reading.z,
        o1.pair_collisions as f64 / secs / 1e6
    );
    assert!(de < 1e-10);
    assert!(worst < 1e-9);
    assert!(reading.z.is_finite() && reading.z > 5.0);
}

sized!(
    polydisperse_one_to_ten,
    polydisperse_one_to_ten_full,
    polydisperse_one_to_ten_case
);

/// Polydisperse 1:10: every tenth disk has diameter 1, the others 0.1 (cells are sized by the largest
/// diameter, so a cell holds many small disks). Elastic energy exact; inelastic momentum exact.
fn polydisperse_one_to_ten_case(size: Size) {
    let (n, tau) = if size == Size::Full {
        (20_000, 100.0)
    } else {
        (2000, 20.0)
    };
    let radii: Vec<f64> = (0..n)
        .map(|i| if i % 10 == 0 { 0.5 } else { 0.05 })
        .collect();
    let side = 30.0 * (n as f64 / 2000.0).sqrt();
    for eps in [1.0, 0.9] {
        let mut p = InitParams::<2>::in_box(n, Vector::<2>::repeat(side));
        p.radii = Some(radii.clone());
        p.seed = 4;
        let phi = p.packing_fraction();
        let mut sim = p
            .build::<Periodic, _>(Rule::new(ConstantRestitution::new(eps).unwrap()))
            .unwrap();
        let o0 = sim.observe();
        let start = Instant::now();
        let mut worst: f64 = 0.0;
        while sim.tau() < tau {
            sim.run(Stop::Tau(sim.tau() + 5.0));
            worst = worst.max(deepest(&sim));
        }
        let secs = start.elapsed().as_secs_f64();
        let o1 = sim.observe();
        let de = (o1.kinetic_energy - o0.kinetic_energy) / o0.kinetic_energy;
        let dp = (o1.momentum - o0.momentum).norm() / o1.momentum_scale;
        println!(
            "stress: polydisperse 1:10 phi {phi:.3} N {n} eps {eps}: dE/E = {de:.2e}, |dP|/sum|p| = {dp:.1e}, deepest overlap {worst:.1e} sigma, {:.2} M collisions/s",
            o1.pair_collisions as f64 / secs / 1e6
        );
        assert!(worst < 1e-9);
        assert!(dp < 1e-12);
        if eps == 1.0 {
            assert!(de.abs() < 1e-10);
        } else {
            assert!(de < 0.0);
        }
    }
}

sized!(very_dilute_gas, very_dilute_gas_full, very_dilute_gas_case);

/// Very dilute gas, φ = 1e-4 (mean free path ≈ 2800 σ): cells of one diameter would be nearly all
/// empty and crossings would dominate; `SimParams::for_density` sizes cells for ~0.4 disks each. The
/// run must stay exact, the collision rate must be Enskog's, and the three cell sizes are reported.
fn very_dilute_gas_case(size: Size) {
    let (n, tau) = if size == Size::Full {
        (10_000, 20.0)
    } else {
        (1000, 5.0)
    };
    let auto = SimParams::for_density::<2>(1e-4).cell_factor;
    // Cells of one diameter (7000 crossings per collision, 30 kB per disk; measured at N = 10^4:
    // 42 collisions/s) only in the full run, and only for 1000 disks.
    let sides: &[f64] = if size == Size::Full {
        &[1.0, auto, 4.0 * auto]
    } else {
        &[auto, 4.0 * auto]
    };
    for &cell_factor in sides {
        let n = if cell_factor == 1.0 { 1000 } else { n };
        let mut p = InitParams::<2>::with_packing(n, 1e-4).unwrap();
        p.seed = 9;
        p.sim = Some(SimParams {
            cell_factor,
            seed: 9,
            ..SimParams::default()
        });
        let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
        let o0 = sim.observe();
        let start = Instant::now();
        // One-diameter cells: τ = 2 (2000 collisions, 1.4·10^7 crossings) says enough.
        sim.run(Stop::Tau(if cell_factor == 1.0 { 2.0 } else { tau }));
        let secs = start.elapsed().as_secs_f64();
        let o1 = sim.observe();
        let c = sim.counters();
        let de = (o1.kinetic_energy - o0.kinetic_energy).abs() / o0.kinetic_energy;
        println!(
            "stress: dilute phi 1e-4 N {n} cell side {cell_factor:.0} sigma: {} collisions, {:.1} crossings per collision, {:.0} collisions/s, {} B/particle, |dE/E| = {de:.1e}",
            c.pair_collisions,
            c.crossings as f64 / c.pair_collisions as f64,
            c.pair_collisions as f64 / secs,
            sim.heap_bytes() / n
        );
        assert!(de < 1e-10);
        assert!(deepest(&sim) < 1e-9);
        // The collision rate per particle is Enskog's (χ ≈ 1): 2C/(N t) within 3 statistical errors.
        let nu = edmd_core::theory::collision_frequency(
            2,
            1e-4,
            edmd_core::theory::chi(2, 1e-4),
            1.0,
            1.0,
            1.0,
        );
        let measured = 2.0 * c.pair_collisions as f64 / n as f64 / o1.time;
        let tol = 3.0 / (c.pair_collisions as f64).sqrt();
        assert!(
            (measured / nu - 1.0).abs() < tol,
            "rate {measured} vs Enskog {nu} (tolerance {tol})"
        );
    }
}

sized!(
    ten_million_disks,
    ten_million_disks_full,
    ten_million_disks_case
);

/// N = 10^7 disks at φ = 0.3 (10^5 in CI): builds, runs τ = 1, reports collisions/s and bytes per
/// particle; no overlap.
fn ten_million_disks_case(size: Size) {
    let n = if size == Size::Full {
        10_000_000
    } else {
        100_000
    };
    let start = Instant::now();
    let mut p = InitParams::<2>::with_packing(n, 0.3).unwrap();
    p.seed = 1;
    let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
    let built = start.elapsed().as_secs_f64();
    let t0 = Instant::now();
    sim.run(Stop::Tau(1.0));
    let secs = t0.elapsed().as_secs_f64();
    let bytes = sim.heap_bytes() as f64 / n as f64;
    let worst = deepest(&sim);
    println!(
        "stress: N {n} disks phi 0.3: built in {built:.1} s, {:.2} M collisions/s over tau 1, {bytes:.0} B/particle (engine heap), deepest overlap {worst:.1e} sigma",
        sim.counters().pair_collisions as f64 / secs / 1e6
    );
    assert!(worst < 1e-9);
    assert!(bytes < 250.0, "{bytes} bytes per particle");
}
