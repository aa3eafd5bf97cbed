//! What a calendar can say ahead of its pops, for prefetching.
//!
//! Nothing here changes which event comes next or when: a hint only lets the event loop ask for
//! the lines the coming events will read (`sim/hints.rs`). The Paul calendar knows its next
//! particle and the particles its coming buckets hold; a calendar that knows nothing ahead, such
//! as the oracle [`super::HeapCalendar`], names [`NoHints`] and offers none.

use super::HasEntry;

/// Read-only knowledge of a calendar about its coming pops.
pub trait Hints: std::fmt::Debug + Send {
    /// The particle most likely to be popped next, if known cheaply (used to prefetch its data).
    fn next_hint(&self) -> Option<u32>;
    /// Asks for the lines that filing an entry at time `t`, and removing particle `i`'s present
    /// one, will touch (called where the time is known some work before the filing).
    fn prefetch_filing<E: HasEntry>(&self, e: &[E], i: u32, t: f64);
    /// The particles filed in the bucket `k` places after the current one, as far as it holds them
    /// in place (for a look-ahead several events deep; empty where unknown). Reads that bucket's
    /// line.
    fn ahead(&self, k: usize) -> &[u32];
    /// Asks for the line of the bucket `k` places after the current one.
    fn prefetch_bucket(&self, k: usize);
    /// The current bucket's number: it changes whenever the calendar moves on to a later bucket.
    fn position(&self) -> i64;
}

/// The hints of a calendar that knows nothing ahead: no next particle, no buckets.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoHints;

impl Hints for NoHints {
    #[inline(always)]
    fn next_hint(&self) -> Option<u32> {
        None
    }
    #[inline(always)]
    fn prefetch_filing<E: HasEntry>(&self, _: &[E], _: u32, _: f64) {}
    #[inline(always)]
    fn ahead(&self, _: usize) -> &[u32] {
        &[]
    }
    #[inline(always)]
    fn prefetch_bucket(&self, _: usize) {}
    #[inline(always)]
    fn position(&self) -> i64 {
        0
    }
}
