//! The Paul calendar's deferred filings: entries filed into a later bucket wait, with that bucket's
//! line asked for, until the line has had time to arrive (see `PaulCalendar::deferred`).

use super::{HasEntry, PaulCalendar, DEFER, DEFERRED, IN_OVERFLOW};

impl PaulCalendar {
    /// Files particle `i` at time `t`; a bucket filing is deferred (see [`Self::deferred`]).
    #[inline]
    pub(super) fn insert<E: HasEntry>(&mut self, e: &mut [E], i: u32, t: f64) {
        e[i as usize].entry_mut().time = t;
        let k = self.bucket_of(t) - self.cur;
        if k <= 0 {
            self.current_push(e, t, i);
        } else if (k as u64) < self.nb as u64 {
            let b = ((self.cur + k) as u64 as usize) & (self.nb - 1);
            if !self.defer {
                self.link(e, i, b);
                self.in_buckets += 1;
                return;
            }
            crate::prefetch::prefetch_at(&self.buckets, b);
            if self.deferred.len() == DEFER {
                self.link_deferred(e);
            }
            e[i as usize].entry_mut().loc = DEFERRED | self.deferred.len() as u32;
            self.deferred.push((i, b as u32, self.loads));
            self.in_buckets += 1;
        } else {
            e[i as usize].entry_mut().loc = IN_OVERFLOW | self.overflow.len() as u32;
            self.overflow.push(i);
        }
    }

    /// Links every deferred filing into its bucket.
    pub(super) fn link_deferred<E: HasEntry>(&mut self, e: &mut [E]) {
        for k in 0..self.deferred.len() {
            let (i, b, _) = self.deferred[k];
            self.link(e, i, b as usize);
        }
        self.deferred.clear();
    }

    /// Links the deferred filings of bucket `b` (about to be loaded) and those made before the
    /// last load (whose lines have arrived by now) into their buckets.
    pub(super) fn link_deferred_due<E: HasEntry>(&mut self, e: &mut [E], b: usize) {
        let mut k = 0;
        while k < self.deferred.len() {
            let (i, bk, filed) = self.deferred[k];
            if bk as usize == b || filed != self.loads {
                self.deferred_remove(e, k);
                self.link(e, i, bk as usize);
            } else {
                k += 1;
            }
        }
    }

    /// Removes the deferred filing at `pos`; the last one takes its place.
    pub(super) fn deferred_remove<E: HasEntry>(&mut self, e: &mut [E], pos: usize) {
        self.deferred.swap_remove(pos);
        if let Some(&(moved, _, _)) = self.deferred.get(pos) {
            e[moved as usize].entry_mut().loc = DEFERRED | pos as u32;
        }
    }
}
