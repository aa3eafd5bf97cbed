//! Event calendars: one pending event per particle, earliest first.
//!
//! [`PaulCalendar`] follows G. Paul, J. Comput. Phys. 221, 615 (2007): time is cut into buckets of a
//! fixed width; the current bucket is a small indexed binary heap, the next `M` buckets are unsorted
//! (up to six entries in place, in half a cache line, and a spill list beyond: O(1) insert and
//! remove that touch only the bucket and the particle's own entry), and everything later waits in an
//! unordered overflow array that is redistributed once per cycle of `M` buckets. With a width of a
//! few mean inter-event times the heap stays a handful of entries long, so every operation is O(1)
//! amortised.
//!
//! [`HeapCalendar`] is a plain `BinaryHeap` with lazy deletion. It has the same API and exists as a
//! test oracle and as the benchmark baseline.
//!
//! Both order events by `(time, particle index)`, so the two produce identical sequences.

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
    /// Asks for the cache line of particle `i`'s entry, which its next filing will touch (a hint).
    #[inline(always)]
    fn prefetch(&self, i: u32) {
        let _ = i;
    }
    /// Asks for the lines that filing an entry at time `t`, and removing particle `i`'s present
    /// one, will touch (a hint: called where the time is known some work before the filing).
    #[inline(always)]
    fn prefetch_filing(&self, i: u32, t: f64) {
        let _ = (i, t);
    }
    /// The particles filed in the bucket `k` places after the current one, as far as it holds them
    /// in place (a hint for a look-ahead several events deep; empty where unknown). Reads that
    /// bucket's line.
    #[inline(always)]
    fn ahead(&self, k: usize) -> &[u32] {
        let _ = k;
        &[]
    }
    /// Asks for the line of the bucket `k` places after the current one (a hint).
    #[inline(always)]
    fn prefetch_bucket(&self, k: usize) {
        let _ = k;
    }
    /// The current bucket's number: it changes whenever the calendar moves on to a later bucket.
    #[inline(always)]
    fn position(&self) -> i64 {
        0
    }
    /// Lets filings into later buckets wait until their bucket line has arrived: a hint that
    /// changes no pop (the Paul calendar defers by default; tests compare both).
    fn defer_filings(&mut self, on: bool) {
        let _ = on;
    }
    /// Empties the calendar and sets its time origin and bucket width (a hint; `width > 0`).
    fn reset(&mut self, origin: f64, width: f64);
}

#[inline(always)]
pub(crate) fn earlier(a: (f64, u32), b: (f64, u32)) -> bool {
    a.0 < b.0 || (a.0 == b.0 && a.1 < b.1)
}

mod heap;
mod paul;
#[cfg(test)]
mod tests;

pub use heap::HeapCalendar;
pub use paul::PaulCalendar;
