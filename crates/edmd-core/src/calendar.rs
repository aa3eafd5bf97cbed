//! Event calendars: one pending event per particle, earliest first.
//!
//! [`PaulCalendar`] follows G. Paul, J. Comput. Phys. 221, 615 (2007): time is cut into buckets of a
//! fixed width; the current bucket is a small indexed binary heap, the next `M` buckets are unsorted
//! intrusive lists (O(1) insert and remove), and everything later waits in an overflow list that is
//! redistributed once per cycle of `M` buckets. With a width of a few mean inter-event times the heap
//! stays a handful of entries long, so every operation is O(1) amortised.
//!
//! [`HeapCalendar`] is a plain `BinaryHeap` with lazy deletion. It has the same API and exists as a
//! test oracle and as the benchmark baseline.
//!
//! Both order events by `(time, particle index)`, so the two produce identical sequences.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

const NONE: u32 = u32::MAX;
const IN_HEAP: u32 = 1 << 31;

/// A priority queue holding at most one event time per particle.
pub trait Calendar: std::fmt::Debug + Send {
    /// An empty calendar for particles `0..n`.
    fn with_capacity(n: usize) -> Self
    where
        Self: Sized;
    /// Sets particle `i`'s event to time `t`, replacing any earlier entry. `t = ∞` removes it.
    fn schedule(&mut self, i: u32, t: f64);
    /// Removes particle `i`'s entry, if any.
    fn remove(&mut self, i: u32);
    /// Removes and returns the earliest entry `(particle, time)`; ties go to the lower index.
    fn pop(&mut self) -> Option<(u32, f64)>;
    /// The time of the earliest entry without removing it.
    fn peek_time(&mut self) -> Option<f64>;
    /// Number of scheduled particles.
    fn len(&self) -> usize;
    /// True when nothing is scheduled.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The particle most likely to be popped next, if known cheaply (used to prefetch its data).
    fn next_hint(&self) -> Option<u32> {
        None
    }
    /// Empties the calendar and sets its time origin and bucket width (a hint; `width > 0`).
    fn reset(&mut self, origin: f64, width: f64);
}

#[inline(always)]
fn earlier(a: (f64, u32), b: (f64, u32)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

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

/// `f64` with a total order, for the oracle heap.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Key(f64, u32, u32);

impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Key {
    fn cmp(&self, other: &Self) -> Ordering {
        // Reversed: BinaryHeap is a max-heap.
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// `BinaryHeap` calendar with lazy deletion (stale entries are skipped by a per-particle version).
#[derive(Debug, Clone)]
pub struct HeapCalendar {
    heap: BinaryHeap<Key>,
    version: Vec<u32>,
    active: Vec<bool>,
    len: usize,
}

impl HeapCalendar {
    fn discard_stale(&mut self) {
        while let Some(k) = self.heap.peek() {
            if self.active[k.1 as usize] && self.version[k.1 as usize] == k.2 {
                return;
            }
            self.heap.pop();
        }
    }
}

impl Calendar for HeapCalendar {
    fn with_capacity(n: usize) -> Self {
        HeapCalendar {
            heap: BinaryHeap::with_capacity(2 * n),
            version: vec![0; n],
            active: vec![false; n],
            len: 0,
        }
    }

    fn schedule(&mut self, i: u32, t: f64) {
        self.remove(i);
        if t < f64::INFINITY {
            let v = &mut self.version[i as usize];
            *v = v.wrapping_add(1);
            self.heap.push(Key(t, i, *v));
            self.active[i as usize] = true;
            self.len += 1;
        }
        if self.heap.len() > 4 * self.version.len() + 64 {
            // Compact: drop stale entries so memory stays bounded.
            let (version, active) = (&self.version, &self.active);
            self.heap
                .retain(|k| active[k.1 as usize] && version[k.1 as usize] == k.2);
        }
    }

    fn remove(&mut self, i: u32) {
        if self.active[i as usize] {
            self.active[i as usize] = false;
            self.len -= 1;
        }
    }

    fn pop(&mut self) -> Option<(u32, f64)> {
        self.discard_stale();
        let k = self.heap.pop()?;
        self.active[k.1 as usize] = false;
        self.len -= 1;
        Some((k.1, k.0))
    }

    fn peek_time(&mut self) -> Option<f64> {
        self.discard_stale();
        self.heap.peek().map(|k| k.0)
    }

    fn len(&self) -> usize {
        self.len
    }

    fn reset(&mut self, _origin: f64, _width: f64) {
        self.heap.clear();
        self.active.fill(false);
        self.len = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// Random schedule/remove/pop traffic, the way an event loop produces it: both calendars must
    /// return identical sequences.
    fn compare(n: usize, width: f64, steps: usize, seed: u64) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        let mut a = PaulCalendar::with_capacity(n);
        let mut b = HeapCalendar::with_capacity(n);
        a.reset(0.0, width);
        b.reset(0.0, width);
        for i in 0..n as u32 {
            let t = rng.random::<f64>() * 3.0;
            a.schedule(i, t);
            b.schedule(i, t);
        }
        let mut now = 0.0;
        for _ in 0..steps {
            let (ia, ta) = a.pop().unwrap();
            let (ib, tb) = b.pop().unwrap();
            assert_eq!((ia, ta), (ib, tb));
            assert!(ta >= now);
            now = ta;
            // Reschedule the popped particle and disturb a random other one, sometimes far ahead,
            // sometimes at exactly `now`, sometimes removing it.
            let dt = if rng.random::<f64>() < 0.05 {
                rng.random::<f64>() * 1e3
            } else {
                rng.random::<f64>()
            };
            a.schedule(ia, now + dt);
            b.schedule(ib, now + dt);
            let j = rng.random_range(0..n as u32);
            match rng.random_range(0..4) {
                0 => {
                    a.remove(j);
                    b.remove(j);
                }
                1 => {
                    a.schedule(j, now);
                    b.schedule(j, now);
                }
                _ => {
                    let t = now + rng.random::<f64>() * 2.0;
                    a.schedule(j, t);
                    b.schedule(j, t);
                }
            }
            assert_eq!(a.len(), b.len());
            if a.is_empty() {
                break;
            }
        }
    }

    #[test]
    fn paul_matches_binary_heap() {
        compare(1000, 1e-3, 200_000, 1);
        compare(50, 0.5, 100_000, 2); // wide buckets: big heap
        compare(300, 1e-6, 50_000, 3); // narrow buckets: mostly overflow
    }

    #[test]
    fn ties_break_by_index() {
        let mut c = PaulCalendar::with_capacity(4);
        c.reset(0.0, 1.0);
        for i in [3, 1, 2, 0] {
            c.schedule(i, 5.0);
        }
        let order: Vec<u32> = std::iter::from_fn(|| c.pop().map(|e| e.0)).collect();
        assert_eq!(order, vec![0, 1, 2, 3]);
    }

    #[test]
    fn infinite_time_means_unscheduled() {
        let mut c = PaulCalendar::with_capacity(2);
        c.reset(0.0, 1.0);
        c.schedule(0, 1.0);
        c.schedule(0, f64::INFINITY);
        assert!(c.is_empty());
        assert_eq!(c.pop(), None);
    }
}
