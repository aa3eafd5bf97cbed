//! Free cooling of inelastic hard disks against Haff's law (the engine demo run by `make run`).
//!
//! For each ε: N = 4000 disks at φ = 0.1 in a periodic box, Maxwellian start equilibrated elastically
//! (20 collisions per particle), then cooled to τ = C/N = 20. Printed: T/T0 from the simulation and
//! from the homogeneous-cooling theory T0·exp(−k(ε)τ) (PHYSICS.md §2.2, first Sonine order), their
//! ratio, and the collision rate. Larger ε stays homogeneous; smaller ε leaves Haff's law once the
//! shear instability grows (PHYSICS.md §3).
//!
//! `cargo run --release -p edmd-core --example cooling [-- N PHI]`

use edmd_core::theory::{critical_sizes, haff_rate, Transport};
use edmd_core::{ConstantRestitution, InitParams, Periodic, Schedule, Stop};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(4000);
    let phi: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0.1);
    println!("edmd engine demo: free cooling of {n} disks at phi = {phi} (periodic), T/T0 against Haff's law\n");
    println!(
        "{:>5} {:>6} {:>12} {:>12} {:>8} {:>12}",
        "eps", "tau", "T/T0 (sim)", "T/T0 (Haff)", "ratio", "coll/s"
    );
    for eps in [0.99, 0.9, 0.7] {
        let mut p = InitParams::<2>::with_packing(n, phi).expect("valid parameters");
        p.seed = 1;
        p.melt_tau = Some(20.0);
        let rule = ConstantRestitution::new(eps).expect("valid epsilon");
        let mut sim = p.build::<Periodic, _>(rule).expect("valid state");
        let t0 = sim.temperature();
        let k = haff_rate(2, eps);
        let start = std::time::Instant::now();
        let mut rows = Vec::new();
        sim.run_sampled(Stop::Tau(20.0), &Schedule::every(4.0), |s| {
            rows.push((s.tau(), s.temperature() / t0));
        });
        let rate = sim.counters().pair_collisions as f64 / start.elapsed().as_secs_f64();
        let (l_perp, l_par) = critical_sizes(2, eps, phi, 1.0, Transport::Enskog);
        let side = sim.box_len()[0];
        println!(
            "eps = {eps}: box L = {side:.0}, L/L_perp = {:.2}, L/L_par = {:.2} ({})",
            side / l_perp,
            side / l_par,
            if side < l_perp {
                "homogeneous cooling expected"
            } else {
                "shear (and beyond L_par clustering) will grow"
            }
        );
        for (tau, t) in rows {
            let theory = (-k * tau).exp();
            println!(
                "{eps:>5} {tau:>6.1} {t:>12.5e} {theory:>12.5e} {:>8.4} {rate:>12.3e}",
                t / theory
            );
        }
        println!();
    }
}
