//! Collisions per second and peak heap bytes per particle of the engine, for one case or a matrix.
//!
//! ```text
//! edmd-bench --d 2 --n 10000 --phi 0.3 [--eps 1.0] [--repeats 3] [--collisions-per-particle 100]
//! edmd-bench --matrix
//! ```
//! Each case: random (or lattice) start, elastic equilibration of 5 collisions per particle, then
//! timed runs; prints the median collisions/s and ends with one line
//! `collisions_per_s=<number> bytes_per_particle=<number>` for scripts.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::Instant;

use edmd::{ConstantRestitution, InitParams, Periodic, Stop};

struct Counting;
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY-free wrapper: forwards to the system allocator and only counts bytes.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let now = CURRENT.fetch_add(layout.size(), Relaxed) + layout.size();
        PEAK.fetch_max(now, Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        CURRENT.fetch_sub(layout.size(), Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

struct Case {
    d: usize,
    n: usize,
    phi: f64,
    eps: f64,
}

struct Outcome {
    collisions: u64,
    secs: f64,
    median: f64,
    spread: f64,
    bytes_per_particle: f64,
}

fn measure<const D: usize>(
    case: &Case,
    repeats: usize,
    per_particle: f64,
    melt_tau: f64,
) -> Result<Outcome, String> {
    let base = CURRENT.load(Relaxed);
    PEAK.store(base, Relaxed);
    let mut p = InitParams::<D>::with_packing(case.n, case.phi).map_err(|e| e.to_string())?;
    p.seed = 1;
    p.melt_tau = Some(melt_tau);
    let rule = ConstantRestitution::new(case.eps).map_err(|e| e.to_string())?;
    let mut sim = p.build::<Periodic, _>(rule).map_err(|e| e.to_string())?;
    let mut rates = Vec::new();
    let (mut collisions, mut total) = (0, 0.0);
    for _ in 0..repeats {
        let c0 = sim.counters().pair_collisions;
        let tau0 = sim.tau();
        let start = Instant::now();
        sim.run(Stop::Tau(tau0 + per_particle));
        let secs = start.elapsed().as_secs_f64();
        rates.push((sim.counters().pair_collisions - c0) as f64 / secs);
        collisions += sim.counters().pair_collisions - c0;
        total += secs;
        if case.eps < 1.0 {
            // Keep an inelastic gas at T ≈ 1 so every repeat sees the same event rate.
            let t = sim.temperature();
            sim.scale_velocities(t.recip().sqrt());
        }
    }
    let peak = PEAK.load(Relaxed) - base;
    drop(sim);
    rates.sort_by(f64::total_cmp);
    let median = rates[rates.len() / 2];
    let spread = (rates[rates.len() - 1] - rates[0]) / median;
    Ok(Outcome {
        collisions,
        secs: total,
        median,
        spread,
        bytes_per_particle: peak as f64 / case.n as f64,
    })
}

fn run_case(
    case: &Case,
    repeats: usize,
    per_particle: Option<f64>,
    melt_tau: f64,
) -> Result<Outcome, String> {
    // About 5·10^6 collisions per repeat (at least 2 and at most 200 per particle).
    let per_particle = per_particle.unwrap_or_else(|| (5e6 / case.n as f64).clamp(2.0, 200.0));
    match case.d {
        2 => measure::<2>(case, repeats, per_particle, melt_tau),
        3 => measure::<3>(case, repeats, per_particle, melt_tau),
        d => Err(format!("invalid --d = {d}: the dimension must be 2 or 3")),
    }
}

fn arg<T: std::str::FromStr>(args: &[String], name: &str, default: T) -> Result<T, String> {
    match args.iter().position(|a| a == name) {
        Some(i) => args
            .get(i + 1)
            .ok_or(format!("{name} needs a value"))?
            .parse()
            .map_err(|_| format!("invalid {name} = {}", args[i + 1])),
        None => Ok(default),
    }
}

fn main() {
    if let Err(e) = real_main() {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}

fn real_main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--help" || a == "-h") {
        println!("usage: edmd-bench [--d 2|3] [--n N] [--phi PHI] [--eps EPS] [--repeats K] [--collisions-per-particle C] [--melt-tau TAU] [--json]\n       edmd-bench --matrix [--max-n N]\n\n  --repeats K                  timed runs per case; the median is reported (default 3)\n  --collisions-per-particle C  length of each timed run (default: 5e6/N, within [2, 200])\n  --melt-tau TAU               elastic equilibration before timing, in collisions per particle (default 5)\n  --json                       print one JSON object instead of the text lines");
        return Ok(());
    }
    let repeats: usize = arg(&args, "--repeats", 3)?;
    let per: f64 = arg(&args, "--collisions-per-particle", 0.0)?;
    let per = (per > 0.0).then_some(per);
    let melt_tau: f64 = arg(&args, "--melt-tau", 5.0)?;
    if !(melt_tau >= 0.0) {
        return Err(format!("invalid --melt-tau = {melt_tau}: must be >= 0"));
    }
    if args.iter().any(|a| a == "--matrix") {
        let max_n: usize = arg(&args, "--max-n", 1_000_000)?;
        println!(
            "{:>2} {:>8} {:>5} {:>5} {:>14} {:>8} {:>10}",
            "D", "N", "phi", "eps", "collisions/s", "spread", "bytes/N"
        );
        for d in [2usize, 3] {
            let phis: &[f64] = if d == 2 {
                &[0.05, 0.3, 0.5, 0.7]
            } else {
                &[0.05, 0.3, 0.45]
            };
            for n in [1_000usize, 10_000, 100_000, 1_000_000]
                .into_iter()
                .filter(|&n| n <= max_n)
            {
                for &phi in phis {
                    let case = Case {
                        d,
                        n,
                        phi,
                        eps: 1.0,
                    };
                    let o = run_case(&case, repeats, per, melt_tau)?;
                    println!(
                        "{d:>2} {n:>8} {phi:>5} {:>5} {:>14.0} {:>7.1}% {:>10.1}",
                        1.0,
                        o.median,
                        100.0 * o.spread,
                        o.bytes_per_particle
                    );
                }
            }
        }
        return Ok(());
    }
    let case = Case {
        d: arg(&args, "--d", 2)?,
        n: arg(&args, "--n", 10_000)?,
        phi: arg(&args, "--phi", 0.3)?,
        eps: arg(&args, "--eps", 1.0)?,
    };
    let o = run_case(&case, repeats, per, melt_tau)?;
    if args.iter().any(|a| a == "--json") {
        println!(
            "{{\"d\":{},\"n\":{},\"phi\":{},\"eps\":{},\"repeats\":{},\"collisions\":{},\"seconds\":{:.4},\"collisions_per_s\":{:.0},\"spread\":{:.4},\"bytes_per_particle\":{:.1}}}",
            case.d,
            case.n,
            case.phi,
            case.eps,
            repeats,
            o.collisions,
            o.secs,
            o.median,
            o.spread,
            o.bytes_per_particle
        );
        return Ok(());
    }
    println!(
        "D={} N={} phi={} eps={} repeats={} spread={:.1}%",
        case.d,
        case.n,
        case.phi,
        case.eps,
        repeats,
        100.0 * o.spread
    );
    println!(
        "collisions_per_s={:.0} bytes_per_particle={:.1}",
        o.median, o.bytes_per_particle
    );
    Ok(())
}
