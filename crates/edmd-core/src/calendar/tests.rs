//! The Paul calendar against the heap oracle.

use super::*;
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Random schedule/remove/pop traffic, the way an event loop produces it: both calendars must
/// return identical sequences.
fn compare(n: usize, width: f64, steps: usize, seed: u64) {
    compare_with(n, width, steps, seed, false);
    compare_with(n, width, steps, seed, true);
}

/// [`compare`] with the Paul calendar's filings deferred or not.
fn compare_with(n: usize, width: f64, steps: usize, seed: u64, defer: bool) {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut a = Standalone::<PaulCalendar>::with_capacity(n);
    a.defer_filings(defer);
    let mut b = Standalone::<HeapCalendar>::with_capacity(n);
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
    compare(1000, 0.05, 200_000, 4); // ~16 entries per bucket: spill lists in use
    compare(3000, 1e3, 100_000, 5); // every entry in the current bucket: a heap
}

/// A width far too wide puts every entry in the current bucket, which then runs as a heap: the
/// pops are the heap oracle's, with half the entries tied in time and every particle filed once
/// more among the ties (filings and removals in heap mode, and back to a sorted array after it).
#[test]
fn crowded_current_bucket_matches_the_heap() {
    let n = 5000;
    let mut c = Standalone::<PaulCalendar>::with_capacity(n);
    c.reset(0.0, 1e6);
    let mut heap = Standalone::<HeapCalendar>::with_capacity(n);
    heap.reset(0.0, 1e6);
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(6);
    for i in 0..n as u32 {
        let t = if i % 2 == 0 {
            rng.random::<f64>() * 3.0
        } else {
            2.0
        };
        c.schedule(i, t);
        heap.schedule(i, t);
    }
    let mut again = vec![true; n];
    let mut pops = 0;
    while let Some(p) = c.pop() {
        assert_eq!(Some(p), heap.pop());
        pops += 1;
        if p.1 <= 2.0 && std::mem::replace(&mut again[p.0 as usize], false) {
            c.schedule(p.0, 2.0);
            heap.schedule(p.0, 2.0);
        }
        if pops % 7 == 0 {
            let j = rng.random_range(0..n as u32);
            c.remove(j);
            heap.remove(j);
        }
    }
    assert!(heap.pop().is_none());
}

#[test]
fn ties_break_by_index() {
    let mut c = Standalone::<PaulCalendar>::with_capacity(4);
    c.reset(0.0, 1.0);
    for i in [3, 1, 2, 0] {
        c.schedule(i, 5.0);
    }
    let order: Vec<u32> = std::iter::from_fn(|| c.pop().map(|e| e.0)).collect();
    assert_eq!(order, vec![0, 1, 2, 3]);
}

#[test]
fn infinite_time_means_unscheduled() {
    let mut c = Standalone::<PaulCalendar>::with_capacity(2);
    c.reset(0.0, 1.0);
    c.schedule(0, 1.0);
    c.schedule(0, f64::INFINITY);
    assert!(c.is_empty());
    assert_eq!(c.pop(), None);
}

/// Bursts of filings between pops, more than the Paul calendar defers before linking them, and
/// removals of filings still deferred: the same pops as the heap.
#[test]
fn deferred_filings_overflow_and_removal_match_the_heap() {
    let n = 500;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(9);
    let mut a = Standalone::<PaulCalendar>::with_capacity(n);
    let mut b = Standalone::<HeapCalendar>::with_capacity(n);
    a.defer_filings(true);
    a.reset(0.0, 0.01);
    b.reset(0.0, 0.01);
    let mut now = 0.0;
    for _ in 0..300 {
        for _ in 0..100 {
            let i = rng.random_range(0..n as u32);
            let t = now + rng.random::<f64>();
            a.schedule(i, t);
            b.schedule(i, t);
        }
        for _ in 0..20 {
            let j = rng.random_range(0..n as u32);
            a.remove(j);
            b.remove(j);
        }
        assert_eq!(a.len(), b.len());
        for _ in 0..50 {
            let (pa, pb) = (a.pop(), b.pop());
            assert_eq!(pa, pb);
            match pa {
                Some((_, t)) => now = t,
                None => break,
            }
        }
    }
}

/// The look-ahead hint: every particle named for the bucket `k` places ahead is filed there.
#[test]
fn ahead_names_particles_of_that_bucket() {
    let n = 2000;
    let width = 1e-3;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(10);
    let mut c = Standalone::<PaulCalendar>::with_capacity(n);
    c.defer_filings(true);
    c.reset(0.0, width);
    let mut times = vec![f64::INFINITY; n];
    for i in 0..n {
        times[i] = rng.random::<f64>();
        c.schedule(i as u32, times[i]);
    }
    let mut named = 0;
    for _ in 0..5000 {
        let (i, t) = c.pop().unwrap();
        times[i as usize] = t + rng.random::<f64>();
        c.schedule(i, times[i as usize]);
        for k in 1..=5 {
            for &j in c.peek().unwrap().ahead(k) {
                let bucket = (times[j as usize] / width) as i64;
                assert_eq!(
                    bucket,
                    c.peek().unwrap().position() + k as i64,
                    "particle {j}, {k} ahead"
                );
                named += 1;
            }
        }
    }
    assert!(named > 5000, "the hint named only {named} particles");
}

/// Filings are deferred by default only where the buckets and the records outgrow the L2: a
/// calendar of 64 particles (2 KiB of buckets and entries) files at once, one of 2²⁰ (48 MiB, more
/// than any per-core L2) defers; an explicit setting holds through a reset.
#[test]
fn deferral_follows_the_size_unless_set() {
    let mut small = Standalone::<PaulCalendar>::with_capacity(64);
    small.reset(0.0, 1.0);
    assert!(!small.defers_filings());
    let mut large = Standalone::<PaulCalendar>::with_capacity(1 << 20);
    large.reset(0.0, 1.0);
    assert!(large.defers_filings());
    small.defer_filings(true);
    small.reset(0.0, 1.0);
    assert!(small.defers_filings());
}
