//! The engine against independent oracles: an O(N²) brute-force collision predictor, and the
//! `BinaryHeap` calendar (identical event sequences).

use edmd_core::{
    Boundary, Calendar, CollisionRule, ConstantRestitution, Elastic, EventKind, HeapCalendar,
    InitParams, LeesEdwards, ParticleInit, PaulCalendar, Periodic, SimParams, Simulation, Vector,
    Walls,
};

/// Earliest contact over all pairs, from scratch, with the minimum image on periodic axes; the plain
/// (not the engine's) form of the root.
fn brute_force_next<const D: usize>(
    pos: &[Vector<D>],
    vel: &[Vector<D>],
    radius: f64,
    box_len: &Vector<D>,
) -> (usize, usize, f64) {
    let mut best = (usize::MAX, usize::MAX, f64::INFINITY);
    for i in 0..pos.len() {
        for j in i + 1..pos.len() {
            let mut dr = pos[i] - pos[j];
            for a in 0..D {
                dr[a] -= box_len[a] * (dr[a] / box_len[a]).round();
            }
            let dv = vel[i] - vel[j];
            if let Some(t) = contact_time(&dr, &dv, 2.0 * radius) {
                if t < best.2 {
                    best = (i, j, t);
                }
            }
        }
    }
    best
}

/// When a pair at separation `dr` with relative velocity `dv` comes to contact distance `sigma`
/// (the plain form of the root; 0 if already touching and approaching), or None if it never does.
pub(crate) fn contact_time<const D: usize>(
    dr: &Vector<D>,
    dv: &Vector<D>,
    sigma: f64,
) -> Option<f64> {
    let b = dr.dot(dv);
    if b >= 0.0 {
        return None;
    }
    let v2 = dv.norm_squared();
    let disc = b * b - v2 * (dr.norm_squared() - sigma * sigma);
    (disc >= 0.0).then(|| ((-b - disc.sqrt()) / v2).max(0.0))
}

fn next_collision<const D: usize, B: Boundary, C: Calendar>(
    sim: &mut Simulation<D, B, Elastic, C>,
) -> (usize, usize) {
    loop {
        if let EventKind::Collision(a, b) = sim.step().expect("events left") {
            let (x, y) = (a as usize, b as usize);
            return (x.min(y), x.max(y));
        }
    }
}

/// Neighbour lists with skin `skin` (0: cell crossings) in otherwise default settings.
fn with_skin<const D: usize>(p: &mut InitParams<D>, phi: f64, skin: f64) {
    p.sim = Some(SimParams {
        neighbour_skin: skin,
        ..SimParams::for_density::<D>(phi)
    });
}

fn check_against_brute_force<const D: usize>(phi: f64, skin: f64) {
    let mut p = InitParams::<D>::with_packing(200, phi).unwrap();
    with_skin(&mut p, phi, skin);
    check_built_against_brute_force(p, &format!("skin {skin}"));
}

fn check_built_against_brute_force<const D: usize>(mut p: InitParams<D>, label: &str) {
    p.seed = 7;
    let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
    let box_len = *sim.box_len();
    let mut worst: f64 = 0.0;
    for k in 0..10_000 {
        let (pos, vel, now) = (sim.positions(), sim.velocities(), sim.time());
        let (i, j, dt) = brute_force_next(&pos, &vel, 0.5, &box_len);
        let expected = now + dt;
        let pair = next_collision(&mut sim);
        assert_eq!(pair, (i, j), "collision {k}: engine {pair:?} at t = {}, brute force {:?} at t = {expected} (now {now})", sim.time(), (i, j));
        let rel = (sim.time() - expected).abs() / expected;
        worst = worst.max(rel);
        assert!(
            rel < 1e-9,
            "collision {k}: engine t = {}, brute force t = {expected}",
            sim.time()
        );
    }
    println!("D = {D}, {label}: 10^4 collisions match, worst relative time error {worst:.2e}");
}

#[test]
fn first_ten_thousand_collisions_match_brute_force_2d() {
    check_against_brute_force::<2>(0.3, 0.0);
}

#[test]
fn first_ten_thousand_collisions_match_brute_force_3d() {
    check_against_brute_force::<3>(0.2, 0.0);
}

/// A dilute gas in cells of one diameter: a particle crosses many cells between collisions, and
/// most crossings find it with no collision candidate, when only the newly adjacent cells are
/// searched.
#[test]
fn dilute_gas_in_small_cells_matches_brute_force() {
    fn small_cells<const D: usize>(phi: f64) -> InitParams<D> {
        let mut p = InitParams::<D>::with_packing(200, phi).unwrap();
        p.sim = Some(SimParams {
            cell_factor: 1.0,
            ..SimParams::default()
        });
        p
    }
    check_built_against_brute_force(small_cells::<2>(0.05), "phi 0.05, cells of one diameter");
    check_built_against_brute_force(small_cells::<3>(0.05), "phi 0.05, cells of one diameter");
}

#[test]
fn neighbour_lists_match_brute_force() {
    check_against_brute_force::<2>(0.3, 0.3);
    check_against_brute_force::<3>(0.4, 0.4);
    // A skin so thin that lists are renewed more often than particles collide.
    check_against_brute_force::<3>(0.2, 0.02);
}

fn same_sequences<const D: usize, B: Boundary>(phi: f64, events: usize) {
    same_sequences_with::<D, B>(phi, events, 0.0);
}

fn same_sequences_with<const D: usize, B: Boundary>(phi: f64, events: usize, skin: f64) {
    let mut p = InitParams::<D>::with_packing(1000, phi).unwrap();
    p.seed = 11;
    with_skin(&mut p, phi, skin);
    let mut a = p
        .build_with_calendar::<B, _, PaulCalendar>(Elastic)
        .unwrap();
    let mut b = p
        .build_with_calendar::<B, _, HeapCalendar>(Elastic)
        .unwrap();
    for k in 0..events {
        let (ea, eb) = (a.step(), b.step());
        assert_eq!(ea, eb, "event {k}");
        assert_eq!(a.time().to_bits(), b.time().to_bits(), "event {k}");
    }
    assert_eq!(a.counters(), b.counters());
}

#[test]
fn paul_and_binary_heap_calendars_agree_2d() {
    same_sequences::<2, Periodic>(0.3, 100_000);
    same_sequences::<2, Walls>(0.5, 100_000);
}

#[test]
fn paul_and_binary_heap_calendars_agree_3d() {
    same_sequences::<3, Periodic>(0.3, 100_000);
    same_sequences::<3, Walls>(0.2, 100_000);
}

#[test]
fn paul_and_binary_heap_calendars_agree_with_neighbour_lists() {
    same_sequences_with::<3, Periodic>(0.45, 100_000, 0.4);
    same_sequences_with::<3, Walls>(0.3, 100_000, 0.3);
    same_sequences_with::<2, Walls>(0.5, 100_000, 0.5);
}

/// The large-system look-ahead (prefetch hints several events deep) must not change a single
/// event: forced on in systems small enough to check, against the same system without it. Walls
/// and small boxes put many cells on the box's faces, where the look-ahead skips its hints.
fn look_ahead_changes_nothing<const D: usize, B: Boundary>(n: usize, phi: f64, skin: f64) {
    let mut p = InitParams::<D>::with_packing(n, phi).unwrap();
    p.seed = 17;
    with_skin(&mut p, phi, skin);
    let mut a = p.build::<B, _>(Elastic).unwrap();
    let mut b = p.build::<B, _>(Elastic).unwrap();
    assert!(
        !a.look_ahead(),
        "a system this small starts without the look-ahead"
    );
    a.set_look_ahead(true);
    step_in_step(&mut a, &mut b, 100_000);
}

/// Steps `a` and `b` side by side for `events` events: the same events at the same times to the
/// bit, then the same counters and particle records.
fn step_in_step<const D: usize, B: Boundary, R: edmd_core::CollisionRule>(
    a: &mut Simulation<D, B, R>,
    b: &mut Simulation<D, B, R>,
    events: usize,
) {
    for k in 0..events {
        let (ea, eb) = (a.step(), b.step());
        assert_eq!(ea, eb, "event {k}");
        assert_eq!(a.time().to_bits(), b.time().to_bits(), "event {k}");
    }
    assert_eq!(a.counters(), b.counters());
    for (pa, pb) in a.particles().iter().zip(b.particles().iter()) {
        assert_eq!(pa, pb);
    }
}

#[test]
fn look_ahead_changes_no_event() {
    look_ahead_changes_nothing::<2, Periodic>(4000, 0.3, 0.0);
    look_ahead_changes_nothing::<2, Periodic>(300, 0.05, 0.0);
    look_ahead_changes_nothing::<2, Walls>(2000, 0.5, 0.0);
    look_ahead_changes_nothing::<3, Periodic>(2000, 0.3, 0.0);
    look_ahead_changes_nothing::<3, Periodic>(2000, 0.45, 0.4);
}

/// Whether this processor runs the four-wide list scan (x86-64 with AVX2).
fn wide_scan_here() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    return false;
}

/// The four-wide list scan (x86-64 with AVX2) must find exactly the events of the two-wide one: the
/// same cheap test on four lanes, the same exact test in list order. Dense periodic, walled and
/// sheared boxes (the scan's three variants: far from the faces, nearest images, sliding images),
/// inelastic so that the sheared gas reaches its steady state.
fn wide_scan_changes_nothing<const D: usize, B: Boundary, R: CollisionRule + Clone>(
    phi: f64,
    skin: f64,
    shear_rate: f64,
    rule: R,
) {
    let mut p = InitParams::<D>::with_packing(1500, phi).unwrap();
    p.seed = 23;
    p.sim = Some(SimParams {
        neighbour_skin: skin,
        shear_rate,
        ..SimParams::for_density::<D>(phi)
    });
    let mut a = p.build::<B, _>(rule.clone()).unwrap();
    let mut b = p.build::<B, _>(rule).unwrap();
    if !wide_scan_here() {
        eprintln!("no AVX2 here: only the two-wide scan runs, nothing to compare");
        return;
    }
    assert!(a.wide_scan(), "lists in use, scanned four-wide");
    b.use_portable_scan();
    assert!(!b.wide_scan());
    step_in_step(&mut a, &mut b, 100_000);
}

#[test]
fn wide_scan_changes_no_event() {
    wide_scan_changes_nothing::<3, Periodic, _>(0.45, 0.4, 0.0, Elastic);
    wide_scan_changes_nothing::<3, Walls, _>(0.4, 0.3, 0.0, Elastic);
    wide_scan_changes_nothing::<2, Periodic, _>(0.7, 0.4, 0.0, Elastic);
    let inelastic = edmd_core::Rule::new(ConstantRestitution::new(0.9).unwrap());
    wide_scan_changes_nothing::<3, LeesEdwards, _>(0.45, 0.4, 0.5, inelastic);
    wide_scan_changes_nothing::<2, LeesEdwards, _>(0.6, 0.4, 0.5, inelastic);
}

/// The four-wide scan reads the partners' radii only where they differ: a dense 3D packing with
/// every other grain shrunk by 10 % (a mixture on lists) against the two-wide scan, and the same
/// grains all shrunk (one radius again).
#[test]
fn wide_scan_with_two_radii_changes_no_event() {
    let phi = 0.45;
    let p = InitParams::<3>::with_packing(1500, phi).unwrap();
    let melted = p.build::<Periodic, _>(Elastic).unwrap();
    for shrink_all in [false, true] {
        let grains: Vec<ParticleInit<3>> = melted
            .positions()
            .into_iter()
            .zip(melted.velocities())
            .enumerate()
            .map(|(i, (pos, vel))| ParticleInit {
                pos,
                vel,
                radius: if shrink_all || i % 2 == 1 { 0.9 } else { 1.0 } * p.radius,
                mass: 1.0,
            })
            .collect();
        let params = SimParams {
            neighbour_skin: 0.4,
            ..SimParams::for_density::<3>(phi)
        };
        let mut a =
            Simulation::<3, Periodic, _>::new(*melted.box_len(), grains.clone(), Elastic, params)
                .unwrap();
        let mut b =
            Simulation::<3, Periodic, _>::new(*melted.box_len(), grains, Elastic, params).unwrap();
        if !wide_scan_here() {
            eprintln!("no AVX2 here: only the two-wide scan runs, nothing to compare");
            return;
        }
        assert!(a.wide_scan(), "lists in use, scanned four-wide");
        b.use_portable_scan();
        step_in_step(&mut a, &mut b, 100_000);
    }
}
