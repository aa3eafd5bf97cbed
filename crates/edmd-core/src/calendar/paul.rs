//! The bucket calendar of G. Paul (2007).

use super::{earlier, Calendar};

const NONE: u32 = u32::MAX;
const IN_HEAP: u32 = 1 << 31;

/// One particle's place in a [`PaulCalendar`].
#[derive(Debug, Clone, Copy)]
struct Slot {
    time: f64,
    next: u32,
    prev: u32,
    /// `NONE`, `IN_HEAP | position`, or a list index (bucket, or `nb` = overflow).
    loc: u32,
}

const EMPTY_SLOT: Slot = Slot {
    time: f64::INFINITY,
    next: NONE,
    prev: NONE,
    loc: NONE,
};

/// O(1)-amortised calendar of Paul (2007); see the module documentation.
#[derive(Debug, Clone)]
pub struct PaulCalendar {
    /// Per-particle entry: time, list links and location, together in one cache line.
    slots: Vec<Slot>,
    /// Heads of the `nb` bucket lists, then the overflow list.
    heads: Vec<u32>,
    heap: Vec<(f64, u32)>,
    origin: f64,
    width: f64,
    inv_width: f64,
    /// Absolute number of the current bucket: it covers `[origin + cur·w, origin + (cur+1)·w)`.
    cur: i64,
    nb: usize,
    in_buckets: usize,
    in_overflow: usize,
    len: usize,
}

impl PaulCalendar {
    /// Number of buckets in one cycle.
    pub fn buckets(&self) -> usize {
        self.nb
    }

    /// Current bucket width.
    pub fn width(&self) -> f64 {
        self.width
    }

    #[inline(always)]
    fn bucket_of(&self, t: f64) -> i64 {
        // Truncation equals floor here (t ≥ origin); `as` saturates for huge values and is monotone
        // in t, so every entry's bucket is consistent with the order of times.
        ((t - self.origin) * self.inv_width) as i64
    }

    #[inline]
    fn link(&mut self, i: u32, list: usize) {
        let h = self.heads[list];
        self.slots[i as usize].next = h;
        self.slots[i as usize].prev = NONE;
        if h != NONE {
            self.slots[h as usize].prev = i;
        }
        self.heads[list] = i;
        self.slots[i as usize].loc = list as u32;
    }

    #[inline]
    fn unlink(&mut self, i: u32, list: usize) {
        let (n, p) = (self.slots[i as usize].next, self.slots[i as usize].prev);
        if p == NONE {
            self.heads[list] = n;
        } else {
            self.slots[p as usize].next = n;
        }
        if n != NONE {
            self.slots[n as usize].prev = p;
        }
    }

    #[inline]
    fn insert(&mut self, i: u32, t: f64) {
        self.slots[i as usize].time = t;
        let k = self.bucket_of(t) - self.cur;
        if k <= 0 {
            self.heap_push(t, i);
        } else {
            if (k as u64) < self.nb as u64 {
                self.link(i, ((self.cur + k) as u64 as usize) & (self.nb - 1));
                self.in_buckets += 1;
            } else {
                self.link(i, self.nb);
                self.in_overflow += 1;
            }
        }
    }

    fn heap_push(&mut self, t: f64, i: u32) {
        let pos = self.heap.len();
        self.heap.push((t, i));
        self.slots[i as usize].loc = IN_HEAP | pos as u32;
        self.sift_up(pos);
    }

    #[inline]
    fn heap_set(&mut self, pos: usize, e: (f64, u32)) {
        self.heap[pos] = e;
        self.slots[e.1 as usize].loc = IN_HEAP | pos as u32;
    }

    fn sift_up(&mut self, mut pos: usize) {
        let e = self.heap[pos];
        while pos > 0 {
            let parent = (pos - 1) / 2;
            let pe = self.heap[parent];
            if !earlier(e, pe) {
                break;
            }
            self.heap_set(pos, pe);
            pos = parent;
        }
        self.heap_set(pos, e);
    }

    fn sift_down(&mut self, mut pos: usize) {
        let e = self.heap[pos];
        let len = self.heap.len();
        loop {
            let l = 2 * pos + 1;
            if l >= len {
                break;
            }
            let r = l + 1;
            let c = if r < len && earlier(self.heap[r], self.heap[l]) {
                r
            } else {
                l
            };
            if !earlier(self.heap[c], e) {
                break;
            }
            self.heap_set(pos, self.heap[c]);
            pos = c;
        }
        self.heap_set(pos, e);
    }

    fn heap_remove(&mut self, pos: usize) {
        let last = self
            .heap
            .pop()
            .expect("heap position of a scheduled particle");
        if pos < self.heap.len() {
            self.heap_set(pos, last);
            self.sift_down(pos);
            self.sift_up(pos);
        }
    }

    /// Moves overflow entries that fall in the coming cycle into buckets (or the heap).
    fn redistribute(&mut self) {
        let mut i = self.heads[self.nb];
        self.heads[self.nb] = NONE;
        self.in_overflow = 0;
        while i != NONE {
            let next = self.slots[i as usize].next;
            self.insert(i, self.slots[i as usize].time);
            i = next;
        }
    }

    /// Advances to the next non-empty bucket and loads it into the heap.
    fn advance(&mut self) {
        debug_assert!(self.heap.is_empty() && self.len > 0);
        if self.in_buckets == 0 {
            // Every bucket is empty: jump to the cycle that holds the earliest overflow entry.
            let mut tmin = f64::INFINITY;
            let mut i = self.heads[self.nb];
            while i != NONE {
                tmin = tmin.min(self.slots[i as usize].time);
                i = self.slots[i as usize].next;
            }
            let nb = self.nb as i64;
            let start = self.bucket_of(tmin).div_euclid(nb) * nb;
            if start > self.cur {
                self.cur = start;
                self.redistribute();
                if !self.heap.is_empty() {
                    return;
                }
            }
        }
        loop {
            self.cur += 1;
            let b = (self.cur as u64 as usize) & (self.nb - 1);
            if b == 0 {
                self.redistribute();
            }
            let mut i = self.heads[b];
            self.heads[b] = NONE;
            while i != NONE {
                let next = self.slots[i as usize].next;
                self.in_buckets -= 1;
                self.heap_push(self.slots[i as usize].time, i);
                i = next;
            }
            if !self.heap.is_empty() {
                return;
            }
        }
    }
}

impl Calendar for PaulCalendar {
    fn with_capacity(n: usize) -> Self {
        let nb = n.max(16).next_power_of_two();
        PaulCalendar {
            slots: vec![EMPTY_SLOT; n],
            heads: vec![NONE; nb + 1],
            heap: Vec::with_capacity(64),
            origin: 0.0,
            width: 1.0,
            inv_width: 1.0,
            cur: 0,
            nb,
            in_buckets: 0,
            in_overflow: 0,
            len: 0,
        }
    }

    #[inline]
    fn schedule(&mut self, i: u32, t: f64) {
        debug_assert!(!t.is_nan(), "NaN event time for particle {i}");
        self.remove(i);
        if t < f64::INFINITY {
            self.insert(i, t);
            self.len += 1;
        }
    }

    #[inline]
    fn remove(&mut self, i: u32) {
        let l = self.slots[i as usize].loc;
        if l == NONE {
            return;
        }
        if l & IN_HEAP != 0 {
            self.heap_remove((l & !IN_HEAP) as usize);
        } else {
            self.unlink(i, l as usize);
            if l as usize == self.nb {
                self.in_overflow -= 1;
            } else {
                self.in_buckets -= 1;
            }
        }
        self.slots[i as usize].loc = NONE;
        self.len -= 1;
    }

    #[inline]
    fn pop(&mut self) -> Option<(u32, f64)> {
        if self.heap.is_empty() {
            if self.len == 0 {
                return None;
            }
            self.advance();
        }
        let (t, i) = self.heap[0];
        self.heap_remove(0);
        self.slots[i as usize].loc = NONE;
        self.len -= 1;
        Some((i, t))
    }

    fn peek_time(&mut self) -> Option<f64> {
        if self.heap.is_empty() {
            if self.len == 0 {
                return None;
            }
            self.advance();
        }
        Some(self.heap[0].0)
    }

    fn len(&self) -> usize {
        self.len
    }

    #[inline(always)]
    fn next_hint(&self) -> Option<u32> {
        self.heap.first().map(|e| e.1)
    }

    fn reset(&mut self, origin: f64, width: f64) {
        assert!(
            width > 0.0 && width.is_finite(),
            "calendar bucket width must be positive"
        );
        self.slots.fill(EMPTY_SLOT);
        self.heads.fill(NONE);
        self.heap.clear();
        self.origin = origin;
        self.width = width;
        self.inv_width = 1.0 / width;
        self.cur = 0;
        self.in_buckets = 0;
        self.in_overflow = 0;
        self.len = 0;
    }
}
