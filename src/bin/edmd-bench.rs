//! Collisions per second and peak heap bytes per particle of the engine, for one case or a matrix.
//!
//! ```text
//! edmd-bench --d 2 --n 10000 --phi 0.3 [--eps 1.0] [--repeats 3] [--collisions-per-particle 100]
//! edmd-bench --matrix
//! ```
//! Each case: random (or lattice) start, elastic equilibration of 5 collisions per particle, then
//! timed runs; prints the median collisions/s and the events per collision by kind, and ends with
//! one line `collisions_per_s=<number> bytes_per_particle=<number>` for scripts. `--cool-from TAU`
//! times free cooling instead: each repeat runs a new inelastic gas untimed to τ = TAU, then times
//! the next collisions as the gas cools (the regimes the sweeps run through).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
use std::time::Instant;

use clap::Parser;
use serde::Serialize;

use edmd::{
    Boundary, ConstantRestitution, Counters, InitParams, LeesEdwards, LineAligned, Periodic, Stop,
};

struct Counting;
static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// Forwards to the engine's line-aligning allocator (what the `edmd` binary runs with) and only
// counts bytes.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let now = CURRENT.fetch_add(layout.size(), Relaxed) + layout.size();
        PEAK.fetch_max(now, Relaxed);
        unsafe { INNER.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        CURRENT.fetch_sub(layout.size(), Relaxed);
        unsafe { INNER.dealloc(ptr, layout) }
    }
}

static INNER: LineAligned = LineAligned(System);

#[global_allocator]
static ALLOC: Counting = Counting;

struct Case {
    d: usize,
    n: usize,
    phi: f64,
    eps: f64,
    /// Lees–Edwards shear rate (0: the periodic box).
    shear_rate: f64,
    /// The calendar look-ahead forced on or off (`None`: the engine's own choice).
    look_ahead: Option<bool>,
    /// The searches of the x86-64 baseline even where AVX2 would run four lanes.
    portable: bool,
    /// Free cooling: each repeat a new gas, untimed to this τ, then timed without rescaling.
    cool_from: Option<f64>,
    /// Neighbour lists of this skin instead of the engine's choice (0: cells).
    skin: Option<f64>,
}

struct Outcome {
    collisions: u64,
    secs: f64,
    median: f64,
    spread: f64,
    bytes_per_particle: f64,
    neighbours: &'static str,
    per_collision: EventsPerCollision,
}

/// The events of the timed runs other than pair collisions, per pair collision, by kind.
#[derive(Debug, Clone, Copy, Default, Serialize)]
struct EventsPerCollision {
    /// All events (pair collisions included).
    events: f64,
    /// Collision candidates whose partner had collided since.
    stale: f64,
    /// Cell crossings (cell mode) or shell exits (list mode).
    crossings: f64,
    /// Wall contacts.
    walls: f64,
    /// System events (the shear shift).
    system: f64,
    /// Calendar re-tunings by the event count.
    maintenances: f64,
    /// Full re-predictions (deep-cooling rescales, drift removals).
    restarts: f64,
}

/// The counters of each field of [`EventsPerCollision`], in its order.
const KINDS: [fn(&Counters) -> u64; 7] = [
    |c| c.events,
    |c| c.stale,
    |c| c.crossings,
    |c| c.wall_collisions,
    |c| c.system_events,
    |c| c.maintenances,
    |c| c.restarts,
];

impl EventsPerCollision {
    fn from_fields(
        [events, stale, crossings, walls, system, maintenances, restarts]: [f64; 7],
    ) -> Self {
        Self {
            events,
            stale,
            crossings,
            walls,
            system,
            maintenances,
            restarts,
        }
    }

    fn fields(&self) -> [f64; 7] {
        [
            self.events,
            self.stale,
            self.crossings,
            self.walls,
            self.system,
            self.maintenances,
            self.restarts,
        ]
    }

    /// The counts between `from` and `to` per pair collision.
    fn between(from: &Counters, to: &Counters) -> Self {
        let pairs = (to.pair_collisions - from.pair_collisions).max(1) as f64;
        Self::from_fields(KINDS.map(|f| (f(to) - f(from)) as f64 / pairs))
    }

    /// Rounded to `digits` decimals for the report.
    fn rounded(&self, digits: i32) -> Self {
        let scale = 10f64.powi(digits);
        Self::from_fields(self.fields().map(|x| (x * scale).round() / scale))
    }

    /// The mean over the repeats (their collision counts are equal).
    fn mean(repeats: &[Self]) -> Self {
        let n = repeats.len() as f64;
        let sum = |k: usize| repeats.iter().map(|e| e.fields()[k]).sum::<f64>() / n;
        Self::from_fields(std::array::from_fn(sum))
    }
}

/// A new gas of the case, equilibrated elastically for `melt_tau` collisions per particle.
fn build<const D: usize, B: Boundary>(
    case: &Case,
    melt_tau: f64,
) -> Result<edmd::Simulation<D, B, ConstantRestitution>, String> {
    let mut p = InitParams::<D>::with_packing(case.n, case.phi).map_err(|e| e.to_string())?;
    p.seed = 1;
    p.melt_tau = Some(melt_tau);
    if case.shear_rate > 0.0 || case.skin.is_some() {
        let own = p.default_sim_params();
        p.sim = Some(edmd::SimParams {
            shear_rate: case.shear_rate,
            neighbour_skin: case.skin.unwrap_or(own.neighbour_skin),
            ..own
        });
    }
    let rule = ConstantRestitution::new(case.eps).map_err(|e| e.to_string())?;
    let mut sim = p.build::<B, _>(rule).map_err(|e| e.to_string())?;
    if let Some(on) = case.look_ahead {
        sim.set_look_ahead(on);
    }
    if case.portable {
        sim.use_portable_scan();
    }
    Ok(sim)
}

fn measure<const D: usize, B: Boundary>(
    case: &Case,
    repeats: usize,
    per_particle: f64,
    melt_tau: f64,
) -> Result<Outcome, String> {
    let base = CURRENT.load(Relaxed);
    PEAK.store(base, Relaxed);
    let mut sim = build::<D, B>(case, melt_tau)?;
    let neighbours = if sim.uses_neighbour_lists() {
        "lists"
    } else {
        "cells"
    };
    let mut rates = Vec::new();
    let (mut collisions, mut total) = (0, 0.0);
    let mut kinds = Vec::new();
    for _ in 0..repeats {
        if let Some(tau) = case.cool_from {
            drop(sim);
            sim = build::<D, B>(case, melt_tau)?;
            sim.run(Stop::Tau(tau));
        }
        let c0 = *sim.counters();
        let tau0 = sim.tau();
        let start = Instant::now();
        sim.run(Stop::Tau(tau0 + per_particle));
        let secs = start.elapsed().as_secs_f64();
        let pairs = sim.counters().pair_collisions - c0.pair_collisions;
        rates.push(pairs as f64 / secs);
        kinds.push(EventsPerCollision::between(&c0, sim.counters()));
        collisions += pairs;
        total += secs;
        // (Not under shear: scaling the velocities would scale the imposed flow too.)
        if case.eps < 1.0 && case.shear_rate == 0.0 && case.cool_from.is_none() {
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
        neighbours,
        per_collision: EventsPerCollision::mean(&kinds),
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
    if let Some(tau) = case.cool_from.filter(|t| !(*t >= 0.0 && t.is_finite())) {
        return Err(format!(
            "invalid --cool-from = {tau}: must be ≥ 0 and finite"
        ));
    }
    if !(case.shear_rate >= 0.0 && case.shear_rate.is_finite()) {
        return Err(format!(
            "invalid --shear-rate = {}: must be ≥ 0 and finite",
            case.shear_rate
        ));
    }
    match (case.d, case.shear_rate > 0.0) {
        (2, false) => measure::<2, Periodic>(case, repeats, per_particle, melt_tau),
        (3, false) => measure::<3, Periodic>(case, repeats, per_particle, melt_tau),
        (2, true) => measure::<2, LeesEdwards>(case, repeats, per_particle, melt_tau),
        (3, true) => measure::<3, LeesEdwards>(case, repeats, per_particle, melt_tau),
        (d, _) => Err(format!("invalid --d = {d}: the dimension must be 2 or 3")),
    }
}

/// Collisions per second and peak heap bytes per particle of the engine (elastic start, periodic box).
#[derive(Debug, Parser)]
#[command(name = "edmd-bench", version)]
struct Args {
    /// Dimension, 2 or 3.
    #[arg(long, default_value_t = 2)]
    d: usize,
    /// Particles.
    #[arg(long, default_value_t = 10_000)]
    n: usize,
    /// Packing fraction.
    #[arg(long, default_value_t = 0.3)]
    phi: f64,
    /// Restitution (an inelastic gas is rescaled to T = 1 between repeats).
    #[arg(long, default_value_t = 1.0)]
    eps: f64,
    /// Lees–Edwards shear rate a (0: the periodic box); the elastic gas then heats up slowly, so
    /// the rate per collision, not per unit time, is what compares.
    #[arg(long, default_value_t = 0.0)]
    shear_rate: f64,
    /// Timed runs per case; the median is reported.
    #[arg(long, default_value_t = 3)]
    repeats: usize,
    /// Length of each timed run in collisions per particle [default: 5e6/N, within 2..=200].
    #[arg(long)]
    collisions_per_particle: Option<f64>,
    /// Elastic equilibration before timing, in collisions per particle.
    #[arg(long, default_value_t = 5.0)]
    melt_tau: f64,
    /// Free cooling: each repeat builds the gas again, runs it untimed (no rescale) to this τ
    /// (collisions per particle after the melt), then times `--collisions-per-particle` more.
    #[arg(long)]
    cool_from: Option<f64>,
    /// The large-system look-ahead (prefetch hints over the calendar's next buckets): `auto` (the
    /// engine's choice by the state's size), `on` or `off`, to measure where it pays.
    #[arg(long, default_value = "auto", value_parser = ["auto", "on", "off"])]
    look_ahead: String,
    /// Search two partners at a time, as on any x86-64 processor, even where AVX2 would test four
    /// (the same events; to measure what the four-wide searches save).
    #[arg(long)]
    portable_scan: bool,
    /// Neighbour lists with this skin (in diameters) instead of the engine's choice by density; 0
    /// forces cell crossings (to measure one search against the other on the same gas).
    #[arg(long)]
    skin: Option<f64>,
    /// Print one JSON object instead of the text lines.
    #[arg(long)]
    json: bool,
    /// Run the matrix of D, N and phi instead of one case.
    #[arg(long)]
    matrix: bool,
    /// Largest N of the matrix.
    #[arg(long, default_value_t = 1_000_000)]
    max_n: usize,
}

/// The `--json` line.
#[derive(Debug, Serialize)]
struct Report {
    d: usize,
    n: usize,
    phi: f64,
    eps: f64,
    shear_rate: f64,
    repeats: usize,
    collisions: u64,
    seconds: f64,
    collisions_per_s: f64,
    spread: f64,
    bytes_per_particle: f64,
    /// The instruction set the binary was compiled for: [`BUILT_FOR`].
    isa: &'static str,
    /// The neighbour strategy the engine chose: "cells" or "lists".
    neighbours: &'static str,
    /// `--cool-from` (absent: the gas is kept at T ≈ 1 between repeats).
    #[serde(skip_serializing_if = "Option::is_none")]
    cool_from: Option<f64>,
    /// The timed runs' events per pair collision by kind (the mean over the repeats).
    events_per_collision: EventsPerCollision,
}

/// The instruction set this binary was compiled for (`-C target-cpu`), so that a benchmark's history
/// keeps builds apart: "x86-64" for the default build (whose list scans still pick AVX2 at run time
/// where the processor has it), "x86-64-v3" where AVX2 and FMA are on throughout (e.g. `-C
/// target-cpu=native` on such a processor), "x86-64-v4" with AVX-512 too; other architectures by
/// name.
const BUILT_FOR: &str = if cfg!(all(target_arch = "x86_64", target_feature = "avx512f")) {
    "x86-64-v4"
} else if cfg!(all(
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
)) {
    "x86-64-v3"
} else if cfg!(target_arch = "x86_64") {
    "x86-64"
} else {
    std::env::consts::ARCH
};

fn main() {
    if let Err(e) = real_main(Args::parse()) {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}

/// `--matrix`: every D, N up to `--max-n` and φ of the matrix, elastic, one line each.
fn run_matrix(
    args: &Args,
    repeats: usize,
    per: Option<f64>,
    melt_tau: f64,
    look_ahead: Option<bool>,
) -> Result<(), String> {
    let max_n = args.max_n;
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
                    shear_rate: args.shear_rate,
                    look_ahead,
                    portable: args.portable_scan,
                    cool_from: None,
                    skin: args.skin,
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
    Ok(())
}

fn real_main(args: Args) -> Result<(), String> {
    let repeats = args.repeats;
    if repeats == 0 {
        return Err("invalid --repeats = 0: need at least one timed run".into());
    }
    let per = args.collisions_per_particle.filter(|&c| c > 0.0);
    let melt_tau = args.melt_tau;
    if !(melt_tau >= 0.0) {
        return Err(format!("invalid --melt-tau = {melt_tau}: must be >= 0"));
    }
    let look_ahead = match args.look_ahead.as_str() {
        "on" => Some(true),
        "off" => Some(false),
        _ => None,
    };
    if args.matrix {
        return run_matrix(&args, repeats, per, melt_tau, look_ahead);
    }
    let case = Case {
        d: args.d,
        n: args.n,
        phi: args.phi,
        eps: args.eps,
        shear_rate: args.shear_rate,
        look_ahead,
        portable: args.portable_scan,
        cool_from: args.cool_from,
        skin: args.skin,
    };
    let o = run_case(&case, repeats, per, melt_tau)?;
    if args.json {
        let round = |x: f64, digits: i32| (x * 10f64.powi(digits)).round() / 10f64.powi(digits);
        let report = Report {
            d: case.d,
            n: case.n,
            phi: case.phi,
            eps: case.eps,
            shear_rate: case.shear_rate,
            repeats,
            collisions: o.collisions,
            seconds: round(o.secs, 4),
            collisions_per_s: o.median.round(),
            spread: round(o.spread, 4),
            bytes_per_particle: round(o.bytes_per_particle, 1),
            isa: BUILT_FOR,
            neighbours: o.neighbours,
            cool_from: case.cool_from,
            events_per_collision: o.per_collision.rounded(4),
        };
        println!(
            "{}",
            serde_json::to_string(&report).expect("report serialises")
        );
        return Ok(());
    }
    println!(
        "D={} N={} phi={} eps={} shear_rate={} repeats={} spread={:.1}%",
        case.d,
        case.n,
        case.phi,
        case.eps,
        case.shear_rate,
        repeats,
        100.0 * o.spread
    );
    let k = o.per_collision;
    println!(
        "per collision ({}): events {:.3} stale {:.3} crossings {:.3} walls {:.3} system {:.4} \
         maintenances {:.5} restarts {:.5}",
        o.neighbours, k.events, k.stale, k.crossings, k.walls, k.system, k.maintenances, k.restarts
    );
    println!(
        "collisions_per_s={:.0} bytes_per_particle={:.1}",
        o.median, o.bytes_per_particle
    );
    Ok(())
}
