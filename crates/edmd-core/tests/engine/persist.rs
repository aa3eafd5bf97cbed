//! A simulation saved between two events and loaded into another built from the same parameters
//! (but another seed, so that nothing is shared by chance) goes on bit for bit as the saved one:
//! cells and lists, walls, a sheared box, rough grains with the TC memory, deep cooling's rescales,
//! the white-noise thermostat's clock and random stream.

use edmd_core::{
    Boundary, CollisionRule, ConstantRestitution, InitParams, Periodic, Rule, SimParams,
    Simulation, Stop, Vector, Walls,
};

use crate::lees_edwards::build as build_sheared;

/// Runs `a` `first` events, saves it, loads the state into `b`, runs both `then` more events and
/// compares everything a run reports, bit for bit.
fn continues_identically<const D: usize, B: Boundary, R: CollisionRule>(
    mut a: Simulation<D, B, R>,
    mut b: Simulation<D, B, R>,
    first: u64,
    then: u64,
) {
    a.run(Stop::Events(first));
    let saved = a.save_state();
    assert_ne!(
        b.positions(),
        a.positions(),
        "the loader must start elsewhere"
    );
    b.load_state(&saved).expect("same parameters");
    assert_eq!(b.save_state(), saved, "a loaded state saves as it was");
    a.run(Stop::Events(then));
    b.run(Stop::Events(then));
    assert_eq!(a.counters(), b.counters());
    assert_eq!(a.time().to_bits(), b.time().to_bits());
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.velocities(), b.velocities());
    assert_eq!(a.spins(), b.spins());
    assert_eq!(a.collapse(), b.collapse());
    assert_eq!(a.save_state(), b.save_state());
}

fn build<const D: usize, B: Boundary, R: CollisionRule>(
    n: usize,
    phi: f64,
    skin: Option<f64>,
    seed: u64,
    rule: R,
) -> Simulation<D, B, R> {
    let mut p = InitParams::<D>::with_packing(n, phi).unwrap();
    p.seed = seed;
    if let Some(skin) = skin {
        p.sim = Some(SimParams {
            neighbour_skin: skin,
            ..SimParams::for_density::<D>(phi)
        });
    }
    p.build::<B, R>(rule).unwrap()
}

#[test]
fn a_loaded_state_goes_on_bit_for_bit_in_cells_and_lists() {
    let eps = ConstantRestitution::new(0.8).unwrap();
    let cells = |seed| build::<2, Periodic, _>(600, 0.3, Some(0.0), seed, eps);
    continues_identically(cells(1), cells(2), 37_001, 60_000);
    let lists = |seed| build::<3, Walls, _>(500, 0.35, Some(0.3), seed, eps);
    assert!(lists(1).uses_neighbour_lists());
    continues_identically(lists(1), lists(2), 41_003, 60_000);
}

#[test]
fn a_loaded_state_goes_on_bit_for_bit_sheared_and_rough() {
    let rough = Rule::new(ConstantRestitution::new(0.7).unwrap())
        .with_tc(1e-4)
        .unwrap()
        .rough(0.4, 0.5)
        .unwrap();
    let sheared = |seed| build_sheared::<2, _>(500, 0.3, 0.5, seed, rough);
    continues_identically(sheared(1), sheared(2), 29_999, 60_000);
}

#[test]
fn a_loaded_state_goes_on_bit_for_bit_through_deep_cooling() {
    let cooling = |seed| {
        let mut p = InitParams::<2>::in_box(183, Vector::<2>::new(24.0, 24.0));
        p.seed = seed;
        p.build::<Periodic, _>(Rule::new(ConstantRestitution::new(0.9).unwrap()))
            .unwrap()
    };
    let mut a = cooling(3);
    a.run(Stop::Tau(150.0));
    let rescales = a.counters().rescales;
    continues_identically(a, cooling(4), 1_001, 200_000);
    assert!(rescales > 0);
}

#[test]
fn a_loaded_state_goes_on_bit_for_bit_under_white_noise() {
    let driven = |seed| {
        let mut p = InitParams::<3>::with_packing(400, 0.1).unwrap();
        p.seed = seed;
        p.sim = Some(SimParams {
            white_noise: 0.5,
            kick_interval: 0.3,
            ..p.default_sim_params()
        });
        p.build::<Periodic, _>(Rule::new(ConstantRestitution::new(0.8).unwrap()))
            .unwrap()
    };
    let mut a = driven(5);
    a.run(Stop::Events(30_000));
    let kicks = a.counters().system_events;
    continues_identically(a, driven(6), 7_777, 60_000);
    assert!(kicks > 0);
}

#[test]
fn a_state_of_another_system_is_refused() {
    let eps = ConstantRestitution::new(0.8).unwrap();
    let a = build::<2, Periodic, _>(600, 0.3, Some(0.0), 1, eps);
    let mut other_n = build::<2, Periodic, _>(500, 0.3, Some(0.0), 1, eps);
    let e = other_n.load_state(&a.save_state()).unwrap_err();
    assert!(e.to_string().contains("600 particles"), "{e}");
    let mut other_phi = build::<2, Periodic, _>(600, 0.2, Some(0.0), 1, eps);
    assert!(other_phi.load_state(&a.save_state()).is_err());
    assert!(other_phi.load_state(&a.save_state()[..100]).is_err());
    assert!(other_phi.load_state(&[7, 1, 2]).is_err());
}
