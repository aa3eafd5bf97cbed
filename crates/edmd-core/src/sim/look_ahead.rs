//! Cell mode in large systems: a look-ahead several events deep, staged over the calendar's
//! coming buckets.
//!
//! An event reads its lines in a chain of dependent levels: its particle and bookkeeping, then the
//! heads of the cells around it (their address needs the particle's cell), then the members of
//! those cells (their slots are what the heads hold). A prefetch one event ahead starts the first
//! level only; the second needs the first to have arrived, and asking for it early costs a wait
//! instead of hiding one. The calendar, however, knows which particles its next few buckets hold.
//! So each time it moves on to a new bucket, each of the buckets 2 to [`RECORDS`] + 1 places ahead
//! is taken one level further, reading only lines an earlier move asked for:
//!
//! | bucket ahead | asked for |
//! |---|---|
//! | 5 | the bucket's own line |
//! | 4 | each entry's particle record and bookkeeping (which holds its calendar entry) |
//! | 3 | collision (or stale candidate): the heads of the 3^D cells it will search, the partner's record and bookkeeping; crossing: the heads of the cell it enters, of the newly adjacent cells and of the cell it leaves |
//! | 2 | collision: the first member of each of those cells, the partner's cell heads and calendar bucket; crossing: the first members of the newly adjacent cells and of the cell it leaves (its removal walks from there) |
//!
//! Entries that a collision reschedules before their bucket comes are simply asked for in vain; the
//! few events filed into the next buckets meanwhile get only the one-event look-ahead of the step.
//! All of it is hints: which events happen, and in which order, does not change.

use super::{Aux, Simulation};
use crate::calendar::Calendar;
use crate::cells::NONE;
use crate::prefetch::prefetch_record;
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
    /// One stage of the look-ahead for each of the buckets 2 to [`RECORDS`] + 1 places ahead (module docs); called
    /// once per bucket the calendar moves to.
    #[inline(never)]
    pub(super) fn look_ahead_cells(&self) {
        let cal = &self.calendar;
        cal.prefetch_bucket(RECORDS + 1);
        for &i in cal.ahead(RECORDS) {
            let i = i as usize;
            prefetch_record(&self.particles[i]);
            prefetch_record(&self.meta[i]);
        }
        for &i in cal.ahead(HEADS) {
            let i = i as usize;
            match self.reads(i) {
                Reads::Search { centre, partner } => {
                    self.prefetch_heads(centre, &self.grid.full);
                    if partner != NONE {
                        let j = partner as usize;
                        prefetch_record(&self.particles[j]);
                        prefetch_record(&self.meta[j]);
                    }
                }
                Reads::Cross { centre, side } => {
                    self.grid.prefetch_head(centre);
                    self.prefetch_heads(centre, &self.grid.partial[side]);
                    // The cell it leaves, which its removal walks from the head.
                    self.grid.prefetch_head(self.grid.index(&self.meta[i].cell));
                }
                Reads::Nothing => {}
            }
        }
        for &i in cal.ahead(MEMBERS) {
            let i = i as usize;
            match self.reads(i) {
                Reads::Search { centre, partner } => {
                    self.prefetch_members(centre, &self.grid.full);
                    if partner != NONE {
                        if let Some(c) = self.interior_cell(&self.meta[partner as usize].cell) {
                            self.prefetch_heads(c, &self.grid.full);
                        }
                        cal.prefetch_filing(&self.meta, partner, f64::INFINITY);
                    }
                }
                Reads::Cross { centre, side } => {
                    self.prefetch_members(centre, &self.grid.partial[side]);
                    let first = self.grid.first(self.grid.index(&self.meta[i].cell));
                    if first != NONE && first as usize != i {
                        prefetch_record(&self.particles[first as usize]);
                    }
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
            return match self.interior_cell(&m.cell) {
                Some(centre) => Reads::Search {
                    centre,
                    partner: m.ev.partner,
                },
                None => Reads::Nothing,
            };
        }
        match m.aux {
            Aux::Crossing { axis, up } => {
                let mut c = m.cell;
                let a = axis as usize;
                c[a] = if up { c[a] + 1 } else { c[a].wrapping_sub(1) };
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

    /// Asks for the heads of the cells at `offsets` from the interior cell `centre`.
    #[inline(always)]
    fn prefetch_heads(&self, centre: usize, offsets: &[isize]) {
        for &o in offsets {
            self.grid.prefetch_head((centre as isize + o) as usize);
        }
    }

    /// Asks for the first member of each cell at `offsets` from the interior cell `centre`.
    #[inline(always)]
    fn prefetch_members(&self, centre: usize, offsets: &[isize]) {
        for &o in offsets {
            let k = self.grid.first((centre as isize + o) as usize);
            if k != NONE {
                prefetch_record(&self.particles[k as usize]);
            }
        }
    }
}
