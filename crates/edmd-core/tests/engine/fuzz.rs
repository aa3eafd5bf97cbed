//! Random fuzzing of scene × rule × remedy × parameters (proptest): whatever the combination, the
//! engine must not panic, must never let two particles overlap, must conserve momentum where the
//! scene has no walls, and must never create energy (kinetic + rotational + potential). Half the
//! cases use neighbour lists (a random skin) instead of cell crossings.
//!
//! `cargo test` runs 48 cases; the ignored 2000-case test runs in `make stress`. `EDMD_FUZZ_VERBOSE=1`
//! prints every case.

use edmd_core::{
    Boundary, Channel, CollisionRule, ConstantRestitution, Container, InitParams, Law, Periodic,
    Remedy, Rule, SimParams, Stop, ThesisRestitution, ThresholdRestitution, Viscoelastic, Walls,
};
use proptest::prelude::*;

#[derive(Debug, Clone)]
struct Case {
    d: usize,
    scene: u8,
    rule: u8,
    remedy: u8,
    n: usize,
    phi: f64,
    eps: f64,
    beta: f64,
    wall_eps: f64,
    knob: f64,
    seed: u64,
    events: u64,
    /// Neighbour-list skin (0: cell crossings).
    skin: f64,
}

fn cases() -> impl Strategy<Value = Case> {
    (
        (2usize..=3, 0u8..4, 0u8..5, 0u8..3),
        (2usize..150, 0.002f64..0.45, 0.0f64..=1.0, -1.0f64..=1.0),
        (
            0.0f64..=1.0,
            0.0f64..=1.0,
            any::<u64>(),
            500u64..6000,
            prop_oneof![Just(0.0), 0.02f64..1.0],
        ),
    )
        .prop_map(
            |(
                (d, scene, rule, remedy),
                (n, phi, eps, beta),
                (wall_eps, knob, seed, events, skin),
            )| {
                Case {
                    d,
                    scene,
                    rule,
                    remedy,
                    n,
                    // Random placement reaches φ ≈ 0.45 in 2D and ≈ 0.3 in 3D.
                    phi: if d == 3 { phi.min(0.28) } else { phi },
                    eps,
                    beta,
                    wall_eps,
                    knob,
                    seed,
                    events,
                    skin,
                }
            },
        )
}

/// Kinetic + rotational + potential energy in physical units.
fn energy<const D: usize, B: Boundary, R: CollisionRule>(
    sim: &edmd_core::Simulation<D, B, R>,
) -> f64 {
    let kinetic: f64 = sim
        .velocities()
        .iter()
        .zip(sim.masses())
        .map(|(v, m)| 0.5 * m * v.norm_squared())
        .sum();
    kinetic + sim.rotational_energy() + sim.potential_energy()
}

fn check<const D: usize, B: Boundary, R: CollisionRule>(
    case: &Case,
    rule: R,
) -> Result<(), TestCaseError> {
    let gravity = case.scene == 3;
    let Ok(mut init) = InitParams::<D>::with_packing(case.n, case.phi) else {
        return Ok(());
    };
    init.seed = case.seed;
    init.melt_tau = Some(0.0);
    init.placement = edmd_core::Placement::Random;
    init.sim = Some(SimParams {
        wall_epsilon: case.wall_eps,
        gravity: if gravity { 0.05 + case.knob } else { 0.0 },
        wall_threshold: if gravity { 0.05 } else { 0.0 },
        seed: case.seed,
        neighbour_skin: case.skin,
        ..SimParams::for_density::<D>(case.phi)
    });
    // Bad combinations (a box too small for three cells, a packing too dense to place at random)
    // must be errors, never panics.
    let Ok(mut sim) = init.build::<B, R>(rule) else {
        return Ok(());
    };
    let periodic = case.scene == 0;
    let o0 = sim.observe();
    let mut last = energy(&sim);
    let energy_at_start = last;
    let chunk = 250;
    let mut done = 0;
    while done < case.events {
        let end = sim.run(Stop::Events(chunk));
        done += chunk;
        let e = energy(&sim);
        prop_assert!(e.is_finite(), "energy {e}");
        prop_assert!(
            e <= last * (1.0 + 1e-9) + 1e-300,
            "energy created: {last} -> {e}"
        );
        last = e;
        let overlap = sim.deepest_overlap().map_or(0.0, |o| o.2);
        prop_assert!(overlap < 1e-9, "overlap {overlap} sigma");
        if periodic {
            let o = sim.observe();
            let dp = (o.momentum - o0.momentum).norm();
            prop_assert!(
                dp <= 1e-10 * o.momentum_scale.max(o0.momentum_scale),
                "momentum changed by {dp} (scale {})",
                o.momentum_scale
            );
        }
        if end != edmd_core::RunEnd::Reached {
            break;
        }
    }
    if std::env::var_os("EDMD_FUZZ_VERBOSE").is_some() {
        eprintln!(
            "ran: {} events, {} collisions, log10 E/E0 = {:.1}, neighbour lists {}",
            sim.counters().events,
            sim.counters().pair_collisions,
            (last / energy_at_start).log10(),
            sim.uses_neighbour_lists()
        );
    }
    Ok(())
}

/// The case's remedy on top of `law`, for smooth grains or (`rough`) rough ones: every law ×
/// remedy × roughness is one [`Rule`].
fn with_remedy<const D: usize>(
    case: &Case,
    law: impl Into<Law>,
    rough: bool,
) -> Result<(), TestCaseError> {
    let remedy = match case.remedy {
        0 => Remedy::None,
        1 => Remedy::Tc {
            tc: 1e-4 * case.knob,
        },
        _ => Remedy::Rotation {
            theta_max: case.knob * std::f64::consts::FRAC_PI_2,
        },
    };
    let rule = Rule::new(law).with_remedy(remedy).unwrap();
    if rough {
        with_scene::<D, _>(case, rule.rough(case.beta, 0.4 + 0.1 * case.knob).unwrap())
    } else {
        with_scene::<D, _>(case, rule)
    }
}

fn with_scene<const D: usize, R: CollisionRule>(case: &Case, rule: R) -> Result<(), TestCaseError> {
    match case.scene {
        0 => check::<D, Periodic, R>(case, rule),
        1 => check::<D, Walls, R>(case, rule),
        2 => check::<D, Channel, R>(case, rule),
        _ => check::<D, Container, R>(case, rule),
    }
}

fn run_case<const D: usize>(case: &Case) -> Result<(), TestCaseError> {
    let eps = case.eps;
    match case.rule {
        0 => with_remedy::<D>(case, ConstantRestitution::new(eps).unwrap(), false),
        1 => with_remedy::<D>(
            case,
            ThresholdRestitution::new(eps, 1.0, 0.01 + case.knob).unwrap(),
            false,
        ),
        2 => with_remedy::<D>(
            case,
            ThesisRestitution::new(0.5 + 0.5 * eps, 0.1 + case.knob).unwrap(),
            false,
        ),
        3 => {
            // A damping giving ε at the thermal speed; the series needs ε above ~0.3.
            let Ok(v) = Viscoelastic::from_reference(eps.max(0.35), 1.0, 0.5, 0.25, 1e5, 0.3)
            else {
                return Ok(());
            };
            with_remedy::<D>(case, v, false)
        }
        // Rough grains with any remedy (spin and the TC model's memory live side by side).
        _ => with_remedy::<D>(case, ConstantRestitution::new(eps).unwrap(), true),
    }
}

/// One fuzz case, in the dimension it draws.
fn fuzz_one(case: &Case) -> Result<(), TestCaseError> {
    if std::env::var_os("EDMD_FUZZ_VERBOSE").is_some() {
        eprintln!("{case:?}");
    }
    if case.d == 2 {
        run_case::<2>(case)
    } else {
        run_case::<3>(case)
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn any_scene_rule_and_remedy_is_safe(case in cases()) {
        fuzz_one(&case)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    #[ignore = "2000 cases: make stress"]
    fn any_scene_rule_and_remedy_is_safe_2000_cases(case in cases()) {
        fuzz_one(&case)?;
    }
}
