//! The Paul calendar's current bucket: a short array sorted latest first, which becomes an indexed
//! binary heap when it grows past [`CROWDED`] entries.
//!
//! With the width the engine tunes (two events per bucket) a filing into the current bucket finds
//! one to three entries there in most cases: shifting the later ones up costs less than a heap's
//! moves, each of which rewrites the moved particle's entry (its heap position), and a pop takes the
//! last entry. A width far too wide for the event rate (between two re-tunings), or many events at
//! the same time, crowds the bucket: past [`CROWDED`] entries it turns into a heap (the sorted array
//! reversed is one) until it runs empty, so no operation costs more than a heap's O(log m). The order
//! of pops is that of `(time, index)` either way.

use super::{earlier, HasEntry, PaulCalendar, CROWDED, IN_CURRENT};

impl PaulCalendar {
    /// Files `(t, i)` in the current bucket.
    #[inline]
    pub(super) fn current_push<E: HasEntry>(&mut self, e: &mut [E], t: f64, i: u32) {
        let h = (t, i);
        if self.heap_mode || self.current.len() >= CROWDED {
            self.heap_push(e, h);
            return;
        }
        e[i as usize].entry_mut().loc = IN_CURRENT;
        let v = &mut self.current;
        v.push(h);
        let mut k = v.len() - 1;
        while k > 0 && earlier(v[k - 1], h) {
            v[k] = v[k - 1];
            k -= 1;
        }
        v[k] = h;
    }

    /// Removes particle `i`, whose entry's place is `loc`, from the current bucket.
    #[inline]
    pub(super) fn current_remove<E: HasEntry>(&mut self, e: &mut [E], i: u32, loc: u32) {
        if self.heap_mode {
            self.heap_remove(e, (loc & !IN_CURRENT) as usize);
            self.heap_mode = !self.current.is_empty();
            return;
        }
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

    /// Removes and returns the current bucket's earliest entry.
    #[inline]
    pub(super) fn current_pop<E: HasEntry>(&mut self, e: &mut [E]) -> Option<(f64, u32)> {
        if !self.heap_mode {
            return self.current.pop();
        }
        let h = *self.current.first()?;
        self.heap_remove(e, 0);
        self.heap_mode = !self.current.is_empty();
        Some(h)
    }

    /// The current bucket's earliest entry.
    #[inline(always)]
    pub(super) fn current_first(&self) -> Option<&(f64, u32)> {
        if self.heap_mode {
            self.current.first()
        } else {
            self.current.last()
        }
    }

    /// Files `h` in the heap, turning the sorted array into one first if it is not yet.
    #[cold]
    #[inline(never)]
    fn heap_push<E: HasEntry>(&mut self, e: &mut [E], h: (f64, u32)) {
        if !self.heap_mode {
            // Sorted latest first, reversed: earliest first, which is a heap.
            self.current.reverse();
            for (pos, &(_, i)) in self.current.iter().enumerate() {
                e[i as usize].entry_mut().loc = IN_CURRENT | pos as u32;
            }
            self.heap_mode = true;
        }
        let pos = self.current.len();
        self.current.push(h);
        e[h.1 as usize].entry_mut().loc = IN_CURRENT | pos as u32;
        self.sift_up(e, pos);
    }

    #[inline]
    fn heap_set<E: HasEntry>(&mut self, e: &mut [E], pos: usize, h: (f64, u32)) {
        self.current[pos] = h;
        e[h.1 as usize].entry_mut().loc = IN_CURRENT | pos as u32;
    }

    fn sift_up<E: HasEntry>(&mut self, e: &mut [E], mut pos: usize) {
        let h = self.current[pos];
        while pos > 0 {
            let parent = (pos - 1) / 2;
            let ph = self.current[parent];
            if !earlier(h, ph) {
                break;
            }
            self.heap_set(e, pos, ph);
            pos = parent;
        }
        self.heap_set(e, pos, h);
    }

    fn sift_down<E: HasEntry>(&mut self, e: &mut [E], mut pos: usize) {
        let h = self.current[pos];
        let len = self.current.len();
        loop {
            let l = 2 * pos + 1;
            if l >= len {
                break;
            }
            let r = l + 1;
            let c = if r < len && earlier(self.current[r], self.current[l]) {
                r
            } else {
                l
            };
            if !earlier(self.current[c], h) {
                break;
            }
            self.heap_set(e, pos, self.current[c]);
            pos = c;
        }
        self.heap_set(e, pos, h);
    }

    fn heap_remove<E: HasEntry>(&mut self, e: &mut [E], pos: usize) {
        let last = self
            .current
            .pop()
            .expect("heap position of a scheduled particle");
        if pos < self.current.len() {
            self.heap_set(e, pos, last);
            self.sift_down(e, pos);
            self.sift_up(e, pos);
        }
    }
}
