//! Neighbour lists with a skin, the alternative to cell crossings for dense packings (after
//! F. Smallenburg, Eur. Phys. J. E 45, 22 (2022), arXiv:2201.01100).
//!
//! Each particle `i` is confined to a *shell*: a ball of radius `δ/2` around a centre `c_i` (its
//! position when the shell was drawn). Its list holds every `j` with `|c_i − c_j| < σ_ij + δ`, so
//! two particles that are not listed cannot touch while both stay in their shells. Leaving the shell
//! is an event: the particle draws a new shell around its current position, leaves the lists of old
//! neighbours that are no longer near and joins those of new ones (lists stay symmetric), and
//! predicts against them. Cells
//! (side ≥ σ_max + δ) are used only for that search, and a particle's cell is the cell of its
//! centre, so there are no crossing events at all.
//!
//! In a dense gas a particle rattles in its cage: it needs many collisions to travel `δ/2`, while a
//! prediction scans ~10 listed partners instead of the ~23 occupants of 27 cells (3D, φ = 0.45).

use super::NONE;
use crate::Vector;

/// The top bit of a slot's `len` entry: its shell centre is far from every periodic face
/// ([`NeighbourLists::far`]). Kept in the word a scan reads anyway; the count is the other 31 bits.
const FAR: u32 = 1 << 31;

/// Per-particle neighbour lists in one flat array of fixed stride, grown when a list overflows.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) struct NeighbourLists<const D: usize> {
    /// Skin `δ` (absolute length).
    pub skin: f64,
    /// Radius of the shell that triggers a renewal: `δ/2` less a round-off margin.
    pub shell: f64,
    /// The largest centre distance that is listed: largest diameter + `δ`.
    pub max_reach: f64,
    /// Shell centres, per slot.
    pub centre: Vec<Vector<D>>,
    cap: usize,
    /// Per slot, the length of its list, and [`FAR`].
    len: Vec<u32>,
    items: Vec<u32>,
    /// The neighbours a renewal found, before they replace the old list.
    pub fresh: Vec<u32>,
    /// The occupants of the cells a four-wide search tests, in the order it walks them.
    pub candidates: Vec<u32>,
    /// Per slot, the renewal stamp that last marked it ([`Self::renew`]): membership in the old and
    /// the new list is read off it instead of searching one list for each entry of the other.
    mark: Vec<u32>,
    /// Each slot's link in the list grid's cells ([`crate::sim::neighbours::CellLink`]): in list mode the grid
    /// links through this array, not through the records (whose own link then stays unused), so
    /// that a renewal walks its cells by four bytes a member instead of each member's record.
    pub(crate) links: Vec<u32>,
    /// The stamp of the last renewal (even; the odd one above it marks "in both lists").
    stamp: u32,
    /// Whether list scans test four partners at once (`sim/neighbours/wide_scan.rs`): where the processor
    /// can; [`Self::use_portable_scan`] turns it off.
    pub wide: bool,
    /// Whether every particle has the same radius (set by the engine at construction; radii never
    /// change): the four-wide scan then reads no partner's radius.
    pub same_radius: bool,
    /// Whether a four-wide scan first asks for every partner's record: where the records outgrow
    /// twice the L2 ([`crate::caches::partner_hints_threshold`]; the two-wide scan always does).
    pub hint_partners: bool,
}

/// Whether this processor runs the four-wide scan, for `n` particles: AVX2, and every particle's
/// last coordinate addressable by a gather's 32-bit index (over 2.6 · 10⁸ particles in 3D).
pub(crate) fn wide_scan_available<const D: usize>(n: usize) -> bool {
    let words = std::mem::size_of::<crate::Particle<D>>() / 8;
    let fits = n.checked_mul(words).is_some_and(|w| w < i32::MAX as usize);
    #[cfg(target_arch = "x86_64")]
    return fits && std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    return {
        let _ = fits;
        false
    };
}

impl<const D: usize> NeighbourLists<D> {
    /// Empty lists for `n` particles with skin `skin` and largest diameter `max_d`.
    pub fn new(n: usize, skin: f64, max_d: f64) -> Self {
        let cap = 16;
        NeighbourLists {
            skin,
            shell: 0.5 * skin * (1.0 - 1e-6),
            max_reach: max_d + skin,
            centre: vec![Vector::<D>::zeros(); n],
            cap,
            len: vec![0; n],
            items: vec![0; n * cap],
            fresh: Vec::new(),
            candidates: Vec::new(),
            mark: vec![0; n],
            links: vec![NONE; n],
            stamp: 0,
            same_radius: false,
            wide: wide_scan_available::<D>(n),
            hint_partners: n * std::mem::size_of::<crate::Particle<D>>()
                > crate::caches::partner_hints_threshold(),
        }
    }

    /// Scans lists two partners at a time on every processor (the x86-64 baseline), for comparing
    /// the two scans.
    pub fn use_portable_scan(&mut self) {
        self.wide = false;
    }

    /// How many neighbours slot `i` has.
    #[inline(always)]
    fn count(&self, i: usize) -> usize {
        (self.len[i] & !FAR) as usize
    }

    /// Whether slot `i`'s shell centre was found far from every periodic face when it was drawn
    /// ([`Self::set_far`]): the test of every prediction, answered once per shell.
    #[inline(always)]
    pub fn far(&self, i: usize) -> bool {
        self.len[i] & FAR != 0
    }

    /// Records [`Self::far`] for slot `i`'s new shell centre.
    #[inline(always)]
    pub fn set_far(&mut self, i: usize, far: bool) {
        self.len[i] = (self.len[i] & !FAR) | if far { FAR } else { 0 };
    }

    /// The neighbours of slot `i`.
    #[inline(always)]
    pub fn of(&self, i: usize) -> &[u32] {
        let start = i * self.cap;
        &self.items[start..start + self.count(i)]
    }

    /// The neighbours of slot `i` followed by `i` itself up to a multiple of four entries (the
    /// stride is a multiple of 16), for a four-wide scan: against itself a particle has no
    /// separation and no approach, so those entries never pass its test and need no mask.
    #[inline(always)]
    pub fn of_padded(&self, i: usize) -> &[u32] {
        let start = i * self.cap;
        let len = (self.count(i) + 3) & !3;
        &self.items[start..start + len]
    }

    /// Asks for what a prediction of slot `i` reads of the lists: the first cache line of its list,
    /// its length and its shell centre (the next event's particle will read them). No bounds
    /// checks: a prefetch never faults ([`crate::prefetch::prefetch_at`]).
    #[inline(always)]
    pub fn prefetch(&self, i: usize) {
        crate::prefetch::prefetch_at(&self.items, i.wrapping_mul(self.cap));
        crate::prefetch::prefetch_at(&self.len, i);
        crate::prefetch::prefetch_at(&self.centre, i);
    }

    /// Empties every list (and clears every [`Self::far`]).
    pub fn clear(&mut self) {
        self.len.fill(0);
    }

    /// Adds `j` to `i`'s list and `i` to `j`'s.
    #[inline]
    pub fn link(&mut self, i: usize, j: usize) {
        if self.count(i) == self.cap || self.count(j) == self.cap {
            self.grow();
        }
        self.push(i, j as u32);
        self.push(j, i as u32);
    }

    #[inline(always)]
    fn push(&mut self, i: usize, j: u32) {
        let l = self.count(i);
        self.items[i * self.cap + l] = j;
        self.len[i] += 1;
        self.pad(i);
    }

    /// Fills slot `i`'s entries after its list, up to a multiple of four, with `i`
    /// ([`Self::of_padded`]).
    #[inline(always)]
    fn pad(&mut self, i: usize) {
        let start = i * self.cap;
        let l = self.count(i);
        self.items[start + l..start + ((l + 3) & !3)].fill(i as u32);
    }

    /// Removes `j` from `i`'s list (order is not kept).
    #[inline]
    fn remove(&mut self, i: usize, j: u32) {
        let start = i * self.cap;
        let l = self.count(i);
        let list = &mut self.items[start..start + l];
        if let Some(k) = list.iter().position(|&x| x == j) {
            list[k] = list[l - 1];
            self.len[i] -= 1;
            self.pad(i);
        } else {
            debug_assert!(
                false,
                "neighbour lists out of symmetry: {j} not in {i}'s list"
            );
        }
    }

    /// Makes [`Self::fresh`] slot `i`'s list. Only the partners whose neighbourhood changed are
    /// touched: `i` leaves the lists of old neighbours that are not among the new ones and joins
    /// those of new ones (a renewal after a short flight changes a few of some 10–15, so most
    /// partners' lists, which lie in lines far from `i`'s, are not read at all). Which list a
    /// partner is in is marked per slot with this renewal's stamp, so the work is linear in the
    /// lists' lengths; removals come in the old list's order and additions in the new one's.
    pub fn renew(&mut self, i: usize) {
        if self.stamp >= u32::MAX - 2 {
            self.mark.fill(0);
            self.stamp = 0;
        }
        self.stamp += 2;
        let (new_only, both) = (self.stamp, self.stamp + 1);
        let fresh = std::mem::take(&mut self.fresh);
        for &j in &fresh {
            self.mark[j as usize] = new_only;
        }
        let start = i * self.cap;
        for k in start..start + self.count(i) {
            let j = self.items[k] as usize;
            if self.mark[j] == new_only {
                self.mark[j] = both;
            } else {
                self.remove(j, i as u32);
            }
        }
        while fresh.len() > self.cap {
            self.grow();
        }
        for &j in &fresh {
            if self.mark[j as usize] == new_only {
                if self.count(j as usize) == self.cap {
                    self.grow();
                }
                self.push(j as usize, i as u32);
            }
        }
        let start = i * self.cap;
        self.items[start..start + fresh.len()].copy_from_slice(&fresh);
        self.len[i] = (self.len[i] & FAR) | fresh.len() as u32;
        self.pad(i);
        self.fresh = fresh;
    }

    /// Widens every list by 16 entries (one cache line): the longest list sets the stride, and
    /// doubling would waste up to half of it.
    fn grow(&mut self) {
        let cap = self.cap + 16;
        let mut items = vec![0u32; self.len.len() * cap];
        for (i, &l) in self.len.iter().enumerate() {
            let l = (l & !FAR) as usize;
            items[i * cap..i * cap + l]
                .copy_from_slice(&self.items[i * self.cap..i * self.cap + l]);
        }
        self.items = items;
        self.cap = cap;
        for i in 0..self.len.len() {
            self.pad(i);
        }
    }

    /// Renumbers slots: slot `new` takes the old slot `perm[new]`; `inv` is the inverse permutation.
    /// In place (following the permutation's cycles), so that it needs no second copy of the lists.
    pub fn permute(&mut self, perm: &[u32], inv: &[u32]) {
        let n = self.len.len();
        let cap = self.cap;
        for i in 0..n {
            let l = self.count(i);
            for x in &mut self.items[i * cap..i * cap + l] {
                *x = inv[*x as usize];
            }
        }
        let mut done = vec![false; n];
        let mut saved = vec![0u32; cap];
        for start in 0..n {
            if done[start] {
                continue;
            }
            saved.copy_from_slice(&self.items[start * cap..(start + 1) * cap]);
            let (saved_len, saved_centre) = (self.len[start], self.centre[start]);
            let mut cur = start;
            loop {
                done[cur] = true;
                let src = perm[cur] as usize;
                if src == start {
                    self.items[cur * cap..(cur + 1) * cap].copy_from_slice(&saved);
                    self.len[cur] = saved_len;
                    self.centre[cur] = saved_centre;
                    break;
                }
                self.items
                    .copy_within(src * cap..(src + 1) * cap, cur * cap);
                self.len[cur] = self.len[src];
                self.centre[cur] = self.centre[src];
                cur = src;
            }
        }
        for i in 0..n {
            self.pad(i);
        }
    }

    /// Heap bytes held by the lists.
    pub fn heap_bytes(&self) -> usize {
        4 * (self.items.capacity()
            + self.len.capacity()
            + self.fresh.capacity()
            + self.candidates.capacity()
            + self.mark.capacity()
            + self.links.capacity())
            + self.centre.capacity() * std::mem::size_of::<Vector<D>>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every list is followed by its own slot up to a multiple of four entries.
    fn assert_padded<const D: usize>(nl: &NeighbourLists<D>) {
        for i in 0..nl.len.len() {
            let padded = nl.of_padded(i);
            assert_eq!(padded.len() % 4, 0);
            assert!(
                padded[nl.of(i).len()..].iter().all(|&x| x as usize == i),
                "slot {i}"
            );
        }
    }

    #[test]
    fn lists_stay_symmetric_through_growth_renewal_and_permutation() {
        // 39 neighbours of slot 0 make the lists grow twice (16 -> 32 -> 48).
        let mut nl = NeighbourLists::<2>::new(40, 0.3, 1.0);
        // Slot 0's flag rides in its length word: links, growth, renewals and the permutation
        // below keep it, and it never counts as an entry.
        nl.set_far(0, true);
        for j in 1..40 {
            nl.link(0, j);
        }
        nl.link(3, 4);
        assert_eq!(nl.of(0).len(), 39);
        assert_eq!(nl.of(0), (1..40).collect::<Vec<u32>>().as_slice());
        assert_eq!(nl.of(4), &[0, 3]);
        assert_padded(&nl);
        // A renewal with no neighbours takes 3 out of every list.
        nl.fresh.clear();
        nl.renew(3);
        assert!(nl.of(3).is_empty());
        assert_eq!(nl.of(4), &[0]);
        assert!(!nl.of(0).contains(&3));
        assert_padded(&nl);
        // One that keeps 0 and adds 5: 0's list is untouched, 5 gains 4.
        let before = nl.of(0).to_vec();
        nl.fresh = vec![5, 0];
        nl.renew(4);
        assert_eq!(nl.of(4), &[5, 0]);
        assert_eq!(nl.of(0), before.as_slice());
        assert_eq!(nl.of(5), &[0, 4]);
        assert_padded(&nl);
        assert!(nl.far(0) && !nl.far(4) && nl.of(0).len() == before.len());
        nl.fresh = vec![0];
        nl.renew(4);
        assert_eq!(nl.of(5), &[0]);
        assert_eq!(nl.of(4), &[0]);
        // Reverse the slots.
        let perm: Vec<u32> = (0..40).rev().collect();
        let inv = perm.clone();
        nl.permute(&perm, &inv);
        assert_eq!(nl.of(35), &[39]);
        assert_eq!(nl.of(39).len(), 38);
        assert!(nl.of(39).contains(&38) && !nl.of(39).contains(&36));
        assert_padded(&nl);
        assert!(nl.far(39) && (0..39).all(|i| !nl.far(i)));
        nl.set_far(39, false);
        assert!(!nl.far(39) && nl.of(39).len() == 38);
    }
}
