//! The event loop's performance hints, in one place: prefetches that change no event.
//!
//! An event reads a chain of lines (its particle, its cells or list, its partner, the calendar
//! buckets it files into) whose addresses are known some work before they are needed. The step
//! (`sim/event.rs`) calls four hooks of this component and nothing else of it:
//!
//! * [`Simulation::hint_popped`], right after the pop: the next particle the calendar will pop
//!   (its record, bookkeeping and list), and in large cell-mode systems the staged look-ahead over
//!   the calendar's coming buckets (`sim/look_ahead.rs`) each time the calendar moves on;
//! * [`Simulation::hint_pair`], before a collision is resolved: in 2D cell mode the heads of both
//!   particles' neighbour cells, which their searches read right after; in list mode the partner's
//!   list;
//! * [`Simulation::hint_filing`], between the two predictions of a collision and their filings:
//!   the calendar lines each filing will touch;
//! * [`Simulation::hint_done`], at the end of the event: in large neighbour-list systems the next
//!   event's partner and the records its particle's prediction scans.
//!
//! What a calendar can tell ahead comes from its [`Hints`]; the oracle calendar has none
//! ([`crate::calendar::NoHints`]), and then every hook reduces to nothing. The staged look-ahead
//! and the partner prefetch run only when [`LookAhead::on`] (the engine's arrays are far larger
//! than a cache, `Simulation::set_look_ahead`); the others always, where measured to pay
//! (docs/benchmarks.md).

use super::{Search, Simulation};
use crate::calendar::{Calendar, Hints};
use crate::cells::NONE;
use crate::prefetch::prefetch_at;
use crate::{Boundary, CollisionRule};

/// The state of the large-system look-ahead.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LookAhead {
    /// On when the state is far larger than a cache.
    pub on: bool,
    /// The calendar's bucket at the last stage of the cell-mode look-ahead.
    pub at: i64,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// After the pop: asks for the next particle's lines, and runs the cell-mode look-ahead when
    /// the calendar has moved to a later bucket.
    #[inline(always)]
    pub(super) fn hint_popped<S: Search>(&mut self) {
        let hints = self.calendar.hints();
        if let Some(next) = hints.next_hint() {
            prefetch_at(&self.particles, next as usize);
            prefetch_at(&self.meta, next as usize);
            if let Some(nl) = S::lists(&self.nl) {
                nl.prefetch(next as usize);
            }
        }
        if !S::LISTS && self.look_ahead.on {
            let at = hints.position();
            if at != self.look_ahead.at {
                let jump = at.wrapping_sub(self.look_ahead.at);
                self.look_ahead.at = at;
                self.look_ahead_cells(jump);
            }
        }
    }

    /// Before the collision of slots `i` and `j`: in 2D cell mode (where the look-ahead is off)
    /// the heads of both particles' neighbour cells, whose searches follow the collision (2D only:
    /// in 3D the nine rows cost more than they save; docs/benchmarks.md, "What bounds 2D N 10⁴
    /// here, and the pair's cell heads asked for"); in list mode `j`'s list, which the prediction
    /// after it scans.
    #[inline(always)]
    pub(super) fn hint_pair<S: Search>(&self, i: usize, j: usize) {
        if D == 2 && !S::LISTS && !self.look_ahead.on {
            self.prefetch_heads_around(i);
            self.prefetch_heads_around(j);
        }
        if let Some(nl) = S::lists(&self.nl) {
            nl.prefetch(j);
            if self.look_ahead.on {
                self.prefetch_listed(nl, j);
            }
        }
    }

    /// Slot `i`'s event is known to come at `t` and is about to be filed: the calendar lines the
    /// filing touches (large systems only).
    #[inline(always)]
    pub(super) fn hint_filing(&self, i: usize, t: f64) {
        if self.look_ahead.on {
            self.calendar
                .hints()
                .prefetch_filing(&self.meta, i as u32, t);
        }
    }

    /// At the end of an event, in large neighbour-list systems: the next event's partner.
    #[inline(always)]
    pub(super) fn hint_done<S: Search>(&self) {
        if S::LISTS && self.look_ahead.on {
            self.prefetch_next_partner();
        }
    }

    /// Asks for the heads of the 3^D cells around slot `i`'s cell: the first and the last head of
    /// each row. Without a test for the box's edge: there the rows wrap or fall outside the grid,
    /// and a hint past it is only wasted (a prefetch never faults).
    #[inline(always)]
    fn prefetch_heads_around(&self, i: usize) {
        let centre = self.grid.index(&self.meta[i].cell);
        self.grid.for_each_row(centre, |row| {
            self.grid.prefetch_head(row);
            self.grid.prefetch_head(row.wrapping_add(2));
        });
    }

    /// Asks for the records of slot `i`'s listed partners, which a scan of its list reads.
    #[inline(always)]
    pub(super) fn prefetch_listed(&self, nl: &crate::nlist::NeighbourLists<D>, i: usize) {
        for &k in nl.of(i) {
            prefetch_at(&self.particles, k as usize);
        }
    }

    /// Neighbour-list mode: asks for the lines the next event will read after its own particle's
    /// (prefetched when it reached the calendar's front): its listed partners' records, and its
    /// collision partner's record, bookkeeping and list. Their address needs the next particle's
    /// bookkeeping, which has arrived by the end of the current event. (In cell mode the same, and the first members of the
    /// neighbour cells, measured no gain: docs/benchmarks.md.)
    #[inline]
    fn prefetch_next_partner(&self) {
        let next = self.calendar.hints().next_hint();
        // A system event's slot has no list.
        let next = next.filter(|&k| (k as usize) < self.len());
        let (Some(next), Some(nl)) = (next, &self.nl) else {
            return;
        };
        // The next particle's listed partners, whose records its prediction scans (its list was
        // asked for when it reached the calendar's front); it pays only far beyond the caches.
        // (docs/benchmarks.md).
        self.prefetch_listed(nl, next as usize);
        let e = &self.meta[next as usize].ev;
        if e.coll_t <= e.aux_t && e.partner != NONE {
            let j = e.partner as usize;
            prefetch_at(&self.particles, j);
            prefetch_at(&self.meta, j);
            nl.prefetch(j);
        }
    }
}
