//! Lees–Edwards boundaries (uniform shear flow, PHYSICS.md §7): checks that need no theory.
//!
//! * **Energy balance, exactly.** Between events a grain's peculiar velocity V = v − a (y − L_y/2) e_x
//!   changes as dV_x/dt = −a V_y; a collision changes the pair's peculiar energy by
//!   −a (Δp_i)_x (r_ij)_y beyond what the law removes; crossings of the sliding faces leave V as it
//!   was. So E_pec(t) − E_pec(0) = −a ∫ Σ m V_x V_y dt − a Σ_coll (Δp_i)_x (r_ij)_y − (energy the
//!   law removed), i.e. −a V ∫ P_xy dt for elastic grains. The test integrates the kinetic part
//!   exactly from event to event (Σ m V_x V_y is linear in time between events, slope −a Σ m V_y²)
//!   and holds the balance to 10⁻⁹ of the energy: any image, shift or crossing taken at the wrong
//!   place breaks it by far more.
//! * **No overlaps** with the sliding images, by an O(N²) check independent of the cells.
//! * **Every collision, in order, against an O(N²) brute-force predictor** that tries every image
//!   of every pair (three rows of images across y, five along x as they slide): same pairs, same
//!   times to 10⁻⁹, for 4000 collisions in 2D and 3D.
//! * **The flow.** An elastic sheared gas heats up. An inelastic one (ε = 0.9) reaches a steady
//!   state where the shear's heating equals the dissipation (`Counters::dissipated`) within 1 %
//!   and the stream profile is linear with slope a within 2 % (2D and 3D, N = 500, φ = 0.1; small
//!   enough boxes to stay homogeneous: the measured profile is a line within its errors).

use edmd_core::{
    CollisionRule, ConstantRestitution, Elastic, InitParams, LeesEdwards, SimParams, Simulation,
    Vector,
};

pub(crate) fn build<const D: usize, R: CollisionRule>(
    n: usize,
    phi: f64,
    rate: f64,
    seed: u64,
    rule: R,
) -> Simulation<D, LeesEdwards, R> {
    build_with_skin(n, phi, rate, seed, rule, None)
}

/// [`build`] with the skin `skin` in place of the default.
fn build_with_skin<const D: usize, R: CollisionRule>(
    n: usize,
    phi: f64,
    rate: f64,
    seed: u64,
    rule: R,
    skin: Option<f64>,
) -> Simulation<D, LeesEdwards, R> {
    let side = (n as f64 * edmd_core::init::unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
    let mut p = InitParams::<D>::in_box(n, Vector::<D>::repeat(side));
    p.seed = seed;
    let defaults = SimParams::for_density::<D>(phi);
    p.sim = Some(SimParams {
        shear_rate: rate,
        neighbour_skin: skin.unwrap_or(defaults.neighbour_skin),
        ..defaults
    });
    p.build::<LeesEdwards, _>(rule).unwrap()
}

/// Peculiar energy, Σ m V_x V_y and Σ m V_y².
pub(crate) fn peculiar<const D: usize, R: CollisionRule>(
    sim: &Simulation<D, LeesEdwards, R>,
) -> (f64, f64, f64) {
    let (mut e, mut kxy, mut syy) = (0.0, 0.0, 0.0);
    for (v, m) in sim.peculiar_velocities().iter().zip(sim.masses()) {
        e += 0.5 * m * v.norm_squared();
        kxy += m * v[0] * v[1];
        syy += m * v[1] * v[1];
    }
    (e, kxy, syy)
}

/// The exact time integral of Σ m V_x V_y, advanced event by event: between events it is linear in
/// time with slope −a Σ m V_y².
pub(crate) struct KineticStress {
    rate: f64,
    kxy: f64,
    syy: f64,
    t: f64,
    pub(crate) integral: f64,
}

impl KineticStress {
    pub(crate) fn new<const D: usize, R: CollisionRule>(
        sim: &Simulation<D, LeesEdwards, R>,
    ) -> Self {
        let (_, kxy, syy) = peculiar(sim);
        KineticStress {
            rate: sim.shear_rate(),
            kxy,
            syy,
            t: sim.time(),
            integral: 0.0,
        }
    }

    /// After an event: the integral up to now, then the new state's values.
    pub(crate) fn advance<const D: usize, R: CollisionRule>(
        &mut self,
        sim: &Simulation<D, LeesEdwards, R>,
    ) {
        let dt = sim.time() - self.t;
        self.integral += self.kxy * dt - 0.5 * self.rate * self.syy * dt * dt;
        (_, self.kxy, self.syy) = peculiar(sim);
        self.t = sim.time();
    }
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
fn brute_force_next<const D: usize, R: CollisionRule>(
    sim: &Simulation<D, LeesEdwards, R>,
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

fn against_brute_force<const D: usize, R: CollisionRule>(
    n: usize,
    phi: f64,
    rate: f64,
    rule: R,
    collisions: usize,
) {
    // Dense spheres search their neighbour lists, renewed near the sliding faces at each shift; a
    // skin of 0.45 gives the small dense box the four columns of cells a sheared list search needs
    // (the default 0.65 would leave it three, hence cell mode).
    let skin = (D == 3 && phi >= 0.38).then_some(0.45);
    let mut sim = build_with_skin::<D, _>(n, phi, rate, 11, rule, skin);
    assert_eq!(sim.uses_neighbour_lists(), skin.is_some());
    let (mut shifts, mut worst) = (0u64, 0.0f64);
    for k in 0..collisions {
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
    println!("D = {D}, N = {n}, phi = {phi}, a = {rate}: {collisions} collisions as brute force predicts (worst time {worst:.1e}), {shifts} shifts");
    assert!(
        shifts > 10,
        "the images slid by too little: {shifts} shifts"
    );
}

#[test]
fn sheared_disks_collide_as_brute_force_predicts() {
    against_brute_force::<2, _>(120, 0.2, 1.0, Elastic, 4000);
}

#[test]
fn sheared_spheres_collide_as_brute_force_predicts() {
    against_brute_force::<3, _>(150, 0.2, 1.0, Elastic, 4000);
}

/// List mode (φ 0.45, N = 180: a 4 × 4 × 4 grid of cells of side σ + δ): lazily wrapped
/// trajectories, lists across the sliding faces gathered for a window of Δ and renewed at each
/// shift. Inelastic (ε = 0.5) at the rate whose steady temperature kinetic theory puts at T0, so
/// that the images slide by many cells in 7500 collisions (an elastic gas would heat up and collide
/// ever faster than they slide).
#[test]
fn dense_sheared_spheres_on_neighbour_lists_collide_as_brute_force_predicts() {
    let rate = edmd_core::theory::EnskogShear::new(3, 0.5, 0.45)
        .solve()
        .unwrap()
        .shear_rate;
    against_brute_force::<3, _>(
        180,
        0.45,
        rate,
        edmd_core::Rule::new(ConstantRestitution::new(0.5).unwrap()),
        7500,
    );
}

fn energy_balance<const D: usize>(n: usize, phi: f64, rate: f64, tau: f64) {
    let mut sim = build::<D, _>(n, phi, rate, 7, Elastic);
    let e0 = peculiar(&sim).0;
    let w0 = sim.counters().virial_tensor[0][1];
    let mut stress = KineticStress::new(&sim);
    let (mut shifts, mut steps, mut worst) = (0u64, 0u64, f64::NEG_INFINITY);
    while sim.tau() < tau {
        if sim.step().expect("events left") == edmd_core::EventKind::ShearShift {
            shifts += 1;
        }
        stress.advance(&sim);
        steps += 1;
        if steps.is_multiple_of(5000) {
            worst = worst.max(deepest_overlap(&sim));
        }
    }
    let e1 = peculiar(&sim).0;
    let collisional = sim.counters().virial_tensor[0][1] - w0;
    let predicted = -rate * (stress.integral + collisional);
    let dev = (e1 - e0) - predicted;
    worst = worst.max(deepest_overlap(&sim));
    println!(
        "D = {D}, N = {n}, phi = {phi}, a = {rate}: E_pec {e0:.4} -> {e1:.4} (balance {predicted:.6}, off by {dev:.2e}), kinetic part {:.4}, collisional {:.4}, {shifts} shifts, deepest overlap {worst:.2e}",
        -rate * stress.integral,
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
    // Neighbour lists.
    energy_balance::<3>(500, 0.45, 3.0, 100.0);
}

/// An inelastic sheared gas (ε = 0.9) reaches a steady state in which the shear heats exactly what
/// the collisions dissipate; the balance including the dissipated energy holds at every time to
/// round-off, over the steady second half the heating −a V ∫ P_xy dt equals the dissipation
/// within 1 % (their difference is the change of the peculiar energy, a fluctuation of order
/// E/√N against a heating of many E), and the stream profile ⟨v_x⟩(y), in 8 slabs, is a line of
/// slope a within 2 % (standard error of the fitted slope printed and required below 0.7 %).
fn steady_state<const D: usize>(n: usize, phi: f64, rate: f64, eps: f64, profile: [f64; 2]) {
    let mut sim = build::<D, _>(
        n,
        phi,
        rate,
        3,
        edmd_core::Rule::new(ConstantRestitution::new(eps).unwrap()),
    );
    let (tau_end, tau_half) = (120.0, 60.0);
    let e0 = peculiar(&sim).0;
    let mut stress = KineticStress::new(&sim);
    let mut half: Option<(f64, f64, f64)> = None;
    const SLABS: usize = 8;
    let (mut flow, mut count) = ([0.0f64; SLABS], [0usize; SLABS]);
    let mut next_sample = tau_half;
    while sim.tau() < tau_end {
        sim.step().expect("events left");
        stress.advance(&sim);
        if half.is_none() && sim.tau() >= tau_half {
            let c = sim.counters();
            half = Some((stress.integral, c.virial_tensor[0][1], c.dissipated));
        }
        if sim.tau() >= next_sample {
            next_sample += 0.5;
            let l = sim.box_len()[1];
            for (x, v) in sim.positions().iter().zip(sim.velocities()) {
                let k = ((x[1] / l * SLABS as f64) as usize).min(SLABS - 1);
                flow[k] += v[0];
                count[k] += 1;
            }
        }
    }
    let c = *sim.counters();
    let e1 = peculiar(&sim).0;
    let balance = -rate * (stress.integral + c.virial_tensor[0][1]) - c.dissipated;
    let dev = (e1 - e0) - balance;
    assert!(
        dev.abs() < 1e-9 * (c.dissipated + e1),
        "balance off by {dev:e}"
    );
    let (kh, wh, dh) = half.unwrap();
    let heating = -rate * ((stress.integral - kh) + (c.virial_tensor[0][1] - wh));
    let dissipation = c.dissipated - dh;
    // The stream profile: least squares of the slab means on the slab centres.
    let l = sim.box_len()[1];
    let ys: Vec<f64> = (0..SLABS)
        .map(|k| (k as f64 + 0.5) * l / SLABS as f64)
        .collect();
    let us: Vec<f64> = (0..SLABS).map(|k| flow[k] / count[k] as f64).collect();
    let (my, mu) = (
        ys.iter().sum::<f64>() / SLABS as f64,
        us.iter().sum::<f64>() / SLABS as f64,
    );
    let sxx: f64 = ys.iter().map(|y| (y - my).powi(2)).sum();
    let slope = ys
        .iter()
        .zip(&us)
        .map(|(y, u)| (y - my) * (u - mu))
        .sum::<f64>()
        / sxx;
    let resid: f64 = ys
        .iter()
        .zip(&us)
        .map(|(y, u)| (u - mu - slope * (y - my)).powi(2))
        .sum();
    let slope_se = (resid / (SLABS as f64 - 2.0) / sxx).sqrt();
    let temperature = 2.0 * e1 / (D as f64 * n as f64);
    println!(
        "D = {D}, N = {n}, phi = {phi}, a = {rate}, eps = {eps}: T = {temperature:.4}; balance off by {dev:.1e}; second half: heating {heating:.4}, dissipation {dissipation:.4} ({:+.3} %); profile slope {slope:.5} ± {slope_se:.5} ({:+.2} % of a)",
        100.0 * (heating / dissipation - 1.0),
        100.0 * (slope / rate - 1.0)
    );
    assert!(
        (heating / dissipation - 1.0).abs() < 0.01,
        "heating {heating} against dissipation {dissipation}"
    );
    let [tolerance, noise] = profile;
    assert!(slope_se < noise * rate, "profile too noisy: {slope_se}");
    assert!(
        (slope / rate - 1.0).abs() < tolerance,
        "profile slope {slope} against a = {rate}"
    );
}

#[test]
fn inelastic_sheared_disks_reach_a_steady_balanced_flow() {
    steady_state::<2>(500, 0.1, 0.1, 0.9, DILUTE_PROFILE);
}

#[test]
fn inelastic_sheared_spheres_reach_a_steady_balanced_flow() {
    steady_state::<3>(500, 0.1, 0.1, 0.9, DILUTE_PROFILE);
}

/// The stream profile's tolerance on its slope and on the slope's standard error, relative to a.
const DILUTE_PROFILE: [f64; 2] = [0.02, 0.007];

/// The same on neighbour lists (φ 0.45), where trajectories past a sliding face are wrapped only
/// at list renewals: the profile is read through the positions and velocities of the grains'
/// images in the box. Sheared at the rate whose steady temperature kinetic theory puts at T0. The
/// balances are as exact as in the dilute gas; the profile of slab means is noisier (standard
/// error 0.7–1.6 % of a) and lies 0–4 % below a in the dense fluid, in list and in cell mode alike
/// (4 seeds each: −3.5, +0.1, −2.2, −1.3 % on lists, −2.7, −1.5, −1.1, −3.6 % on cells), hence 6 %
/// and 2 %.
#[test]
fn dense_sheared_spheres_on_neighbour_lists_reach_a_steady_balanced_flow() {
    let rate = edmd_core::theory::EnskogShear::new(3, 0.9, 0.45)
        .solve()
        .unwrap()
        .shear_rate;
    steady_state::<3>(500, 0.45, rate, 0.9, [0.06, 0.02]);
}
