//! What a vibrating floor costs: pair collisions per second of a shaken 2D bed against the same
//! bed, from the same state, on a floor that stands still (docs/benchmarks.md, "The vibrating
//! floor's cost"). The bed: 2000 disks of diameter 1 in a column 100 wide (20 layers), ε = 0.9
//! with the TC model, a floor of restitution 0.9, shaken at Γ = 4, S = 4 (A = 1, ω = 2, g = 1).
//!
//! `cargo run --release -p edmd-core --example shaken_bed_cost -- [rounds] [collisions] [which]`,
//! `which` one of `both` (default), `shaken`, `static`: one of them alone, for instruction counts
//! (`valgrind --tool=cachegrind` at two collision counts; the difference is the run's own work).

use std::time::Instant;

use edmd_core::{
    Column, ConstantRestitution, InitParams, ParticleInit, Placement, Rule, SimParams, Simulation,
    Stop, Vector,
};

fn params(amplitude: f64) -> SimParams {
    SimParams {
        gravity: 1.0,
        wall_epsilon: 0.9,
        wall_threshold: 0.05,
        floor_amplitude: amplitude,
        floor_omega: 2.0,
        ..SimParams::default()
    }
}

fn rule() -> Rule {
    Rule::new(ConstantRestitution::new(0.9).unwrap())
        .with_tc(1e-3)
        .unwrap()
}

/// Pair collisions per second of `sim` over `collisions` more of them.
fn rate(mut sim: Simulation<2, Column, Rule>, collisions: u64) -> f64 {
    let n = sim.len() as f64;
    let start = Instant::now();
    sim.run(Stop::Tau(collisions as f64 / n));
    sim.counters().pair_collisions as f64 / start.elapsed().as_secs_f64()
}

fn median(mut x: Vec<f64>) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

fn main() {
    let words: Vec<String> = std::env::args().skip(1).collect();
    let which = words.get(2).map_or("both", |w| w.as_str());
    let args: Vec<u64> = words
        .iter()
        .take(2)
        .map(|a| a.parse().expect("rounds and collisions are integers"))
        .collect();
    let (rounds, collisions) = (
        args.first().copied().unwrap_or(3),
        args.get(1).copied().unwrap_or(2_000_000),
    );
    let box_len = Vector::<2>::new(100.0, 200.0);
    let mut p = InitParams::<2>::in_box(2000, box_len);
    p.seed = 1;
    p.placement = Placement::Random;
    p.temperature = 1.0;
    p.sim = Some(params(1.0));
    let mut shaken = p.build::<Column, _>(rule()).unwrap();
    shaken.run(Stop::Time(200.0)); // the shaken steady state
    shaken.reset_counters();
    let state: Vec<ParticleInit<2>> = shaken
        .positions()
        .iter()
        .zip(shaken.velocities())
        .zip(shaken.radii())
        .map(|((&pos, vel), radius)| ParticleInit {
            // Lifted by the floor's height, so that the still floor at 0 sees the same gaps.
            pos: pos - Vector::<2>::new(0.0, shaken.floor_height()),
            vel,
            radius,
            mass: 1.0,
        })
        .collect();
    let (mut ratios, mut rates) = (Vec::new(), [Vec::new(), Vec::new()]);
    for round in 0..rounds {
        let mut moving = shaken.clone();
        moving.reset_counters();
        let still = Simulation::<2, Column, _>::new(box_len, state.clone(), rule(), params(0.0))
            .expect("the same state on a floor at rest");
        if which != "both" {
            let rate = rate(if which == "shaken" { moving } else { still }, collisions);
            println!("{which}: {rate:.4e}/s");
            return;
        }
        // Alternate which runs first, so that a drift of the machine's speed cancels.
        let (m, s) = if round % 2 == 0 {
            let m = rate(moving, collisions);
            (m, rate(still, collisions))
        } else {
            let s = rate(still, collisions);
            (rate(moving, collisions), s)
        };
        println!(
            "round {round}: shaken {m:.4e}/s, static {s:.4e}/s, ratio {:.3}",
            m / s
        );
        ratios.push(m / s);
        rates[0].push(m);
        rates[1].push(s);
    }
    println!(
        "median: shaken {:.4e}/s, static {:.4e}/s, ratio {:.3}",
        median(rates[0].clone()),
        median(rates[1].clone()),
        median(ratios)
    );
}
