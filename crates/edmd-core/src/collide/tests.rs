//! Domains, limits and composition of the collision rules.

use super::*;

#[test]
fn epsilon_domain_is_checked() {
    assert!(ConstantRestitution::new(0.0).is_ok());
    assert!(ConstantRestitution::new(1.0).is_ok());
    let e = ConstantRestitution::new(1.5).unwrap_err().to_string();
    assert!(e.contains("epsilon") && e.contains("1.5"), "{e}");
    assert!(ConstantRestitution::new(f64::NAN).is_err());
    assert!(ConstantRestitution::new(-0.1).is_err());
    assert!(ThresholdRestitution::new(0.9, 1.0, 0.0)
        .unwrap_err()
        .to_string()
        .contains("delta"));
    assert!(Viscoelastic::from_material(1.0, 0.7, 0.1)
        .unwrap_err()
        .to_string()
        .contains("poisson"));
}

#[test]
fn tc_model_is_elastic_within_tc() {
    let r = Rule::new(ConstantRestitution::new(0.5).unwrap())
        .with_tc(1e-3)
        .unwrap();
    let (mut a, mut b, mut c) = <[(LastCollision, ()); 3]>::default().into();
    assert_eq!(r.restitution_at(1.0, 0.5, 0.25, 1.0, &mut a, &mut b), 0.5);
    // a collided at t = 1: within t_c any collision of a is elastic, whoever the partner.
    assert_eq!(
        r.restitution_at(1.0, 0.5, 0.25, 1.0005, &mut a, &mut c),
        1.0
    );
    assert_eq!(r.restitution_at(1.0, 0.5, 0.25, 1.002, &mut b, &mut c), 0.5);
    assert!(Rule::new(Elastic).with_tc(0.0).is_err());
    assert!(Rule::new(Elastic).with_rotation(2.0).is_err());
}

#[test]
fn threshold_switches_at_delta() {
    let r = ThresholdRestitution::new(0.7, 1.0, 0.01).unwrap();
    assert_eq!(r.restitution(0.009, 0.5, 0.25), 1.0);
    assert_eq!(r.restitution(0.01, 0.5, 0.25), 0.7);
}

/// PHYSICS.md §6.2 item 4: 0.9747 (v = 0.01), 0.9599 (0.1), 0.95 (0.3), 0.703 (1), 0.534 (3);
/// continuous at v₀.
#[test]
fn thesis_law_values_and_continuity() {
    let r = ThesisRestitution::default();
    for (v, want) in [
        (0.01, 0.9747),
        (0.1, 0.9599),
        (0.3, 0.95),
        (1.0, 0.703),
        (3.0, 0.534),
    ] {
        assert!(
            (r.restitution(v, 0.5, 0.25) - want).abs() < 5e-4,
            "v = {v}: {}",
            r.restitution(v, 0.5, 0.25)
        );
    }
    let below = r.restitution(0.3 * (1.0 - 1e-12), 0.5, 0.25);
    let above = r.restitution(0.3 * (1.0 + 1e-12), 0.5, 0.25);
    assert!((below - above).abs() < 1e-10);
}

#[test]
fn viscoelastic_constants() {
    // C₁ from its Gamma-function form: Γ(3/5) = 1.4891922488128169, Γ(21/10) = 1.0464858468535607.
    let c1 = 1.489_192_248_812_816_9 * std::f64::consts::PI.sqrt()
        / (2f64.powf(0.2) * 5f64.powf(0.4) * 1.046_485_846_853_560_7);
    assert!((c1 - VISCOELASTIC_C1).abs() < 1e-15, "{c1}");
    assert!((VISCOELASTIC_C2 - 0.79827).abs() < 1e-5);
}

/// Integrates the Hertz + damping contact ODE `m ξ'' = −ρ_H (ξ^{3/2} + (3/2) A ξ^{1/2} ξ')` from
/// ξ = 0, ξ' = g until the particles separate (ξ back to 0, or the force turning attractive), and
/// returns −ξ'/g at that moment.
fn restitution_from_ode(rho: f64, m: f64, a: f64, g: f64) -> f64 {
    let force = |x: f64, v: f64| {
        let x = x.max(0.0);
        -(rho / m) * (x.powf(1.5) + 1.5 * a * x.sqrt() * v)
    };
    // Time scale of the contact ~ (m/ρ)^{2/5} g^{−1/5}.
    let dt = (m / rho).powf(0.4) * g.powf(-0.2) * 1e-5;
    let (mut x, mut v) = (0.0f64, g);
    loop {
        // RK4
        let (k1x, k1v) = (v, force(x, v));
        let (k2x, k2v) = (
            v + 0.5 * dt * k1v,
            force(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v),
        );
        let (k3x, k3v) = (
            v + 0.5 * dt * k2v,
            force(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v),
        );
        let (k4x, k4v) = (v + dt * k3v, force(x + dt * k3x, v + dt * k3v));
        let (nx, nv) = (
            x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
            v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
        );
        // Separation: overlap gone, or the (tensile) force would pull the spheres back.
        if nx <= 0.0 || (nv < 0.0 && nx.powf(1.5) + 1.5 * a * nx.sqrt() * nv <= 0.0) {
            return -nv / g;
        }
        x = nx;
        v = nv;
    }
}

/// The two-term series against a direct integration of the contact, at small speeds (where the
/// neglected third term, ~(A κ^{2/5} g^{1/5})³, is below 1e-5).
#[test]
fn viscoelastic_series_matches_the_contact_ode() {
    let rule = Viscoelastic::from_material(1.0e3, 0.3, 2e-3).unwrap();
    let (m_eff, r_eff): (f64, f64) = (0.5, 0.25);
    let rho = rule.stiffness * r_eff.sqrt();
    for g in [1e-4, 1e-3, 1e-2] {
        let series = rule.restitution(g, m_eff, r_eff);
        let ode = restitution_from_ode(rho, m_eff, rule.damping, g);
        let x = rule.damping * rule.kappa(m_eff, r_eff).powf(0.4) * g.powf(0.2);
        println!("g = {g:e}: series {series:.7}, ODE {ode:.7}, expansion parameter {x:.4}");
        assert!(
            (series - ode).abs() < 1e-4,
            "g = {g}: series {series} vs ODE {ode}"
        );
    }
}

#[test]
fn viscoelastic_reference_point_is_reproduced() {
    let rule = Viscoelastic::from_reference(0.9, 1.0, 0.5, 0.25, 1e4, 0.3).unwrap();
    assert!((rule.restitution(1.0, 0.5, 0.25) - 0.9).abs() < 1e-12);
    assert!(
        rule.restitution(0.1, 0.5, 0.25) > 0.9,
        "slower impacts are more elastic"
    );
}

/// Every law × remedy on rough grains is a rough rule: it carries spin and its roughness, whatever
/// the remedy (a rotation wrapped around a rough rule once forwarded neither, and silently made the
/// grains smooth), and the TC model keeps its memory beside the spin.
#[test]
fn every_law_and_remedy_keeps_rough_grains_rough() {
    let laws: [Law; 4] = [
        ConstantRestitution::new(0.8).unwrap().into(),
        ThresholdRestitution::new(0.8, 1.0, 0.01).unwrap().into(),
        ThesisRestitution::default().into(),
        Viscoelastic::from_reference(0.8, 1.0, 0.5, 0.25, 1e5, 0.3)
            .unwrap()
            .into(),
    ];
    let remedies = [
        Remedy::None,
        Remedy::Tc { tc: 1e-3 },
        Remedy::Rotation { theta_max: 0.1 },
    ];
    for law in laws {
        for remedy in remedies {
            let smooth = Rule::new(law).with_remedy(remedy).unwrap();
            let rough = smooth.rough(0.5, 0.4).unwrap();
            assert_eq!(rough.roughness(), (0.5, 0.4), "{law:?} {remedy:?}");
            assert_eq!(smooth.roughness().0, -1.0);
            let mut st = <Rule<Rough> as CollisionRule>::State::default();
            Rule::<Rough>::set_spin(&mut st, [0.0, 0.0, 2.5]);
            assert_eq!(Rule::<Rough>::spin(&st), [0.0, 0.0, 2.5]);
            assert_eq!(rough.rotates(), matches!(remedy, Remedy::Rotation { .. }));
            // The same restitution, smooth or rough, and the TC model's memory kept per particle.
            let (mut a, mut b) = Default::default();
            let (mut c, mut d) = Default::default();
            let es = smooth.restitution_at(0.3, 0.5, 0.25, 1.0, &mut a, &mut b);
            let er = rough.restitution_at(0.3, 0.5, 0.25, 1.0, &mut c, &mut d);
            assert_eq!(es, er, "{law:?} {remedy:?}");
            assert_eq!(
                rough.restitution_at(0.3, 0.5, 0.25, 1.0 + 1e-4, &mut c, &mut d),
                if matches!(remedy, Remedy::Tc { .. }) {
                    1.0
                } else {
                    er
                },
                "{law:?} {remedy:?}"
            );
            assert_eq!(Rule::<Rough>::spin(&c), [0.0; 3]);
        }
    }
    const { assert!(<Rule<Rough> as CollisionRule>::ROUGH) };
    const { assert!(!<Rule as CollisionRule>::ROUGH) };
}

proptest::proptest! {
    /// Viscoelastic ε(g) never increases with the impact speed, over 24 decades of speed and any
    /// damping and pair (the two-term series alone rose back to 1 past its minimum).
    #[test]
    fn viscoelastic_restitution_never_rises_with_speed(
        log_a in -8.0f64..1.0,
        log_g in -12.0f64..12.0,
        step in 1e-6f64..3.0,
        m_eff in 0.01f64..10.0,
        r_eff in 0.05f64..2.0,
    ) {
        let rule = Viscoelastic::from_material(1.0, 0.3, 10f64.powf(log_a)).unwrap();
        let (g, faster) = (10f64.powf(log_g), 10f64.powf(log_g + step));
        let (e, f) = (rule.restitution(g, m_eff, r_eff), rule.restitution(faster, m_eff, r_eff));
        proptest::prop_assert!(f <= e, "eps({faster}) = {f} > eps({g}) = {e}");
        proptest::prop_assert!((VISCOELASTIC_EPS_MIN..=1.0).contains(&e));
    }
}

#[test]
fn viscoelastic_series_limit_is_where_the_series_turns() {
    use super::rules::VISCOELASTIC_X_MAX;
    let rule = Viscoelastic::from_reference(0.9, 1.0, 0.5, 0.25, 1.0, 0.3).unwrap();
    let g = rule.series_limit(0.5, 0.25);
    // x(g) = x* exactly, and the series' own slope vanishes there.
    let x = rule.damping() * rule.kappa(0.5, 0.25).powf(0.4) * g.powf(0.2);
    assert!((x / VISCOELASTIC_X_MAX - 1.0).abs() < 1e-12, "{x}");
    assert!((VISCOELASTIC_EPS_MIN - 7.0 / 12.0).abs() < 1e-12);
    let below = rule.restitution(0.999 * g, 0.5, 0.25);
    assert!(below > VISCOELASTIC_EPS_MIN && below - VISCOELASTIC_EPS_MIN < 1e-6);
}
