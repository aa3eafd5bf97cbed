//! List mode's search around a shell centre: the particles whose centres lie within reach, found
//! in the cells around it (list builds and renewals, `sim/neighbours/list_search.rs`).

use super::space::{centre_far_from_periodic_faces, Space};
#[cfg(target_arch = "x86_64")]
use super::wide_scan::within_reach_wide;
use super::NeighbourLists;
use super::NONE;
use crate::sim::scene::image_near;
use crate::{Boundary, Vector};

impl<const D: usize> NeighbourLists<D> {
    /// Hands `found` every particle whose shell centre lies within `σ + δ` of slot `i`'s, found in
    /// the 3^D cells around `i`'s cell; with `later_only`, only slots above `i` (full builds). `ci` is `i`'s cell.
    #[inline(always)]
    pub(in crate::sim) fn gather<B: Boundary>(
        &mut self,
        space: &Space<'_, D, B>,
        ci: &[u32; D],
        i: usize,
        later_only: bool,
        found: impl FnMut(&mut Self, u32),
    ) {
        let centre = self.centre[i];
        let (firsts, count) = self.first_members::<B>(space.grid, ci, &centre);
        let firsts = &firsts[..count];
        // Both walks read the links beside the lists; the one-by-one test reads the records as
        // well.
        let occupied = firsts.iter().filter(|&&k| k != NONE);
        if self.wide {
            for &k in occupied {
                crate::prefetch::prefetch_at(&self.links, k as usize);
                crate::prefetch::prefetch_at(&self.centre, k as usize);
            }
        } else {
            for &k in occupied {
                crate::prefetch::prefetch_at(space.particles, k as usize);
                crate::prefetch::prefetch_at(&self.links, k as usize);
                crate::prefetch::prefetch_at(&self.centre, k as usize);
            }
        }
        // Centres farther than the reach from every periodic face have no neighbour across one.
        let wrap = !centre_far_from_periodic_faces::<D, B>(
            space.box_len,
            space.half_box,
            &centre,
            self.max_reach,
            self.max_reach,
        );
        #[cfg(target_arch = "x86_64")]
        if self.wide {
            self.gather_wide(space, firsts, i, later_only, wrap, found);
            return;
        }
        self.gather_one_by_one(space, firsts, i, later_only, wrap, found);
    }

    /// The first member of each of the 3^D cells around cell `ci` that can hold a particle within
    /// the largest reach of `centre`, all loads started before any list is walked; and their count.
    #[inline(always)]
    fn first_members<B: Boundary>(
        &self,
        grid: &super::CellGrid<D>,
        ci: &[u32; D],
        centre: &Vector<D>,
    ) -> ([u32; 27], usize) {
        let ci = *ci;
        // Squared distance from the centre to the lower and upper face of its cell, per axis: a
        // neighbour cell farther than the largest reach cannot hold a neighbour (in 3D about a
        // quarter of the 27, mostly corners, for a centre anywhere in its cell).
        let mut face2 = [[0.0; 3]; D];
        for a in 0..D {
            let lo = ci[a] as f64 * grid.side[a];
            face2[a][0] = (centre[a] - lo).powi(2);
            face2[a][2] = (lo + grid.side[a] - centre[a]).powi(2);
        }
        let far = self.max_reach * self.max_reach * (1.0 + 1e-9);
        // The squared distance to each neighbour cell, by its code Σ_a digit_a 3^a (the order of
        // `grid.full`), built axis by axis in place: entry k of the first 3^a expands into
        // k + digit·3^a (higher k first, so that no entry is overwritten before it is read).
        let mut cell_d2 = [0.0f64; 27];
        let mut filled = 1;
        for f in &face2 {
            for k in (0..filled).rev() {
                let base = cell_d2[k];
                for (digit, face) in f.iter().enumerate() {
                    cell_d2[digit * filled + k] = base + face;
                }
            }
            filled *= 3;
        }
        let out_of_reach = |code: usize| cell_d2[code] > far;
        let mut firsts = [NONE; 27];
        let mut count = 0;
        if grid.is_interior(&ci) {
            let c = grid.index(&ci) as isize;
            for (code, &o) in grid.full.iter().enumerate() {
                if out_of_reach(code) {
                    continue;
                }
                firsts[count] = grid.first((c + o) as usize);
                count += 1;
            }
        } else {
            let cells = grid.neighbours(&ci, B::is_wall);
            for (code, &idx) in cells[..3usize.pow(D as u32)].iter().enumerate() {
                if out_of_reach(code) || idx == usize::MAX {
                    continue;
                }
                firsts[count] = grid.first(idx);
                count += 1;
            }
        }
        (firsts, count)
    }

    /// [`Self::gather`]'s walk on x86-64 with AVX2: the occupants of the cells from `firsts` in
    /// walking order, tested four at a time.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn gather_wide<B: Boundary>(
        &mut self,
        space: &Space<'_, D, B>,
        firsts: &[u32],
        i: usize,
        later_only: bool,
        wrap: bool,
        mut found: impl FnMut(&mut Self, u32),
    ) {
        let nl = self;
        // The occupants in walking order, `i` and (with `later_only`) those below it
        // included: the test on four at a time masks them off.
        let mut candidates = std::mem::take(&mut nl.candidates);
        candidates.clear();
        for &first in firsts {
            let mut k = first;
            while k != NONE {
                candidates.push(k);
                // The cell links beside the lists: four bytes a member instead of its record's
                // line (with equal radii the test reads only the centres).
                k = nl.links[k as usize];
            }
        }
        let len = candidates.len();
        // Padded with slot `i` to whole groups; the test masks the padding off.
        candidates.resize((len + 3) & !3, i as u32);
        // SAFETY: `nl.wide` is set only where `wide_scan_available` found AVX2 and the slots'
        // offsets fit; the candidates are slots.
        #[allow(unsafe_code)]
        unsafe {
            macro_rules! test {
                ($wrap:literal, $same:literal) => {
                    within_reach_wide::<D, B, $wrap, $same>(
                        nl,
                        space,
                        &candidates,
                        len,
                        i,
                        later_only,
                        &mut found,
                    )
                };
            }
            match (wrap, nl.same_radius) {
                (true, true) => test!(true, true),
                (true, false) => test!(true, false),
                (false, true) => test!(false, true),
                (false, false) => test!(false, false),
            }
        }
        nl.candidates = candidates;
    }

    /// [`Self::gather`]'s walk one candidate at a time (any processor).
    #[inline(always)]
    fn gather_one_by_one<B: Boundary>(
        &mut self,
        space: &Space<'_, D, B>,
        firsts: &[u32],
        i: usize,
        later_only: bool,
        wrap: bool,
        mut found: impl FnMut(&mut Self, u32),
    ) {
        let nl = self;
        let particles = space.particles;
        let centre = nl.centre[i];
        let ri = particles[i].radius;
        for &first in firsts {
            let mut k = first;
            while k != NONE {
                let j = k as usize;
                let pj = &particles[j];
                k = nl.links[j];
                if k != NONE {
                    crate::prefetch::prefetch(&particles[k as usize]);
                    crate::prefetch::prefetch(&nl.links[k as usize]);
                    crate::prefetch::prefetch(&nl.centre[k as usize]);
                }
                if j == i || (later_only && j < i) {
                    continue;
                }
                let d = if wrap {
                    image_near::<D, B>(space.box_len, space.half_box, &centre, &nl.centre[j])
                        - nl.centre[j]
                } else {
                    centre - nl.centre[j]
                };
                let reach = ri + pj.radius + nl.skin;
                if d.norm_squared() < reach * reach {
                    found(nl, j as u32);
                }
            }
        }
    }
}
