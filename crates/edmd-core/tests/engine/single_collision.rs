//! One oblique collision of unequal particles, for every rule: momentum is conserved to round-off and
//! the kinetic energy drops by exactly (1 − ε²) μ g_n² / 2, with ε computed here by hand from each
//! law's definition at the measured normal speed. Also walls with their own restitution.

use edmd_core::{
    Boundary, CollisionRule, ConstantRestitution, EventKind, ParticleInit, Periodic, Rule,
    SimParams, Simulation, ThesisRestitution, ThresholdRestitution, Vector, Viscoelastic, Walls,
};

/// Two unequal particles on course for an oblique collision, and their velocities.
fn two_particles<const D: usize>() -> (Vec<ParticleInit<D>>, Vector<D>, Vector<D>) {
    let mut a = Vector::<D>::repeat(5.0);
    let mut b = Vector::<D>::repeat(5.2);
    a[0] = 3.0;
    b[0] = 5.5;
    let mut va = Vector::<D>::zeros();
    va[0] = 1.0;
    va[1] = 0.3;
    let mut vb = Vector::<D>::zeros();
    vb[0] = -0.5;
    let parts = vec![
        ParticleInit {
            pos: a,
            vel: va,
            radius: 0.5,
            mass: 1.0,
        },
        ParticleInit {
            pos: b,
            vel: vb,
            radius: 0.7,
            mass: 1.96,
        },
    ];
    (parts, va, vb)
}

struct Outcome {
    gn: f64,
    m_eff: f64,
    r_eff: f64,
    energy_loss: f64,
    momentum_error: f64,
}

fn collide_once<const D: usize, R: CollisionRule>(rule: R) -> Outcome {
    let (parts, va, vb) = two_particles::<D>();
    let mut sim = Simulation::<D, Periodic, R>::new(
        Vector::<D>::repeat(10.0),
        parts.clone(),
        rule,
        SimParams::default(),
    )
    .unwrap();
    let (e0, p0) = (sim.kinetic_energy(), sim.observe().momentum);
    loop {
        if let EventKind::Collision(..) = sim.step().unwrap() {
            break;
        }
    }
    let pos = sim.positions();
    let mut dr = pos[0] - pos[1];
    for a in 0..D {
        dr[a] -= 10.0 * (dr[a] / 10.0).round();
    }
    let gn = (va - vb).dot(&dr) / dr.norm();
    let m_eff = 1.0 * 1.96 / 2.96;
    let o = sim.observe();
    Outcome {
        gn,
        m_eff,
        r_eff: 0.5 * 0.7 / 1.2,
        energy_loss: e0 - o.kinetic_energy,
        momentum_error: (o.momentum - p0).norm() / o.momentum_scale,
    }
}

fn check<const D: usize, R: CollisionRule>(
    rule: R,
    epsilon_by_hand: impl Fn(f64, f64, f64) -> f64,
    label: &str,
) {
    let o = collide_once::<D, R>(rule);
    assert!(o.gn < 0.0);
    let eps = epsilon_by_hand(-o.gn, o.m_eff, o.r_eff);
    let expected = 0.5 * (1.0 - eps * eps) * o.m_eff * o.gn * o.gn;
    println!(
        "{label} (D = {D}): g_n = {:.6}, eps = {eps:.6}, energy loss {:.12} (law {expected:.12})",
        o.gn, o.energy_loss
    );
    assert!(
        (o.energy_loss - expected).abs() < 1e-13,
        "{label}: lost {} instead of {expected}",
        o.energy_loss
    );
    assert!(
        o.momentum_error < 1e-15,
        "{label}: momentum error {}",
        o.momentum_error
    );
}

fn all_rules<const D: usize>() {
    check::<D, _>(
        Rule::new(ConstantRestitution::new(0.8).unwrap()),
        |_, _, _| 0.8,
        "constant 0.8",
    );
    check::<D, _>(
        Rule::new(ConstantRestitution::new(0.0).unwrap()),
        |_, _, _| 0.0,
        "constant 0",
    );
    // The normal speed here is about 1.4: a threshold above it applies eps_low, one below applies eps.
    check::<D, _>(
        Rule::new(ThresholdRestitution::new(0.6, 0.95, 5.0).unwrap()),
        |_, _, _| 0.95,
        "threshold (slow)",
    );
    check::<D, _>(
        Rule::new(ThresholdRestitution::new(0.6, 0.95, 0.1).unwrap()),
        |_, _, _| 0.6,
        "threshold (fast)",
    );
    check::<D, _>(
        Rule::new(ThesisRestitution::new(0.95, 0.3).unwrap()),
        |v, _, _| 0.95 * (v / 0.3).powf(-0.25),
        "thesis eq. 5.1",
    );
    check::<D, _>(
        Rule::new(ThesisRestitution::new(0.95, 3.0).unwrap()),
        |v, _, _| 1.0 - 0.05 * (v / 3.0).powf(0.2),
        "thesis eq. 5.1, slow branch",
    );
    let (young, poisson, a) = (1e4, 0.3, 1e-3);
    check::<D, _>(
        Rule::new(Viscoelastic::from_material(young, poisson, a).unwrap()),
        |v, m, r| {
            let rho = 2.0 * young / (3.0 * (1.0 - poisson * poisson)) * r.sqrt();
            let kappa = 1.5f64.powf(2.5) * rho / m;
            let x = a * kappa.powf(0.4) * v.powf(0.2);
            // C₁ = Γ(3/5)√π / (2^{1/5} 5^{2/5} Γ(21/10)), C₂ = (3/5)C₁².
            let c1 = 1.489_192_248_812_816_9 * std::f64::consts::PI.sqrt()
                / (2f64.powf(0.2) * 5f64.powf(0.4) * 1.046_485_846_853_560_7);
            1.0 - c1 * x + 0.6 * c1 * c1 * x * x
        },
        "viscoelastic",
    );
}

/// Post-collision relative velocity of the pair (same set-up as `collide_once`).
fn relative_after<const D: usize, R: CollisionRule>(rule: R, seed: u64) -> Vector<D> {
    let (parts, _, _) = two_particles::<D>();
    let params = SimParams {
        seed,
        ..SimParams::default()
    };
    let mut sim =
        Simulation::<D, Periodic, R>::new(Vector::<D>::repeat(10.0), parts, rule, params).unwrap();
    loop {
        if let EventKind::Collision(..) = sim.step().unwrap() {
            break;
        }
    }
    let v = sim.velocities();
    v[0] - v[1]
}

/// Random rotation (alone and in the thesis's combination with a threshold): energy and momentum are
/// those of the underlying law; the relative velocity turns by at most θ_max, and by more than zero.
fn rotations<const D: usize>() {
    let theta = 10f64.to_radians();
    check::<D, _>(
        Rule::new(ConstantRestitution::new(0.8).unwrap())
            .with_rotation(theta)
            .unwrap(),
        |_, _, _| 0.8,
        "rotation + constant",
    );
    check::<D, _>(
        Rule::new(ThresholdRestitution::new(0.6, 0.95, 5.0).unwrap())
            .with_rotation(theta)
            .unwrap(),
        |_, _, _| 0.95,
        "rotation + threshold (thesis)",
    );
    let mut turned = Vec::new();
    for seed in 0..20 {
        let g_plain =
            relative_after::<D, _>(Rule::new(ConstantRestitution::new(0.8).unwrap()), seed);
        let g_rot = relative_after::<D, _>(
            Rule::new(ConstantRestitution::new(0.8).unwrap())
                .with_rotation(theta)
                .unwrap(),
            seed,
        );
        assert!((g_rot.norm() - g_plain.norm()).abs() < 1e-14);
        let angle = (g_rot.dot(&g_plain) / (g_rot.norm() * g_plain.norm()))
            .clamp(-1.0, 1.0)
            .acos();
        assert!(
            angle <= theta + 1e-12,
            "turned by {} degrees",
            angle.to_degrees()
        );
        turned.push(angle);
    }
    let mean = turned.iter().sum::<f64>() / turned.len() as f64;
    println!(
        "D = {D}: mean rotation {:.2} degrees (uniform in [0, 10]: 5)",
        mean.to_degrees()
    );
    assert!(mean > 0.2 * theta && mean < 0.8 * theta);
}

#[test]
fn random_rotation_conserves_and_turns_2d() {
    rotations::<2>();
}

#[test]
fn random_rotation_conserves_and_turns_3d() {
    rotations::<3>();
}

#[test]
fn every_rule_dissipates_what_its_law_says_2d() {
    all_rules::<2>();
}

#[test]
fn every_rule_dissipates_what_its_law_says_3d() {
    all_rules::<3>();
}

fn bounce<B: Boundary>(wall_epsilon: f64) -> (f64, f64) {
    let parts = vec![ParticleInit {
        pos: Vector::<2>::new(5.0, 5.0),
        vel: Vector::<2>::new(1.0, 0.0),
        radius: 0.5,
        mass: 1.0,
    }];
    let params = SimParams {
        wall_epsilon,
        ..SimParams::default()
    };
    let mut sim = Simulation::<2, B, Rule>::new(
        Vector::<2>::new(10.0, 10.0),
        parts,
        Rule::new(ConstantRestitution::new(0.5).unwrap()),
        params,
    )
    .unwrap();
    let e0 = sim.kinetic_energy();
    while sim.counters().wall_collisions < 3 {
        sim.step().unwrap();
    }
    (e0, sim.kinetic_energy())
}

#[test]
fn walls_have_their_own_restitution() {
    let (e0, e3) = bounce::<Walls>(0.9);
    assert!((e3 / e0 - 0.9f64.powi(6)).abs() < 1e-14, "{}", e3 / e0);
    let (e0, e3) = bounce::<Walls>(1.0);
    assert_eq!(e0, e3);
    let e = Simulation::<2, Walls, Rule>::new(
        Vector::<2>::new(10.0, 10.0),
        vec![],
        Rule::new(ConstantRestitution::new(0.5).unwrap()),
        SimParams {
            wall_epsilon: 1.2,
            ..SimParams::default()
        },
    );
    assert!(e.is_err());
    let bad = SimParams {
        wall_epsilon: 1.2,
        ..SimParams::default()
    };
    let parts = vec![ParticleInit {
        pos: Vector::<2>::new(5.0, 5.0),
        vel: Vector::<2>::new(1.0, 0.0),
        radius: 0.5,
        mass: 1.0,
    }];
    let msg = Simulation::<2, Walls, Rule>::new(
        Vector::<2>::new(10.0, 10.0),
        parts,
        Rule::new(ConstantRestitution::new(0.5).unwrap()),
        bad,
    )
    .unwrap_err()
    .to_string();
    assert!(msg.contains("wall_epsilon = 1.2"), "{msg}");
}
