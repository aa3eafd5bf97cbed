//! No pair ever overlaps by more than 1e-9 of its contact distance, checked every 10^4 events, in
//! every scene: dense (φ = 0.7) elastic disks, strongly inelastic (ε = 0.3) gases, walls, channels,
//! spheres and polydisperse disks.

use edmd_core::{
    Boundary, Channel, CollisionRule, ConstantRestitution, Elastic, InitParams, Periodic,
    Placement, Rule, RunEnd, SimParams, Simulation, Stop, ThresholdRestitution, Walls,
};

fn check<const D: usize, B: Boundary, R: CollisionRule>(
    mut sim: Simulation<D, B, R>,
    events: u64,
    label: &str,
) {
    let mut worst = f64::NEG_INFINITY;
    for _ in 0..events / 10_000 {
        if sim.run(Stop::Events(10_000)) != RunEnd::Reached {
            println!("{label}: run ended early ({:?})", sim.collapse());
            break;
        }
        let (i, j, depth) = sim.deepest_overlap().unwrap();
        worst = worst.max(depth);
        assert!(
            depth < 1e-9,
            "{label}: particles {i} and {j} overlap by {depth:e} at tau = {}",
            sim.tau()
        );
    }
    println!(
        "{label}: deepest overlap {worst:.2e} after {events} events, tau = {:.1}",
        sim.tau()
    );
}

fn eps(e: f64) -> Rule {
    Rule::new(ConstantRestitution::new(e).unwrap())
}

#[test]
fn dense_elastic_disks_phi_0_7() {
    let p = InitParams::<2>::with_packing(2000, 0.7).unwrap();
    check(
        p.build::<Periodic, _>(Elastic).unwrap(),
        300_000,
        "2D periodic phi=0.7 elastic",
    );
    check(
        p.build::<Walls, _>(Elastic).unwrap(),
        300_000,
        "2D walls phi=0.7 elastic",
    );
}

#[test]
fn strongly_inelastic_gases() {
    let p = InitParams::<2>::with_packing(2000, 0.5).unwrap();
    check(
        p.build::<Periodic, _>(eps(0.3)).unwrap(),
        300_000,
        "2D periodic phi=0.5 eps=0.3",
    );
    let p = InitParams::<2>::with_packing(2000, 0.3).unwrap();
    check(
        p.build::<Channel, _>(eps(0.3)).unwrap(),
        300_000,
        "2D channel phi=0.3 eps=0.3",
    );
    check(
        p.build::<Walls, _>(eps(0.0)).unwrap(),
        200_000,
        "2D walls phi=0.3 eps=0",
    );
    let p = InitParams::<3>::with_packing(2000, 0.45).unwrap();
    check(
        p.build::<Periodic, _>(eps(0.3)).unwrap(),
        300_000,
        "3D periodic phi=0.45 eps=0.3",
    );
    check(
        p.build::<Walls, _>(eps(0.3)).unwrap(),
        300_000,
        "3D walls phi=0.45 eps=0.3",
    );
}

#[test]
fn random_rotation_remedy() {
    let p = InitParams::<2>::with_packing(2000, 0.5).unwrap();
    let rule = Rule::new(ThresholdRestitution::new(0.5, 1.0, 1e-3).unwrap())
        .with_rotation(5f64.to_radians())
        .unwrap();
    check(
        p.build::<Periodic, _>(rule).unwrap(),
        300_000,
        "2D periodic phi=0.5, threshold + rotation",
    );
    let p = InitParams::<3>::with_packing(2000, 0.3).unwrap();
    let rule = Rule::new(ConstantRestitution::new(0.5).unwrap())
        .with_rotation(10f64.to_radians())
        .unwrap();
    check(
        p.build::<Walls, _>(rule).unwrap(),
        300_000,
        "3D walls phi=0.3, eps=0.5 + rotation",
    );
}

#[test]
fn neighbour_lists() {
    let mut p = InitParams::<2>::with_packing(2000, 0.7).unwrap();
    p.sim = Some(SimParams {
        neighbour_skin: 0.5,
        ..SimParams::for_density::<2>(0.7)
    });
    let sim = p.build::<Walls, _>(eps(0.6)).unwrap();
    assert!(sim.uses_neighbour_lists());
    check(sim, 300_000, "2D walls phi=0.7 eps=0.6, neighbour lists");
    let n = 2000;
    let mut p = InitParams::<3>::with_packing(n, 0.25).unwrap();
    p.radii = Some((0..n).map(|i| 0.25 + 0.25 * (i % 5) as f64 / 4.0).collect());
    p.placement = Placement::Random;
    p.sim = Some(SimParams {
        neighbour_skin: 0.3,
        ..SimParams::for_density::<3>(0.25)
    });
    let sim = p.build::<Periodic, _>(eps(0.5)).unwrap();
    assert!(sim.uses_neighbour_lists());
    check(sim, 300_000, "3D polydisperse eps=0.5, neighbour lists");
}

#[test]
fn polydisperse_disks() {
    let n = 2000;
    let mut p = InitParams::<2>::with_packing(n, 0.3).unwrap();
    p.radii = Some((0..n).map(|i| 0.2 + 0.3 * (i % 7) as f64 / 6.0).collect());
    p.placement = Placement::Random;
    check(
        p.build::<Periodic, _>(eps(0.7)).unwrap(),
        300_000,
        "2D polydisperse eps=0.7",
    );
}

/// `deepest_overlap` (cells, pre-test without the root) against every pair with its nearest image,
/// after enough events to mix the slots: the same depth, and a pair that has it.
fn matches_all_pairs<const D: usize, B: Boundary>(p: InitParams<D>, label: &str) {
    let mut sim = p.build::<B, _>(eps(0.8)).unwrap();
    sim.run(Stop::Events(20_000));
    let pos = sim.positions();
    let sigma = 2.0 * p.radius;
    let l = *sim.box_len();
    let depth_of = |i: usize, j: usize| {
        let mut dr = pos[i] - pos[j];
        for a in 0..D {
            if !B::is_wall(a) {
                dr[a] -= l[a] * (dr[a] / l[a]).round();
            }
        }
        (sigma - dr.norm()) / sigma
    };
    let mut want = f64::NEG_INFINITY;
    for i in 0..pos.len() {
        for j in i + 1..pos.len() {
            want = want.max(depth_of(i, j));
        }
    }
    let (i, j, got) = sim.deepest_overlap().unwrap();
    assert_eq!(got, want, "{label}");
    assert_eq!(depth_of(i, j), want, "{label}: pair ({i}, {j})");
}

#[test]
fn deepest_overlap_matches_all_pairs() {
    matches_all_pairs::<2, Periodic>(InitParams::with_packing(600, 0.5).unwrap(), "2D periodic");
    matches_all_pairs::<2, Walls>(InitParams::with_packing(600, 0.3).unwrap(), "2D walls");
    matches_all_pairs::<3, Periodic>(InitParams::with_packing(700, 0.45).unwrap(), "3D periodic");
    matches_all_pairs::<3, Channel>(InitParams::with_packing(700, 0.2).unwrap(), "3D channel");
}
