//! The engine's event counters (`Counters`) against a tally of what `step` returned, event by
//! event: each kind counted once and nothing else counted, in cell and list mode, with walls, in a
//! sheared box (its system events), and through deep cooling (rescales and restarts).

use edmd_core::{
    Boundary, ConstantRestitution, Counters, EventKind, InitParams, Periodic, Rule, SimParams,
    Simulation, Stop, Vector, Walls,
};

use crate::lees_edwards::build;

/// Events by kind as `step` reported them.
#[derive(Debug, Default)]
struct Tally {
    pairs: u64,
    stale: u64,
    crossings: u64,
    walls: u64,
    system: u64,
}

/// Steps `events` events, tallying their kinds; then checks the counters' increments against it.
fn tally_matches<const D: usize, B: Boundary, R: edmd_core::CollisionRule>(
    sim: &mut Simulation<D, B, R>,
    events: usize,
) -> Tally {
    let before = *sim.counters();
    let mut t = Tally::default();
    for _ in 0..events {
        match sim.step().expect("the gas moves") {
            EventKind::Collision(..) => t.pairs += 1,
            EventKind::Stale(_) => t.stale += 1,
            EventKind::CellCrossing(_) | EventKind::ShellExit(_) => t.crossings += 1,
            EventKind::Wall(_) => t.walls += 1,
            EventKind::ShearShift | EventKind::Kick => t.system += 1,
        }
    }
    let c = sim.counters();
    let d = |f: fn(&Counters) -> u64| f(c) - f(&before);
    assert_eq!(d(|c| c.events), events as u64);
    assert_eq!(d(|c| c.pair_collisions), t.pairs);
    assert_eq!(d(|c| c.stale), t.stale);
    assert_eq!(d(|c| c.crossings), t.crossings);
    assert_eq!(d(|c| c.wall_collisions), t.walls);
    assert_eq!(d(|c| c.system_events), t.system);
    assert!(t.pairs > 0 && t.stale > 0 && t.crossings > 0, "{t:?}");
    t
}

fn build_with<const D: usize, B: Boundary>(
    n: usize,
    phi: f64,
    skin: Option<f64>,
) -> Simulation<D, B, ConstantRestitution> {
    let mut p = InitParams::<D>::with_packing(n, phi).unwrap();
    p.seed = 5;
    if let Some(skin) = skin {
        p.sim = Some(SimParams {
            neighbour_skin: skin,
            ..SimParams::for_density::<D>(phi)
        });
    }
    p.build::<B, _>(ConstantRestitution::new(0.9).unwrap())
        .unwrap()
}

#[test]
fn counters_match_the_events_stepped_in_cells_and_lists() {
    let mut cells = build_with::<2, Periodic>(1000, 0.3, Some(0.0));
    assert!(!cells.uses_neighbour_lists());
    tally_matches(&mut cells, 50_000);
    let mut lists = build_with::<3, Walls>(1000, 0.3, Some(0.3));
    assert!(lists.uses_neighbour_lists());
    let t = tally_matches(&mut lists, 50_000);
    assert!(t.walls > 0, "{t:?}");
    // Maintenance comes every few N events: some in 50 000 events of 1000 particles.
    assert!(lists.counters().maintenances > 0);
}

#[test]
fn counters_match_the_events_stepped_in_a_sheared_box() {
    let mut sim = build::<2, _>(800, 0.3, 0.5, 3, ConstantRestitution::new(0.9).unwrap());
    let t = tally_matches(&mut sim, 50_000);
    assert!(t.system > 0, "no shear shift in 50 000 events: {t:?}");
}

/// Deep cooling rescales the velocity scale every few decades of T; each rescale predicts every
/// event again (a restart), as does each drift removal.
#[test]
fn deep_cooling_counts_its_rescales_and_restarts() {
    let mut p = InitParams::<2>::in_box(183, Vector::<2>::new(24.0, 24.0));
    p.seed = 3;
    let mut sim = p
        .build::<Periodic, _>(Rule::new(ConstantRestitution::new(0.9).unwrap()))
        .unwrap();
    let start = *sim.counters();
    sim.run(Stop::Tau(300.0));
    let c = sim.counters();
    assert!(
        c.rescales > start.rescales,
        "no rescale by T/T0 = 10^{:.0}",
        sim.ln_temperature() / std::f64::consts::LN_10
    );
    assert!(c.restarts - start.restarts >= c.rescales - start.rescales);
    assert!(c.maintenances > 0);
}
