//! Event calendars: one pending event per slot (each particle's, and each kind of system event's),
//! earliest first.
//!
//! [`PaulCalendar`] follows G. Paul, J. Comput. Phys. 221, 615 (2007): time is cut into buckets of a
//! fixed width; the current bucket is a short array sorted latest first (a pop takes the last
//! entry, a filing shifts the later ones up), the next `M` buckets are unsorted (up to six entries
//! in place, in half a cache line, and a spill list beyond: O(1) insert and remove that touch only
//! the bucket and the particle's own entry), and everything later waits in an unordered overflow
//! array that is redistributed once per cycle of `M` buckets. With a width of a few mean
//! inter-event times the current bucket holds a handful of entries, so every operation is O(1)
//! amortised; a current bucket crowded past 32 entries (a width far too wide for the event rate, or
//! events tied in time) runs as an indexed binary heap until it is empty.
//!
//! [`HeapCalendar`] is a plain `BinaryHeap` with lazy deletion. It has the same API and exists as a
//! test oracle and as the benchmark baseline.
//!
//! Both order events by `(time, particle index)`, so the two produce identical sequences.
//!
//! What the bucket calendar knows ahead of its pops (the next particle, the particles of the coming
//! buckets) it shows as a read-only [`Peek`], for prefetching; the oracle shows none.

/// One particle's place in a calendar: its filed time and where the calendar keeps it.
///
/// The calendar does not own these: each lives in the caller's per-particle record (the engine's
/// bookkeeping, [`HasEntry`]), so that filing or popping a particle touches the line its event has
/// read anyway, not a line of a separate array. Outside an engine, [`Standalone`] keeps them in a
/// vector of their own.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Entry {
    time: f64,
    /// The next entry of its bucket's spill list.
    next: u32,
    /// `NONE`, `IN_CURRENT` (in the current bucket), `IN_OVERFLOW | overflow position`, `DEFERRED |
    /// position among the deferred filings`, or a bucket index (Paul calendar).
    loc: u32,
}

impl Entry {
    /// Not filed.
    pub const EMPTY: Entry = Entry {
        time: f64::INFINITY,
        next: u32::MAX,
        loc: u32::MAX,
    };
}

impl Default for Entry {
    fn default() -> Self {
        Entry::EMPTY
    }
}

/// A per-particle record that carries its calendar [`Entry`].
pub trait HasEntry {
    /// The entry.
    fn entry(&self) -> &Entry;
    /// The entry, to be changed by the calendar.
    fn entry_mut(&mut self) -> &mut Entry;
}

impl HasEntry for Entry {
    #[inline(always)]
    fn entry(&self) -> &Entry {
        self
    }
    #[inline(always)]
    fn entry_mut(&mut self) -> &mut Entry {
        self
    }
}

/// A priority queue holding at most one event time per particle. The particles' entries are the
/// caller's (`e`, indexed by particle; see [`Entry`]); every call that files, removes or pops is
/// handed the same slice.
pub trait Calendar:
    std::fmt::Debug + Send + serde::Serialize + serde::de::DeserializeOwned
{
    /// An empty calendar for particles `0..n`.
    fn with_capacity(n: usize) -> Self
    where
        Self: Sized;
    /// Sets particle `i`'s event to time `t`, replacing any earlier entry. `t = ∞` removes it.
    fn schedule<E: HasEntry>(&mut self, e: &mut [E], i: u32, t: f64);
    /// Removes particle `i`'s entry, if any.
    fn remove<E: HasEntry>(&mut self, e: &mut [E], i: u32);
    /// Removes and returns the earliest entry `(particle, time)`; ties go to the lower index.
    fn pop<E: HasEntry>(&mut self, e: &mut [E]) -> Option<(u32, f64)>;
    /// The time of the earliest entry without removing it.
    fn peek_time<E: HasEntry>(&mut self, e: &mut [E]) -> Option<f64>;
    /// Number of scheduled particles.
    fn len(&self) -> usize;
    /// True when nothing is scheduled.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// A view of the coming pops, for prefetching, where the calendar has one (the bucket
    /// calendar's [`Peek`]); none by default, so that a calendar such as the oracle
    /// [`HeapCalendar`] carries nothing for it.
    #[inline(always)]
    fn peek(&self) -> Option<Peek<'_>> {
        None
    }
    /// Empties the calendar (every entry of `e` included) and sets its time origin and bucket
    /// width (a hint; `width > 0`).
    fn reset<E: HasEntry>(&mut self, e: &mut [E], origin: f64, width: f64);
}

/// A calendar with entries of its own, for use outside an engine (tests, benchmarks): the
/// [`Calendar`] calls without the entries argument.
#[derive(Debug, Clone)]
pub struct Standalone<C> {
    calendar: C,
    entries: Vec<Entry>,
}

impl<C: Calendar> Standalone<C> {
    /// An empty calendar for particles `0..n`.
    pub fn with_capacity(n: usize) -> Self {
        Standalone {
            calendar: C::with_capacity(n),
            entries: vec![Entry::EMPTY; n],
        }
    }
    /// [`Calendar::schedule`].
    pub fn schedule(&mut self, i: u32, t: f64) {
        self.calendar.schedule(&mut self.entries, i, t);
    }
    /// [`Calendar::remove`].
    pub fn remove(&mut self, i: u32) {
        self.calendar.remove(&mut self.entries, i);
    }
    /// [`Calendar::pop`].
    pub fn pop(&mut self) -> Option<(u32, f64)> {
        self.calendar.pop(&mut self.entries)
    }
    /// [`Calendar::peek_time`].
    pub fn peek_time(&mut self) -> Option<f64> {
        self.calendar.peek_time(&mut self.entries)
    }
    /// [`Calendar::len`].
    pub fn len(&self) -> usize {
        self.calendar.len()
    }
    /// [`Calendar::is_empty`].
    pub fn is_empty(&self) -> bool {
        self.calendar.is_empty()
    }
    /// [`Calendar::peek`].
    pub fn peek(&self) -> Option<Peek<'_>> {
        self.calendar.peek()
    }
    /// [`Calendar::reset`].
    pub fn reset(&mut self, origin: f64, width: f64) {
        self.calendar.reset(&mut self.entries, origin, width);
    }
}

impl Standalone<PaulCalendar> {
    /// [`PaulCalendar::defer_filings`].
    pub fn defer_filings(&mut self, on: bool) {
        self.calendar.defer_filings(&mut self.entries, on);
    }
    /// [`PaulCalendar::defers_filings`].
    pub fn defers_filings(&self) -> bool {
        self.calendar.defers_filings()
    }
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
pub use paul::{PaulCalendar, Peek};
