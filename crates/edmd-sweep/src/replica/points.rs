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
