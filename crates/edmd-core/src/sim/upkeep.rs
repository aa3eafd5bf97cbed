//! Upkeep between events: clock rebase, re-sorting of the slots in cell order, and the calendar's
//! re-tuning to the current event rate.

use super::{Cells, Lists, Search, Simulation};
use crate::calendar::Calendar;
use crate::sim::neighbours::NONE;
use crate::{Boundary, CollisionRule};

/// Events per calendar bucket the re-tuning aims at.
const EVENTS_PER_BUCKET: f64 = 2.0;

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Predicts every particle's event from scratch and sizes the calendar's buckets from them.
    pub fn restart_events(&mut self) {
        self.counters.restarts += 1;
        let n = self.particles.len();
        self.rebase_clock();
        self.sort_by_cell();
        let (sum, count) = if self.uses_lists() {
            self.predict_all::<Lists>()
        } else {
            self.predict_all::<Cells>()
        };
        // Each event renews about 1.5 predictions: the mean time between events is ≈ ⟨Δt⟩ / (0.7 N).
        let width = if count > 0 && sum > 0.0 {
            EVENTS_PER_BUCKET * sum / count as f64 / (0.7 * n as f64)
        } else {
            1.0
        };
        self.reschedule_all(width);
        self.next_maintenance = self.counters.events + n.max(64) as u64;
        self.last_maintenance = (self.counters.events, self.now);
    }

    /// Predicts every slot's event without filing it; returns the sum and count of the finite
    /// waiting times.
    fn predict_all<S: Search>(&mut self) -> (f64, usize) {
        let mut sum = 0.0;
        let mut count = 0usize;
        for i in 0..self.particles.len() {
            let t = self.predict_event::<S>(i);
            if t.is_finite() {
                sum += t - self.now;
                count += 1;
            }
        }
        (sum, count)
    }

    /// Empties the calendar, gives it bucket width `width` and files every slot's pending event.
    pub(super) fn reschedule_all(&mut self, width: f64) {
        self.calendar.reset(&mut self.meta, self.now, width);
        for i in 0..self.particles.len() {
            let e = &self.meta[i].ev;
            let t = e.coll_t.min(e.aux_t);
            self.calendar.schedule(&mut self.meta, i as u32, t);
        }
        self.file_system_events();
    }

    /// Renumbers the slots in cell order (row-major in cell mode, the Z order in list mode) so that
    /// neighbours sit close in memory. The event slots' partners are renumbered; the calendar must
    /// be rebuilt by the caller.
    pub(super) fn sort_by_cell(&mut self) {
        let n = self.particles.len();
        // List mode reads partners all around a particle through its list: the Z order keeps them
        // near along every axis. Cell mode walks rows of cells, which the row-major order keeps
        // contiguous (docs/benchmarks.md, "Slot order, one-line records and the partners ahead").
        let rank = self.uses_lists().then(|| z_order_ranks(&self.grid.n));
        let cells: Vec<u32> = self.meta[..n]
            .iter()
            .map(|m| {
                let idx = self.grid.index(&m.cell);
                rank.as_ref().map_or(idx as u32, |r| r[idx])
            })
            .collect();
        if cells.windows(2).all(|w| w[0] <= w[1]) {
            return;
        }
        // Counting sort: perm[new] = old.
        let mut start = vec![0u32; self.grid.len() + 1];
        for &c in &cells {
            start[c as usize + 1] += 1;
        }
        for k in 1..start.len() {
            start[k] += start[k - 1];
        }
        let mut perm = vec![0u32; n];
        for (old, &c) in cells.iter().enumerate() {
            let slot = &mut start[c as usize];
            perm[*slot as usize] = old as u32;
            *slot += 1;
        }
        let mut inv = vec![0u32; n];
        for (new, &old) in perm.iter().enumerate() {
            inv[old as usize] = new as u32;
        }
        // In place, following cycles (no second copy of the big arrays): slot `new` takes `perm[new]`.
        fn permute<T: Copy>(v: &mut [T], perm: &[u32], done: &mut [bool]) {
            done.fill(false);
            for start in 0..v.len() {
                if done[start] {
                    continue;
                }
                let first = v[start];
                let mut cur = start;
                loop {
                    done[cur] = true;
                    let src = perm[cur] as usize;
                    if src == start {
                        v[cur] = first;
                        break;
                    }
                    v[cur] = v[src];
                    cur = src;
                }
            }
        }
        let mut done = vec![false; n];
        permute(&mut self.particles, &perm, &mut done);
        permute(&mut self.meta[..n], &perm, &mut done);
        if std::mem::size_of::<R::State>() > 0 {
            permute(&mut self.rule_state, &perm, &mut done);
        }
        for m in &mut self.meta {
            if m.ev.partner != NONE {
                m.ev.partner = inv[m.ev.partner as usize];
            }
        }
        if let Some(nl) = &mut self.nl {
            nl.permute(&perm, &inv);
        }
        self.grid.clear();
        for s in (0..n).rev() {
            let idx = self.grid.index(&self.meta[s].cell);
            self.file_in_cell(s as u32, idx);
        }
    }

    /// Moves the origin of the local clock to now: trajectories and pending event times are shifted,
    /// the epoch absorbs the elapsed time. The caller rebuilds the calendar.
    pub(super) fn rebase_clock(&mut self) {
        let now = self.now;
        if now == 0.0 {
            return;
        }
        self.rebase_trajectories(now);
        for m in &mut self.meta {
            m.ev.coll_t -= now;
            m.ev.aux_t -= now;
        }
        self.rebase_shear(now);
        self.thermostat.next -= now;
        self.epoch += now;
        self.now = 0.0;
    }

    /// Rebases the clock to zero and re-tunes the calendar to the current event rate.
    pub(super) fn maintenance(&mut self) {
        self.counters.maintenances += 1;
        let drifted = self.remove_drift_if_large();
        if self.rescale_if_cold() || drifted {
            self.restart_events();
            return;
        }
        let (events0, t0) = self.last_maintenance;
        let elapsed = self.now - t0;
        let count = self.counters.events - events0;
        self.rebase_clock();
        self.sort_by_cell();
        if elapsed > 0.0 && count > 0 {
            self.reschedule_all(EVENTS_PER_BUCKET * elapsed / count as f64);
        } else {
            self.reschedule_all(1.0);
        }
        let n = self.particles.len() as f64;
        self.next_maintenance =
            self.counters.events + (self.params.rebase_events_per_particle * n).max(64.0) as u64;
        self.last_maintenance = (self.counters.events, 0.0);
    }
}

/// Each cell's rank (by its row-major index) in the Z (Morton) order of the cells of a grid with `n`
/// cells per axis: cells close in space are close in this order along every axis, where the
/// row-major order puts the neighbours across the slowest axis a plane of cells away.
fn z_order_ranks<const D: usize>(n: &[usize; D]) -> Vec<u32> {
    let total: usize = n.iter().product();
    let mut keys: Vec<(u64, u32)> = Vec::with_capacity(total);
    let bits = 64 / D;
    for idx in 0..total {
        let mut rest = idx;
        let mut key = 0u64;
        for (a, &len) in n.iter().enumerate() {
            let c = (rest % len) as u64;
            rest /= len;
            for b in 0..bits {
                key |= ((c >> b) & 1) << (b * D + a);
            }
        }
        keys.push((key, idx as u32));
    }
    keys.sort_unstable();
    let mut rank = vec![0u32; total];
    for (r, &(_, idx)) in keys.iter().enumerate() {
        rank[idx as usize] = r as u32;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::z_order_ranks;

    #[test]
    fn z_order_ranks_interleave_the_axes() {
        // A 4 × 4 grid, x fastest in the row-major index: (0,0) (1,0) (0,1) (1,1) (2,0) ...
        let r = z_order_ranks(&[4, 4]);
        let at = |x: usize, y: usize| r[x + 4 * y];
        assert_eq!([at(0, 0), at(1, 0), at(0, 1), at(1, 1)], [0, 1, 2, 3]);
        assert_eq!(
            [at(2, 0), at(3, 0), at(2, 1), at(3, 1), at(0, 2)],
            [4, 5, 6, 7, 8]
        );
        assert_eq!(at(3, 3), 15);
        // Uneven 3D grid: a permutation of the cells.
        let mut r = z_order_ranks(&[5, 3, 7]);
        r.sort_unstable();
        assert!(r.iter().enumerate().all(|(k, &x)| x as usize == k));
    }
}
