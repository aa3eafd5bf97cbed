//! The bucket calendar of G. Paul (2007).

use super::{earlier, Calendar, Entry, HasEntry};

mod current;
mod deferred;
mod peek;

pub use peek::Peek;

const NONE: u32 = u32::MAX;
const IN_CURRENT: u32 = 1 << 31;
const IN_OVERFLOW: u32 = 1 << 30;
/// Filed in a bucket, but not yet linked into it (see [`PaulCalendar::deferred`]).
const DEFERRED: u32 = IN_CURRENT | IN_OVERFLOW;
/// Filings held back at most before they are all linked at once.
const DEFER: usize = 32;
/// Entries a bucket holds in its own cache-line half; more spill into a list through the entries.
const INLINE: usize = 6;
/// Entries of the current bucket beyond which it is kept as a heap instead of a sorted array
/// (`paul/current.rs`).
const CROWDED: usize = 32;

/// One bucket: up to [`INLINE`] particles in place, the rest in a singly linked spill list (rare:
/// the width aims at a few entries per bucket). Filing or removing an entry then touches the
/// bucket's line and the particle's own entry, not the entries of unrelated particles that a linked
/// bucket would thread through.
#[derive(Debug, Clone, Copy, serde::Serialize, serde::Deserialize)]
#[repr(C, align(32))]
struct Bucket {
    len: u32,
    spill: u32,
    ids: [u32; INLINE],
}

const EMPTY_BUCKET: Bucket = Bucket {
    len: 0,
    spill: NONE,
    ids: [NONE; INLINE],
};

/// O(1)-amortised calendar of Paul (2007); see the module documentation.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct PaulCalendar {
    /// The `nb` buckets of one cycle.
    buckets: Vec<Bucket>,
    /// Entries beyond the cycle, unordered (removal swaps the last one into the hole).
    overflow: Vec<u32>,
    /// The current bucket's entries: sorted latest first (the next pop is the last), or a heap
    /// where crowded (`heap_mode`; `paul/current.rs`).
    current: Vec<(f64, u32)>,
    /// Whether `current` is a heap, earliest first, rather than sorted latest first.
    heap_mode: bool,
    /// Filings into buckets after the current one, as `(particle, bucket, loads at filing)`, whose
    /// bucket line was asked for but not yet written: linked at the second bucket load after their
    /// filing, or just before their own bucket is loaded if that comes first (no bucket is read
    /// before), or all at once when [`DEFER`] are waiting. By then the line has arrived instead
    /// of stalling the event that filed them. The order of pops does not change.
    deferred: Vec<(u32, u32, u32)>,
    /// Bucket loads so far (wrapping): a deferred filing records it, and is linked at the second
    /// load after its own (its line has had a whole bucket's events to arrive) or when due.
    loads: u32,
    /// Whether bucket filings are deferred ([`PaulCalendar::defer_filings`]).
    defer: bool,
    /// Whether [`Calendar::reset`] sets `defer` by the size of the buckets and records (until
    /// [`PaulCalendar::defer_filings`] sets it).
    defer_by_size: bool,
    origin: f64,
    width: f64,
    inv_width: f64,
    /// Absolute number of the current bucket: it covers `[origin + cur·w, origin + (cur+1)·w)`.
    cur: i64,
    nb: usize,
    in_buckets: usize,
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
    fn link<E: HasEntry>(&mut self, e: &mut [E], i: u32, b: usize) {
        let bucket = &mut self.buckets[b];
        let l = bucket.len as usize;
        let entry = e[i as usize].entry_mut();
        if l < INLINE {
            bucket.ids[l] = i;
            bucket.len += 1;
        } else {
            entry.next = bucket.spill;
            bucket.spill = i;
        }
        entry.loc = b as u32;
    }

    #[inline]
    fn unlink<E: HasEntry>(&mut self, e: &mut [E], i: u32, b: usize) {
        let bucket = &mut self.buckets[b];
        let l = bucket.len as usize;
        if let Some(k) = bucket.ids[..l].iter().position(|&x| x == i) {
            bucket.ids[k] = bucket.ids[l - 1];
            // Refill from the spill list, so that the list stays empty while the bucket has room.
            let s = bucket.spill;
            if s == NONE {
                bucket.len -= 1;
            } else {
                bucket.ids[l - 1] = s;
                bucket.spill = e[s as usize].entry().next;
            }
            return;
        }
        let mut prev = NONE;
        let mut k = bucket.spill;
        while k != i {
            debug_assert!(k != NONE, "particle {i} not in bucket {b}");
            prev = k;
            k = e[k as usize].entry().next;
        }
        let next = e[i as usize].entry().next;
        if prev == NONE {
            bucket.spill = next;
        } else {
            e[prev as usize].entry_mut().next = next;
        }
    }

    /// Files particle `i` at time `t` at once (while the calendar redistributes its overflow).
    #[inline]
    fn insert_now<E: HasEntry>(&mut self, e: &mut [E], i: u32, t: f64) {
        e[i as usize].entry_mut().time = t;
        let k = self.bucket_of(t) - self.cur;
        if k <= 0 {
            self.current_push(e, t, i);
        } else if (k as u64) < self.nb as u64 {
            self.link(e, i, ((self.cur + k) as u64 as usize) & (self.nb - 1));
            self.in_buckets += 1;
        } else {
            e[i as usize].entry_mut().loc = IN_OVERFLOW | self.overflow.len() as u32;
            self.overflow.push(i);
        }
    }

    fn overflow_remove<E: HasEntry>(&mut self, e: &mut [E], pos: usize) {
        let last = self
            .overflow
            .pop()
            .expect("overflow position of a filed particle");
        if pos < self.overflow.len() {
            self.overflow[pos] = last;
            e[last as usize].entry_mut().loc = IN_OVERFLOW | pos as u32;
        }
    }

    /// Moves overflow entries that fall in the coming cycle into buckets (or the current one); the rest
    /// close up in place.
    fn redistribute<E: HasEntry>(&mut self, e: &mut [E]) {
        let mut overflow = std::mem::take(&mut self.overflow);
        let mut kept = 0;
        for k in 0..overflow.len() {
            let i = overflow[k];
            let t = e[i as usize].entry().time;
            if self.bucket_of(t) - self.cur >= self.nb as i64 {
                overflow[kept] = i;
                e[i as usize].entry_mut().loc = IN_OVERFLOW | kept as u32;
                kept += 1;
            } else {
                self.insert_now(e, i, t);
            }
        }
        overflow.truncate(kept);
        self.overflow = overflow;
    }

    /// Advances to the next non-empty bucket and makes its entries the current ones.
    fn advance<E: HasEntry>(&mut self, e: &mut [E]) {
        debug_assert!(self.current.is_empty() && self.len > 0);
        self.heap_mode = false;
        if self.in_buckets == 0 {
            // Every bucket is empty: jump to the cycle that holds the earliest overflow entry.
            let tmin = self
                .overflow
                .iter()
                .map(|&i| e[i as usize].entry().time)
                .fold(f64::INFINITY, f64::min);
            let nb = self.nb as i64;
            let start = self.bucket_of(tmin).div_euclid(nb) * nb;
            if start > self.cur {
                self.cur = start;
                self.redistribute(e);
                if !self.current.is_empty() {
                    return;
                }
            }
        }
        loop {
            self.cur += 1;
            let b = (self.cur as u64 as usize) & (self.nb - 1);
            if b == 0 {
                self.redistribute(e);
            }
            if !self.deferred.is_empty() {
                self.link_deferred_due(e, b);
            }
            let bucket = std::mem::replace(&mut self.buckets[b], EMPTY_BUCKET);
            for &i in &bucket.ids[..bucket.len as usize] {
                self.in_buckets -= 1;
                let t = e[i as usize].entry().time;
                self.current_push(e, t, i);
            }
            let mut i = bucket.spill;
            while i != NONE {
                let next = e[i as usize].entry().next;
                self.in_buckets -= 1;
                let t = e[i as usize].entry().time;
                self.current_push(e, t, i);
                i = next;
            }
            if !self.current.is_empty() {
                self.loads = self.loads.wrapping_add(1);
                self.prefetch_ahead(e);
                return;
            }
        }
    }

    /// Asks for the next two buckets' lines and the entries of the next one (whose line the
    /// previous advance asked for): the advance after this one then finds them in cache, and
    /// [`Peek::next`] can name the next bucket's first entry while the current one is empty.
    #[inline]
    fn prefetch_ahead<E: HasEntry>(&self, e: &[E]) {
        let mask = self.nb - 1;
        let next = &self.buckets[(self.cur.wrapping_add(1) as u64 as usize) & mask];
        crate::prefetch::prefetch_at(
            &self.buckets,
            (self.cur.wrapping_add(2) as u64 as usize) & mask,
        );
        for &i in &next.ids[..(next.len as usize).min(INLINE)] {
            if let Some(x) = e.get(i as usize) {
                crate::prefetch::prefetch(x.entry());
            }
        }
    }

    /// Lets filings into later buckets wait until their bucket line has arrived: a setting that
    /// changes no pop (the tests compare both). By default it is on where the buckets and the
    /// particles' records outgrow twice the L2 ([`crate::caches::calendar_deferral_threshold`]),
    /// set at every [`Calendar::reset`]; this call fixes it.
    pub fn defer_filings<E: HasEntry>(&mut self, e: &mut [E], on: bool) {
        if !on {
            self.link_deferred(e);
        }
        self.defer = on;
        self.defer_by_size = false;
    }

    /// Whether filings are deferred now.
    pub fn defers_filings(&self) -> bool {
        self.defer
    }
}

impl Calendar for PaulCalendar {
    fn with_capacity(n: usize) -> Self {
        // The power of two nearest to n: about one 32-byte bucket per particle (a cycle then spans
        // ~N mean inter-event times), never the nearly two per particle of rounding up.
        let up = n.max(16).next_power_of_two();
        let nb = if up - n.max(16) > n.max(16) - up / 2 {
            up / 2
        } else {
            up
        };
        PaulCalendar {
            buckets: vec![EMPTY_BUCKET; nb],
            overflow: Vec::new(),
            current: Vec::with_capacity(64),
            heap_mode: false,
            deferred: Vec::with_capacity(DEFER),
            loads: 0,
            defer: false,
            defer_by_size: true,
            origin: 0.0,
            width: 1.0,
            inv_width: 1.0,
            cur: 0,
            nb,
            in_buckets: 0,
            len: 0,
        }
    }

    #[inline]
    fn schedule<E: HasEntry>(&mut self, e: &mut [E], i: u32, t: f64) {
        debug_assert!(!t.is_nan(), "NaN event time for particle {i}");
        self.remove(e, i);
        if t < f64::INFINITY {
            self.insert(e, i, t);
            self.len += 1;
        }
    }

    #[inline]
    fn remove<E: HasEntry>(&mut self, e: &mut [E], i: u32) {
        let l = e[i as usize].entry().loc;
        if l == NONE {
            return;
        }
        if l & DEFERRED == DEFERRED {
            self.deferred_remove(e, (l & !DEFERRED) as usize);
            self.in_buckets -= 1;
        } else if l & IN_CURRENT != 0 {
            self.current_remove(e, i, l);
        } else if l & IN_OVERFLOW != 0 {
            self.overflow_remove(e, (l & !IN_OVERFLOW) as usize);
        } else {
            self.unlink(e, i, l as usize);
            self.in_buckets -= 1;
        }
        e[i as usize].entry_mut().loc = NONE;
        self.len -= 1;
    }

    #[inline]
    fn pop<E: HasEntry>(&mut self, e: &mut [E]) -> Option<(u32, f64)> {
        if self.current.is_empty() {
            if self.len == 0 {
                return None;
            }
            self.advance(e);
        }
        let (t, i) = self.current_pop(e)?;
        e[i as usize].entry_mut().loc = NONE;
        self.len -= 1;
        Some((i, t))
    }

    fn peek_time<E: HasEntry>(&mut self, e: &mut [E]) -> Option<f64> {
        if self.current.is_empty() {
            if self.len == 0 {
                return None;
            }
            self.advance(e);
        }
        self.current_first().map(|h| h.0)
    }

    fn len(&self) -> usize {
        self.len
    }

    #[inline(always)]
    fn peek(&self) -> Option<Peek<'_>> {
        Some(Peek(self))
    }

    fn reset<E: HasEntry>(&mut self, e: &mut [E], origin: f64, width: f64) {
        assert!(
            width > 0.0 && width.is_finite(),
            "calendar bucket width must be positive"
        );
        for x in e.iter_mut() {
            *x.entry_mut() = Entry::EMPTY;
        }
        self.buckets.fill(EMPTY_BUCKET);
        self.overflow.clear();
        self.current.clear();
        self.heap_mode = false;
        self.deferred.clear();
        if self.defer_by_size {
            let bytes = self.nb * std::mem::size_of::<Bucket>() + std::mem::size_of_val(e);
            self.defer = bytes > crate::caches::calendar_deferral_threshold();
        }
        self.origin = origin;
        self.width = width;
        self.inv_width = 1.0 / width;
        self.cur = 0;
        self.in_buckets = 0;
        self.len = 0;
    }
}
