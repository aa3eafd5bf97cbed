//! Run loops: until a stop condition, optionally sampling on a schedule.

use super::{Cells, Lists, Search, Simulation};
use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule};

/// When to stop a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stop {
    /// After this many pair collisions per particle, τ = C/N (counted since the last counter reset).
    Tau(f64),
    /// At this physical time.
    Time(f64),
    /// After this many more events of any kind.
    Events(u64),
    /// After this many more events, or at this physical time, whichever comes first (a runner that
    /// samples at set times between collision targets).
    EventsOrTime(u64, f64),
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunEnd {
    /// The stop condition was reached.
    Reached,
    /// No event is left (every particle at rest).
    Exhausted,
    /// Inelastic collapse was detected (see [`Simulation::collapse`]).
    Collapsed,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Simulated local time at physical time `t`.
    pub(super) fn local_time_of(&self, t: f64) -> f64 {
        t * self.inv_scale - self.epoch
    }

    /// Whether a run to physical time `t` ends before the next event: then the clock moves on to
    /// `t` and the end is `Reached`, or `Exhausted` when no event is left.
    fn stop_at_time(&mut self, t: f64) -> Option<RunEnd> {
        let local = self.local_time_of(t);
        match self.calendar.peek_time(&mut self.meta) {
            Some(next) if next <= local => None,
            next => {
                self.now = local.max(self.now);
                Some(if next.is_some() {
                    RunEnd::Reached
                } else {
                    RunEnd::Exhausted
                })
            }
        }
    }

    /// Runs until `stop`.
    pub fn run(&mut self, stop: Stop) -> RunEnd {
        if self.uses_lists() {
            self.run_with::<Lists>(stop)
        } else {
            self.run_with::<Cells>(stop)
        }
    }

    /// [`Self::run`] for a neighbour strategy fixed at compile time. One loop with one call of the
    /// step, whatever the stop condition: the step is then inlined into it, which saves its call
    /// and the reloads around it on every event (docs/benchmarks.md).
    fn run_with<S: Search>(&mut self, stop: Stop) -> RunEnd {
        if self.collapse().is_some() {
            return RunEnd::Collapsed;
        }
        let target = match stop {
            Stop::Tau(tau) => (tau * self.len() as f64).ceil().max(0.0) as u64,
            Stop::Events(n) | Stop::EventsOrTime(n, _) => self.counters.events + n,
            Stop::Time(_) => 0,
        };
        loop {
            match stop {
                Stop::Tau(_) => {
                    if self.counters.pair_collisions >= target {
                        return RunEnd::Reached;
                    }
                }
                Stop::Events(_) => {
                    if self.counters.events >= target {
                        return RunEnd::Reached;
                    }
                }
                Stop::Time(t) => {
                    if let Some(end) = self.stop_at_time(t) {
                        return end;
                    }
                }
                Stop::EventsOrTime(_, t) => {
                    if self.counters.events >= target {
                        return RunEnd::Reached;
                    }
                    if let Some(end) = self.stop_at_time(t) {
                        return end;
                    }
                }
            }
            if self.step_with::<S>().is_none() {
                return RunEnd::Exhausted;
            }
            if self.collapse().is_some() {
                return RunEnd::Collapsed;
            }
        }
    }

    /// Runs until `stop`, calling `observe` whenever τ passes a point of `schedule` (including the
    /// current τ if the schedule holds it).
    pub fn run_sampled(
        &mut self,
        stop: Stop,
        schedule: &crate::schedule::Schedule,
        observe: impl FnMut(&Self),
    ) -> RunEnd {
        if self.uses_lists() {
            self.run_sampled_with::<Lists>(stop, schedule, observe)
        } else {
            self.run_sampled_with::<Cells>(stop, schedule, observe)
        }
    }

    /// [`Self::run_sampled`] for a neighbour strategy fixed at compile time.
    fn run_sampled_with<S: Search>(
        &mut self,
        stop: Stop,
        schedule: &crate::schedule::Schedule,
        mut observe: impl FnMut(&Self),
    ) -> RunEnd {
        let n = self.len() as f64;
        let mut next = schedule.first_at_or_after(self.tau());
        let event_target = match stop {
            Stop::Events(k) | Stop::EventsOrTime(k, _) => self.counters.events + k,
            _ => u64::MAX,
        };
        loop {
            while let Some(tau) = next {
                if (self.counters.pair_collisions as f64) < (tau * n).ceil() {
                    break;
                }
                observe(self);
                next = schedule.next_after(tau);
            }
            let done = match stop {
                Stop::Tau(t) => self.counters.pair_collisions as f64 >= (t * n).ceil(),
                Stop::Events(_) => self.counters.events >= event_target,
                Stop::Time(t) => self.stop_at_time(t).is_some(),
                Stop::EventsOrTime(_, t) => {
                    self.counters.events >= event_target || self.stop_at_time(t).is_some()
                }
            };
            if done {
                return RunEnd::Reached;
            }
            if self.step_with::<S>().is_none() {
                return RunEnd::Exhausted;
            }
            if self.collapse().is_some() {
                return RunEnd::Collapsed;
            }
        }
    }
}
