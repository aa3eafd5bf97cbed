//! A completely inelastic ball on a vibrating floor, flown with the floor's contact search
//! (`edmd_core::floor`), against the map analysis of PHYSICS.md §8.2
//! (`edmd_core::theory::bouncing_ball`): from the lift-off phase at Γ = √(1 + π²) the flight
//! lasts one period to 10⁻⁹; below Γ = √(4 + π²) the motion settles on flights of one period,
//! above it the flights alternate (the period doubles), checked at 1 % on either side. Units:
//! g = ω = 1, so A = Γ and time is the phase.

use std::f64::consts::PI;

use edmd_core::floor::{Flight, Floor};
use edmd_core::theory::{
    lift_off_phase, one_period_gamma, one_period_take_off, period_doubling_gamma,
};

/// The flight time from a take-off with the floor at phase `t` (the ball moving with it).
fn flight(gamma: f64, t: f64) -> f64 {
    let floor = Floor {
        amplitude: gamma,
        omega: 1.0,
        phase: t.rem_euclid(2.0 * PI),
    };
    // On the floor, with its velocity, to the last bit.
    let ball = Flight {
        z0: floor.height(0.0),
        v0: floor.speed(0.0),
        g: 1.0,
    };
    ball.first_contact(&floor, 20.0 * PI)
        .expect("the ball lands")
}

/// The next take-off after landing at phase `t`: at once if the floor falls faster than g there,
/// else at the next lift-off phase.
fn take_off_after(gamma: f64, t: f64) -> f64 {
    if gamma * t.sin() > 1.0 {
        return t;
    }
    let lift = lift_off_phase(gamma).unwrap();
    let k = ((t - lift) / (2.0 * PI)).ceil();
    lift + 2.0 * PI * k
}

/// The flight times of `bounces` bounces from the lift-off phase, the transient left out.
fn flights(gamma: f64, bounces: usize, kept: usize) -> Vec<f64> {
    let mut t = lift_off_phase(gamma).unwrap();
    let mut out = Vec::new();
    for k in 0..bounces {
        let s = flight(gamma, t);
        if k + kept >= bounces {
            out.push(s);
        }
        t = take_off_after(gamma, t + s);
    }
    out
}

#[test]
fn one_period_from_lift_off_at_the_threshold() {
    let gamma = one_period_gamma();
    let lift = lift_off_phase(gamma).unwrap();
    assert!((lift - one_period_take_off(gamma).unwrap()).abs() < 1e-12);
    let s = flight(gamma, lift);
    assert!((s / (2.0 * PI) - 1.0).abs() < 1e-9, "flight {s} against 2π");
}

#[test]
fn the_period_doubles_where_the_map_says() {
    let gamma_pd = period_doubling_gamma();
    // Below: flights of one period, from the map's take-off phase cos θ = π/Γ.
    let below = flights(0.99 * gamma_pd, 3000, 10);
    for s in &below {
        assert!(
            (s / (2.0 * PI) - 1.0).abs() < 1e-6,
            "Γ = {:.4}: flight {s}",
            0.99 * gamma_pd
        );
    }
    // Above: two flights that alternate.
    let above = flights(1.01 * gamma_pd, 3000, 10);
    for w in above.windows(2) {
        assert!(
            (w[0] - w[1]).abs() > 1e-3,
            "Γ = {:.4}: flights {w:?} do not alternate",
            1.01 * gamma_pd
        );
    }
    for w in above.windows(3) {
        assert!(
            (w[0] - w[2]).abs() < 1e-6,
            "Γ = {:.4}: not period two: {w:?}",
            1.01 * gamma_pd
        );
    }
    println!(
        "Γ_pd = {gamma_pd:.4}: below {:.6} (2π = {:.6}), above {:.4} / {:.4}",
        below[0],
        2.0 * PI,
        above[0],
        above[1]
    );
}
