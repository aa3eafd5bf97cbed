//! What the bucket calendar shows of its coming pops, for prefetching (`sim/prefetch.rs`): the
//! next particle, the particles its next buckets hold in place, and the lines a filing will touch.
//! Read-only: nothing here changes which event comes next or when. A calendar without such a view
//! (the oracle [`crate::calendar::HeapCalendar`]) offers none ([`crate::calendar::Calendar::peek`]).

use super::{HasEntry, PaulCalendar, INLINE, IN_CURRENT, IN_OVERFLOW};

/// A read-only view of a [`PaulCalendar`]'s coming pops.
#[derive(Debug, Clone, Copy)]
pub struct Peek<'a>(pub(super) &'a PaulCalendar);

impl<'a> Peek<'a> {
    #[inline(always)]
    /// The particle most likely to be popped next.
    pub fn next(&self) -> Option<u32> {
        let c = self.0;
        match c.current_first() {
            Some(h) => Some(h.1),
            // The current bucket runs dry after its last entry: the next bucket's first is the best
            // guess (its line was asked for at the last advance).
            None => {
                let b = &c.buckets[(c.cur.wrapping_add(1) as u64 as usize) & (c.nb - 1)];
                (b.len > 0).then_some(b.ids[0])
            }
        }
    }

    #[inline(always)]
    /// Asks for the lines that filing an entry at time `t`, and removing particle `i`'s present
    /// one, will touch (called where the time is known some work before the filing).
    pub fn prefetch_filing<E: HasEntry>(&self, e: &[E], i: u32, t: f64) {
        let c = self.0;
        let k = c.bucket_of(t) - c.cur;
        if k > 0 && (k as u64) < c.nb as u64 {
            let b = ((c.cur + k) as u64 as usize) & (c.nb - 1);
            crate::prefetch::prefetch_at(&c.buckets, b);
        }
        if let Some(x) = e.get(i as usize) {
            let l = x.entry().loc;
            if l & (IN_CURRENT | IN_OVERFLOW) == 0 {
                crate::prefetch::prefetch_at(&c.buckets, l as usize);
            }
        }
    }

    #[inline(always)]
    /// The particles held in place in the bucket `k` places after the current one (reads that
    /// bucket's line).
    pub fn ahead(&self, k: usize) -> &'a [u32] {
        let c = self.0;
        let b = &c.buckets[(c.cur.wrapping_add(k as i64) as u64 as usize) & (c.nb - 1)];
        &b.ids[..(b.len as usize).min(INLINE)]
    }

    #[inline(always)]
    /// Asks for the line of the bucket `k` places after the current one.
    pub fn prefetch_bucket(&self, k: usize) {
        let c = self.0;
        let b = (c.cur.wrapping_add(k as i64) as u64 as usize) & (c.nb - 1);
        crate::prefetch::prefetch_at(&c.buckets, b);
    }

    #[inline(always)]
    /// The current bucket's number: it changes whenever the calendar moves on.
    pub fn position(&self) -> i64 {
        self.0.cur
    }
}
