//! Cost of deep cooling: N disks at φ (periodic, default N = 10⁴, φ = 0.1), cooled with ε (default
//! 0.6) to τ = C/N (default 2000), against an elastic run of the same system over the same number of
//! collisions per particle. Prints, per seed, how each run ended, the lowest T/T0 reached (kept as a
//! logarithm) and collisions per second, and the ratio of the two rates.
//!
//! The default system clusters (its box is ten times L∥): it cools only to T/T0 ≈ 10^-4.6 by τ = 2000,
//! and without a remedy some seeds collapse (with TC = 1e-4 mean free times none does:
//! `-- 3 10000 0.1 2000 0.6 1e-4`). A homogeneous box shows the cost of deep cooling itself,
//! e.g. `-- 3 270 0.05 4000 0.9` (0.5 L⊥, Haff: T/T0 = 10^-328).
//!
//! `cargo run --release -p edmd-core --example deep_cooling_speed [-- SEEDS [N [PHI [TAU [EPS [TC]]]]]]`

use edmd_core::theory::{chi, collision_frequency};
use edmd_core::{CollisionRule, ConstantRestitution, InitParams, Periodic, Rule, RunEnd, Stop};
use std::time::Instant;

/// Runs ε-restitution (with the TC model if `tc` > 0, in mean free times at T = 1) for `tau`.
fn run(eps: f64, tc: f64, n: usize, phi: f64, tau: f64, seed: u64) -> (RunEnd, f64, f64, f64) {
    let rule = ConstantRestitution::new(eps).expect("valid epsilon");
    if tc > 0.0 && eps < 1.0 {
        let nu = collision_frequency(2, phi, chi(2, phi), 1.0, 1.0, 1.0);
        let tc_model = Rule::new(rule).with_tc(tc / nu).expect("valid t_c");
        run_rule(tc_model, n, phi, tau, seed)
    } else {
        run_rule(rule, n, phi, tau, seed)
    }
}

fn run_rule<R: CollisionRule>(
    rule: R,
    n: usize,
    phi: f64,
    tau: f64,
    seed: u64,
) -> (RunEnd, f64, f64, f64) {
    let mut p = InitParams::<2>::with_packing(n, phi).expect("valid parameters");
    p.seed = seed;
    let mut sim = p.build::<Periodic, _>(rule).expect("valid state");
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
    let (eps, tc) = (arg(5, 0.6), arg(6, 0.0));
    println!("deep cooling: N = {n}, phi = {phi}, eps = {eps} (TC model t_c = {tc} mean free times at T0; 0: none) against eps = 1, tau = {tau}");
    println!(
        "{:>5} {:>5} {:>10} {:>8} {:>12} {:>12} {:>7}",
        "seed", "eps", "end", "tau", "log10 T/T0", "coll/s", "ratio"
    );
    let mut ratios = Vec::new();
    for seed in 1..=seeds {
        let (e1, t1, l1, r1) = run(1.0, 0.0, n, phi, tau, seed);
        let (e6, t6, l6, r6) = run(eps, tc, n, phi, tau, seed);
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
