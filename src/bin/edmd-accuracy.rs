//! Run time against error (`make bench-accuracy`): prints one JSON object per measurement.
//!
//! ```text
//! edmd-accuracy remedies    # collapse remedies at eps = 0.7 and 0.9: cost per tau, cooling-rate error
//! edmd-accuracy statistics  # errors of the cooling rate and of chi against theory vs N x seeds x tau
//! ```
//! Cooling rates are least-squares slopes of ln T(τ) over τ ∈ [5, τ_end] in periodic boxes of half the
//! shear-critical size L⊥ (homogeneous cooling), averaged over seeds; `scripts/bench-accuracy.py`
//! turns the lines into a table and a figure.

use std::time::Instant;

use clap::{Parser, ValueEnum};
use serde_json::json;

use edmd::{
    CollisionRule, ConstantRestitution, Elastic, InitParams, Periodic, Rule, Schedule, Stop,
    ThresholdRestitution, Vector,
};
use edmd_core::geometry::ball_volume;
use edmd_core::theory::{chi, chi_from_frequency, critical_sizes, haff_rate, Transport};

/// Large arrays on cache-line boundaries: faster large 3D systems (edmd_core's `alloc` module).
#[global_allocator]
static ALLOC: edmd_core::LineAligned = edmd_core::LineAligned(std::alloc::System);

/// Slopes −d ln T/dτ on [5, tau_end] of `seeds` runs, their mean, standard error and wall seconds.
fn cooling<R: CollisionRule + Copy>(
    rule: R,
    n: usize,
    side: f64,
    seeds: u64,
    tau_end: f64,
) -> (f64, f64, f64, u64) {
    let mut slopes = Vec::new();
    let mut secs = 0.0;
    let mut collisions = 0;
    for seed in 0..seeds {
        let mut p = InitParams::<2>::in_box(n, Vector::<2>::repeat(side));
        p.seed = 5000 + seed;
        p.melt_tau = Some(5.0);
        let mut sim = p.build::<Periodic, _>(rule).unwrap();
        let start = Instant::now();
        let (mut xs, mut ys) = (Vec::new(), Vec::new());
        sim.run_sampled(Stop::Tau(tau_end), &Schedule::every(0.5), |s| {
            if s.tau() >= 5.0 {
                xs.push(s.tau());
                ys.push(s.ln_temperature());
            }
        });
        secs += start.elapsed().as_secs_f64();
        collisions += sim.counters().pair_collisions;
        slopes.push(edmd_core::decay_rate(&xs, &ys));
    }
    let m = slopes.iter().sum::<f64>() / slopes.len() as f64;
    let se = if slopes.len() > 1 {
        (slopes.iter().map(|s| (s - m).powi(2)).sum::<f64>()
            / (slopes.len() as f64 - 1.0)
            / slopes.len() as f64)
            .sqrt()
    } else {
        f64::NAN
    };
    (m, se, secs, collisions)
}

/// Homogeneous box for (ε, φ): side L⊥/2 and its particle count, at most `cap`.
fn homogeneous_box(eps: f64, phi: f64, cap: usize) -> (usize, f64) {
    let (l_perp, _) = critical_sizes(2, eps, phi, 1.0, Transport::Enskog);
    let mut side = 0.5 * l_perp;
    let mut n = (phi * side * side / ball_volume(2, 0.5)) as usize;
    if n > cap {
        n = cap;
    }
    side = (n as f64 * ball_volume(2, 0.5) / phi).sqrt();
    (n, side)
}

fn remedies() {
    let tau_end = 40.0;
    // Two settings: a dilute homogeneous box (L⊥/2 at φ = 0.05), where Haff's law is exact, and the
    // McNamara–Young box (N = 1024, φ = 0.25, L > L⊥), where phase-diagram work happens and
    // structure forms.
    for (setting, phi, eps) in [
        ("homogeneous", 0.05, 0.7),
        ("homogeneous", 0.05, 0.9),
        ("mcnamara-young", 0.25, 0.7),
        ("mcnamara-young", 0.25, 0.9),
    ] {
        let (n, side, seeds) = if setting == "homogeneous" {
            let (n, side) = homogeneous_box(eps, phi, 2000);
            (n, side, (64_000 / n).clamp(8, 400) as u64)
        } else {
            (1024, (1024.0 * ball_volume(2, 0.5) / phi).sqrt(), 16)
        };
        let c = ConstantRestitution::new(eps).unwrap();
        let theory = haff_rate(2, eps);
        // Mean free time at T0 = 1 (Enskog): the unit of t_c.
        let t_mf = 1.0 / edmd_core::theory::collision_frequency(2, phi, chi(2, phi), 1.0, 1.0, 1.0);
        let (k0, se0, s0, c0) = cooling(c, n, side, seeds, tau_end);
        let cost0 = s0 / c0 as f64;
        let line = |remedy: &str, param: f64, unit: &str, r: (f64, f64, f64, u64)| {
            let (k, se, secs, coll) = r;
            emit(json!({
                "study": "remedy", "setting": setting, "eps": eps, "phi": phi, "n": n,
                "seeds": seeds, "tau_end": tau_end, "remedy": remedy, "param": param, "unit": unit,
                "k": round(k, 6), "k_se": round(se, 6), "k_exact": round(k0, 6),
                "k_exact_se": round(se0, 6), "k_theory": round(theory, 6),
                "error_vs_exact": round(k / k0 - 1.0, 6),
                "error_vs_theory": round(k / theory - 1.0, 6),
                "seconds": round(secs, 3),
                "us_per_collision": round(1e6 * secs / coll as f64, 4),
                "cost_ratio": round(secs / coll as f64 / cost0, 4),
            }));
        };
        line("none", 0.0, "-", (k0, se0, s0, c0));
        for f in [1e-5, 1e-4, 1e-3, 1e-2] {
            let r = Rule::new(c).with_tc(f * t_mf).unwrap();
            line(
                "tc",
                f,
                "mean free time at T0",
                cooling(r, n, side, seeds, tau_end),
            );
        }
        for d in [1e-5, 1e-4, 1e-3, 1e-2] {
            let r = ThresholdRestitution::new(eps, 1.0, d).unwrap();
            line(
                "threshold",
                d,
                "sqrt(T0/m)",
                cooling(r, n, side, seeds, tau_end),
            );
        }
        for deg in [1.0, 2.0, 5.0, 10.0] {
            let r = Rule::new(c).with_rotation(f64::to_radians(deg)).unwrap();
            line(
                "rotation",
                deg,
                "degrees",
                cooling(r, n, side, seeds, tau_end),
            );
        }
        for d in [1e-4, 1e-3] {
            let r = Rule::new(ThresholdRestitution::new(eps, 1.0, d).unwrap())
                .with_rotation(f64::to_radians(5.0))
                .unwrap();
            line(
                "threshold+rotation 5deg",
                d,
                "sqrt(T0/m)",
                cooling(r, n, side, seeds, tau_end),
            );
        }
    }
}

fn statistics() {
    // Cooling rate: eps = 0.9, phi = 0.05, homogeneous box; seeds and window length.
    let (eps, phi) = (0.9, 0.05);
    let theory = haff_rate(2, eps);
    // The homogeneous box holds 251 disks; 60 shows the effect of N at the same cost per seed.
    for n_cap in [60usize, 1000] {
        let (n, side) = homogeneous_box(eps, phi, n_cap);
        let c = ConstantRestitution::new(eps).unwrap();
        for seeds in [4u64, 16, 64] {
            for tau_end in [20.0, 40.0] {
                let (k, se, secs, coll) = cooling(c, n, side, seeds, tau_end);
                emit(json!({
                    "study": "haff", "eps": eps, "phi": phi, "n": n, "seeds": seeds,
                    "tau_end": tau_end, "k": round(k, 6), "k_se": round(se, 6),
                    "k_theory": round(theory, 6), "error": round(k / theory - 1.0, 6),
                    "rel_se": round(se / theory, 6), "seconds": round(secs, 3), "collisions": coll,
                }));
            }
        }
    }
    // χ from the collision rate, elastic, φ = 0.25, against Luding's χ.
    let phi = 0.25;
    let reference = chi(2, phi);
    for n in [500usize, 2000, 8000] {
        for tau in [50.0, 200.0, 800.0] {
            let seeds = 3u64;
            let mut chis = Vec::new();
            let mut secs = 0.0;
            for seed in 0..seeds {
                let mut p = InitParams::<2>::with_packing(n, phi).unwrap();
                p.seed = 7000 + seed;
                p.melt_tau = Some(20.0);
                let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
                let start = Instant::now();
                let meter = edmd::VirialMeter::start(&sim);
                sim.run(Stop::Tau(tau));
                secs += start.elapsed().as_secs_f64();
                let r = meter.read(&sim);
                chis.push(chi_from_frequency(
                    2,
                    phi,
                    r.nu,
                    1.0,
                    sim.temperature(),
                    1.0,
                ));
            }
            let m = chis.iter().sum::<f64>() / chis.len() as f64;
            let se = (chis.iter().map(|c| (c - m).powi(2)).sum::<f64>()
                / (chis.len() as f64 - 1.0)
                / chis.len() as f64)
                .sqrt();
            emit(json!({
                "study": "chi", "phi": phi, "n": n, "seeds": seeds, "tau": tau,
                "chi": round(m, 6), "chi_se": round(se, 6), "chi_luding": round(reference, 6),
                "error": round(m / reference - 1.0, 6), "rel_se": round(se / reference, 6),
                "seconds": round(secs, 3), "collisions": (n as f64 * tau) as u64 * seeds,
            }));
        }
    }
}

/// `x` rounded to `digits` decimals (the JSON lines carry no more than their precision).
fn round(x: f64, digits: i32) -> f64 {
    let f = 10f64.powi(digits);
    (x * f).round() / f
}

/// Prints one measurement as a JSON line.
fn emit(v: serde_json::Value) {
    println!("{v}");
}

/// A study of run time against error.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Study {
    /// Collapse remedies at eps = 0.7 and 0.9: cost per tau, cooling-rate error.
    Remedies,
    /// Errors of the cooling rate and of chi against theory, over N x seeds x tau.
    Statistics,
}

/// Run time against error: one JSON object per measurement on stdout.
#[derive(Debug, Parser)]
#[command(name = "edmd-accuracy", version)]
struct Args {
    /// The studies to run, in order.
    #[arg(required = true, value_enum)]
    studies: Vec<Study>,
}

fn main() {
    for study in Args::parse().studies {
        match study {
            Study::Remedies => remedies(),
            Study::Statistics => statistics(),
        }
    }
}
