//! Running one replica: build the scene, rule and remedy as monomorphised types, run to the stop
//! condition, and collect the observables and snapshots in memory.

use std::time::Instant;

use edmd_core::theory::{haff_rate, haff_temperature_tau};
use edmd_core::{
    order_parameters, Boundary, Channel, CollisionRule, ConstantRestitution, EdmdError, InitParams,
    Periodic, RandomRotation, RunEnd, Schedule, Simulation, Stop, TcModel, ThesisRestitution,
    ThresholdRestitution, Vector, Velocities, VirialMeter, Walls,
};

use crate::classify::{
    classify, critical_box_sides, settled, Class, Classification, OrderSeries, Theory,
};
pub use crate::record::Status;
use crate::spec::{viscoelastic, BoundaryKind, Remedy, Replica, RuleSpec, Spec, VelocityKind};

/// Observables sampled at the points of the schedule.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    /// Pair collisions C (the H5MD `step`).
    pub step: Vec<i64>,
    /// Physical time.
    pub time: Vec<f64>,
    /// τ = C/N.
    pub tau: Vec<f64>,
    /// Granular temperature T (underflows to 0 below 1e-308; see `ln_temperature`).
    pub temperature: Vec<f64>,
    /// ln T, finite however deep the cooling.
    pub ln_temperature: Vec<f64>,
    /// Total kinetic energy.
    pub kinetic_energy: Vec<f64>,
    /// Speed kurtosis ⟨v⁴⟩/⟨v²⟩².
    pub kurtosis: Vec<f64>,
    /// Particle–wall collisions.
    pub wall_collisions: Vec<i64>,
    /// Compressibility factor Z = pV/(NT) from the collision virial since the previous sample
    /// (NaN at the first sample).
    pub compressibility: Vec<f64>,
    /// Pressure p = Z N T / V (NaN at the first sample).
    pub pressure: Vec<f64>,
    /// |Σ m v| / Σ m|v|: momentum conservation (round-off level in periodic boxes).
    pub momentum_error: Vec<f64>,
    /// Haff's law T0 exp(−k(ε) τ) (first Sonine order), for the constant-restitution rule only.
    pub haff_temperature: Vec<f64>,
    /// Order parameters (empty unless the spec has a `classify` section).
    pub order: OrderSeries,
}

/// Positions and velocities at one instant, in the original particle order.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Pair collisions C.
    pub step: i64,
    /// Physical time.
    pub time: f64,
    /// Positions, N × D, row-major.
    pub position: Vec<f64>,
    /// Velocities, N × D, row-major.
    pub velocity: Vec<f64>,
}

/// Everything a replica produced.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// How it ended.
    pub status: Status,
    /// Why (empty when done normally).
    pub message: String,
    /// Sampled observables.
    pub series: Series,
    /// Stored snapshots.
    pub snapshots: Vec<Snapshot>,
    /// Box sides.
    pub box_len: Vec<f64>,
    /// Particle radii.
    pub radius: Vec<f64>,
    /// Particle masses.
    pub mass: Vec<f64>,
    /// Initial temperature T0.
    pub t0: f64,
    /// Pair collisions run.
    pub collisions: u64,
    /// (time, τ) of a detected collapse.
    pub collapse: Option<(f64, f64)>,
    /// Wall-clock seconds spent simulating.
    pub wall_s: f64,
    /// The classifier's verdict (None unless the spec has a `classify` section).
    pub classification: Option<Classification>,
    /// Particles per cell of the order-parameter grid (NaN without classification).
    pub per_cell: f64,
}

impl Outcome {
    fn failed(message: String) -> Outcome {
        Outcome {
            status: Status::Failed,
            message,
            series: Series::default(),
            snapshots: Vec::new(),
            box_len: Vec::new(),
            radius: Vec::new(),
            mass: Vec::new(),
            t0: f64::NAN,
            collisions: 0,
            collapse: None,
            wall_s: 0.0,
            classification: None,
            per_cell: f64::NAN,
        }
    }

    /// The last sample's τ, or 0.
    pub fn final_tau(&self) -> f64 {
        self.series.tau.last().copied().unwrap_or(0.0)
    }
}

/// Runs a replica. `progress` is called with the number of new pair collisions every so often.
pub fn run(spec: &Spec, r: &Replica, progress: &(dyn Fn(u64) + Sync)) -> Outcome {
    let start = Instant::now();
    let result = match r.dim {
        2 => by_boundary::<2>(spec, r, progress),
        3 => by_boundary::<3>(spec, r, progress),
        d => Err(EdmdError::invalid("dim", d, "dimension must be 2 or 3")),
    };
    let mut outcome = result.unwrap_or_else(|e| Outcome::failed(e.to_string()));
    outcome.wall_s = start.elapsed().as_secs_f64();
    if spec.classify.is_some() && outcome.classification.is_none() {
        outcome.classification = Some(Classification {
            class: Class::Failed,
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: Vec::new(),
            note: String::new(),
        });
    }
    outcome
}

fn by_boundary<const D: usize>(
    spec: &Spec,
    r: &Replica,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Outcome, EdmdError> {
    match r.boundary {
        BoundaryKind::Periodic => by_rule::<D, Periodic>(spec, r, progress),
        BoundaryKind::Walls => by_rule::<D, Walls>(spec, r, progress),
        BoundaryKind::Channel => by_rule::<D, Channel>(spec, r, progress),
    }
}

fn by_rule<const D: usize, B: Boundary>(
    spec: &Spec,
    r: &Replica,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Outcome, EdmdError> {
    match spec.rule {
        RuleSpec::Constant => {
            by_remedy::<D, B, _>(spec, r, ConstantRestitution::new(r.eps)?, progress)
        }
        RuleSpec::Threshold { delta, eps_low } => by_remedy::<D, B, _>(
            spec,
            r,
            ThresholdRestitution::new(r.eps, eps_low, delta)?,
            progress,
        ),
        RuleSpec::Thesis { v0 } => {
            by_remedy::<D, B, _>(spec, r, ThesisRestitution::new(r.eps, v0)?, progress)
        }
        RuleSpec::Viscoelastic { speed } => {
            by_remedy::<D, B, _>(spec, r, viscoelastic(r.eps, speed)?, progress)
        }
    }
}

fn by_remedy<const D: usize, B: Boundary, R: CollisionRule<State = ()>>(
    spec: &Spec,
    r: &Replica,
    rule: R,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Outcome, EdmdError> {
    match r.remedy {
        Remedy::None => simulate::<D, B, R>(spec, r, rule, progress),
        Remedy::Tc { tc } => simulate::<D, B, _>(spec, r, TcModel::new(rule, tc)?, progress),
        Remedy::Rotation { theta_max_deg } => simulate::<D, B, _>(
            spec,
            r,
            RandomRotation::new(rule, theta_max_deg.to_radians())?,
            progress,
        ),
    }
}

/// What linear theory says about a replica's box (critical sizes halved when any axis has walls).
pub fn theory(spec: &Spec, r: &Replica) -> Theory {
    let periodic = r.boundary == BoundaryKind::Periodic;
    let (lp, lq) = critical_box_sides(r.dim, r.eps, r.phi(), periodic);
    let grid = spec
        .classify
        .as_ref()
        .map(|c| c.grid_for(r.n, r.dim))
        .unwrap_or(1);
    Theory {
        haff_rate: matches!(spec.rule, RuleSpec::Constant).then(|| haff_rate(r.dim, r.eps)),
        l_over_l_perp: r.side() / lp,
        l_over_l_par: r.side() / lq,
        per_cell: r.n as f64 / (grid as f64).powi(r.dim as i32),
    }
}

/// Events between progress reports and checks for ceased collisions.
const CHUNK_EVENTS: u64 = 500_000;

/// A replica whose last `STALL_WINDOW_PER_PARTICLE`·N events (at least) brought fewer than one pair
/// collision per `STALL_EVENTS_PER_COLLISION` events has stopped colliding: an inelastic gas can order
/// into lanes that stream past each other and only cross cells. Without this guard such a replica
/// would spend ever more events per τ and never end.
const STALL_EVENTS_PER_COLLISION: u64 = 1000;
const STALL_WINDOW_PER_PARTICLE: u64 = 1000;

fn flat<const D: usize>(v: &[Vector<D>]) -> Vec<f64> {
    v.iter().flat_map(|x| x.iter().copied()).collect()
}

fn simulate<const D: usize, B: Boundary, R: CollisionRule>(
    spec: &Spec,
    r: &Replica,
    rule: R,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Outcome, EdmdError> {
    let mut p = InitParams::<D>::in_box(r.n, Vector::<D>::repeat(r.side()));
    p.seed = r.seed;
    p.velocities = match spec.init.velocities {
        VelocityKind::Maxwell => Velocities::Maxwell,
        VelocityKind::Uniform => Velocities::Uniform,
    };
    p.melt_tau = spec.init.melt_tau;
    let mut sim: Simulation<D, B, R> = p.build::<B, R>(rule)?;
    let t0 = sim.temperature();
    let n = r.n as f64;
    let volume = sim.box_len().iter().product::<f64>();
    let haff = matches!(spec.rule, RuleSpec::Constant);
    let grid = spec.classify.as_ref().map(|c| c.grid_for(r.n, D));
    let masses = sim.masses();
    let theory = theory(spec, r);

    let mut snapshot_points = spec.snapshots.at.clone();
    snapshot_points.retain(|&t| t <= spec.stop.tau_max);
    let schedule = Schedule {
        linear: spec.samples.every,
        log_per_decade: (spec.samples.per_decade > 0).then_some(spec.samples.per_decade),
        log_start: spec.samples.log_from,
        points: snapshot_points
            .iter()
            .copied()
            .chain([0.0, spec.stop.tau_max])
            .collect(),
    };

    let mut series = Series::default();
    let mut snapshots = Vec::new();
    let mut meter: Option<VirialMeter> = None;
    let mut reported = 0u64;
    let mut sampled_at: Option<u64> = None;

    let sample = |sim: &Simulation<D, B, R>,
                  series: &mut Series,
                  snapshots: &mut Vec<Snapshot>,
                  meter: &mut Option<VirialMeter>,
                  snapshot: bool| {
        let o = sim.observe();
        let z = match meter {
            Some(m) if sim.time() > 0.0 => {
                let reading = m.read(sim);
                if reading.duration > 0.0 {
                    reading.z
                } else {
                    f64::NAN
                }
            }
            _ => f64::NAN,
        };
        *meter = Some(VirialMeter::start(sim));
        series.step.push(o.pair_collisions as i64);
        series.time.push(o.time);
        series.tau.push(o.tau);
        series.temperature.push(o.temperature);
        series.ln_temperature.push(o.ln_temperature);
        series.kinetic_energy.push(o.kinetic_energy);
        series.kurtosis.push(o.kurtosis);
        series.wall_collisions.push(o.wall_collisions as i64);
        series.compressibility.push(z);
        series.pressure.push(z * n * o.temperature / volume);
        series
            .momentum_error
            .push(o.momentum.norm() / o.momentum_scale.max(f64::MIN_POSITIVE));
        series.haff_temperature.push(if haff {
            haff_temperature_tau(D, r.eps, t0, o.tau)
        } else {
            f64::NAN
        });
        if let Some(grid) = grid {
            let mut walls = [false; D];
            for (a, w) in walls.iter_mut().enumerate() {
                *w = B::WALL_MASK & (1 << a) != 0;
            }
            let op = order_parameters(
                &sim.positions(),
                &sim.velocities_internal(),
                &masses,
                sim.box_len(),
                walls,
                grid,
            );
            let os = &mut series.order;
            os.tau.push(o.tau);
            os.ln_temperature.push(o.ln_temperature);
            os.f_flow.push(op.f_flow);
            os.s_perp.push(op.s_perp);
            os.delta_rho2.push(op.delta_rho2);
            os.f_2x.push(op.f_2x);
            os.s_rho.push(op.s_rho);
        }
        if snapshot {
            snapshots.push(Snapshot {
                step: o.pair_collisions as i64,
                time: o.time,
                position: flat(&sim.positions()),
                velocity: flat(&sim.velocities()),
            });
        }
    };

    let mut next = schedule.first_at_or_after(0.0);
    let mut end = RunEnd::Reached;
    let mut stopped_cold = false;
    let mut stalled = false;
    let mut window = (sim.counters().events, sim.counters().pair_collisions);
    let mut settled_as: Option<Class> = None;
    while let Some(point) = next {
        // Advance to the sample point in chunks, reporting progress.
        let target = (point * n).ceil() as u64;
        while end == RunEnd::Reached && sim.counters().pair_collisions < target && !stalled {
            // A pair collision is one event, so this many events cannot overshoot the target.
            let left = target - sim.counters().pair_collisions;
            end = sim.run(Stop::Events(left.min(CHUNK_EVENTS)));
            let c = *sim.counters();
            progress(c.pair_collisions - reported);
            reported = c.pair_collisions;
            let (events, pairs) = (c.events - window.0, c.pair_collisions - window.1);
            if events >= STALL_WINDOW_PER_PARTICLE * r.n as u64 {
                stalled = pairs * STALL_EVENTS_PER_COLLISION < events;
                window = (c.events, c.pair_collisions);
            }
        }
        if stalled {
            break;
        }
        if end != RunEnd::Reached {
            break;
        }
        let snap = snapshot_points.contains(&point);
        sample(&sim, &mut series, &mut snapshots, &mut meter, snap);
        sampled_at = Some(sim.counters().pair_collisions);
        if let Some(ratio) = spec.stop.temperature_ratio {
            if sim.ln_temperature() - t0.ln() < ratio.ln() {
                stopped_cold = true;
                break;
            }
        }
        if let (true, Some(c)) = (spec.stop.classified, &spec.classify) {
            settled_as = settled(&series.order, &c.thresholds, &theory);
            if settled_as.is_some() {
                break;
            }
        }
        next = schedule
            .next_after(point)
            .filter(|&t| t <= spec.stop.tau_max);
    }
    let c = sim.counters().pair_collisions;
    progress(c - reported);
    // The final state: sampled once, with a snapshot when asked.
    let final_snapshot = spec.snapshots.last;
    if sampled_at != Some(c) {
        sample(
            &sim,
            &mut series,
            &mut snapshots,
            &mut meter,
            final_snapshot,
        );
    } else if final_snapshot && snapshots.last().map(|s| s.step) != Some(c as i64) {
        snapshots.push(Snapshot {
            step: c as i64,
            time: sim.time(),
            position: flat(&sim.positions()),
            velocity: flat(&sim.velocities()),
        });
    }
    let (status, message, collapse) = match end {
        RunEnd::Collapsed => {
            let col = sim
                .collapse()
                .expect("a collapsed run records its collapse");
            (
                Status::Collapsed,
                format!(
                    "inelastic collapse ({:?}) at time {:.6e}, tau {:.4}",
                    col.reason, col.time, col.tau
                ),
                Some((col.time, col.tau)),
            )
        }
        RunEnd::Exhausted => (
            Status::Done,
            "no events left: every particle at rest".into(),
            None,
        ),
        RunEnd::Reached if stalled => (
            Status::Done,
            format!(
                "collisions ceased at tau = {:.2}: more than {STALL_EVENTS_PER_COLLISION} events per pair collision (the gas streams in lanes)",
                sim.tau()
            ),
            None,
        ),
        RunEnd::Reached if stopped_cold => (
            Status::Done,
            "stopped at stop.temperature_ratio".into(),
            None,
        ),
        RunEnd::Reached if settled_as.is_some() => (
            Status::Done,
            format!(
                "stopped early: class {} settled (stop.classified)",
                settled_as.map(|c| c.name()).unwrap_or_default()
            ),
            None,
        ),
        RunEnd::Reached => (Status::Done, String::new(), None),
    };
    let radius = vec![p.radius; r.n];
    let classification = spec.classify.as_ref().map(|c| match status {
        Status::Done => classify(&series.order, &c.thresholds, &theory),
        Status::Collapsed | Status::Failed | Status::Missing => Classification {
            class: if status == Status::Collapsed {
                Class::Collapsed
            } else {
                Class::Failed
            },
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: crate::classify::haff_deviation(
                &series.order,
                c.thresholds.haff_tau0,
                theory.haff_rate,
            )
            .0,
            note: String::new(),
        },
    });
    Ok(Outcome {
        status,
        message,
        series,
        snapshots,
        box_len: sim.box_len().iter().copied().collect(),
        radius,
        mass: sim.masses(),
        t0,
        collisions: c,
        collapse,
        wall_s: 0.0,
        classification,
        per_cell: theory.per_cell,
    })
}
