//! The sample and snapshot points of a replica: the schedule's points and the snapshot times
//! merged, points closer than round-off taken as one.

use edmd_core::Schedule;

use crate::spec::Spec;

/// The sample and snapshot points of a replica, in τ.
pub(super) struct Points {
    schedule: Schedule,
    snapshot_times: Schedule,
    pub(super) next_snapshot: Option<f64>,
    tau_max: f64,
}

impl Points {
    pub(super) fn new(spec: &Spec) -> Self {
        let tau_max = spec.stop.tau_max;
        let mut snapshot_points = spec.snapshots.at.clone();
        snapshot_points.retain(|&t| t <= tau_max);
        // The snapshot times (the `at` points and the snapshot grids); each is also a sample.
        let snapshot_times = spec.snapshots.schedule();
        let next_snapshot = snapshot_times
            .first_at_or_after(0.0)
            .filter(|&t| t <= tau_max);
        let schedule = Schedule {
            linear: spec.samples.every,
            log_per_decade: (spec.samples.per_decade > 0).then_some(spec.samples.per_decade),
            log_start: spec.samples.log_from,
            points: snapshot_points
                .iter()
                .copied()
                .chain([0.0, tau_max])
                .collect(),
        };
        Points {
            schedule,
            snapshot_times,
            next_snapshot,
            tau_max,
        }
    }

    /// τ_max, the last point.
    pub(super) fn tau_max(&self) -> f64 {
        self.tau_max
    }

    /// Where a run that has reached `p` (a point of an earlier, shorter schedule, not yet sampled)
    /// is heading in this one: the first point at or after `p`; the next snapshot time is set as
    /// the run would have it there. Between the earlier schedule's points below its end and this
    /// one's there is no point that only one of them has.
    pub(super) fn resume_at(&mut self, p: f64) -> Option<f64> {
        let from = p - 1e-9 * p.abs().max(1.0);
        let tau_max = self.tau_max;
        self.next_snapshot = self
            .snapshot_times
            .first_at_or_after(from)
            .filter(|&t| t <= tau_max);
        earliest(
            self.schedule
                .first_at_or_after(from)
                .filter(|&t| t <= tau_max),
            self.next_snapshot,
        )
    }

    pub(super) fn first(&self) -> Option<f64> {
        earliest(self.schedule.first_at_or_after(0.0), self.next_snapshot)
    }

    /// Whether `point` takes a snapshot; if so, the next snapshot time moves on.
    pub(super) fn take_snapshot(&mut self, point: f64) -> bool {
        let snap = self.next_snapshot.is_some_and(|t| same_point(t, point));
        if snap {
            self.next_snapshot = after(&self.snapshot_times, point, self.tau_max);
        }
        snap
    }

    pub(super) fn next(&self, point: f64) -> Option<f64> {
        earliest(
            after(&self.schedule, point, self.tau_max),
            self.next_snapshot,
        )
    }
}

/// Two schedule points closer than round-off are one sample (a snapshot grid point and a sample
/// grid point computed as different products of the same τ).
pub(super) fn same_point(a: f64, b: f64) -> bool {
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
