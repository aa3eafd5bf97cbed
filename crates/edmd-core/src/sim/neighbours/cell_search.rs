//! Cell mode: collision search over the 3^D neighbour cells, the next crossing or wall contact, and
//! the crossing itself.

use super::NONE;
use super::{Cells, Search};
use crate::calendar::Calendar;
use crate::predict::{pair_time, reach_time, select};
use crate::sim::{Aux, Simulation};
use crate::{Boundary, CollisionRule, Particle, Vector};

/// Cell mode predicts by its own search and crossings.
impl Search for Cells {
    const LISTS: bool = false;

    #[inline(always)]
    fn search<const D: usize, B: Boundary, R: CollisionRule, C: Calendar>(
        sim: &Simulation<D, B, R, C>,
        i: usize,
        _horizon: f64,
    ) -> (f64, u32) {
        sim.search_cells(i, None, (f64::INFINITY, NONE))
    }

    #[inline(always)]
    fn next_exit<const D: usize, B: Boundary, R: CollisionRule, C: Calendar>(
        sim: &Simulation<D, B, R, C>,
        i: usize,
    ) -> (f64, Aux) {
        sim.aux_event_cells(i)
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Earliest contact of particle `i` (at now) with the members of its neighbour cells; with
    /// `only = Some((axis, dir))`, just the cells at offset `dir` along `axis`.
    ///
    /// The interior cell's search is inlined at every call site, where `only` is known, so that
    /// the choice between the full and the partial search costs no branch (a coin flip between
    /// collisions and crossings, were both to share one copy); a cell at the box's edge goes out
    /// of line to [`Self::search_edge_cells`].
    #[inline(always)]
    pub(in crate::sim) fn search_cells(
        &self,
        i: usize,
        only: Option<(usize, i32)>,
        mut best: (f64, u32),
    ) -> (f64, u32) {
        let ci = self.meta[i].cell;
        if self.grid.is_interior(&ci) {
            let pi = self.particles[i];
            let pos_i = pi.at(self.now);
            // Interior cell (the common case): fixed offsets, no periodic images; a full search
            // by rows of three cells (in the order of `grid.full`).
            let center = self.grid.index(&ci);
            match only {
                None => {
                    // The occupied cells' first members gathered without a branch (whether a
                    // cell is empty is a coin flip), then walked in the same order.
                    let mut firsts = [NONE; 27];
                    let mut n = 0;
                    self.grid.for_each_row(center, |start| {
                        for first in self.grid.row(start) {
                            firsts[n] = first;
                            n += (first != NONE) as usize;
                        }
                    });
                    for &first in &firsts[..n] {
                        best = self.scan_members(first, i, &pi, &pos_i, best);
                    }
                }
                Some((axis, dir)) => {
                    for &o in &self.grid.partial[2 * axis + (dir > 0) as usize] {
                        let idx = (center as isize + o) as usize;
                        best = self.scan_cell(idx, i, &pi, &pos_i, best);
                    }
                }
            }
            return best;
        }
        self.search_edge_cells(i, only, best)
    }

    /// [`Self::search_cells`] for a cell at the box's edge: periodic images, walls, sliding faces.
    #[inline(never)]
    fn search_edge_cells(
        &self,
        i: usize,
        only: Option<(usize, i32)>,
        mut best: (f64, u32),
    ) -> (f64, u32) {
        if let Some(found) = self.search_sliding_cells(i, only, best) {
            return found;
        }
        let pi = self.particles[i];
        let pos_i = pi.at(self.now);
        let ci = self.meta[i].cell;
        // Per axis: the neighbour rows to visit, as linear-index contribution and image shift.
        let mut lin = [[0usize; 3]; D];
        let mut sh = [[0.0f64; 3]; D];
        let mut count = [0usize; D];
        for a in 0..D {
            let n = self.grid.n[a] as i32;
            for off in -1..=1 {
                if matches!(only, Some((axis, dir)) if axis == a && off != dir) {
                    continue;
                }
                let mut x = ci[a] as i32 + off;
                let mut s = 0.0;
                if x < 0 {
                    if B::is_wall(a) {
                        continue;
                    }
                    x += n;
                    s = -self.box_len[a];
                } else if x >= n {
                    if B::is_wall(a) {
                        continue;
                    }
                    x -= n;
                    s = self.box_len[a];
                }
                lin[a][count[a]] = x as usize * self.grid.stride[a];
                sh[a][count[a]] = s;
                count[a] += 1;
            }
            if count[a] == 0 {
                return best;
            }
        }
        let mut digit = [0usize; D];
        loop {
            let mut idx = 0;
            let mut ri = pos_i;
            for a in 0..D {
                idx += lin[a][digit[a]];
                ri[a] -= sh[a][digit[a]];
            }
            best = self.scan_cell(idx, i, &pi, &ri, best);
            let mut a = 0;
            loop {
                digit[a] += 1;
                if digit[a] < count[a] {
                    break;
                }
                digit[a] = 0;
                a += 1;
                if a == D {
                    return best;
                }
            }
        }
    }

    /// Earliest contact of particle `i` (state `pi`, position image `ri`) with the members of cell `idx`.
    #[inline(always)]
    pub(in crate::sim) fn scan_cell(
        &self,
        idx: usize,
        i: usize,
        pi: &Particle<D>,
        ri: &Vector<D>,
        best: (f64, u32),
    ) -> (f64, u32) {
        self.scan_members(self.grid.first(idx), i, pi, ri, best)
    }

    /// [`Self::scan_cell`] from the cell's first member `first`.
    #[inline(always)]
    fn scan_members(
        &self,
        first: u32,
        i: usize,
        pi: &Particle<D>,
        ri: &Vector<D>,
        mut best: (f64, u32),
    ) -> (f64, u32) {
        let now = self.now;
        let vi2 = pi.vel.norm_squared();
        let mut k = first;
        while k != NONE {
            let pk = &self.particles[k as usize];
            let next = pk.next_in_cell;
            if next != NONE {
                crate::prefetch::prefetch_at(&self.particles, next as usize);
            }
            // The particle itself (in its own cell of a full search) is no partner.
            if k as usize != i {
                let dr = ri - pk.at(now);
                let dv = pi.vel - pk.vel;
                let t =
                    now + pair_time(&dr, &dv, pi.radius + pk.radius, vi2 + pk.vel.norm_squared());
                if t < best.0 {
                    best = (t, k);
                }
            }
            k = next;
        }
        best
    }

    /// Next cell crossing or wall contact of particle `i` (at now).
    #[inline]
    pub(in crate::sim) fn aux_event_cells(&self, i: usize) -> (f64, Aux) {
        let p = &self.particles[i];
        let c = &self.meta[i].cell;
        let mut best = self.fall_exit(p, c);
        for a in 0..D {
            if self.falls_along(a) {
                continue;
            }
            let v = p.vel[a];
            let up = v > 0.0;
            if v == 0.0 {
                continue;
            }
            let edge = if up {
                c[a] as usize + 1 == self.grid.n[a]
            } else {
                c[a] == 0
            };
            let (dt, code) = if B::is_wall(a) && edge {
                (self.wall_ahead(p, a, up), Aux::Wall { axis: a as u8, up })
            } else {
                let face = (c[a] as u32 + up as u32) as f64 * self.grid.side[a];
                (
                    reach_time(p.r0[a] + v * self.now, v, face),
                    Aux::Crossing { axis: a as u8, up },
                )
            };
            // The earlier of the axes, chosen without a branch (which axis comes first is a coin
            // flip): the time by bit masks, the code by a conditional move.
            let t = self.now + dt;
            let earlier = t < best.0;
            best = (
                select(earlier, t, best.0),
                if earlier { code } else { best.1 },
            );
        }
        best
    }

    /// Moves particle `i` into the neighbouring cell along `axis` and searches the new neighbours.
    #[inline]
    pub(in crate::sim) fn cross(&mut self, i: usize, axis: usize, up: bool) {
        self.counters.crossings += 1;
        let old = self.grid.index(&self.meta[i].cell);
        let n = self.grid.n[axis] as u16;
        let c = &mut self.meta[i].cell[axis];
        let from = *c as isize;
        let mut wrapped = false;
        if up {
            *c += 1;
            if *c == n {
                *c = 0;
                self.particles[i].r0[axis] -= self.box_len[axis];
                wrapped = true;
            }
        } else if *c == 0 {
            *c = n - 1;
            self.particles[i].r0[axis] += self.box_len[axis];
            wrapped = true;
        } else {
            *c -= 1;
        }
        let to = *c as isize;
        let sheared = wrapped && self.slides_across(axis);
        let new = if sheared {
            // The sliding face may move the cell along x too.
            self.cross_sheared_face(i, up);
            self.grid.index(&self.meta[i].cell)
        } else {
            (old as isize + (to - from) * self.grid.stride[axis] as isize) as usize
        };
        self.grid.remove(&mut self.particles, i as u32, old);
        self.grid.insert(&mut self.particles, i as u32, new);
        if sheared {
            // A new trajectory: a full search, as after a collision.
            let (t, partner) = self.search_all_cells(i);
            self.store::<Cells>(i, t, partner);
            return;
        }
        // Only the cells that just became adjacent need a search, unless the candidate went stale.
        // Every pair a search has seen keeps a bound: since the last trajectory change of either
        // particle, one of the two searched the other (a velocity change is always followed by a
        // full search), so its stored candidate time is no later than their contact. A valid
        // candidate is thus still the earliest among the old neighbours, and no candidate at all
        // (the common case in a gas) means no old neighbour will be touched; only a stale one
        // loses the bound and calls for a full search.
        let e = self.meta[i].ev;
        let valid =
            e.partner == NONE || self.particles[e.partner as usize].counter == e.partner_count;
        let (t, partner) = if valid {
            self.search_cells(
                i,
                Some((axis, if up { 1 } else { -1 })),
                (e.coll_t, e.partner),
            )
        } else {
            self.search_all_cells(i)
        };
        self.store::<Cells>(i, t, partner);
    }

    /// A full search out of line, for the crossings that need one (a stale candidate, a sliding
    /// face): rare enough that a copy of the full search inlined here would only cost build time.
    #[inline(never)]
    fn search_all_cells(&self, i: usize) -> (f64, u32) {
        self.search_cells(i, None, (f64::INFINITY, NONE))
    }
}
