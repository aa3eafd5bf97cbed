//! The event loop's performance hints, in one place: prefetches that change no event.
//!
//! An event reads a chain of lines (its particle, its cells or list, its partner, the calendar
//! buckets it files into) whose addresses are known some work before they are needed. The step
//! (`sim/event.rs`) calls four hooks of this component and nothing else of it:
//!
//! * [`Simulation::hint_popped`], right after the pop: the next particle the calendar will pop
//!   (its record, bookkeeping and list), and in large cell-mode systems the staged look-ahead over
//!   the calendar's coming buckets (below) each time the calendar moves on;
//! * [`Simulation::hint_pair`], before a collision is resolved: in 2D cell mode the heads of both
//!   particles' neighbour cells, which their searches read right after; in list mode the partner's
//!   list;
//! * [`Simulation::hint_filing`], between the two predictions of a collision and their filings:
//!   the calendar lines each filing will touch;
//! * [`Simulation::hint_done`], at the end of the event: in large neighbour-list systems the next
//!   event's partner and the records its particle's prediction scans.
//!
//! What a calendar can tell ahead comes from its [`Peek`] (`Calendar::peek`); the oracle calendar
//! has none, and then every hook reduces to nothing. The staged look-ahead and the partner
//! prefetch run only when [`LookAhead::on`] (the engine's arrays are far larger than a cache,
//! `Simulation::set_look_ahead`); the others always, where measured to pay (docs/benchmarks.md).
//!
//! ## The look-ahead of large cell-mode systems
//!
//! A look-ahead several events deep, staged over the calendar's coming buckets.
//!
//! An event reads its lines in a chain of dependent levels: its particle and bookkeeping, then the
//! heads of the cells around it (their address needs the particle's cell), then the members of
//! those cells (their slots are what the heads hold). A prefetch one event ahead starts the first
//! level only; the second needs the first to have arrived, and asking for it early costs a wait
//! instead of hiding one. The calendar, however, knows which particles its next few buckets hold.
//! So each time it moves on to a new bucket, each of the buckets 1 to [`RECORDS`] + 1 places ahead
//! is taken one level further, reading only lines an earlier move asked for:
//!
//! | bucket ahead | asked for |
//! |---|---|
//! | 5 | the bucket's own line |
//! | 4 | each entry's particle record and bookkeeping (which holds its calendar entry) |
//! | 3 | collision (or stale candidate): the heads of the 3^D cells it will search, the partner's record and bookkeeping; crossing: the heads of the cell it enters, of the newly adjacent cells and of the cell it leaves |
//! | 2 | collision: the first member of each of those cells, the partner's cell heads and calendar bucket; crossing: the first members of the newly adjacent cells and of the cell it leaves (its removal walks from there) |
//! | 1 | collision: the first member of each cell around the partner (its search follows the particle's) |
//!
//! When the calendar skips an empty bucket, the move it skipped is made up: each stage also runs
//! for the bucket one place nearer. Entries that a collision reschedules before their bucket comes
//! are simply asked for in vain; the few events filed into the next buckets meanwhile get only the
//! one-event look-ahead of the step. All of it is hints: which events happen, and in which order,
//! does not change.
//!
//! At N = 10⁶ the look-ahead runs about once per collision, and its instructions cost time in
//! full (they do not hide under the waits for memory: docs/benchmarks.md), so it is written for
//! few of them: the heads of a row of three cells are asked for by its first and last head, the
//! neighbourhood's rows are unrolled loops over fixed offsets, addresses skip the bounds check
//! (a hint never faults), and an empty cell asks for slot 0 rather than branch.

use super::{Aux, Search, Simulation};
use crate::calendar::{Calendar, Peek};
use crate::prefetch::{prefetch_at, prefetch_record_at};
use crate::sim::neighbours::NONE;
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
        let Some(peek) = self.calendar.peek() else {
            return;
        };
        if let Some(next) = peek.next() {
            prefetch_at(&self.particles, next as usize);
            prefetch_at(&self.meta, next as usize);
            if let (true, Some(nl)) = (S::LISTS, &self.nl) {
                nl.prefetch(next as usize);
            }
        }
        if !S::LISTS && self.look_ahead.on {
            let at = peek.position();
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
        if let (true, Some(nl)) = (S::LISTS, &self.nl) {
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
        if let (true, Some(peek)) = (self.look_ahead.on, self.calendar.peek()) {
            peek.prefetch_filing(&self.meta, i as u32, t);
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
    pub(super) fn prefetch_listed(&self, nl: &crate::sim::neighbours::NeighbourLists<D>, i: usize) {
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
        let next = self.calendar.peek().and_then(|peek| peek.next());
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

/// How many buckets ahead each stage works (module docs), farthest first.
const RECORDS: usize = 4;
const HEADS: usize = 3;
const MEMBERS: usize = 2;

/// What particle `i`'s pending event will read beyond its own records.
#[derive(Clone, Copy)]
enum Reads {
    /// A full search around cell `centre` (a collision or a stale candidate), and the collision
    /// partner's data (or [`NONE`]).
    Search { centre: usize, partner: u32 },
    /// A crossing into cell `centre`: its head, the newly adjacent cells `grid.partial[side]`
    /// around it, and the cell-list links the move rewrites.
    Cross { centre: usize, side: usize },
    /// Nothing worth asking for early (a wall, a face of the box, a shell exit).
    Nothing,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// One stage of the look-ahead for each of the buckets 1 to [`RECORDS`] + 1 places ahead
    /// (module docs); called once per bucket the calendar moves to, `jump` buckets on from the
    /// last call.
    #[inline(never)]
    pub(super) fn look_ahead_cells(&self, jump: i64) {
        let Some(cal) = self.calendar.peek() else {
            return;
        };
        for &i in cal.ahead(1) {
            let m = &self.meta[i as usize];
            if m.ev.coll_t <= m.ev.aux_t && m.ev.partner != NONE {
                if let Some(c) = self.interior_cell(&self.meta[m.ev.partner as usize].cell()) {
                    self.prefetch_members(c);
                }
            }
        }
        if jump >= 2 {
            // The calendar skipped an empty bucket: each stage also runs for the bucket one place
            // nearer, which the skipped move would have taken there.
            self.stage_members(cal, MEMBERS - 1);
            self.stage_heads(cal, HEADS - 1);
            self.stage_records(cal, RECORDS - 1);
        }
        self.stage_members(cal, MEMBERS);
        self.stage_heads(cal, HEADS);
        cal.prefetch_bucket(RECORDS + 1);
        self.stage_records(cal, RECORDS);
    }

    /// The records stage for the bucket `k` places ahead.
    #[inline(always)]
    fn stage_records(&self, cal: Peek<'_>, k: usize) {
        for &i in cal.ahead(k) {
            let i = i as usize;
            prefetch_record_at(&self.particles, i);
            prefetch_record_at(&self.meta, i);
        }
    }

    /// The heads stage for the bucket `k` places ahead.
    #[inline(always)]
    fn stage_heads(&self, cal: Peek<'_>, k: usize) {
        for &i in cal.ahead(k) {
            let i = i as usize;
            match self.reads(i) {
                Reads::Search { centre, partner } => {
                    self.prefetch_heads(centre);
                    if partner != NONE {
                        let j = partner as usize;
                        prefetch_record_at(&self.particles, j);
                        prefetch_record_at(&self.meta, j);
                    }
                }
                Reads::Cross { centre, side } => {
                    self.grid.prefetch_head(centre);
                    for &o in &self.grid.partial_probes[side] {
                        self.grid.prefetch_head((centre as isize + o) as usize);
                    }
                    // The cell it leaves, which its removal walks from the head.
                    self.grid
                        .prefetch_head(self.grid.index(&self.meta[i].cell()));
                }
                Reads::Nothing => {}
            }
        }
    }

    /// The members stage for the bucket `k` places ahead.
    #[inline(always)]
    fn stage_members(&self, cal: Peek<'_>, k: usize) {
        for &i in cal.ahead(k) {
            let i = i as usize;
            match self.reads(i) {
                Reads::Search { centre, partner } => {
                    self.prefetch_members(centre);
                    if partner != NONE {
                        if let Some(c) = self.interior_cell(&self.meta[partner as usize].cell()) {
                            self.prefetch_heads(c);
                        }
                        cal.prefetch_filing(&self.meta, partner, f64::INFINITY);
                    }
                }
                Reads::Cross { centre, side } => {
                    for &o in &self.grid.partial[side] {
                        self.prefetch_first_member((centre as isize + o) as usize);
                    }
                    self.prefetch_first_member(self.grid.index(&self.meta[i].cell()));
                }
                Reads::Nothing => {}
            }
        }
    }

    /// What particle `i`'s pending event will read (see [`Reads`]).
    #[inline(always)]
    fn reads(&self, i: usize) -> Reads {
        let m = &self.meta[i];
        if m.ev.coll_t <= m.ev.aux_t {
            return match self.interior_cell(&m.cell()) {
                Some(centre) => Reads::Search {
                    centre,
                    partner: m.ev.partner,
                },
                None => Reads::Nothing,
            };
        }
        match m.aux {
            Aux::Crossing { axis, up } => {
                let mut c = m.cell();
                let a = axis as usize;
                // One step up or down without a branch (which way is a coin flip).
                c[a] = c[a].wrapping_add(2 * up as u32).wrapping_sub(1);
                match self.interior_cell(&c) {
                    Some(centre) => Reads::Cross {
                        centre,
                        side: 2 * a + up as usize,
                    },
                    None => Reads::Nothing,
                }
            }
            _ => Reads::Nothing,
        }
    }

    /// Linear index of cell `c` if none of its neighbours wraps around the box.
    #[inline(always)]
    fn interior_cell(&self, c: &[u32; D]) -> Option<usize> {
        self.grid.is_interior(c).then(|| self.grid.index(c))
    }

    /// Asks for the heads of the 3^D cells around the interior cell `centre`: the first and the
    /// last head of each row (a row's three heads share a line or straddle two).
    #[inline(always)]
    fn prefetch_heads(&self, centre: usize) {
        self.grid.for_each_row(centre, |row| {
            self.grid.prefetch_head(row);
            self.grid.prefetch_head(row + 2);
        });
    }

    /// Asks for the first member of each of the 3^D cells around the interior cell `centre`.
    #[inline(always)]
    fn prefetch_members(&self, centre: usize) {
        self.grid.for_each_row(centre, |row| {
            for k in self.grid.row(row) {
                self.prefetch_member(k);
            }
        });
    }

    /// Asks for the record of cell `idx`'s first member. Without a branch: an empty cell asks for
    /// slot 0 instead (a line that stays cached), which costs less than the branch mispredicted in
    /// the many empty cells of a gas.
    #[inline(always)]
    fn prefetch_first_member(&self, idx: usize) {
        self.prefetch_member(self.grid.first(idx));
    }

    /// Asks for the record of slot `k`, or of slot 0 where `k` is [`NONE`] (an empty cell's head).
    #[inline(always)]
    fn prefetch_member(&self, k: u32) {
        let k = if k == NONE { 0 } else { k as usize };
        prefetch_record_at(&self.particles, k);
    }
}
