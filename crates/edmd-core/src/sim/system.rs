//! System events: the calendar's entries beside the N particles' own, for what happens to the
//! whole system at a time of its own: the shift of a sheared box's sliding images, the white-noise
//! thermostat's kick. (A vibrating floor's phase is a function of the local clock, moved on at
//! each rebase: no event of its own.)
//!
//! Each kind owns one slot after the particles' (`Meta` records N, N + 1, …), whose event is an
//! auxiliary one, [`Aux::System`]: the step decodes it like any other and hands it to
//! [`Simulation::system_event`], so a new global event is one more variant here, not a test before
//! the step's dispatch. Upkeep that follows the event count rather than time (the clock rebase
//! and calendar re-tuning every few N events, the τ samples) stays with the step and the run
//! loops: its due point is a count, which no calendar time can stand for.

use super::{Aux, EventSlot, Meta, Simulation};
use crate::calendar::{Calendar, Entry};
use crate::sim::neighbours::NONE;
use crate::{Boundary, CollisionRule};

/// A kind of system event, each with its own calendar slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub(crate) enum SystemEvent {
    /// Sheared scenes: the sliding images moved by one cell column (`sim/shear.rs`).
    ShearShift,
    /// The white-noise thermostat's kick of every grain (`sim/thermostat.rs`).
    Kick,
}

impl SystemEvent {
    /// Every kind, in slot order.
    pub const ALL: [SystemEvent; 2] = [SystemEvent::ShearShift, SystemEvent::Kick];

    /// The kind's slot in a simulation of `n` particles.
    #[inline(always)]
    pub fn slot(self, n: usize) -> usize {
        n + self as usize
    }

    /// The record of the kind's slot: no particle (id and partner NONE), never a collision.
    pub fn record<const D: usize>(self) -> Meta<D> {
        Meta {
            ev: EventSlot::EMPTY,
            mass: 0.0,
            id: NONE,
            cell: [0; D],
            aux: Aux::System(self),
            entry: Entry::EMPTY,
        }
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Files system event `kind` at its present time ([`Self::system_time`]; ∞ removes it).
    pub(super) fn file_system_event(&mut self, kind: SystemEvent) {
        let t = self.system_time(kind);
        let slot = kind.slot(self.len());
        self.meta[slot].ev.aux_t = t;
        self.calendar.schedule(&mut self.meta, slot as u32, t);
    }

    /// Files every system event (after the calendar was emptied).
    pub(super) fn file_system_events(&mut self) {
        for kind in SystemEvent::ALL {
            self.file_system_event(kind);
        }
    }

    /// When system event `kind` comes next, in local time (∞: never).
    fn system_time(&self, kind: SystemEvent) -> f64 {
        match kind {
            SystemEvent::ShearShift => self.shear.next,
            SystemEvent::Kick => self.thermostat.next,
        }
    }

    /// Handles system event `kind`, popped at its time, and files its next occurrence.
    #[cold]
    pub(super) fn system_event(&mut self, kind: SystemEvent) -> super::EventKind {
        self.counters.system_events += 1;
        let done = match kind {
            SystemEvent::ShearShift => {
                self.shear_shift();
                super::EventKind::ShearShift
            }
            SystemEvent::Kick => {
                self.kick();
                super::EventKind::Kick
            }
        };
        self.file_system_event(kind);
        done
    }
}
