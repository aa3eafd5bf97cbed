//! The collapse monitor: inelastic collapse detected while it happens (PHYSICS.md §6.4).

use super::Simulation;
use crate::calendar::Calendar;
use crate::sim::neighbours::NONE;
use crate::{Boundary, CollisionRule};

/// Inelastic collapse: infinitely many collisions in a finite time (PHYSICS.md §6.4).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Collapse {
    /// Physical time when it was detected.
    pub time: f64,
    /// τ = C/N when it was detected.
    pub tau: f64,
    /// Which criterion fired.
    pub reason: CollapseReason,
}

/// The collapse criteria of PHYSICS.md §6.4.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum CollapseReason {
    /// The clock advanced by less than 1e-10 of its value over 10 N pair collisions (any window of
    /// them, in steps of N/8).
    ClockStalled,
    /// The same pair collided more than 100 times with no other collision in between.
    RepeatedPair,
}

/// Clock readings kept by the collapse monitor: the clock criterion compares the time now with the
/// time [`CLOCK_SLOTS`] readings ago, one reading every ⌈N/8⌉ pair collisions, so that the window
/// (10 N pair collisions) slides in steps of N/8 and a stall is seen whenever it happens, not only
/// in windows aligned to multiples of 10 N (PHYSICS.md §6.4).
const CLOCK_SLOTS: usize = 80;

/// State of the collapse monitor.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(super) struct CollapseMonitor {
    pair: (u32, u32),
    repeats: u32,
    /// The pair-collision count of the next clock reading (0: at the next pair collision).
    next_check: u64,
    /// Clock readings taken since the last restart; reading `k` is in slot `k % CLOCK_SLOTS`.
    readings: u64,
    #[serde(with = "super::persist::array")]
    clock: [f64; CLOCK_SLOTS],
    found: Option<Collapse>,
}

impl CollapseMonitor {
    /// A wall contact breaks a run of repeats of one pair.
    pub(super) fn forget_pair(&mut self) {
        self.pair = (NONE, NONE);
    }

    /// The clock check compares simulated times: restart it after the units changed.
    pub(super) fn restart_clock_check(&mut self) {
        self.next_check = 0;
        self.readings = 0;
    }

    /// Takes a clock reading at pair collision `count` of a system of `n` particles at time `t`,
    /// when one is due; true when the clock advanced by less than 1e-10 of its value over the
    /// last 10 `n` pair collisions.
    #[inline]
    fn clock_stalled(&mut self, count: u64, n: usize, t: f64) -> bool {
        if count < self.next_check {
            return false;
        }
        let stride = (n as u64).div_ceil(8).max(1);
        let slot = (self.readings % CLOCK_SLOTS as u64) as usize;
        let stalled = self.readings >= CLOCK_SLOTS as u64 && t - self.clock[slot] < 1e-10 * t.abs();
        self.clock[slot] = t;
        self.readings += 1;
        self.next_check = (count / stride + 1) * stride;
        stalled
    }
}

impl Default for CollapseMonitor {
    fn default() -> Self {
        CollapseMonitor {
            pair: (NONE, NONE),
            repeats: 0,
            next_check: 0,
            readings: 0,
            clock: [0.0; CLOCK_SLOTS],
            found: None,
        }
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// The collapse criteria of PHYSICS.md §6.4, after a pair collision of slots `i` and `j`.
    #[inline]
    pub(super) fn watch_collapse(&mut self, i: u32, j: u32) {
        let pair = (i.min(j), i.max(j));
        let t = self.time();
        let m = &mut self.monitor;
        if pair == m.pair {
            m.repeats += 1;
            if m.repeats > 100 && m.found.is_none() {
                m.found = Some(Collapse {
                    time: t,
                    tau: 0.0,
                    reason: CollapseReason::RepeatedPair,
                });
            }
        } else {
            m.pair = pair;
            m.repeats = 0;
        }
        if m.clock_stalled(self.counters.pair_collisions, self.particles.len(), t)
            && m.found.is_none()
        {
            m.found = Some(Collapse {
                time: t,
                tau: 0.0,
                reason: CollapseReason::ClockStalled,
            });
        }
        if let Some(c) = &mut m.found {
            c.tau = self.counters.pair_collisions as f64 / self.particles.len() as f64;
        }
    }

    /// The inelastic collapse detected so far, if any; runs stop with [`RunEnd::Collapsed`].
    pub fn collapse(&self) -> Option<Collapse> {
        self.monitor.found
    }
}
