//! The `BinaryHeap` calendar with lazy deletion: the test oracle and benchmark baseline.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use super::{Calendar, HasEntry};

/// `f64` with a total order, for the oracle heap.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
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
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
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

    fn schedule<E: HasEntry>(&mut self, e: &mut [E], i: u32, t: f64) {
        self.remove(e, i);
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

    fn remove<E: HasEntry>(&mut self, _: &mut [E], i: u32) {
        if self.active[i as usize] {
            self.active[i as usize] = false;
            self.len -= 1;
        }
    }

    fn pop<E: HasEntry>(&mut self, _: &mut [E]) -> Option<(u32, f64)> {
        self.discard_stale();
        let k = self.heap.pop()?;
        self.active[k.1 as usize] = false;
        self.len -= 1;
        Some((k.1, k.0))
    }

    fn peek_time<E: HasEntry>(&mut self, _: &mut [E]) -> Option<f64> {
        self.discard_stale();
        self.heap.peek().map(|k| k.0)
    }

    fn len(&self) -> usize {
        self.len
    }

    fn reset<E: HasEntry>(&mut self, _: &mut [E], _origin: f64, _width: f64) {
        self.heap.clear();
        self.active.fill(false);
        self.len = 0;
    }
}
