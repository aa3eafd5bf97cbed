//! The run of one replica in its monomorphised types: melt, cool to the stop, sample observables
//! and order parameters on the schedule, keep the snapshots, watch for collapse and stalls.

use edmd_core::{Boundary, CollisionRule, EdmdError, Engine, InitParams, RunEnd, Simulation, Stop};

use super::checkpoint::{Checkpoints, Encoded, RunnerSaving, RunnerState, Timer};
use super::points::{same_point, Points};
use super::sampler::{snapshot, Sampler};
use super::setup::init_params;
use super::verdict::classification;
use super::{theory, Outcome, Series, Snapshot, Status};
use crate::classify::{settled, Class, Theory};
use crate::spec::{Replica, Spec};

/// Events between progress reports and checks for ceased collisions.
const CHUNK_EVENTS: u64 = 500_000;
/// A replica whose last `STALL_WINDOW_PER_PARTICLE`·N events (at least) brought fewer than one pair
/// collision per `STALL_EVENTS_PER_COLLISION` events has stopped colliding: an inelastic gas can order
/// into lanes that stream past each other and only cross cells. Without this guard such a replica
/// would spend ever more events per τ and never end.
pub(super) const STALL_EVENTS_PER_COLLISION: u64 = 1000;
const STALL_WINDOW_PER_PARTICLE: u64 = 1000;

/// Runs replica `r` in the scene `B` with `rule`, from its checkpoint if `ckpt` has one: the only
/// part compiled per scene and grain kind is building the simulation; the run itself is [`drive`],
/// compiled once per dimension. `None`: interrupted, its checkpoint written.
pub(super) fn simulate<const D: usize, B: Boundary, R: CollisionRule>(
    spec: &Spec,
    r: &Replica,
    rule: R,
    progress: &(dyn Fn(u64) + Sync),
    ckpt: Option<&Checkpoints>,
) -> Result<Option<Outcome>, EdmdError> {
    let saved = ckpt.and_then(|c| {
        c.load(r.index).unwrap_or_else(|why| {
            c.notice(format!(
                "checkpoint unusable, the replica starts over: {why}"
            ));
            None
        })
    });
    let (p, species_of) = init_params::<D>(spec, r)?;
    let resumed = saved.and_then(|s| {
        // The state comes from the checkpoint: no melt to run first.
        let outline = InitParams {
            melt_tau: Some(0.0),
            ..p.clone()
        };
        let mut sim: Simulation<D, B, R> = match outline.build::<B, R>(rule.clone()) {
            Ok(sim) => sim,
            Err(e) => return Some(Err(e)),
        };
        match sim.load_state(&s.engine) {
            Ok(()) => Some(Ok((sim, s.runner))),
            Err(e) => {
                // Another build's layout, say: the replica starts over rather than fails.
                if let Some(c) = ckpt {
                    c.notice(format!(
                        "checkpoint of replica {} unusable, the replica starts over: {e}",
                        r.index
                    ));
                }
                None
            }
        }
    });
    let (mut sim, resume) = match resumed.transpose()? {
        Some((sim, runner)) => (sim, Some(runner)),
        None => (p.build::<B, R>(rule)?, None),
    };
    drive(spec, r, &p, &species_of, &mut sim, progress, ckpt, resume)
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
    ckpt: Option<&Checkpoints>,
    resume: Option<RunnerState>,
) -> Result<Option<Outcome>, EdmdError> {
    let theory = theory(spec, r);
    let mut sampler = Sampler::new(spec, r, species_of, &*sim);
    let mut run = Run::new(spec, r, *sim.counters(), ckpt);
    if let Some(state) = resume {
        run.resume(state, &mut sampler);
        run.reported = sim.counters().pair_collisions;
        progress(run.reported);
    }
    run.go(sim, &mut sampler, &theory, progress);
    if run.interrupted {
        return Ok(None);
    }
    let c = sim.counters().pair_collisions;
    progress(c - run.reported);
    // The final state: sampled once, with a snapshot when asked.
    let final_snapshot = spec.snapshots.last;
    if run.sampled_at != Some(c) {
        sampler.sample(
            &mut *sim,
            &mut run.series,
            &mut run.snapshots,
            final_snapshot,
        );
    } else if final_snapshot && run.snapshots.last().map(|s| s.step) != Some(c as i64) {
        run.snapshots.push(snapshot(&*sim));
    }
    let (status, message, collapse) = run.ending(&*sim);
    let classification = classification(spec, r, status, &run.series, &theory);
    Ok(Some(Outcome {
        status,
        message,
        series: run.series,
        snapshots: run.snapshots,
        box_len: sim.box_len().iter().copied().collect(),
        profile_bins: sampler.profile_bins,
        radius: p.radii.clone().unwrap_or_else(|| vec![p.radius; r.n]),
        mass: sim.masses(),
        species: if r.species.is_some() {
            species_of.iter().map(|&k| k as i64).collect()
        } else {
            Vec::new()
        },
        t0: sampler.t0(),
        collisions: c,
        collapse,
        wall_s: run.wall_before,
        resumes: run.resumes,
        classification,
        per_cell: theory.per_cell,
        bed: sampler.bed.as_ref().and_then(|b| b.summary(r)),
    }))
}

/// The run of a replica from sample point to sample point, and how it ended.
struct Run<'a> {
    spec: &'a Spec,
    r: &'a Replica,
    series: Series,
    snapshots: Vec<Snapshot>,
    end: RunEnd,
    stopped_cold: bool,
    stalled: Option<String>,
    settled_as: Option<Class>,
    /// Pair collisions already reported to `progress`.
    reported: u64,
    /// The collision count of the last sample.
    sampled_at: Option<u64>,
    /// The counters at the start of the current stall window.
    window: edmd_core::Counters,
    /// The sample and snapshot points, and the one the run is heading for.
    points: Points,
    point: Option<f64>,
    /// Where and when the replica saves its state.
    ckpt: Option<&'a Checkpoints<'a>>,
    timer: Option<Timer>,
    /// Stopped by a signal, its checkpoint written.
    interrupted: bool,
    /// Wall-clock seconds of the runs before this one (from the checkpoint).
    wall_before: f64,
    /// Times this replica went on from a saved state, this run included.
    resumes: u64,
    started: std::time::Instant,
}

impl<'a> Run<'a> {
    fn new(
        spec: &'a Spec,
        r: &'a Replica,
        counters: edmd_core::Counters,
        ckpt: Option<&'a Checkpoints<'a>>,
    ) -> Self {
        Run {
            spec,
            r,
            series: Series::default(),
            snapshots: Vec::new(),
            end: RunEnd::Reached,
            stopped_cold: false,
            stalled: None,
            settled_as: None,
            reported: 0,
            sampled_at: None,
            window: counters,
            points: Points::new(spec),
            point: None,
            ckpt,
            timer: None,
            interrupted: false,
            wall_before: 0.0,
            resumes: 0,
            started: std::time::Instant::now(),
        }
    }

    /// Goes on from a checkpoint's runner state.
    fn resume(&mut self, s: RunnerState, sampler: &mut Sampler<'_>) {
        self.series = s.series;
        self.snapshots = s.snapshots;
        self.point = Some(s.point);
        self.points.next_snapshot = s.next_snapshot;
        self.sampled_at = s.sampled_at;
        self.window = s.window;
        self.wall_before = s.wall_s;
        self.resumes = s.resumes + 1;
        sampler.resume((s.t0, s.meter, s.start), s.bed);
    }

    /// The replica's state now, encoded (with its snapshots, or only their count: a final state's
    /// are in the replica's file).
    fn encoded<const D: usize>(
        &self,
        sim: &dyn Engine<D>,
        sampler: &Sampler<'_>,
        with_snapshots: bool,
    ) -> Encoded {
        let (t0, meter, start) = sampler.state();
        let wall_s = self.wall_before + self.started.elapsed().as_secs_f64();
        let runner = RunnerSaving {
            series: &self.series,
            snapshots: if with_snapshots { &self.snapshots } else { &[] },
            snapshots_in_file: if with_snapshots {
                0
            } else {
                self.snapshots.len()
            },
            point: self.point.expect("a state is saved on the way to a point"),
            next_snapshot: self.points.next_snapshot,
            sampled_at: self.sampled_at,
            window: self.window,
            t0,
            meter,
            start,
            wall_s,
            resumes: self.resumes,
            bed: sampler.bed.as_ref(),
        };
        Encoded::new(&runner, wall_s, sim.save_state())
    }

    /// At τ_max, before its sample: keeps the state for `edmd extend`, which goes on from here.
    fn save_final<const D: usize>(&self, sim: &dyn Engine<D>, sampler: &Sampler<'_>) {
        let Some(c) = self.ckpt.filter(|c| c.keep_final()) else {
            return;
        };
        let state = self.encoded(sim, sampler, false);
        c.save_final(
            self.r.index,
            sim.tau(),
            sim.counters().pair_collisions,
            &state,
        );
    }

    /// Saves the replica's state when a checkpoint is due (between two chunks of events); after a
    /// signal's checkpoint the run stops.
    fn checkpoint_if_due<const D: usize>(&mut self, sim: &dyn Engine<D>, sampler: &Sampler<'_>) {
        let Some(c) = self.ckpt else {
            return;
        };
        let tau = sim.tau();
        let timer = self.timer.get_or_insert_with(|| Timer::new(c, tau));
        let Some(why) = timer.due(c, tau) else {
            return;
        };
        let began = std::time::Instant::now();
        let state = self.encoded(sim, sampler, true);
        let collisions = sim.counters().pair_collisions;
        c.save(self.r.index, tau, collisions, why, &state);
        c.count(began.elapsed().as_secs_f64());
        self.interrupted = why == "signal";
    }

    /// Samples at every point of the schedule until the stop, a collapse, a stall or an early stop.
    fn go<const D: usize>(
        &mut self,
        sim: &mut dyn Engine<D>,
        sampler: &mut Sampler<'_>,
        theory: &Theory,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let t0 = sampler.t0();
        let mut next = self.point.or_else(|| self.points.first());
        while let Some(point) = next {
            self.point = Some(point);
            let target = (point * self.r.n as f64).ceil() as u64;
            self.advance(sim, sampler, target, progress);
            if self.interrupted || self.stalled.is_some() || self.end != RunEnd::Reached {
                break;
            }
            if same_point(point, self.points.tau_max()) {
                self.save_final(&*sim, sampler);
            }
            let snap = self.points.take_snapshot(point);
            let c = sim.counters().pair_collisions;
            if self.sampled_at != Some(c) {
                sampler.sample(&mut *sim, &mut self.series, &mut self.snapshots, snap);
            } else if snap && self.snapshots.last().map(|s| s.step) != Some(c as i64) {
                // Two schedule points on one collision (small N): one sample, and the snapshot
                // asked for here is the state already sampled.
                self.snapshots.push(snapshot(&*sim));
            }
            self.sampled_at = Some(sim.counters().pair_collisions);
            if point >= 0.5 * self.points.tau_max() {
                sampler.start_bed();
            }
            if self.stops_early(&*sim, t0, theory) {
                break;
            }
            next = self.points.next(point);
        }
    }

    /// Advances to `target` pair collisions in chunks, reporting progress and watching for ceased
    /// collisions.
    fn advance<const D: usize>(
        &mut self,
        sim: &mut dyn Engine<D>,
        sampler: &mut Sampler<'_>,
        target: u64,
        progress: &(dyn Fn(u64) + Sync),
    ) {
        let n = self.r.n as u64;
        while self.end == RunEnd::Reached
            && sim.counters().pair_collisions < target
            && self.stalled.is_none()
        {
            // A pair collision is one event, so this many events cannot overshoot the target; a
            // shaken bed also stops at its sample times (`replica::bed_meter`).
            let left = target - sim.counters().pair_collisions;
            let events = left.min(CHUNK_EVENTS);
            let before = sim.counters().events;
            let bed_time = sampler.bed_time();
            self.end =
                sim.run(bed_time.map_or(Stop::Events(events), |t| Stop::EventsOrTime(events, t)));
            // Reached before its events ran out: the run stopped at the sample time.
            if bed_time.is_some()
                && self.end == RunEnd::Reached
                && sim.counters().events - before < events
            {
                sampler.record_bed(&*sim);
            }
            let c = *sim.counters();
            progress(c.pair_collisions - self.reported);
            self.reported = c.pair_collisions;
            let events = c.events - self.window.events;
            let pairs = c.pair_collisions - self.window.pair_collisions;
            if events >= STALL_WINDOW_PER_PARTICLE * n {
                if pairs * STALL_EVENTS_PER_COLLISION < events {
                    self.stalled = Some(super::stall::stall_reason(
                        self.r,
                        &self.window,
                        &c,
                        sim.tau(),
                    ));
                }
                self.window = c;
            }
            if self.stalled.is_none() && self.end == RunEnd::Reached {
                self.checkpoint_if_due(&*sim, sampler);
                if self.interrupted {
                    return;
                }
            }
        }
    }

    /// The early stops: cold enough (`stop.temperature_ratio`), or classified (`stop.classified`).
    fn stops_early<const D: usize>(
        &mut self,
        sim: &dyn Engine<D>,
        t0: f64,
        theory: &Theory,
    ) -> bool {
        if let Some(ratio) = self.spec.stop.temperature_ratio {
            if sim.ln_temperature() - t0.ln() < ratio.ln() {
                self.stopped_cold = true;
                return true;
            }
        }
        if let (true, Some(c), false) = (
            self.spec.stop.classified,
            &self.spec.classify,
            self.r.driven_or_stratified(),
        ) {
            self.settled_as = settled(&self.series.order, &c.thresholds, theory);
            return self.settled_as.is_some();
        }
        false
    }

    /// How the run ended: its status, the message and, for a collapse, its time and τ.
    fn ending<const D: usize>(
        &mut self,
        sim: &dyn Engine<D>,
    ) -> (Status, String, Option<(f64, f64)>) {
        match self.end {
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
            RunEnd::Reached if self.stalled.is_some() => {
                (Status::Stalled, self.stalled.take().unwrap_or_default(), None)
            }
            RunEnd::Reached if self.stopped_cold => (
                Status::Done,
                "stopped at stop.temperature_ratio".into(),
                None,
            ),
            RunEnd::Reached if self.settled_as.is_some() => (
                Status::Done,
                format!(
                    "stopped early: class {} settled (stop.classified)",
                    self.settled_as.map(|c| c.name()).unwrap_or_default()
                ),
                None,
            ),
            RunEnd::Reached => (Status::Done, String::new(), None),
        }
    }
}
