//! Cell mode in large systems: a look-ahead several events deep, staged over the calendar's
//! coming buckets.
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

use super::{Aux, Simulation};
use crate::calendar::{Calendar, Hints};
use crate::cells::NONE;
use crate::prefetch::prefetch_record_at;
use crate::{Boundary, CollisionRule};

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
        let cal = self.calendar.hints();
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
            self.stage_members(MEMBERS - 1);
            self.stage_heads(HEADS - 1);
            self.stage_records(RECORDS - 1);
        }
        self.stage_members(MEMBERS);
        self.stage_heads(HEADS);
        cal.prefetch_bucket(RECORDS + 1);
        self.stage_records(RECORDS);
    }

    /// The records stage for the bucket `k` places ahead.
    #[inline(always)]
    fn stage_records(&self, k: usize) {
        for &i in self.calendar.hints().ahead(k) {
            let i = i as usize;
            prefetch_record_at(&self.particles, i);
            prefetch_record_at(&self.meta, i);
        }
    }

    /// The heads stage for the bucket `k` places ahead.
    #[inline(always)]
    fn stage_heads(&self, k: usize) {
        for &i in self.calendar.hints().ahead(k) {
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
    fn stage_members(&self, k: usize) {
        let cal = self.calendar.hints();
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
