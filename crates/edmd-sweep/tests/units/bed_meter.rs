//! The shaken bed's uniform-time meter on beds whose answers are known by construction: a bed
//! bouncing at f/2, columns rising and falling out of step, a roll of known speed buried in noise,
//! grains touching the floor half the time, a gas whose mean velocity swings with the floor's phase.

use edmd_core::Vector;
use edmd_sweep::replica::bed_meter::{BedMeter, BedSummary, SAMPLES_PER_PERIOD};
use edmd_sweep::spec::{Replica, Spec};

/// A channel 50 wide and 100 high, g = 1, A = 2.5, ω = √1.6: 25 columns, 100 height bins.
fn replica() -> Replica {
    let spec = Spec::from_json(
        r#"{ "name": "m", "grid": { "dim": 2, "boundary": "channel", "eps": 0.9, "n": 50,
             "box": 100, "aspect": [0.5, 1], "gravity": 1, "wall_eps": 0.9,
             "remedy": { "kind": "tc", "tc": 0.001 }, "shake_s": 10, "shake_gamma": 4 },
             "stop": { "tau_max": 10 } }"#,
    )
    .unwrap();
    spec.replicas().remove(0)
}

/// Feeds `samples` samples from the start, the grains at sample k given by `bed(k)`.
fn run(samples: u64, bed: impl Fn(u64) -> (Vec<Vector<2>>, Vec<Vector<2>>)) -> BedSummary {
    let r = replica();
    let mut meter = BedMeter::new(&r, 100, 0.0);
    meter.start();
    for k in 1..=samples {
        let (x, v) = bed(k);
        let t = meter.next_time();
        let period = std::f64::consts::TAU / r.floor_motion().1;
        assert!((t - k as f64 * period / SAMPLES_PER_PERIOD as f64).abs() < 1e-12);
        meter.record(&x, &v, &vec![1.0; x.len()], &vec![0.5; x.len()]);
    }
    meter.summary(&r).unwrap()
}

/// One grain per column at x = 2j + 1, at height `z(j)`, at rest.
fn columns(z: impl Fn(usize) -> f64) -> (Vec<Vector<2>>, Vec<Vector<2>>) {
    let x = (0..25)
        .map(|j| Vector::from([2.0 * j as f64 + 1.0, z(j)]))
        .collect();
    (x, vec![Vector::zeros(); 25])
}

/// cos(π k/16): a swing at half the floor's frequency.
fn half(k: u64) -> f64 {
    (std::f64::consts::PI * k as f64 / SAMPLES_PER_PERIOD as f64).cos()
}

#[test]
fn a_bed_moving_at_half_the_floor_frequency_shows_at_f_over_2_only() {
    let s = run(4096, |k| columns(|_| 20.0 + 0.7 * half(k)));
    assert!((s.com_half_f - 0.7).abs() < 2e-3, "{}", s.com_half_f);
    assert!(
        s.com_f < 1e-6 && s.undulation < 1e-6,
        "{} {}",
        s.com_f,
        s.undulation
    );
    assert!((s.com_mean - 20.0).abs() < 1e-3);
}

#[test]
fn columns_out_of_step_at_f_over_2_are_undulations_not_a_bouncing_centre() {
    // Twelve columns up while twelve go down, the middle one still: the centre of mass stands.
    let s = run(4096, |k| {
        columns(|j| match j {
            0..=11 => 20.0 + 0.7 * half(k),
            12 => 20.0,
            _ => 20.0 - 0.7 * half(k),
        })
    });
    let rms = 0.7 * (24.0f64 / 25.0).sqrt();
    assert!((s.undulation - rms).abs() < 2e-3, "{}", s.undulation);
    assert!(
        s.com_half_f < 1e-6 && s.com_f < 1e-6,
        "{} {}",
        s.com_half_f,
        s.com_f
    );
}

/// A deterministic stream of uniform numbers in (−√3, √3): unit variance.
fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * 3f64.sqrt()
    }
}

/// 500 grains on a lattice 50 × 10 (spacing 1, heights 20.5 to 29.5) with v_z = u sin(2πx/W)
/// plus unit noise.
fn roll(u: f64) -> BedSummary {
    let sites: Vec<Vector<2>> = (0..500)
        .map(|i| Vector::from([(i % 50) as f64 + 0.5, (20 + i / 50) as f64 + 0.5]))
        .collect();
    let kick = std::cell::RefCell::new(noise(2));
    run(2048, |_| {
        let mut kick = kick.borrow_mut();
        let v = sites
            .iter()
            .map(|x| {
                let mean = u * (std::f64::consts::TAU * x[0] / 50.0).sin();
                Vector::from([kick(), mean + kick()])
            })
            .collect();
        (sites.clone(), v)
    })
}

#[test]
fn a_roll_is_measured_at_its_speed_and_noise_alone_is_not_a_roll() {
    let s = roll(0.3);
    assert_eq!(s.convection_mode, 1);
    // A column sums the sine at x ± 1/2 about its centre: cos(π/50) ≈ 0.998 of its speed. The
    // noise's rms is 1/√(2048 · 50) per row and mode, 0.3 % of the speed.
    let expected = 0.3 * (std::f64::consts::PI / 50.0).cos();
    let numbers = |s: &BedSummary| (s.convection, s.convection_mode, s.convection_noise);
    assert!((s.convection - expected).abs() < 0.005, "{:?}", numbers(&s));
    assert!(
        s.convection > 10.0 * s.convection_noise,
        "{:?}",
        numbers(&s)
    );
    let quiet = roll(0.0);
    assert!(
        quiet.convection < 2.0 * quiet.convection_noise,
        "{:?}",
        numbers(&quiet)
    );
    assert!(quiet.convection < 0.02, "{:?}", numbers(&quiet));
}

#[test]
fn contact_fraction_profiles_and_a_phase_locked_mean_velocity() {
    let (a, omega) = replica().floor_motion();
    let period = std::f64::consts::TAU / omega;
    let s = run(4096, |k| {
        let phase = k % SAMPLES_PER_PERIOD;
        let t = k as f64 * period / SAMPLES_PER_PERIOD as f64;
        let floor = a * (1.0 - (omega * t).cos());
        // Grain 0 touches the floor in the first half of each period and hangs 1 d above it in
        // the second; grains 1 and 2 share a bin at height 50.5, their mean velocity swinging with
        // the phase and their spread ±0.4.
        let lift = if phase < SAMPLES_PER_PERIOD / 2 {
            0.0
        } else {
            1.0
        };
        let swing = 3.0 * (phase as f64).sin();
        let x = vec![
            Vector::from([10.0, floor + 0.5 + lift]),
            Vector::from([20.0, 50.5]),
            Vector::from([30.0, 50.5]),
        ];
        let v = vec![
            Vector::zeros(),
            Vector::from([swing + 0.4, 0.0]),
            Vector::from([swing - 0.4, 0.0]),
        ];
        (x, v)
    });
    assert!(
        (s.contact_fraction - 0.5).abs() < 1e-3,
        "{}",
        s.contact_fraction
    );
    assert!((s.touching - 0.5).abs() < 1e-3);
    // T = m v²/D from the spread alone: the phase-locked swing is flow, not heat.
    assert!(
        (s.temperature[50] - 0.4 * 0.4 / 2.0).abs() < 1e-12,
        "{}",
        s.temperature[50]
    );
    assert!(s.temperature[70].is_nan());
    // Two grains in a bin 50 wide and 1 high: packing 2 (π/4)/50.
    let grain = std::f64::consts::FRAC_PI_4 / 50.0;
    assert!((s.packing[50] - 2.0 * grain).abs() < 1e-12);
    let phases = SAMPLES_PER_PERIOD as usize;
    assert_eq!(s.phase_packing.len(), phases * 100);
    assert!((s.phase_packing[3 * 100 + 50] - 2.0 * grain).abs() < 1e-12);
}
