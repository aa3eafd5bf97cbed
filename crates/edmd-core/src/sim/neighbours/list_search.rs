//! Neighbour-list mode ([`crate::sim::neighbours`]): list builds and renewals at shell exits, and the search
//! over a particle's list (the sheared box's parts: `sim/neighbours/shear_lists.rs`).

use std::marker::PhantomData;

use super::shear_lists::wrapped_now_sheared;
use super::space::{centre_far_from_periodic_faces, rootless_test, smaller, Space};
use super::CellGrid;
use super::NeighbourLists;
use super::{Lists, Search, NONE};
use crate::calendar::Calendar;
use crate::predict::pair_time;
use crate::sim::shear::ShearWindow;
use crate::sim::{Aux, Meta, Simulation};
use crate::{Boundary, CollisionRule, Particle, Vector};

/// Partners per group of the list scan's cheap test (two SSE2 registers of `f64`).
const LANES: usize = 2;

/// List mode predicts by its lists' scan and shell exits.
impl Search for Lists {
    const LISTS: bool = true;

    #[inline(always)]
    fn search<const D: usize, B: Boundary, R: CollisionRule, C: Calendar>(
        sim: &Simulation<D, B, R, C>,
        i: usize,
        horizon: f64,
    ) -> (f64, u32) {
        sim.search_list(sim.lists(), i, (f64::INFINITY, NONE), horizon)
    }

    #[inline(always)]
    fn next_exit<const D: usize, B: Boundary, R: CollisionRule, C: Calendar>(
        sim: &Simulation<D, B, R, C>,
        i: usize,
    ) -> (f64, Aux) {
        sim.aux_event_list(sim.lists(), i)
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// List mode's lists (a simulation runs [`Lists`] only when it has them).
    #[inline(always)]
    fn lists(&self) -> &NeighbourLists<D> {
        self.nl.as_ref().expect("list mode runs with lists")
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Neighbour-list mode: the shell exit or wall contact of slot `i` (at now), whichever is first.
    #[inline]
    pub(in crate::sim) fn aux_event_list(&self, nl: &NeighbourLists<D>, i: usize) -> (f64, Aux) {
        let now = self.now;
        let p = &self.particles[i];
        let pos = p.at(now);
        let u = pos - nl.centre[i];
        let v2 = p.vel.norm_squared();
        let mut best = (f64::INFINITY, Aux::ShellExit);
        if v2 > 0.0 {
            // Positive root of |u + v s|² = h² with |u| ≤ h (up to round-off), cancellation-free.
            let b = u.dot(&p.vel);
            let c = (u.norm_squared() - nl.shell * nl.shell).min(0.0);
            let q = (b * b - v2 * c).sqrt();
            let s = if b > 0.0 { -c / (b + q) } else { (q - b) / v2 };
            best.0 = now + s;
        }
        for a in 0..D {
            let v = p.vel[a];
            if !B::is_wall(a) || v == 0.0 {
                continue;
            }
            let up = v > 0.0;
            let t = now + self.wall_ahead(p, a, up);
            if t < best.0 {
                best = (t, Aux::Wall { axis: a as u8, up });
            }
        }
        best
    }

    /// Neighbour-list mode: draws every shell around the particle's current position, files each
    /// particle in the cell of its centre and fills all lists from scratch.
    pub(in crate::sim) fn build_lists(&mut self) {
        let Some(mut l) = self.list_parts() else {
            return;
        };
        l.nl.clear();
        l.grid.clear();
        for i in 0..l.particles.len() {
            let pos = l.wrap_centre(i);
            let c = l.grid.coords_of(&pos);
            l.meta[i].set_cell(c);
            let idx = l.grid.index(&c);
            l.grid.insert(&mut l.nl.links, i as u32, idx);
        }
        for i in 0..l.particles.len() {
            let ci = l.meta[i].cell();
            l.gather(&ci, i, true, |nl, j| nl.link(i, j as usize));
        }
    }

    /// Shell exit of slot `i` (or a shear shift): a new shell around its current position, new
    /// neighbours, and a new prediction. Its trajectory is unchanged (in a sheared box it may be
    /// replaced by its image in the box, which names it anew), so every other particle's event stays
    /// valid.
    pub(in crate::sim) fn renew_list(&mut self, i: usize) {
        let Some(mut l) = self.list_parts() else {
            return;
        };
        let pos = l.wrap_centre(i);
        let c = l.grid.coords_of(&pos);
        if c != l.meta[i].cell() {
            let old = l.grid.index(&l.meta[i].cell());
            l.grid.remove(&mut l.nl.links, i as u32, old);
            let idx = l.grid.index(&c);
            l.grid.insert(&mut l.nl.links, i as u32, idx);
            l.meta[i].set_cell(c);
        }
        l.nl.fresh.clear();
        l.gather(&c, i, false, |nl, j| nl.fresh.push(j));
        l.nl.renew(i);
        self.predict::<Lists>(i);
    }

    /// The lists and, borrowed beside them, what their builds change and read (`None` in cell
    /// mode).
    fn list_parts(&mut self) -> Option<ListParts<'_, D, B>> {
        let Simulation {
            nl: Some(nl),
            particles,
            meta,
            grid,
            box_len,
            half_box,
            now,
            shear,
            ..
        } = self
        else {
            return None;
        };
        let window = shear.window::<B>(*now);
        Some(ListParts {
            nl,
            particles,
            meta,
            grid,
            box_len,
            half_box,
            now: *now,
            window,
            _boundary: PhantomData,
        })
    }

    /// Earliest contact of slot `i` (at now) with its listed neighbours, of those before `horizon`
    /// (absolute time; the particle's shell exit or wall contact, which comes first otherwise and
    /// is followed by a new search).
    #[inline]
    pub(in crate::sim) fn search_list(
        &self,
        nl: &NeighbourLists<D>,
        i: usize,
        best: (f64, u32),
        horizon: f64,
    ) -> (f64, u32) {
        // Ask for every partner's cache line at once: their loads then overlap. (The four-wide
        // scan's gathers overlap without it while the records fit the L2.)
        if nl.hint_partners || !nl.wide {
            self.prefetch_listed(nl, i);
        }
        let far = nl.far(i);
        let sliding = !far && self.slides_near(nl, i);
        // The scan's variant: (WRAP, SHEAR) = no images far from the faces, sliding images near a
        // sliding face, periodic images elsewhere.
        macro_rules! variant {
            ($scan:ident, $list:expr $(, $more:expr)*) => {
                if far {
                    self.$scan::<false, false $(, $more)*>($list, i, best, horizon)
                } else if sliding {
                    self.$scan::<true, true $(, $more)*>($list, i, best, horizon)
                } else {
                    self.$scan::<true, false $(, $more)*>($list, i, best, horizon)
                }
            };
        }
        #[cfg(target_arch = "x86_64")]
        if nl.wide {
            // SAFETY: `nl.wide` is set only where `wide_scan_available` found AVX2 and the slots'
            // offsets fit (`NeighbourLists::new`).
            #[allow(unsafe_code)]
            return unsafe {
                if nl.same_radius {
                    variant!(scan_list_wide, nl, true)
                } else {
                    variant!(scan_list_wide, nl, false)
                }
            };
        }
        variant!(scan_list, nl.of(i))
    }

    /// The list scan of [`Self::search_list`], with (`WRAP`) or without nearest images; `SHEAR`:
    /// near a sliding face of a sheared box, where a partner across it (a y gap over half the box)
    /// skips the cheap test, which knows only the periodic images, and every kept partner gets the
    /// sheared image's exact time ([`Self::consider_sheared`]).
    ///
    /// Partners go through a cheap test in groups of [`LANES`]: the test without the root, written
    /// lane by lane over arrays so that it compiles to packed arithmetic without branches. Only the
    /// partners it keeps (about one in ten) get the exact time from [`Self::consider`], one by one
    /// and in list order, so the result (ties included) is that of a one-by-one scan. The group's
    /// test uses the bound `limit` of the group's start, which is never below the bound a one-by-one
    /// scan would use there: it keeps at least the partners that scan would keep.
    #[inline(always)]
    fn scan_list<const WRAP: bool, const SHEAR: bool>(
        &self,
        list: &[u32],
        i: usize,
        mut best: (f64, u32),
        horizon: f64,
    ) -> (f64, u32) {
        let now = self.now;
        let pi = self.particles[i];
        let pos_i = pi.at(now);
        let vi2 = pi.vel.norm_squared();
        let mut limit = smaller(best.0 - now, horizon - now);
        // A last, partial group is filled up with `i` itself, which the test rejects (b = 0).
        let full = list.len() / LANES * LANES;
        let mut tail = [i as u32; LANES];
        tail[..list.len() - full].copy_from_slice(&list[full..]);
        let tail = (full < list.len()).then_some(&tail[..]);
        for group in list[..full].chunks_exact(LANES).chain(tail) {
            let mut r0 = [[0.0; LANES]; D];
            let mut vel = [[0.0; LANES]; D];
            let mut radius = [0.0; LANES];
            for (k, &j) in group.iter().enumerate() {
                let pj = &self.particles[j as usize];
                for a in 0..D {
                    r0[a][k] = pj.r0[a];
                    vel[a][k] = pj.vel[a];
                }
                radius[k] = pj.radius;
            }
            let mut keep = [false; LANES];
            let mut across = [false; LANES];
            for k in 0..LANES {
                // b = r·v and |r|², summed over the axes in the order of `Vector::dot`.
                let mut b = 0.0;
                let mut dr2 = 0.0;
                for a in 0..D {
                    let pos = r0[a][k] + vel[a][k] * now;
                    let d = if WRAP && !B::is_wall(a) {
                        // `image_near`: the shifted position minus the partner's.
                        let raw = pos_i[a] - pos;
                        if SHEAR && a == 1 {
                            across[k] = raw.abs() > self.half_box[a];
                        }
                        let up = if raw > self.half_box[a] {
                            self.box_len[a]
                        } else {
                            0.0
                        };
                        let down = if raw < -self.half_box[a] {
                            self.box_len[a]
                        } else {
                            0.0
                        };
                        (pos_i[a] - (up - down)) - pos
                    } else {
                        pos_i[a] - pos
                    };
                    let dv = pi.vel[a] - vel[a][k];
                    if a == 0 {
                        b = d * dv;
                        dr2 = d * d;
                    } else {
                        b += d * dv;
                        dr2 += d * d;
                    }
                }
                let sigma = pi.radius + radius[k];
                keep[k] = rootless_test(b, sigma * sigma - dr2, limit) | across[k];
            }
            if keep.iter().any(|&k| k) {
                for (k, &j) in group.iter().enumerate() {
                    if !keep[k] {
                        continue;
                    }
                    if SHEAR {
                        self.consider_sheared(&pi, &pos_i, j, &mut best, &mut limit);
                    } else {
                        self.consider::<WRAP>(&pi, &pos_i, vi2, j, &mut best, &mut limit);
                    }
                }
            }
        }
        best
    }

    /// One partner `j` of the list scan: the test without the root, then the exact contact time,
    /// which replaces `best` (and tightens `limit`, relative to now) when it is earlier.
    #[inline(always)]
    pub(in crate::sim) fn consider<const WRAP: bool>(
        &self,
        pi: &crate::state::Particle<D>,
        pos_i: &Vector<D>,
        vi2: f64,
        j: u32,
        best: &mut (f64, u32),
        limit: &mut f64,
    ) {
        let now = self.now;
        let pj = &self.particles[j as usize];
        let pos_j = pj.at(now);
        // The nearest image, exactly as `collide` takes it.
        let dr = if WRAP {
            self.image_near(pos_i, &pos_j) - pos_j
        } else {
            pos_i - pos_j
        };
        let v2 = vi2 + pj.vel.norm_squared();
        self.keep_if_earlier(
            &dr,
            &(pi.vel - pj.vel),
            pi.radius + pj.radius,
            v2,
            j,
            best,
            limit,
        );
    }

    /// The pair at separation `dr` and relative velocity `dv` (contact at `sigma`; `v2` the two
    /// speeds squared, for round-off): the test without the root, then the exact contact time,
    /// which replaces `best` (and tightens `limit`, relative to now) when it is earlier.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(in crate::sim) fn keep_if_earlier(
        &self,
        dr: &Vector<D>,
        dv: &Vector<D>,
        sigma: f64,
        v2: f64,
        j: u32,
        best: &mut (f64, u32),
        limit: &mut f64,
    ) {
        if rootless_test(dr.dot(dv), sigma * sigma - dr.norm_squared(), *limit) {
            let t = self.now + pair_time(dr, dv, sigma, v2);
            if t < best.0 {
                *best = (t, j);
                *limit = smaller(*limit, t - self.now);
            }
        }
    }
}

/// The lists and the parts of the simulation their builds change and read, borrowed side by side.
struct ListParts<'a, const D: usize, B> {
    nl: &'a mut NeighbourLists<D>,
    particles: &'a mut Vec<Particle<D>>,
    meta: &'a mut [Meta<D>],
    grid: &'a mut CellGrid<D>,
    box_len: &'a Vector<D>,
    half_box: &'a Vector<D>,
    now: f64,
    /// Sheared boxes: the sliding images' window (`None` elsewhere).
    window: Option<ShearWindow>,
    _boundary: PhantomData<B>,
}

impl<const D: usize, B: Boundary> ListParts<'_, D, B> {
    /// Centres slot `i`'s shell on its position now (wrapped into the box) and records whether its
    /// scans need periodic images ([`NeighbourLists::far`]); returns the position.
    ///
    /// No listed partner of `i` can need an image when the centre lies farther than a list's reach
    /// from every periodic face and a list's reach plus both shells is below half the box. A
    /// listed partner's centre (within reach, both centres in the box) is then not across a face,
    /// both particles lie within their shells (positions are wrapped only with their centres), so
    /// their raw separation is at most reach plus both shells, below half the box: it equals the
    /// nearest image that [`Simulation::image_near`] would take.
    fn wrap_centre(&mut self, i: usize) -> Vector<D> {
        let p = &mut self.particles[i];
        let pos = match self.window {
            Some(w) => wrapped_now_sheared(p, self.now, self.box_len, &w),
            None => wrapped_now::<D, B>(p, self.now, self.box_len),
        };
        self.nl.centre[i] = pos;
        let far = centre_far_from_periodic_faces::<D, B>(
            self.box_len,
            self.half_box,
            &pos,
            self.nl.max_reach,
            self.nl.max_reach + self.nl.skin,
        );
        self.nl.set_far(i, far);
        pos
    }

    /// [`NeighbourLists::gather`] for slot `i` in cell `ci`.
    #[inline(always)]
    fn gather(
        &mut self,
        ci: &[u32; D],
        i: usize,
        later_only: bool,
        found: impl FnMut(&mut NeighbourLists<D>, u32),
    ) {
        let space = Space::<D, B> {
            particles: self.particles,
            grid: self.grid,
            box_len: self.box_len,
            half_box: self.half_box,
            _boundary: PhantomData,
        };
        match self.window {
            Some(w) if ci[1] == 0 || ci[1] as usize + 1 == self.grid.n[1] => {
                self.nl.gather_sheared(&space, &w, ci, i, later_only, found)
            }
            _ => self.nl.gather(&space, ci, i, later_only, found),
        }
    }
}

/// The position of particle `p` at local time `now`, with its trajectory moved by whole box lengths
/// so that the position lies in the box on every periodic axis (neighbour-list mode; no gravity).
fn wrapped_now<const D: usize, B: Boundary>(
    p: &mut Particle<D>,
    now: f64,
    box_len: &Vector<D>,
) -> Vector<D> {
    let mut pos = p.at(now);
    for a in 0..D {
        if !B::is_wall(a) {
            let l = box_len[a];
            if pos[a] < 0.0 {
                pos[a] += l;
                p.r0[a] += l;
            } else if pos[a] >= l {
                pos[a] -= l;
                p.r0[a] -= l;
            }
        }
    }
    pos
}
