//! The classifier on synthetic series: each class, its onsets, and the settled label.

use edmd_sweep::classify::*;

/// A series sampled every τ = 1 with Haff cooling at rate `k` and given order parameters.
fn series(n: usize, k: f64, f: impl Fn(f64) -> (f64, f64, f64)) -> OrderSeries {
    let mut s = OrderSeries::default();
    for i in 0..n {
        let t = i as f64;
        let (flow, sp, d2) = f(t);
        s.tau.push(t);
        s.ln_temperature.push(-k * t);
        s.f_flow.push(flow);
        s.s_perp.push(sp);
        s.delta_rho2.push(d2);
        s.f_2x.push(0.0);
        s.s_rho.push(1.0);
    }
    s
}

fn theory(l_perp: f64, l_par: f64) -> Theory {
    Theory {
        haff_rate: Some(0.1),
        l_over_l_perp: l_perp,
        l_over_l_par: l_par,
        per_cell: 16.0,
    }
}

#[test]
fn haff_cooling_without_structure_is_kinetic_and_says_why() {
    let s = series(200, 0.1, |_| (0.0, 1.0, -0.03));
    let th = Thresholds::default();
    let c = classify(&s, &th, &theory(0.8, 0.4));
    assert_eq!(c.class, Class::Kinetic);
    assert!(c.note.contains("linearly stable"), "{}", c.note);
    assert!(c.haff_deviation[10].abs() < 1e-12 && c.haff_deviation[0].is_nan());
    assert!(c.shear_onset.is_nan() && c.cluster_onset.is_nan());
    // Unstable box, run shorter than the onset time 3/r⊥ = 3/(0.1·(1 − 1/1.21)) ≈ 174.
    let c = classify(
        &series(100, 0.1, |_| (0.0, 1.0, 0.0)),
        &th,
        &theory(1.1, 0.5),
    );
    assert_eq!(c.class, Class::Kinetic);
    assert!(c.note.starts_with("too short to tell"), "{}", c.note);
}

#[test]
fn growing_flow_is_shearing_with_its_first_passage() {
    let grow = |t: f64| (t / 20.0).exp().min(500.0);
    let s = series(300, 0.1, |t| (0.001 * grow(t), 10.0 * grow(t), 0.0));
    let c = classify(&s, &Thresholds::default(), &theory(2.0, 0.8));
    assert_eq!(c.class, Class::Shearing);
    // S⊥ = 20 at t = 20 ln 2 = 13.9: first sample at or after is τ = 14.
    assert_eq!(c.shear_onset, 14.0);
    assert!(c.cluster_onset.is_nan());
}

#[test]
fn density_contrast_is_clustering_whatever_the_flow() {
    let s = series(300, 0.1, |t| {
        (0.5, 50.0, -0.02 + if t > 150.0 { 0.2 } else { 0.0 })
    });
    let c = classify(&s, &Thresholds::default(), &theory(3.0, 1.5));
    assert_eq!(c.class, Class::Clustering);
    assert_eq!(c.cluster_onset, 151.0);
    assert_eq!(c.shear_onset, 0.0);
}

#[test]
fn fitted_haff_rate_detects_a_slower_cooling() {
    // Cooling at rate 0.1 until τ = 50, then at 0.05: ΔH grows once the rate changes.
    let mut s = series(200, 0.1, |_| (0.0, 1.0, 0.0));
    for (t, l) in s.tau.iter().zip(s.ln_temperature.iter_mut()) {
        if *t > 50.0 {
            *l = -5.0 - 0.05 * (t - 50.0);
        }
    }
    let (dh, k) = haff_deviation(&s, 5.0, None);
    assert!((k - 0.1).abs() < 1e-12);
    assert!((dh[150] - 0.05 * 100.0).abs() < 1e-9);
    let th = Thresholds::default();
    let mut t = theory(1.5, 0.5);
    t.haff_rate = None;
    let c = classify(&s, &th, &t);
    assert_eq!(c.class, Class::Kinetic);
    assert!(c.note.starts_with("departure from Haff"), "{}", c.note);
}

#[test]
fn settled_only_by_sustained_clustering() {
    let th = Thresholds::default();
    let shear = series(200, 0.1, |t| (if t >= 100.0 { 0.3 } else { 0.0 }, 1.0, 0.0));
    assert_eq!(
        settled(&shear, &th, &theory(2.0, 0.8)),
        None,
        "a shearing gas may still cluster"
    );
    let cluster = series(200, 0.1, |t| (0.3, 1.0, if t >= 120.0 { 0.3 } else { 0.0 }));
    assert_eq!(
        settled(&cluster, &th, &theory(2.0, 1.2)),
        Some(Class::Clustering)
    );
    let short = series(160, 0.1, |t| (0.3, 1.0, if t >= 120.0 { 0.3 } else { 0.0 }));
    assert_eq!(
        settled(&short, &th, &theory(2.0, 1.2)),
        None,
        "held for 39 < 50"
    );
}

#[test]
fn a_sustained_class_never_reverts_but_a_blip_does_not_count() {
    let th = Thresholds::default();
    // Clusters from τ = 50 to 150 that dissolve again: still clustering (monotone label).
    let s = series(300, 0.1, |t| {
        (
            0.3,
            1.0,
            if (50.0..=150.0).contains(&t) {
                0.3
            } else {
                0.0
            },
        )
    });
    let c = classify(&s, &th, &theory(3.0, 1.5));
    assert_eq!(c.class, Class::Clustering);
    assert_eq!(c.cluster_onset, 50.0);
    // A 20-τ blip of density in a shearing gas is not clustering.
    let s = series(300, 0.1, |t| {
        (0.3, 50.0, if (50.0..70.0).contains(&t) { 0.3 } else { 0.0 })
    });
    assert_eq!(classify(&s, &th, &theory(3.0, 1.5)).class, Class::Shearing);
}
