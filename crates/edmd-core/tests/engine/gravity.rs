//! Uniform gravity with a floor: a ball on an elastic floor keeps its height over 10^6 bounces, and a
//! column of 1000 inelastic disks settles on the floor without stalling: the TC model (t_c = 0.01)
//! keeps the pile from collapsing and a threshold on wall contacts keeps grains resting on the floor
//! from bouncing ever faster. (A settled pile still costs many events per unit time: its gaps are
//! tiny. That is inherent to event-driven dynamics of static packings.)

use edmd_core::{
    Column, ConstantRestitution, Container, InitParams, ParticleInit, Placement, RunEnd, SimParams,
    Simulation, Stop, TcModel, Vector,
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
        ConstantRestitution::new(0.5).unwrap(),
        params,
    )
    .unwrap();
    let energy = |s: &Simulation<2, Container, ConstantRestitution>| {
        s.kinetic_energy() + s.potential_energy()
    };
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
    let rule = TcModel::new(ConstantRestitution::new(0.8).unwrap(), 0.01).unwrap();
    let mut sim = p.build::<Column, _>(rule).unwrap();
    let mean_height = |s: &Simulation<2, Column, TcModel<ConstantRestitution>>| {
        s.positions().iter().map(|x| x[1]).sum::<f64>() / 1000.0
    };
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
        ConstantRestitution::new(1.0).unwrap(),
        params,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("gravity = 1"), "{e}");
    let e = Simulation::<2, edmd_core::GravityAxes<0b01>, _>::new(
        Vector::<2>::new(10.0, 10.0),
        parts,
        ConstantRestitution::new(1.0).unwrap(),
        params,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("floor"), "{e}");
}
