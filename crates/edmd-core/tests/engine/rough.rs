//! Rough particles (the thesis's eq. 1.15): one oblique collision of unequal, spinning particles, in 2D
//! and 3D, for β = −1, 0, 1/2, 1. Checked against values computed here by hand from the law: linear
//! and angular momentum (orbital + spin) are conserved, the energy (translational + rotational) drops
//! by (1 − ε²) μ g_n²/2 + (1 − β²) μ_t g_t²/2 with g_t the tangential velocity of the contact points,
//! the new spins are ω_i − R_i (n × P_t)/I_i with P_t = −(1 + β) μ_t g_t; β = −1 leaves spins alone
//! and ε = β = 1 conserves energy.

use edmd_core::{
    ConstantRestitution, EventKind, ParticleInit, Periodic, Rough, Rule, SimParams, Simulation,
    Vector,
};

const R: [f64; 2] = [0.5, 0.7];
const M: [f64; 2] = [1.0, 1.96];

type Sim<const D: usize> = Simulation<D, Periodic, Rule<Rough>>;

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn pad<const D: usize>(v: &Vector<D>) -> [f64; 3] {
    let mut o = [0.0; 3];
    for a in 0..D {
        o[a] = v[a];
    }
    o
}

fn angular<const D: usize>(x: &[Vector<D>], v: &[Vector<D>], w: &[[f64; 3]], q: f64) -> [f64; 3] {
    let mut l = [0.0; 3];
    for k in 0..2 {
        let orbital = cross(pad(&x[k]), pad(&v[k]));
        for a in 0..3 {
            l[a] += M[k] * orbital[a] + q * M[k] * R[k] * R[k] * w[k][a];
        }
    }
    l
}

fn check<const D: usize>(eps: f64, beta: f64, q: f64, spin0: [[f64; 3]; 2]) {
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
            radius: R[0],
            mass: M[0],
        },
        ParticleInit {
            pos: b,
            vel: vb,
            radius: R[1],
            mass: M[1],
        },
    ];
    let rule = Rule::new(ConstantRestitution::new(eps).unwrap())
        .rough(beta, q)
        .unwrap();
    let mut sim =
        Sim::<D>::new(Vector::<D>::repeat(20.0), parts, rule, SimParams::default()).unwrap();
    sim.set_spin(0, spin0[0]);
    sim.set_spin(1, spin0[1]);
    let e0 = sim.kinetic_energy() + sim.rotational_energy();
    let (v0, w0) = (sim.velocities(), sim.spins());
    loop {
        if let EventKind::Collision(..) = sim.step().unwrap() {
            break;
        }
    }
    let (x, v1, w1) = (sim.positions(), sim.velocities(), sim.spins());
    // Angular momentum about the origin, before and after, at the contact configuration.
    let (l0, l1) = (angular(&x, &v0, &w0, q), angular(&x, &v1, &w1, q));
    let mut dr = x[0] - x[1];
    for k in 0..D {
        dr[k] -= 20.0 * (dr[k] / 20.0).round();
    }
    let n = pad(&(dr / dr.norm()));
    let g = pad(&(v0[0] - v0[1]));
    let arm = [
        R[0] * w0[0][0] + R[1] * w0[1][0],
        R[0] * w0[0][1] + R[1] * w0[1][1],
        R[0] * w0[0][2] + R[1] * w0[1][2],
    ];
    let spin_part = cross(arm, n);
    let gc = [
        g[0] - spin_part[0],
        g[1] - spin_part[1],
        g[2] - spin_part[2],
    ];
    let gn = gc[0] * n[0] + gc[1] * n[1] + gc[2] * n[2];
    let gt = [gc[0] - gn * n[0], gc[1] - gn * n[1], gc[2] - gn * n[2]];
    let mu = M[0] * M[1] / (M[0] + M[1]);
    let mu_t = 1.0 / (1.0 / M[0] + 1.0 / M[1] + 1.0 / (q * M[0]) + 1.0 / (q * M[1]));
    let gt2 = gt[0] * gt[0] + gt[1] * gt[1] + gt[2] * gt[2];
    let expected_loss =
        0.5 * (1.0 - eps * eps) * mu * gn * gn + 0.5 * (1.0 - beta * beta) * mu_t * gt2;
    let loss = e0 - (sim.kinetic_energy() + sim.rotational_energy());
    let pt = [
        -(1.0 + beta) * mu_t * gt[0],
        -(1.0 + beta) * mu_t * gt[1],
        -(1.0 + beta) * mu_t * gt[2],
    ];
    let np = cross(n, pt);
    let dp = (v1[0] * M[0] + v1[1] * M[1]) - (v0[0] * M[0] + v0[1] * M[1]);
    let dl = ((l1[0] - l0[0]).powi(2) + (l1[1] - l0[1]).powi(2) + (l1[2] - l0[2]).powi(2)).sqrt();
    println!("D = {D}, eps = {eps}, beta = {beta}: loss {loss:.12} (law {expected_loss:.12}), |dP| = {:.1e}, |dL| = {dl:.1e}", dp.norm());
    assert!(
        (loss - expected_loss).abs() < 1e-13,
        "energy loss {loss} vs {expected_loss}"
    );
    assert!(dp.norm() < 1e-14 && dl < 1e-13);
    for k in 0..2 {
        let ii = q * M[k] * R[k] * R[k];
        for c in 0..3 {
            let hand = w0[k][c] - R[k] * np[c] / ii;
            assert!(
                (w1[k][c] - hand).abs() < 1e-13,
                "spin {k}[{c}] {} vs {hand}",
                w1[k][c]
            );
        }
    }
    if beta == -1.0 {
        assert_eq!(w1, w0);
    }
}

#[test]
fn rough_collisions_follow_the_law_2d() {
    for (eps, beta) in [(0.8, -1.0), (0.8, 0.0), (0.5, 0.5), (0.8, 1.0), (1.0, 1.0)] {
        check::<2>(eps, beta, 0.5, [[0.0, 0.0, 0.7], [0.0, 0.0, -1.3]]);
    }
}

#[test]
fn rough_collisions_follow_the_law_3d() {
    for (eps, beta) in [(0.8, -1.0), (0.8, 0.0), (0.5, 0.5), (0.8, 1.0), (1.0, 1.0)] {
        check::<3>(eps, beta, 0.4, [[0.3, -0.2, 0.7], [1.1, 0.4, -1.3]]);
    }
}

#[test]
fn smooth_rules_carry_no_spin() {
    assert_eq!(
        std::mem::size_of::<<ConstantRestitution as edmd_core::CollisionRule>::State>(),
        0
    );
}

/// A gas of perfectly rough, elastic disks (ε = β = 1) conserves translational + rotational energy
/// over 10^6 collisions, and a rough inelastic gas never overlaps.
#[test]
fn rough_gases() {
    use edmd_core::{InitParams, Stop};
    let p = InitParams::<2>::with_packing(2000, 0.3).unwrap();
    let mut sim = p
        .build::<Periodic, _>(
            Rule::new(ConstantRestitution::new(1.0).unwrap())
                .rough(1.0, 0.5)
                .unwrap(),
        )
        .unwrap();
    let e0 = sim.kinetic_energy() + sim.rotational_energy();
    sim.run(Stop::Tau(500.0));
    let e1 = sim.kinetic_energy() + sim.rotational_energy();
    println!(
        "rough elastic: |dE/E| = {:.2e}, rotational share {:.3}",
        ((e1 - e0) / e0).abs(),
        sim.rotational_energy() / e1
    );
    assert!(((e1 - e0) / e0).abs() < 1e-10);
    // Equipartition: the rotational degree of freedom takes its share (1/3 in 2D).
    assert!((sim.rotational_energy() / e1 - 1.0 / 3.0).abs() < 0.03);
    let mut sim = p
        .build::<Periodic, _>(
            Rule::new(ConstantRestitution::new(0.7).unwrap())
                .rough(0.0, 0.5)
                .unwrap(),
        )
        .unwrap();
    sim.run(Stop::Tau(100.0));
    assert!(sim.deepest_overlap().unwrap().2 < 1e-9);
}
