//! Inelastic collapse (PHYSICS.md §6): detected, not endless; prevented by the TC model; and the 1D
//! three-particle threshold ε = 7 − 4√3 reproduced.

use edmd_core::{
    Collapse, ConstantRestitution, EventKind, InitParams, ParticleInit, Periodic, Rule, RunEnd,
    SimParams, Simulation, Stop, Vector, Walls,
};

#[test]
fn dense_strongly_inelastic_gas_collapses_and_the_run_ends() {
    let mut p = InitParams::<2>::with_packing(4096, 0.5).unwrap();
    p.seed = 1;
    let mut sim = p
        .build::<Periodic, _>(Rule::new(ConstantRestitution::new(0.3).unwrap()))
        .unwrap();
    let start = std::time::Instant::now();
    let end = sim.run(Stop::Tau(500.0));
    let c: Collapse = sim.collapse().expect("collapse detected");
    println!(
        "collapsed at tau = {:.1}, t = {:.4e} ({:?}) after {:.2} s",
        c.tau,
        c.time,
        c.reason,
        start.elapsed().as_secs_f64()
    );
    assert_eq!(end, RunEnd::Collapsed);
    assert!(c.tau < 500.0);
    // A collapsed simulation stays stopped.
    assert_eq!(sim.run(Stop::Tau(1000.0)), RunEnd::Collapsed);
}

#[test]
fn tc_model_prevents_the_collapse() {
    let mut p = InitParams::<2>::with_packing(4096, 0.5).unwrap();
    p.seed = 1;
    // t_c = 1e-4 mean free times at T0 = 1 (the mean free time at φ = 0.5 is 1/ν ≈ 0.14).
    let rule = Rule::new(ConstantRestitution::new(0.3).unwrap())
        .with_tc(1.4e-5)
        .unwrap();
    let mut sim = p.build::<Periodic, _>(rule).unwrap();
    let end = sim.run(Stop::Tau(500.0));
    println!(
        "TC model: {end:?} at tau = {:.1}, T/T0 = {:.3e}",
        sim.tau(),
        sim.temperature()
    );
    assert_eq!(end, RunEnd::Reached, "collapse: {:?}", sim.collapse());
    assert!(sim.deepest_overlap().unwrap().2 < 1e-9);
}

/// Three disks on a line between walls: 1 and 3 approach the resting 2. Below ε = 7 − 4√3 ≈ 0.0718
/// the sequence of collisions never ends (collapse); above it ends after finitely many.
fn three_particle_collisions(eps: f64) -> (usize, bool) {
    let y = 5.0;
    let parts = vec![
        ParticleInit {
            pos: Vector::<2>::new(3.0, y),
            vel: Vector::<2>::new(1.0, 0.0),
            radius: 0.5,
            mass: 1.0,
        },
        ParticleInit {
            pos: Vector::<2>::new(5.0, y),
            vel: Vector::<2>::zeros(),
            radius: 0.5,
            mass: 1.0,
        },
        ParticleInit {
            pos: Vector::<2>::new(7.3, y),
            vel: Vector::<2>::new(-1.0, 0.0),
            radius: 0.5,
            mass: 1.0,
        },
    ];
    let mut sim = Simulation::<2, Walls, _>::new(
        Vector::<2>::new(40.0, 10.0),
        parts,
        Rule::new(ConstantRestitution::new(eps).unwrap()),
        SimParams::default(),
    )
    .unwrap();
    let mut collisions = 0;
    loop {
        match sim.step() {
            Some(EventKind::Collision(..)) => collisions += 1,
            // The first wall contact means the three have separated for good.
            Some(EventKind::Wall(_)) | None => return (collisions, false),
            Some(_) => {}
        }
        if sim.collapse().is_some() {
            return (collisions, true);
        }
        if collisions > 1_000_000 {
            return (collisions, true);
        }
    }
}

#[test]
fn three_particle_collapse_threshold() {
    let threshold = 7.0 - 4.0 * 3f64.sqrt();
    for eps in [0.03, 0.06, 0.07, 0.0715] {
        let (n, collapsed) = three_particle_collisions(eps);
        println!("eps = {eps}: {n} collisions, collapsed = {collapsed}");
        assert!(
            collapsed,
            "eps = {eps} < {threshold} must collapse ({n} collisions)"
        );
    }
    for eps in [0.0722, 0.075, 0.1, 0.3] {
        let (n, collapsed) = three_particle_collisions(eps);
        println!("eps = {eps}: {n} collisions, collapsed = {collapsed}");
        assert!(
            !collapsed,
            "eps = {eps} > {threshold} must not collapse ({n} collisions)"
        );
    }
}
