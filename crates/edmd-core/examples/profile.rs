//! Event statistics of a short elastic run: events, crossings and stale events per pair collision.
//! `cargo run --release -p edmd-core --example profile -- D N PHI` (environment: `TAU` run length,
//! `SKIN` neighbour-list skin in diameters, 0 for cells; `CELL` cell side in diameters; defaults
//! from `SimParams::for_density`)
use edmd_core::{Elastic, InitParams, Periodic, SimParams, Stop};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let d: usize = args.get(1).map_or(2, |s| s.parse().unwrap());
    let n: usize = args.get(2).map_or(10_000, |s| s.parse().unwrap());
    let phi: f64 = args.get(3).map_or(0.3, |s| s.parse().unwrap());
    if d == 2 {
        go::<2>(n, phi)
    } else {
        go::<3>(n, phi)
    }
}

fn go<const D: usize>(n: usize, phi: f64) {
    let mut p = InitParams::<D>::with_packing(n, phi).unwrap();
    p.melt_tau = Some(5.0);
    let env = |name: &str| std::env::var(name).ok().and_then(|s| s.parse::<f64>().ok());
    let mut sim_params = SimParams::for_density::<D>(phi);
    if let Some(skin) = env("SKIN") {
        sim_params.neighbour_skin = skin;
    }
    if let Some(factor) = env("CELL") {
        sim_params.cell_factor = factor;
    }
    p.sim = Some(sim_params);
    let mut sim = p.build::<Periodic, _>(Elastic).unwrap();
    let e0 = sim.counters().events;
    let start = std::time::Instant::now();
    sim.run(Stop::Tau(
        std::env::var("TAU")
            .ok()
            .and_then(|s| s.parse().ok())
            .unwrap_or(50.0),
    ));
    let secs = start.elapsed().as_secs_f64();
    let c = *sim.counters();
    let ev = (c.events - e0) as f64;
    let pc = c.pair_collisions as f64;
    println!(
        "cells {:?} side {:?}; events/coll {:.3} crossings/coll {:.3} stale/coll {:.3}; {:.0} coll/s, {:.0} events/s",
        sim.grid().n,
        sim.grid().side,
        ev / pc,
        c.crossings as f64 / pc,
        (ev - pc - c.crossings as f64 - c.wall_collisions as f64) / pc,
        pc / secs,
        ev / secs
    );
}
