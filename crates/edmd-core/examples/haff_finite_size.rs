//! Finite-size study of the homogeneous cooling rate: −d ln T/dτ fitted over τ ∈ [5, 40] in periodic
//! boxes of side f·L⊥ (Enskog) for several f, averaged over seeds, against k(ε) (PHYSICS.md §2.2) and
//! against k(ε)·N/(N − 1), the rate of N disks whose total momentum is zero (their temperature
//! m⟨v²⟩/d counts N particles but only N − 1 of them are free).
//!
//! `cargo run --release -p edmd-core --example haff_finite_size -- D EPS PHI PARTICLE_RUNS F1 [F2 …]`
//! (PARTICLE_RUNS = N × seeds per box size, e.g. 40000).

use edmd_core::theory::{critical_sizes, haff_rate, Transport};
use edmd_core::{decay_rate, ConstantRestitution, InitParams, Periodic, Schedule, Stop, Vector};

fn study<const D: usize>(eps: f64, phi: f64, budget: usize, fractions: &[f64]) {
    let (l_perp, _) = critical_sizes(D, eps, phi, 1.0, Transport::Enskog);
    let k = haff_rate(D, eps);
    println!("D = {D}, eps = {eps}, phi = {phi}: L_perp = {l_perp:.2}, k = {k:.5}");
    println!(
        "{:>6} {:>6} {:>6} {:>10} {:>9} {:>9} {:>9}",
        "L/Lp", "N", "seeds", "k_fit", "s.e. %", "vs k %", "vs kN %"
    );
    for &f in fractions {
        let side = f * l_perp;
        let n =
            (phi * side.powi(D as i32) / edmd_core::init::unit_volume::<D>(0.5)).round() as usize;
        let side = (n as f64 * edmd_core::init::unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
        let seeds = (budget / n).max(8) as u64;
        let mut slopes = Vec::new();
        for seed in 0..seeds {
            let mut p = InitParams::<D>::in_box(n, Vector::<D>::repeat(side));
            p.seed = 5000 + seed;
            p.melt_tau = Some(5.0);
            let mut sim = p
                .build::<Periodic, _>(ConstantRestitution::new(eps).unwrap())
                .unwrap();
            let (mut xs, mut ys) = (Vec::new(), Vec::new());
            sim.run_sampled(Stop::Tau(40.0), &Schedule::every(0.5), |s| {
                if s.tau() >= 5.0 {
                    xs.push(s.tau());
                    ys.push(s.ln_temperature());
                }
            });
            slopes.push(decay_rate(&xs, &ys));
        }
        let m = slopes.iter().sum::<f64>() / slopes.len() as f64;
        let se = (slopes.iter().map(|s| (s - m).powi(2)).sum::<f64>()
            / (slopes.len() as f64 - 1.0)
            / slopes.len() as f64)
            .sqrt();
        let kn = k * n as f64 / (n as f64 - 1.0);
        println!(
            "{:>6.3} {:>6} {:>6} {:>10.5} {:>9.2} {:>+9.2} {:>+9.2}",
            side / l_perp,
            n,
            seeds,
            m,
            100.0 * se / k,
            100.0 * (m / k - 1.0),
            100.0 * (m / kn - 1.0)
        );
    }
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 6 {
        eprintln!("usage: haff_finite_size D EPS PHI PARTICLE_RUNS F1 [F2 ...]");
        std::process::exit(2);
    }
    let num = |i: usize| -> f64 {
        a[i].parse().unwrap_or_else(|_| {
            eprintln!("error: argument {i} ({:?}) is not a number", a[i]);
            std::process::exit(2)
        })
    };
    let (d, eps, phi, budget) = (num(1) as usize, num(2), num(3), num(4) as usize);
    let fractions: Vec<f64> = (5..a.len()).map(num).collect();
    match d {
        2 => study::<2>(eps, phi, budget, &fractions),
        3 => study::<3>(eps, phi, budget, &fractions),
        _ => {
            eprintln!("error: D = {d}: must be 2 or 3");
            std::process::exit(2)
        }
    }
}
