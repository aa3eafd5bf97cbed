//! Cost of deep cooling: N disks at φ (periodic, default N = 10⁴, φ = 0.1), cooled with ε (default
//! 0.6) to τ = C/N (default 2000), against an elastic run of the same system over the same number of
//! collisions per particle. Prints, per seed, how each run ended, the lowest T/T0 reached (kept as a
//! logarithm) and collisions per second, and the ratio of the two rates.
//!
//! The default system clusters (its box is ten times L∥): it cools only to T/T0 ≈ 10^-4.6 by τ = 2000,
//! and without a remedy some seeds collapse. A homogeneous box shows the cost of deep cooling itself,
//! e.g. `-- 3 270 0.05 4000 0.9` (0.5 L⊥, Haff: T/T0 = 10^-328).
//!
//! `cargo run --release -p edmd-core --example deep_cooling_speed [-- SEEDS [N [PHI [TAU [EPS]]]]]`

use edmd_core::{ConstantRestitution, InitParams, Periodic, RunEnd, Stop};
use std::time::Instant;

fn run(eps: f64, n: usize, phi: f64, tau: f64, seed: u64) -> (RunEnd, f64, f64, f64) {
    let mut p = InitParams::<2>::with_packing(n, phi).expect("valid parameters");
    p.seed = seed;
    let mut sim = p
        .build::<Periodic, _>(ConstantRestitution::new(eps).expect("valid epsilon"))
        .expect("valid state");
    let (c0, tau0, ln_t0) = (
        sim.counters().pair_collisions,
        sim.tau(),
        sim.ln_temperature(),
    );
    let start = Instant::now();
    let end = sim.run(Stop::Tau(tau0 + tau));
    let secs = start.elapsed().as_secs_f64();
    let rate = (sim.counters().pair_collisions - c0) as f64 / secs;
    let log10_t = (sim.ln_temperature() - ln_t0) / std::f64::consts::LN_10;
    if let Some(c) = sim.collapse() {
        println!(
            "    (collapse at tau = {:.1}: {:?})",
            c.tau - tau0,
            c.reason
        );
    }
    (end, sim.tau() - tau0, log10_t, rate)
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let arg = |i: usize, default: f64| -> f64 {
        a.get(i).map_or(default, |s| {
            s.parse().unwrap_or_else(|_| {
                eprintln!("error: argument {i} ({s:?}) is not a number");
                std::process::exit(2)
            })
        })
    };
    let (seeds, n, phi, tau) = (
        arg(1, 3.0) as u64,
        arg(2, 1e4) as usize,
        arg(3, 0.1),
        arg(4, 2000.0),
    );
    let eps = arg(5, 0.6);
    println!("deep cooling: N = {n}, phi = {phi}, eps = {eps} against eps = 1, tau = {tau}");
    println!(
        "{:>5} {:>5} {:>10} {:>8} {:>12} {:>12} {:>7}",
        "seed", "eps", "end", "tau", "log10 T/T0", "coll/s", "ratio"
    );
    let mut ratios = Vec::new();
    for seed in 1..=seeds {
        let (e1, t1, l1, r1) = run(1.0, n, phi, tau, seed);
        let (e6, t6, l6, r6) = run(eps, n, phi, tau, seed);
        println!(
            "{seed:>5} {:>5} {:>10} {t1:>8.1} {l1:>12.2} {r1:>12.0}",
            1.0,
            format!("{e1:?}")
        );
        println!(
            "{seed:>5} {:>5} {:>10} {t6:>8.1} {l6:>12.2} {r6:>12.0} {:>7.3}",
            eps,
            format!("{e6:?}"),
            r6 / r1
        );
        ratios.push(r6 / r1);
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "median rate ratio eps {eps} / eps 1: {:.3}",
        ratios[ratios.len() / 2]
    );
}
