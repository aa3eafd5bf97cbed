//! Lees–Edwards boundaries (uniform shear flow, PHYSICS.md §7): checks that need no theory.
//!
//! * **Energy balance, exactly.** Between events a grain's peculiar velocity V = v − a (y − L_y/2) e_x
//!   changes as dV_x/dt = −a V_y; a collision changes the pair's peculiar energy by
//!   −a (r_ij)_x (Δp_i)_y beyond what the law removes; crossings of the sliding faces leave V as it
//!   was. So E_pec(t) − E_pec(0) = −a ∫ Σ m V_x V_y dt − a Σ_coll (r_ij)_x (Δp_i)_y − (energy the
//!   law removed), i.e. −a V ∫ P_xy dt for elastic grains. The test integrates the kinetic part
//!   exactly from event to event (Σ m V_x V_y is linear in time between events, slope −a Σ m V_y²)
//!   and holds the balance to 10⁻⁹ of the energy: any image, shift or crossing taken at the wrong
//!   place breaks it by far more.
//! * **No overlaps** with the sliding images, by an O(N²) check independent of the cells.
//! * **Every collision, in order, against an O(N²) brute-force predictor** that tries every image
//!   of every pair (three rows of images across y, five along x as they slide): same pairs, same
//!   times to 10⁻⁹, for 4000 collisions in 2D and 3D.
//! * **The flow.** An elastic sheared gas heats up (P_xy < 0 once the profile has formed).

use edmd_core::{Boundary, Elastic, InitParams, LeesEdwards, SimParams, Simulation, Vector};

fn build<const D: usize>(
    n: usize,
    phi: f64,
    rate: f64,
    seed: u64,
) -> Simulation<D, LeesEdwards, Elastic> {
    let side = (n as f64 * edmd_core::init::unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
    let mut p = InitParams::<D>::in_box(n, Vector::<D>::repeat(side));
    p.seed = seed;
    p.sim = Some(SimParams {
        shear_rate: rate,
        ..SimParams::for_density::<D>(phi)
    });
    p.build::<LeesEdwards, _>(Elastic).unwrap()
}

/// Peculiar energy, Σ m V_x V_y and Σ m V_y².
fn peculiar<const D: usize, B: Boundary>(sim: &Simulation<D, B, Elastic>) -> (f64, f64, f64) {
    let (mut e, mut kxy, mut syy) = (0.0, 0.0, 0.0);
    for (v, m) in sim.peculiar_velocities().iter().zip(sim.masses()) {
        e += 0.5 * m * v.norm_squared();
        kxy += m * v[0] * v[1];
        syy += m * v[1] * v[1];
    }
    (e, kxy, syy)
}

/// The deepest overlap with the sliding images (O(N²)), as a fraction of the contact distance,
/// checked every 5000 events and at the end (the brute-force test below sees every collision).
fn deepest_overlap<const D: usize>(sim: &Simulation<D, LeesEdwards, Elastic>) -> f64 {
    let (pos, l, delta) = (sim.positions(), *sim.box_len(), sim.shear_offset());
    let mut worst = f64::NEG_INFINITY;
    for i in 0..pos.len() {
        for j in 0..i {
            let mut d = pos[i] - pos[j];
            let wrap = (d[1] / l[1]).round();
            d[1] -= wrap * l[1];
            d[0] -= wrap * delta;
            d[0] -= l[0] * (d[0] / l[0]).round();
            for a in 2..D {
                d[a] -= l[a] * (d[a] / l[a]).round();
            }
            // Equal grains of unit diameter (the builder's).
            worst = worst.max(1.0 - d.norm());
        }
    }
    worst
}

/// Earliest contact over all pairs and all their images (y rows −1, 0, 1; x shifts −2 … 2 box
/// lengths beyond the sliding offset), from scratch: the images move with the partner's velocity
/// ± a L_y along x, so each is a straight line and the plain quadratic applies.
fn brute_force_next<const D: usize>(
    sim: &Simulation<D, LeesEdwards, Elastic>,
) -> (usize, usize, f64) {
    let (pos, vel, l) = (sim.positions(), sim.velocities(), *sim.box_len());
    let (delta, speed) = (sim.shear_offset(), sim.shear_rate() * l[1]);
    let mut best = (usize::MAX, usize::MAX, f64::INFINITY);
    for i in 0..pos.len() {
        for j in i + 1..pos.len() {
            for wrap in -1..=1i32 {
                for kx in -2..=2i32 {
                    let mut dr = pos[i] - pos[j];
                    dr[1] -= wrap as f64 * l[1];
                    dr[0] -= wrap as f64 * delta + kx as f64 * l[0];
                    for a in 2..D {
                        dr[a] -= l[a] * (dr[a] / l[a]).round();
                    }
                    let mut dv = vel[i] - vel[j];
                    dv[0] -= wrap as f64 * speed;
                    let Some(t) = super::oracle::contact_time(&dr, &dv, 1.0) else {
                        continue;
                    };
                    if t < best.2 {
                        best = (i, j, t);
                    }
                }
            }
        }
    }
    best
}

fn against_brute_force<const D: usize>(n: usize, phi: f64, rate: f64) {
    let mut sim = build::<D>(n, phi, rate, 11);
    let (mut shifts, mut worst) = (0u64, 0.0f64);
    for k in 0..4000 {
        let now = sim.time();
        let (i, j, dt) = brute_force_next(&sim);
        let expected = now + dt;
        let pair = loop {
            match sim.step().expect("events left") {
                edmd_core::EventKind::Collision(a, b) => {
                    break ((a as usize).min(b as usize), (a as usize).max(b as usize))
                }
                edmd_core::EventKind::ShearShift => shifts += 1,
                _ => {}
            }
        };
        assert_eq!(
            pair,
            (i, j),
            "collision {k}: engine {pair:?} at t = {}, brute force {:?} at t = {expected}",
            sim.time(),
            (i, j)
        );
        let rel = (sim.time() - expected).abs() / expected.max(1e-300);
        worst = worst.max(rel);
        assert!(
            rel < 1e-9,
            "collision {k}: time {} against {expected}",
            sim.time()
        );
    }
    println!("D = {D}, N = {n}, phi = {phi}, a = {rate}: 4000 collisions as brute force predicts (worst time {worst:.1e}), {shifts} shifts");
    assert!(
        shifts > 10,
        "the images slid by too little: {shifts} shifts"
    );
}

#[test]
fn sheared_disks_collide_as_brute_force_predicts() {
    against_brute_force::<2>(120, 0.2, 1.0);
}

#[test]
fn sheared_spheres_collide_as_brute_force_predicts() {
    against_brute_force::<3>(150, 0.2, 1.0);
}

fn energy_balance<const D: usize>(n: usize, phi: f64, rate: f64, tau: f64) {
    let mut sim = build::<D>(n, phi, rate, 7);
    let (e0, mut kxy, mut syy) = peculiar(&sim);
    let w0 = sim.counters().shear_virial;
    let (mut t_prev, mut kinetic, mut shifts, mut crossings_y) = (sim.time(), 0.0, 0u64, 0u64);
    let mut worst: f64 = f64::NEG_INFINITY;
    let mut steps = 0u64;
    while sim.tau() < tau {
        let kind = sim.step().expect("events left");
        if kind == edmd_core::EventKind::ShearShift {
            shifts += 1;
        }
        let t = sim.time();
        let dt = t - t_prev;
        kinetic += kxy * dt - 0.5 * rate * syy * dt * dt;
        (_, kxy, syy) = peculiar(&sim);
        t_prev = t;
        steps += 1;
        if steps.is_multiple_of(5000) {
            worst = worst.max(deepest_overlap(&sim));
        }
        if let edmd_core::EventKind::CellCrossing(_) = kind {
            crossings_y += 1;
        }
    }
    let (e1, _, _) = peculiar(&sim);
    let collisional = sim.counters().shear_virial - w0;
    let predicted = -rate * (kinetic + collisional);
    let dev = (e1 - e0) - predicted;
    worst = worst.max(deepest_overlap(&sim));
    println!(
        "D = {D}, N = {n}, phi = {phi}, a = {rate}: E_pec {e0:.4} -> {e1:.4} (balance {predicted:.6}, off by {dev:.2e}), kinetic part {:.4}, collisional {:.4}, {shifts} shifts, {crossings_y} crossings, deepest overlap {worst:.2e}",
        -rate * kinetic,
        -rate * collisional
    );
    assert!(
        shifts > 10,
        "the images slid by too little to test the shifts: {shifts}"
    );
    assert!(dev.abs() < 1e-9 * e1, "energy balance off by {dev:e}");
    assert!(e1 > e0, "an elastic sheared gas heats up");
    assert!(worst < 1e-9, "overlap {worst:e}");
}

#[test]
fn elastic_sheared_disks_balance_heating_and_shear_stress() {
    energy_balance::<2>(400, 0.2, 0.5, 20.0);
}

#[test]
fn elastic_sheared_spheres_balance_heating_and_shear_stress() {
    energy_balance::<3>(500, 0.2, 0.5, 20.0);
}
