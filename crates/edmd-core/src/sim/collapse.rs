//! The collapse monitor: inelastic collapse detected while it happens (PHYSICS.md §6.4).

use super::Simulation;
use crate::calendar::Calendar;
use crate::cells::NONE;
use crate::{Boundary, CollisionRule};

/// Inelastic collapse: infinitely many collisions in a finite time (PHYSICS.md §6.4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collapse {
    /// Physical time when it was detected.
    pub time: f64,
    /// τ = C/N when it was detected.
    pub tau: f64,
    /// Which criterion fired.
    pub reason: CollapseReason,
}

/// The collapse criteria of PHYSICS.md §6.4.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CollapseReason {
    /// The clock advanced by less than 1e-10 of its value over 10 N pair collisions.
    ClockStalled,
    /// The same pair collided more than 100 times with no other collision in between.
    RepeatedPair,
}

/// State of the collapse monitor.
#[derive(Debug, Clone, Copy)]
pub(super) struct CollapseMonitor {
    pair: (u32, u32),
    repeats: u32,
    next_check: u64,
    check_time: f64,
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
    }
}

impl Default for CollapseMonitor {
    fn default() -> Self {
        CollapseMonitor {
            pair: (NONE, NONE),
            repeats: 0,
            next_check: 0,
            check_time: 0.0,
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
        if self.counters.pair_collisions >= m.next_check {
            if m.next_check > 0 && t - m.check_time < 1e-10 * t.abs() && m.found.is_none() {
                m.found = Some(Collapse {
                    time: t,
                    tau: 0.0,
                    reason: CollapseReason::ClockStalled,
                });
            }
            m.next_check = self.counters.pair_collisions + 10 * self.particles.len() as u64;
            m.check_time = t;
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
