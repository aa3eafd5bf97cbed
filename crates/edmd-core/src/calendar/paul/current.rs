//! The Paul calendar's current bucket: a short array sorted latest first, and the narrowing of the
//! buckets when it is crowded.

use super::{earlier, HasEntry, PaulCalendar, CROWDED, EMPTY_BUCKET, IN_CURRENT, NONE, SHORT};

impl PaulCalendar {
    /// Files `(t, i)` among the current bucket's entries, kept sorted latest first (the next pop
    /// is the last). The width aims at a few entries (the re-tuning's two events per bucket give
    /// 1–3 at a filing in most cases), where shifting the later ones up costs less than a heap's
    /// moves, each of which rewrites the moved particle's entry; [`CROWDED`] bounds the shifts.
    #[inline]
    pub(super) fn current_push<E: HasEntry>(&mut self, e: &mut [E], t: f64, i: u32) {
        e[i as usize].entry_mut().loc = IN_CURRENT;
        let h = (t, i);
        if self.current.len() >= SHORT {
            self.current_push_long(h);
            return;
        }
        let v = &mut self.current;
        v.push(h);
        let mut k = v.len() - 1;
        while k > 0 && earlier(v[k - 1], h) {
            v[k] = v[k - 1];
            k -= 1;
        }
        v[k] = h;
    }

    /// [`Self::current_push`] into a long current bucket: the place by bisection, the later
    /// entries moved at once.
    #[cold]
    #[inline(never)]
    fn current_push_long(&mut self, h: (f64, u32)) {
        let k = self.current.partition_point(|&x| earlier(h, x));
        self.current.insert(k, h);
        self.crowded |= self.current.len() > self.crowd_limit;
    }

    /// Removes particle `i` from the current bucket's entries.
    #[inline]
    pub(super) fn current_remove(&mut self, i: u32) {
        let v = &mut self.current;
        let mut k = v
            .iter()
            .rposition(|h| h.1 == i)
            .expect("a particle filed in the current bucket");
        let last = v.len() - 1;
        while k < last {
            v[k] = v[k + 1];
            k += 1;
        }
        v.pop();
    }

    /// Files every entry again with buckets narrow enough that about `EVENTS` of the current
    /// bucket's `m` entries fall in one: the time origin moves to the earliest entry. The order of pops
    /// does not change (it is that of the times); only a width far too wide for the event rate
    /// (between two re-tunings by the engine) comes here.
    #[cold]
    pub(super) fn narrow<E: HasEntry>(&mut self, e: &mut [E]) {
        const EVENTS: f64 = 4.0;
        self.crowded = false;
        let m = self.current.len();
        if m <= self.crowd_limit {
            return;
        }
        self.narrowings += 1;
        // The crowd's span in time (latest first): with about `EVENTS` of it per bucket. Ties span
        // nothing, and no width separates them; the width then stays.
        let span = self.current[0].0 - self.current[m - 1].0;
        if span > 0.0 && span.is_finite() {
            self.width = self.width.min(span) * EVENTS / m as f64;
            self.inv_width = 1.0 / self.width;
        }
        let mut filed: Vec<u32> = self.current.drain(..).map(|h| h.1).collect();
        filed.append(&mut self.overflow);
        filed.extend(self.deferred.drain(..).map(|d| d.0));
        for b in 0..self.nb {
            let bucket = std::mem::replace(&mut self.buckets[b], EMPTY_BUCKET);
            filed.extend_from_slice(&bucket.ids[..bucket.len as usize]);
            let mut k = bucket.spill;
            while k != NONE {
                filed.push(k);
                k = e[k as usize].entry().next;
            }
        }
        let origin = filed
            .iter()
            .map(|&i| e[i as usize].entry().time)
            .fold(f64::INFINITY, f64::min);
        self.origin = origin;
        self.cur = 0;
        self.in_buckets = 0;
        for i in filed {
            let t = e[i as usize].entry().time;
            self.insert_now(e, i, t);
        }
        self.crowded = false;
        self.crowd_limit = CROWDED.max(2 * self.current.len());
    }
}
