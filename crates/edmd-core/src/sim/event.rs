//! The step: one event popped, decoded once, and handed to the handler of its kind; the next shell
//! exit or wall contact of list mode.

use super::{Aux, Cells, Lists, Search, Simulation, NONE};
use crate::calendar::Calendar;
use crate::{Boundary, CollisionRule};

/// What an event was, with original particle indices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// A pair collision between two particles.
    Collision(u32, u32),
    /// A collision candidate whose partner had changed; the particle was predicted again.
    Stale(u32),
    /// A particle moved to a neighbouring cell (cell mode).
    CellCrossing(u32),
    /// A particle left its shell and renewed its neighbour list (neighbour-list mode).
    ShellExit(u32),
    /// A particle hit a wall.
    Wall(u32),
    /// Sheared scenes: the sliding images moved by one cell and the outer rows were searched again.
    ShearShift,
    /// The white-noise thermostat kicked every grain; every event was predicted again.
    Kick,
}

/// The popped event of a slot, decoded from its [`super::EventSlot`].
#[derive(Debug, Clone, Copy)]
enum Event {
    /// A collision with slot `j`, whose candidate is still valid.
    Collision(usize),
    /// A collision candidate whose partner has collided since.
    Stale,
    /// A crossing, wall contact or shell exit.
    Aux(Aux),
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Processes the next event. Returns `None` when nothing will ever happen again (all at rest).
    #[inline]
    pub fn step(&mut self) -> Option<EventKind> {
        if self.uses_lists() {
            self.step_with::<Lists>()
        } else {
            self.step_with::<Cells>()
        }
    }

    /// [`Self::step`] for a neighbour strategy fixed at compile time: pop, decode, handle. The
    /// prefetch hints are the four `hint_*` hooks (`sim/prefetch.rs`); they change no event.
    #[inline]
    pub(super) fn step_with<S: Search>(&mut self) -> Option<EventKind> {
        let (i, t) = self.calendar.pop(&mut self.meta)?;
        self.hint_popped::<S>();
        debug_assert!(t >= self.now, "event in the past: {t} < {}", self.now);
        self.now = t;
        self.counters.events += 1;
        let i = i as usize;
        let id = self.meta[i].id;
        let kind = match self.decode(i) {
            Event::Collision(j) => {
                self.pair_event::<S>(i, j);
                EventKind::Collision(id, self.meta[j].id)
            }
            Event::Stale => {
                self.counters.stale += 1;
                self.predict::<S>(i);
                EventKind::Stale(id)
            }
            Event::Aux(Aux::Wall { axis, up }) => {
                self.wall(i, axis as usize, up);
                self.predict::<S>(i);
                self.monitor.forget_pair();
                EventKind::Wall(id)
            }
            Event::Aux(Aux::ShellExit) => {
                self.counters.crossings += 1;
                self.renew_list(i);
                EventKind::ShellExit(id)
            }
            Event::Aux(Aux::Crossing { axis, up }) => {
                self.cross(i, axis as usize, up);
                EventKind::CellCrossing(id)
            }
            // Upkeep by the event count waits for the next particle's event.
            Event::Aux(Aux::System(kind)) => return Some(self.system_event(kind)),
        };
        self.hint_done::<S>();
        if self.counters.events >= self.next_maintenance {
            self.maintenance();
        }
        Some(kind)
    }

    /// The collision of slots `i` and `j`, then both predictions before either filing: the
    /// calendar lines each filing touches are asked for as soon as its time is known and arrive
    /// during the other's work.
    #[inline(always)]
    fn pair_event<S: Search>(&mut self, i: usize, j: usize) {
        self.hint_pair::<S>(i, j);
        self.collide(i, j);
        let ti = self.predict_event::<S>(i);
        self.hint_filing(i, ti);
        let tj = self.predict_event::<S>(j);
        self.hint_filing(j, tj);
        self.calendar.schedule(&mut self.meta, i as u32, ti);
        self.calendar.schedule(&mut self.meta, j as u32, tj);
        self.watch_collapse(i as u32, j as u32);
    }

    /// The event slot `i` holds now: its collision candidate if that comes first, else its
    /// auxiliary event.
    #[inline(always)]
    fn decode(&self, i: usize) -> Event {
        let e = &self.meta[i].ev;
        if e.coll_t <= e.aux_t {
            let j = e.partner as usize;
            if self.particles[j].counter == e.partner_count {
                Event::Collision(j)
            } else {
                Event::Stale
            }
        } else {
            Event::Aux(self.meta[i].aux)
        }
    }

    /// Full prediction for slot `i` (already advanced to now), then reschedule it.
    #[inline]
    pub(super) fn predict<S: Search>(&mut self, i: usize) {
        let t = self.predict_event::<S>(i);
        self.calendar.schedule(&mut self.meta, i as u32, t);
    }

    /// Records the candidate `(coll_t, partner)` of slot `i` and files its next event.
    #[inline]
    pub(super) fn store<S: Search>(&mut self, i: usize, coll_t: f64, partner: u32) {
        let aux = S::next_exit(self, i);
        let t = self.set_event(i, coll_t, partner, aux);
        self.calendar.schedule(&mut self.meta, i as u32, t);
    }

    /// Predicts slot `i`'s next event and records it without filing it; returns its time. One
    /// out-of-line copy for the step's several callers: inlined at each, its branches mispredict
    /// more than the call costs (docs/benchmarks.md, "The redesign: speed").
    #[inline(never)]
    pub(super) fn predict_event<S: Search>(&mut self, i: usize) -> f64 {
        let aux = S::next_exit(self, i);
        let (coll_t, partner) = S::search(self, i, aux.0);
        self.set_event(i, coll_t, partner, aux)
    }

    /// Records particle `i`'s collision candidate and its next crossing, shell exit or wall contact
    /// `(aux_t, aux)`; returns the earlier of the two.
    #[inline]
    pub(super) fn set_event(
        &mut self,
        i: usize,
        coll_t: f64,
        partner: u32,
        (aux_t, aux): (f64, Aux),
    ) -> f64 {
        let partner_count = if partner == NONE {
            0
        } else {
            self.particles[partner as usize].counter
        };
        self.meta[i].ev = super::EventSlot {
            coll_t,
            aux_t,
            partner,
            partner_count,
        };
        self.meta[i].aux = aux;
        coll_t.min(aux_t)
    }
}
