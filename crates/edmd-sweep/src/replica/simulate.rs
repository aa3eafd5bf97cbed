//! The run of one replica in its monomorphised types: melt, cool to the stop, sample observables
//! and order parameters on the schedule, keep the snapshots, watch for collapse and stalls.

use edmd_core::theory::haff_temperature_tau;
use edmd_core::{
    order_parameters, Boundary, CollisionRule, EdmdError, Engine, InitParams, RunEnd, Schedule,
    SimParams, Simulation, Stop, Vector, Velocities, VirialMeter,
};

use super::{theory, Outcome, Series, Snapshot, Status};
use crate::classify::{classify, settled, Class, Classification};
use crate::spec::{Replica, RuleSpec, Spec, VelocityKind};

/// Events between progress reports and checks for ceased collisions.
const CHUNK_EVENTS: u64 = 500_000;

/// A replica whose last `STALL_WINDOW_PER_PARTICLE`·N events (at least) brought fewer than one pair
/// collision per `STALL_EVENTS_PER_COLLISION` events has stopped colliding: an inelastic gas can order
/// into lanes that stream past each other and only cross cells. Without this guard such a replica
/// would spend ever more events per τ and never end.
pub(super) const STALL_EVENTS_PER_COLLISION: u64 = 1000;
const STALL_WINDOW_PER_PARTICLE: u64 = 1000;

fn flat<const D: usize>(v: &[Vector<D>]) -> Vec<f64> {
    v.iter().flat_map(|x| x.iter().copied()).collect()
}

/// Angular velocities of rough grains, N × 1 (ω_z) in 2D and N × 3 in 3D; empty for smooth grains.
fn spins<const D: usize>(sim: &dyn Engine<D>) -> Vec<f64> {
    if !sim.rough() {
        return Vec::new();
    }
    let w = sim.spins();
    if D == 2 {
        w.iter().map(|s| s[2]).collect()
    } else {
        w.iter().flat_map(|s| s.iter().copied()).collect()
    }
}

/// The state now, in the original particle order.
fn snapshot<const D: usize>(sim: &dyn Engine<D>) -> Snapshot {
    Snapshot {
        step: sim.counters().pair_collisions as i64,
        time: sim.time(),
        position: flat(&sim.positions()),
        velocity: flat(&sim.velocities()),
        angular_velocity: spins(sim),
        box_offset: sim.shear_offset(),
    }
}

/// Rotational degrees of freedom per particle: 1 for disks, 3 for spheres.
const fn rotational_dof(d: usize) -> f64 {
    if d == 2 {
        1.0
    } else {
        3.0
    }
}

/// Runs replica `r` in the scene `B` with `rule`: the only part compiled per scene and grain kind
/// is building the simulation; the run itself is [`drive`], compiled once per dimension.
pub(super) fn simulate<const D: usize, B: Boundary, R: CollisionRule>(
    spec: &Spec,
    r: &Replica,
    rule: R,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Outcome, EdmdError> {
    let (p, species_of) = init_params::<D>(spec, r);
    let mut sim: Simulation<D, B, R> = p.build::<B, R>(rule)?;
    drive(spec, r, &p, &species_of, &mut sim, progress)
}

/// The set-up of replica `r`: box, seed, velocities, species (and the species of each slot), walls,
/// gravity and floor.
pub(super) fn init_params<const D: usize>(spec: &Spec, r: &Replica) -> (InitParams<D>, Vec<usize>) {
    let sides = r.sides();
    let mut p = InitParams::<D>::in_box(r.n, Vector::<D>::from_fn(|a, _| sides[a]));
    p.seed = r.seed;
    p.velocities = match spec.init.velocities {
        VelocityKind::Maxwell => Velocities::Maxwell,
        VelocityKind::Uniform => Velocities::Uniform,
    };
    p.melt_tau = spec.init.melt_tau;
    // A mixture: species k takes the next N_k slots (diameter σ_k, mass m_k); PHYSICS.md §2.4.
    let species_of: Vec<usize> = r
        .species_counts()
        .iter()
        .enumerate()
        .flat_map(|(k, &c)| std::iter::repeat_n(k, c))
        .collect();
    if let Some(m) = &r.species {
        p.radii = Some(species_of.iter().map(|&k| 0.5 * m[k].diameter).collect());
        p.masses = Some(species_of.iter().map(|&k| m[k].mass_in(D)).collect());
    }
    // Walls, gravity and a thermal floor of the scene (PHYSICS.md §1.4), or its shear (§7).
    if r.gravity > 0.0 || r.wall_eps != 1.0 || r.floor_temperature > 0.0 || r.sheared() {
        p.sim = Some(SimParams {
            gravity: r.gravity,
            wall_epsilon: r.wall_eps,
            floor_temperature: r.floor_temperature,
            shear_rate: if r.sheared() { r.shear_rate } else { 0.0 },
            ..p.default_sim_params()
        });
    }
    (p, species_of)
}

/// Melts, cools to the stop, samples observables and order parameters on the schedule, keeps the
/// snapshots, watches for collapse and stalls, and classifies: the whole run of a replica against
/// the object-safe [`Engine`].
fn drive<const D: usize>(
    spec: &Spec,
    r: &Replica,
    p: &InitParams<D>,
    species_of: &[usize],
    sim: &mut dyn Engine<D>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Outcome, EdmdError> {
    let sides = r.sides();
    let counts = r.species_counts();
    let t0 = sim.temperature();
    let n = r.n as f64;
    let volume = sim.box_len().iter().product::<f64>();
    // Haff's law of one species of smooth grains; rough grains and mixtures cool by other laws.
    let haff = matches!(spec.rule, RuleSpec::Constant {})
        && !r.rough()
        && r.species.is_none()
        && !r.driven_or_stratified()
        && r.wall_eps == 1.0;
    // Order parameters only where the classes apply (free cooling).
    let grid = spec
        .classify
        .as_ref()
        .filter(|_| !r.driven_or_stratified())
        .map(|c| c.grid_for(r.n, D));
    // Under gravity: the number density n(z) along the last axis in bins of about one diameter.
    let profile_bins = if r.gravity > 0.0 {
        (sides[D - 1].floor() as usize).max(1)
    } else {
        0
    };
    let cross_section: f64 = sides[..D - 1].iter().product();
    let masses = sim.masses();
    let theory = theory(spec, r);

    let mut snapshot_points = spec.snapshots.at.clone();
    snapshot_points.retain(|&t| t <= spec.stop.tau_max);
    // The snapshot times (the `at` points and the snapshot grids); each is also a sample.
    let snapshot_times = spec.snapshots.schedule();
    let mut next_snapshot = snapshot_times
        .first_at_or_after(0.0)
        .filter(|&t| t <= spec.stop.tau_max);
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

    let sample = |sim: &mut dyn Engine<D>,
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
        if profile_bins > 0 {
            let width = sides[D - 1] / profile_bins as f64;
            let mut n_z = vec![0.0; profile_bins];
            for x in sim.positions() {
                let b = ((x[D - 1] / width) as usize).min(profile_bins - 1);
                n_z[b] += 1.0 / (cross_section * width);
            }
            series.density_profile.push(n_z);
        }
        if r.species.is_some() {
            // T_k = Σ_{a∈k} m v_a² / (d N_k), species in order.
            let mut e = vec![0.0; counts.len()];
            for ((v, m), &k) in sim
                .peculiar_velocities()
                .iter()
                .zip(&masses)
                .zip(species_of)
            {
                e[k] += m * v.norm_squared();
            }
            series.species_temperature.push(
                e.iter()
                    .zip(&counts)
                    .map(|(e, &c)| e / (D as f64 * c as f64))
                    .collect(),
            );
        }
        if r.sheared() {
            series.shear.sample(sim, &masses);
        }
        if sim.rough() {
            // T_rot = Σ I ω² / (d_rot N) (PHYSICS.md §6.5), beside the translational T.
            series
                .rotational_temperature
                .push(2.0 * sim.rotational_energy() / (rotational_dof(D) * n));
        }
        series.haff_temperature.push(if haff {
            haff_temperature_tau(D, r.eps, t0, o.tau)
        } else {
            f64::NAN
        });
        if let Some(grid) = grid {
            let mut walls = [false; D];
            for (a, w) in walls.iter_mut().enumerate() {
                *w = sim.has_walls(a);
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
            snapshots.push(self::snapshot(sim));
        }
    };

    let mut next = earliest(schedule.first_at_or_after(0.0), next_snapshot);
    let mut end = RunEnd::Reached;
    let mut stopped_cold = false;
    let mut stalled: Option<String> = None;
    let mut window = *sim.counters();
    let mut settled_as: Option<Class> = None;
    while let Some(point) = next {
        // Advance to the sample point in chunks, reporting progress.
        let target = (point * n).ceil() as u64;
        while end == RunEnd::Reached && sim.counters().pair_collisions < target && stalled.is_none()
        {
            // A pair collision is one event, so this many events cannot overshoot the target.
            let left = target - sim.counters().pair_collisions;
            end = sim.run(Stop::Events(left.min(CHUNK_EVENTS)));
            let c = *sim.counters();
            progress(c.pair_collisions - reported);
            reported = c.pair_collisions;
            let (events, pairs) = (
                c.events - window.events,
                c.pair_collisions - window.pair_collisions,
            );
            if events >= STALL_WINDOW_PER_PARTICLE * r.n as u64 {
                if pairs * STALL_EVENTS_PER_COLLISION < events {
                    stalled = Some(super::stall::stall_reason(r, &window, &c, sim.tau()));
                }
                window = c;
            }
        }
        if stalled.is_some() {
            break;
        }
        if end != RunEnd::Reached {
            break;
        }
        let snap = next_snapshot.is_some_and(|t| same_point(t, point));
        let c = sim.counters().pair_collisions;
        if sampled_at != Some(c) {
            sample(&mut *sim, &mut series, &mut snapshots, &mut meter, snap);
        } else if snap && snapshots.last().map(|s| s.step) != Some(c as i64) {
            // Two schedule points on one collision (small N): one sample, and the snapshot asked
            // for here is the state already sampled.
            snapshots.push(snapshot(&*sim));
        }
        if snap {
            next_snapshot = after(&snapshot_times, point, spec.stop.tau_max);
        }
        sampled_at = Some(sim.counters().pair_collisions);
        if let Some(ratio) = spec.stop.temperature_ratio {
            if sim.ln_temperature() - t0.ln() < ratio.ln() {
                stopped_cold = true;
                break;
            }
        }
        if let (true, Some(c), false) = (
            spec.stop.classified,
            &spec.classify,
            r.driven_or_stratified(),
        ) {
            settled_as = settled(&series.order, &c.thresholds, &theory);
            if settled_as.is_some() {
                break;
            }
        }
        next = earliest(after(&schedule, point, spec.stop.tau_max), next_snapshot);
    }
    let c = sim.counters().pair_collisions;
    progress(c - reported);
    // The final state: sampled once, with a snapshot when asked.
    let final_snapshot = spec.snapshots.last;
    if sampled_at != Some(c) {
        sample(
            &mut *sim,
            &mut series,
            &mut snapshots,
            &mut meter,
            final_snapshot,
        );
    } else if final_snapshot && snapshots.last().map(|s| s.step) != Some(c as i64) {
        snapshots.push(snapshot(&*sim));
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
            Status::Stalled,
            format!(
                "stalled at tau = {:.4}: no events left before the stop (every particle at rest)",
                sim.tau()
            ),
            None,
        ),
        RunEnd::Reached if stalled.is_some() => {
            (Status::Stalled, stalled.take().unwrap_or_default(), None)
        }
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
    let radius = p.radii.clone().unwrap_or_else(|| vec![p.radius; r.n]);
    let classification = spec.classify.as_ref().map(|c| match status {
        Status::Done if r.sheared() => {
            super::shear::classify(&series.shear, r.n, c.thresholds.cluster_density)
        }
        Status::Done if r.driven_or_stratified() => Classification {
            class: Class::NotApplicable,
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: Vec::new(),
            note: if r.gravity > 0.0 {
                "gravity: a stratified column is not free cooling".into()
            } else {
                "driven by a thermal floor: not free cooling".into()
            },
        },
        Status::Done => classify(&series.order, &c.thresholds, &theory),
        Status::Collapsed
        | Status::Stalled
        | Status::Failed
        | Status::Missing
        | Status::Corrupt => Classification {
            class: match status {
                Status::Collapsed => Class::Collapsed,
                Status::Stalled => Class::Stalled,
                _ => Class::Failed,
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
        profile_bins,
        radius,
        mass: sim.masses(),
        species: if r.species.is_some() {
            species_of.iter().map(|&k| k as i64).collect()
        } else {
            Vec::new()
        },
        t0,
        collisions: c,
        collapse,
        wall_s: 0.0,
        classification,
        per_cell: theory.per_cell,
    })
}

/// Two schedule points closer than round-off are one sample (a snapshot grid point and a sample
/// grid point computed as different products of the same τ).
fn same_point(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(1.0)
}

/// The first point of `schedule` after `point` (and not the same point), up to `tau_max`.
fn after(schedule: &Schedule, point: f64, tau_max: f64) -> Option<f64> {
    let mut t = schedule.next_after(point);
    while let Some(x) = t.filter(|&x| same_point(x, point)) {
        t = schedule.next_after(x);
    }
    t.filter(|&x| x <= tau_max)
}

/// The earlier of two optional points.
fn earliest(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => x.or(y),
    }
}
