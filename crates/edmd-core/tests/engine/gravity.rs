//! Uniform gravity with a floor: a ball on an elastic floor keeps its height over 10^6 bounces, and a
//! column of 1000 inelastic disks settles on the floor without stalling: the TC model (t_c = 0.01)
//! keeps the pile from collapsing and a threshold on wall contacts keeps grains resting on the floor
//! from bouncing ever faster. (A settled pile still costs many events per unit time: its gaps are
//! tiny. That is inherent to event-driven dynamics of static packings.)

use edmd_core::{
    Column, ConstantRestitution, Container, InitParams, ParticleInit, Placement, Rule, RunEnd,
    SimParams, Simulation, Stop, Vector,
};

#[test]
fn ball_on_elastic_floor_returns_to_its_height() {
    let (g, h0) = (1.0, 5.0);
    let parts = vec![ParticleInit {
        pos: Vector::<2>::new(5.0, h0),
        vel: Vector::<2>::new(0.0, 0.0),
        radius: 0.5,
        mass: 1.0,
    }];
    let params = SimParams {
        gravity: g,
        cell_factor: 3.0,
        ..SimParams::default()
    };
    let mut sim = Simulation::<2, Container, _>::new(
        Vector::<2>::new(10.0, 10.0),
        parts,
        Rule::new(ConstantRestitution::new(0.5).unwrap()),
        params,
    )
    .unwrap();
    let energy = |s: &Simulation<2, Container, Rule>| s.kinetic_energy() + s.potential_energy();
    let e0 = energy(&sim);
    while sim.counters().wall_collisions < 1_000_000 {
        sim.step().unwrap();
    }
    let e1 = energy(&sim);
    // Apex height above the floor contact (centre at y = 0.5): (E/(m g)) − 0.5.
    let (h_start, h_end) = (e0 / g - 0.5, e1 / g - 0.5);
    // Each bounce period is 2√(2h/g): the clock must agree.
    let period = 2.0 * (2.0 * (h0 - 0.5) / g).sqrt();
    let expected_time = 0.5 * period + (1_000_000.0 - 1.0) * period;
    println!(
        "10^6 bounces: apex {h_end:.15} (start {h_start:.15}), relative change {:.1e}; t = {:.9e} (expected ≈ {expected_time:.9e})",
        (h_end - h_start).abs() / h_start,
        sim.time()
    );
    assert!((h_end - h_start).abs() / h_start < 1e-12);
    assert!((sim.time() - expected_time).abs() / expected_time < 1e-9);
}

#[test]
fn inelastic_column_settles_without_stalling() {
    let mut p = InitParams::<2>::in_box(1000, Vector::<2>::new(40.0, 200.0));
    p.seed = 4;
    p.placement = Placement::Random;
    p.temperature = 0.1;
    p.sim = Some(SimParams {
        gravity: 1.0,
        wall_epsilon: 0.8,
        wall_threshold: 0.05,
        ..SimParams::default()
    });
    let rule = Rule::new(ConstantRestitution::new(0.8).unwrap())
        .with_tc(0.01)
        .unwrap();
    let mut sim = p.build::<Column, _>(rule).unwrap();
    let mean_height =
        |s: &Simulation<2, Column, Rule>| s.positions().iter().map(|x| x[1]).sum::<f64>() / 1000.0;
    let (h0, u0) = (mean_height(&sim), sim.potential_energy());
    let start = std::time::Instant::now();
    // Free fall from the top takes √(2·200/g) = 20.
    let end = sim.run(Stop::Time(45.0));
    let secs = start.elapsed().as_secs_f64();
    let (h1, u1, k1) = (
        mean_height(&sim),
        sim.potential_energy(),
        sim.kinetic_energy(),
    );
    println!(
        "column: {end:?} at t = {:.1} after {} events ({secs:.2} s); mean height {h0:.1} -> {h1:.2}; potential {u0:.0} -> {u1:.0}, kinetic {k1:.3e}",
        sim.time(),
        sim.counters().events
    );
    assert_eq!(end, RunEnd::Reached, "collapse: {:?}", sim.collapse());
    assert!((sim.time() - 45.0).abs() < 1e-9);
    // Settled: a packed bed of 1000 disks 40 wide is about 1000·π/4/(40·0.8) ≈ 25σ high, so its
    // centre of mass sits near 12σ; the kinetic energy is a tiny fraction of what was released.
    assert!(h1 < 13.0, "mean height {h1}");
    assert!(
        k1 < 1e-2 * (u0 - u1),
        "kinetic {k1} vs released {}",
        u0 - u1
    );
    let (i, j, depth) = sim.deepest_overlap().unwrap();
    assert!(depth < 1e-9, "particles {i} and {j} overlap by {depth}");
}

#[test]
fn gravity_needs_a_gravity_scene_and_a_floor() {
    let parts = vec![ParticleInit {
        pos: Vector::<2>::new(5.0, 5.0),
        vel: Vector::<2>::zeros(),
        radius: 0.5,
        mass: 1.0,
    }];
    let params = SimParams {
        gravity: 1.0,
        ..SimParams::default()
    };
    let e = Simulation::<2, edmd_core::Walls, _>::new(
        Vector::<2>::new(10.0, 10.0),
        parts.clone(),
        Rule::new(ConstantRestitution::new(1.0).unwrap()),
        params,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("gravity = 1"), "{e}");
    let e = Simulation::<2, edmd_core::GravityAxes<0b01>, _>::new(
        Vector::<2>::new(10.0, 10.0),
        parts,
        Rule::new(ConstantRestitution::new(1.0).unwrap()),
        params,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("floor"), "{e}");
}

/// Heights of the centres of an elastic 2D column (periodic x, walls in y), gravity g, sampled every
/// 10 time units over [t_skip, t_end], and its mean temperature over the same samples.
fn column_heights(
    g: f64,
    floor_temperature: f64,
    t_end: f64,
) -> (Vec<Vec<f64>>, f64, usize, Vector<2>) {
    let (n, box_len) = (250, Vector::<2>::new(200.0, 120.0));
    let mut p = InitParams::<2>::in_box(n, box_len);
    p.seed = 11;
    p.placement = Placement::Random;
    p.sim = Some(SimParams {
        gravity: g,
        floor_temperature,
        cell_factor: 4.0,
        ..SimParams::default()
    });
    let mut sim = p
        .build::<Column, _>(Rule::new(ConstantRestitution::new(1.0).unwrap()))
        .unwrap();
    let (mut blocks, mut temps) = (vec![Vec::new(); 8], Vec::new());
    let t_skip = 0.1 * t_end;
    let mut t = t_skip;
    assert_eq!(sim.run(Stop::Time(t_skip)), RunEnd::Reached);
    while t < t_end {
        t += 10.0;
        assert_eq!(sim.run(Stop::Time(t)), RunEnd::Reached);
        let block = (((t - t_skip) / (t_end - t_skip)) * 8.0).min(7.0) as usize;
        blocks[block].extend(sim.positions().iter().map(|x| x[1]));
        temps.push(sim.temperature());
    }
    let temperature = temps.iter().sum::<f64>() / temps.len() as f64;
    (blocks, temperature, n, box_len)
}

/// Least-squares decay length 1/rate of ln(count) against height over bins of 2σ in [2, 60].
fn decay_length(heights: &[f64]) -> f64 {
    let bins = 29;
    let mut counts = vec![0.0; bins];
    for &z in heights {
        let b = ((z - 2.0) / 2.0).floor();
        if (0.0..bins as f64).contains(&b) {
            counts[b as usize] += 1.0;
        }
    }
    let xs: Vec<f64> = (0..bins).map(|b| 3.0 + 2.0 * b as f64).collect();
    let ys: Vec<f64> = counts.iter().map(|c: &f64| c.max(1.0).ln()).collect();
    1.0 / edmd_core::decay_rate(&xs, &ys)
}

/// The decay length of the theory's profile (the same bins and fit), for the column's temperature.
fn theory_decay_length(temperature: f64, g: f64, n: usize, box_len: Vector<2>) -> f64 {
    use edmd_core::theory::{barometric_floor, barometric_profile};
    let ell = temperature / g;
    // Centres live in [1/2, H − 1/2]; φ over that layer.
    let height = box_len[1] - 1.0;
    let mean = n as f64 * std::f64::consts::PI / 4.0 / (box_len[0] * height);
    let floor = barometric_floor(2, ell, mean, 0.0, height).unwrap();
    let z: Vec<f64> = (0..29).map(|b| 2.5 + 2.0 * b as f64).collect();
    let phi = barometric_profile(2, ell, floor, &z);
    let ys: Vec<f64> = phi.iter().map(|p| p.ln()).collect();
    1.0 / edmd_core::decay_rate(&z, &ys)
}

/// An elastic column settles into the barometric profile of its own temperature: the decay length of
/// the centres' height histogram (bins of 2σ over z ∈ [2, 60]) matches the local-Enskog hydrostatic
/// profile (`theory::barometric_profile`; the column warms from T = 1 to ≈ 3.6 as it settles, so
/// ℓ = T/(mg) ≈ 36; measured +0.8 %) within 3 %, the profile normalised to the column's N over its
/// height. The standard error from 8 blocks of the run is printed and must stay below 1 % (0.4 %).
/// Finite size: the floor's first layer (z < 2, where the wall orders the fluid) is left out; the
/// profile reaches the ceiling (H = 120 ≈ 3.3 ℓ) and is normalised over the whole height; the Enskog
/// correction is ≈ 5 % of ℓ (floor φ ≈ 0.027), so the dilute law alone would fail the test.
#[test]
fn elastic_column_is_barometric() {
    let g = 0.1;
    let (blocks, temperature, n, box_len) = column_heights(g, 0.0, 40_000.0);
    check_column(&blocks, temperature, g, n, box_len, "closed elastic column");
}

fn check_column(
    blocks: &[Vec<f64>],
    temperature: f64,
    g: f64,
    n: usize,
    box_len: Vector<2>,
    what: &str,
) {
    let all: Vec<f64> = blocks.iter().flatten().copied().collect();
    let measured = decay_length(&all);
    let per_block: Vec<f64> = blocks.iter().map(|b| decay_length(b)).collect();
    let m = per_block.iter().sum::<f64>() / 8.0;
    let se = (per_block.iter().map(|x| (x - m).powi(2)).sum::<f64>() / 7.0 / 8.0).sqrt();
    let theory = theory_decay_length(temperature, g, n, box_len);
    let dev = measured / theory - 1.0;
    println!(
        "{what}: T = {temperature:.4}, decay length {measured:.3} ± {se:.3} against {theory:.3} (dilute T/mg = {:.3}): {:+.2} %",
        temperature / g,
        100.0 * dev
    );
    assert!(se / theory < 0.01, "too noisy: {se}");
    assert!(
        dev.abs() < 0.03,
        "{what}: decay length {:.2} % from theory",
        100.0 * dev
    );
}

/// A thermal floor at T_f = 2 heats a column that starts at T = 1 into equilibrium with it: the mean
/// temperature after the first tenth of the run is T_f within 2 % (measured +0.5 %), and the profile
/// is barometric with ℓ = T_f/(mg) = 20 and the Enskog correction, within 3 % (measured +0.35 %).
#[test]
fn thermal_floor_heats_a_column_to_its_temperature() {
    let (g, t_floor) = (0.1, 2.0);
    let (blocks, temperature, n, box_len) = column_heights(g, t_floor, 40_000.0);
    println!("thermal floor {t_floor}: mean temperature {temperature:.4}");
    assert!(
        (temperature / t_floor - 1.0).abs() < 0.02,
        "T = {temperature}"
    );
    check_column(&blocks, t_floor, g, n, box_len, "column on a thermal floor");
}
