//! Every collision rule in a sheared box (PHYSICS.md §7): each restitution law × collapse remedy ×
//! grain kind (`make test` runs each law with one remedy, `make validate` every pair) keeps the exact energy balance of `lees_edwards.rs`,
//!
//!   E(t) − E(0) = −a ∫ Σ m V_x V_y dt − a Σ_coll (r_ij)_x (Δp_i)_y − (energy the rule removed),
//!
//! with E the peculiar kinetic energy plus, for rough grains, the rotational one, held to 10⁻⁹ of the
//! energy; the collisional sum is the [0][1] entry, (Δp_i)_x (r_ij)_y, which differs from its
//! transpose where impulses leave the line of centres (rough grains: 10⁻³ of the energy). An elastic
//! smooth rule removes nothing (to 10⁻⁹), so its heating is the shear's work alone: a remedy that
//! rotates the lab-frame relative velocity of a pair across a sliding face (which carries the
//! faces' relative speed ±a L_y) creates energy there.
//!
//! Over a steady second half, the shear's work equals the dissipation within 3 %: their difference
//! is the change of E over the half, a fluctuation of order E/√N against a heating of many E.

use edmd_core::{
    CollisionRule, ConstantRestitution, Remedy, Rule, ThesisRestitution, ThresholdRestitution,
    Viscoelastic,
};

use crate::lees_edwards::{build, peculiar, KineticStress};

/// The four laws (ε = 1 among them, elastic), each with its name.
fn laws() -> Vec<(&'static str, edmd_core::Law)> {
    vec![
        ("elastic", ConstantRestitution::new(1.0).unwrap().into()),
        (
            "constant 0.8",
            ConstantRestitution::new(0.8).unwrap().into(),
        ),
        (
            "threshold",
            ThresholdRestitution::new(0.7, 1.0, 0.3).unwrap().into(),
        ),
        ("thesis", ThesisRestitution::new(0.8, 1.0).unwrap().into()),
        (
            "viscoelastic",
            Viscoelastic::from_reference(0.8, 1.0, 0.5, 0.25, 1e5, 0.3)
                .unwrap()
                .into(),
        ),
    ]
}

fn remedies() -> [Remedy; 3] {
    [
        Remedy::None,
        Remedy::Tc { tc: 1e-3 },
        Remedy::Rotation {
            theta_max: std::f64::consts::FRAC_PI_2,
        },
    ]
}

/// Energy balance of one rule to `tau`, and the steady second half's work against dissipation.
/// Returns (balance error / energy, dissipated energy / energy, work / dissipation − 1 over the
/// second half, or NaN when the rule removes nothing).
fn balance<const D: usize, R: CollisionRule>(rule: R, rate: f64, tau: f64) -> (f64, f64, f64) {
    let mut sim = build::<D, _>(300, 0.2, rate, 5, rule);
    let energy = |sim: &edmd_core::Simulation<D, edmd_core::LeesEdwards, R>| {
        peculiar(sim).0 + sim.rotational_energy()
    };
    let e0 = energy(&sim);
    let mut stress = KineticStress::new(&sim);
    let mut half = None;
    while sim.tau() < tau {
        sim.step().expect("events left");
        stress.advance(&sim);
        if half.is_none() && sim.tau() >= tau / 2.0 {
            let c = sim.counters();
            half = Some((stress.integral, c.virial_tensor[0][1], c.dissipated));
        }
    }
    let c = *sim.counters();
    let e1 = energy(&sim);
    let work = -rate * (stress.integral + c.virial_tensor[0][1]);
    let error = ((e1 - e0) - (work - c.dissipated)) / (e1 + c.dissipated);
    let (kh, wh, dh) = half.unwrap();
    let late_work = -rate * ((stress.integral - kh) + (c.virial_tensor[0][1] - wh));
    let late_dissipation = c.dissipated - dh;
    let steady = if c.dissipated > 1e-6 * e1 {
        late_work / late_dissipation - 1.0
    } else {
        f64::NAN
    };
    (error, c.dissipated / e1, steady)
}

/// Every law × remedy, smooth and rough, in 2D and 3D: the balance to 10⁻⁹; an elastic rule removes
/// nothing; an inelastic one, sheared at a = 0.5 to τ = 100, balances work and dissipation over the
/// second half within 3 %.
fn every_rule<const D: usize>(every_remedy: bool) {
    for (i, (name, law)) in laws().into_iter().enumerate() {
        // The short version pairs each law with one remedy, the elastic one with the rotation
        // (the remedy that could create energy), so that every law and every remedy run.
        let remedies: Vec<Remedy> = match every_remedy {
            true => remedies().to_vec(),
            false => vec![remedies()[(i + 2) % 3]],
        };
        for remedy in remedies {
            let smooth = Rule::new(law).with_remedy(remedy).unwrap();
            let rough = smooth.rough(0.4, 0.5).unwrap();
            for (grain, (error, dissipated, steady)) in [
                ("smooth", balance::<D, _>(smooth, 0.5, 100.0)),
                ("rough", balance::<D, _>(rough, 0.5, 100.0)),
            ] {
                println!(
                    "D = {D}, {name}, {remedy:?}, {grain}: balance {error:+.1e}, late work/dissipation − 1 = {steady:+.4}"
                );
                assert!(
                    error.abs() < 1e-9,
                    "D = {D}, {name}, {remedy:?}, {grain}: energy balance off by {error:e} of the energy"
                );
                let elastic = name == "elastic" && grain == "smooth";
                assert!(
                    !elastic || dissipated.abs() < 1e-9,
                    "D = {D}, {name}, {remedy:?}, {grain}: an elastic rule removed {dissipated:e} of the energy: its heating is not the shear's work"
                );
                assert_eq!(
                    steady.is_nan(),
                    elastic,
                    "D = {D}, {name}, {remedy:?}, {grain}: dissipation where none was expected, or none where some was"
                );
                assert!(
                    elastic || steady.abs() < 0.03,
                    "D = {D}, {name}, {remedy:?}, {grain}: work and dissipation differ by {steady:+.4} over the steady half"
                );
            }
        }
    }
}

#[test]
fn every_law_and_remedy_balances_energy_in_a_sheared_box_in_2d() {
    every_rule::<2>(false);
}

#[test]
fn every_law_and_remedy_balances_energy_in_a_sheared_box_in_3d() {
    every_rule::<3>(false);
}

/// Every law with every remedy (`make validate`).
#[test]
#[ignore = "long validation run: make validate"]
fn every_law_with_every_remedy_balances_energy_in_a_sheared_box() {
    every_rule::<2>(true);
    every_rule::<3>(true);
}

/// A gas sheared at a = 10⁻⁸ (ε = 0.9, N = 200, φ = 0.1, 2D): it cools by Haff's law to the steady
/// state of the shear, T ≈ 4·10⁻¹⁵ of its start (reached by τ ≈ 350), where the shear's work over
/// τ = 20 is ~3·10⁻¹² and the energy the collisions removed since the start is ~10².
/// Over each of ten intervals of τ = 20 past τ = 600, with the interval sums restarted at its
/// start, the exact balance ΔE = work − dissipated holds to 10⁻⁶ of the dissipated energy, and the
/// dissipation is ~ the work (the steady state: within a factor two, it fluctuates). A running
/// total of the dissipation would round every such increment to nothing next to the early losses.
#[test]
fn the_dissipation_of_a_barely_sheared_cold_gas_is_resolved() {
    let rate = 1e-8;
    let law = ConstantRestitution::new(0.9).unwrap();
    let mut sim = build::<2, _>(200, 0.1, rate, 9, Rule::new(law));
    while sim.tau() < 600.0 {
        sim.step().expect("events left");
    }
    let mut worst = 0.0f64;
    for interval in 0..10 {
        sim.restart_shear_sums();
        let e0 = peculiar(&sim).0;
        let mut stress = KineticStress::new(&sim);
        let end = sim.tau() + 20.0;
        while sim.tau() < end {
            sim.step().expect("events left");
            stress.advance(&sim);
        }
        let c = *sim.counters();
        let work = -rate * (stress.integral + c.virial_tensor[0][1]);
        let change = peculiar(&sim).0 - e0;
        let error = (change - (work - c.dissipated)) / c.dissipated;
        worst = worst.max(error.abs());
        println!(
            "interval {interval}: T {:.2e}, work {work:.3e}, dissipated {:.3e}, energy change {change:+.2e}, balance {error:+.1e} of the dissipation",
            sim.temperature(),
            c.dissipated
        );
        assert!(c.dissipated > 0.0, "no dissipation resolved");
        assert!(
            (0.5..2.0).contains(&(work / c.dissipated)),
            "not the steady state: work {work:e}, dissipated {:e}",
            c.dissipated
        );
    }
    assert!(
        worst < 1e-6,
        "interval balance off by {worst:e} of the dissipation"
    );
}

/// A dense sheared box starts from a lattice melted under the shear and scaled back to T0: the
/// scaling takes the peculiar velocities only, so T(0) = T0 (to round-off) and the flow the melt
/// built, a (y − L_y/2), is kept (its least-squares slope within 0.1 of a; scaling the lab-frame
/// velocities scaled the flow with them).
#[test]
fn a_melted_sheared_start_keeps_its_flow_at_t0() {
    let sim = build::<2, _>(400, 0.45, 0.5, 3, edmd_core::Elastic);
    let t = sim.temperature();
    let (pos, vel) = (sim.positions(), sim.velocities());
    let n = pos.len() as f64;
    let my = pos.iter().map(|x| x[1]).sum::<f64>() / n;
    let mv = vel.iter().map(|v| v[0]).sum::<f64>() / n;
    let sxy: f64 = pos
        .iter()
        .zip(&vel)
        .map(|(x, v)| (x[1] - my) * (v[0] - mv))
        .sum();
    let sxx: f64 = pos.iter().map(|x| (x[1] - my).powi(2)).sum();
    let slope = sxy / sxx;
    println!("T(0) = {t}, flow slope {slope:.4} (a = 0.5)");
    assert!((t - 1.0).abs() < 1e-12, "T(0) = {t}");
    assert!((slope - 0.5).abs() < 0.1, "flow slope {slope}");
}
