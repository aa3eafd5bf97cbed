//! Cell list: a grid of cells no smaller than the largest particle diameter, with intrusive singly
//! linked member lists.
//!
//! The link of each member lives in the member itself ([`CellLink`]): walking a cell then reads one
//! cache line per member instead of two. The grid keeps only the cell heads. Removing a member walks
//! its cell from the head to its predecessor: a cell holds about one particle (cells are about one
//! diameter wide), so that walk reads the lines the cell's neighbourhood search reads anyway, where
//! backward links cost an array of their own and two more lines per crossing.
//!
//! Membership changes only through cell-crossing events; a particle's cell is authoritative even when
//! its lazily advanced position sits on the far side of a face by round-off.

use crate::error::AXIS_NAMES;
use crate::{EdmdError, Vector};

/// Marks the end of a list.
pub const NONE: u32 = u32::MAX;

/// The most cells along one axis: a particle's cell coordinates are kept in 16 bits
/// (`sim::Meta`). A longer axis gets longer cells, which only adds occupants per cell (a 2D box
/// 10⁶ diameters long at φ 0.3; every other box of the docs has far fewer).
pub const MAX_PER_AXIS: usize = u16::MAX as usize;

/// Uniform grid of cells covering the box.
#[derive(Debug, Clone)]
pub struct CellGrid<const D: usize> {
    /// Cells per axis (at least 3).
    pub n: [usize; D],
    /// Cell side per axis.
    pub side: [f64; D],
    /// Linear-index stride per axis.
    pub stride: [usize; D],
    /// Linear-index offsets of the 3^D neighbour cells of an interior cell.
    pub full: Vec<isize>,
    /// Offsets of the 3^(D−1) cells at offset −1 (index `2a`) or +1 (index `2a + 1`) along axis `a`.
    pub partial: Vec<Vec<isize>>,
    /// [`CellGrid::partial`] with each run of consecutive cells reduced to its first and last
    /// (a run's heads share a line or straddle two): what a prefetch of their heads asks for.
    pub(crate) partial_probes: Vec<Vec<isize>>,
    head: Vec<u32>,
}

/// A cell member that stores its forward link (the next member of its cell, or [`NONE`]).
pub trait CellLink {
    /// The next member of this member's cell.
    fn link(&self) -> u32;
    /// Sets the next member.
    fn set_link(&mut self, next: u32);
}

impl CellLink for u32 {
    #[inline(always)]
    fn link(&self) -> u32 {
        *self
    }
    #[inline(always)]
    fn set_link(&mut self, next: u32) {
        *self = next;
    }
}

impl<const D: usize> CellLink for crate::Particle<D> {
    #[inline(always)]
    fn link(&self) -> u32 {
        self.next_in_cell
    }
    #[inline(always)]
    fn set_link(&mut self, next: u32) {
        self.next_in_cell = next;
    }
}

impl<const D: usize> CellGrid<D> {
    /// A grid over a box `box_len`, with cells of side at least `min_side` (close to `target_side`
    /// when that is larger).
    pub fn new(box_len: &Vector<D>, min_side: f64, target_side: f64) -> Result<Self, EdmdError> {
        let (n, side, stride, total) = Self::layout(box_len, min_side, target_side)?;
        Self::with_layout(n, side, stride, total)
    }

    /// Whether [`CellGrid::new`] would succeed with these arguments, without allocating the grid.
    pub fn check(box_len: &Vector<D>, min_side: f64, target_side: f64) -> Result<(), EdmdError> {
        Self::layout(box_len, min_side, target_side).map(drop)
    }

    /// Cells per axis, their sides, strides and total count.
    #[allow(clippy::type_complexity)]
    fn layout(
        box_len: &Vector<D>,
        min_side: f64,
        target_side: f64,
    ) -> Result<([usize; D], [f64; D], [usize; D], usize), EdmdError> {
        let mut n = [0usize; D];
        let mut side = [0.0; D];
        let mut stride = [0usize; D];
        let want = target_side.max(min_side);
        let mut total = 1usize;
        let mut wanted_total = 1usize;
        for a in 0..D {
            let len = box_len[a];
            let max_cells = (len / min_side).floor();
            if !(max_cells >= 3.0) {
                return Err(EdmdError::BoxTooSmall {
                    axis: AXIS_NAMES[a],
                    len,
                    cell: min_side,
                });
            }
            let wanted = ((len / want).floor().max(3.0)).min(max_cells).min(1e7) as usize;
            // A box too large for the cells it wants is refused, as before the per-axis cap.
            wanted_total = wanted_total
                .checked_mul(wanted)
                .filter(|&t| t < u32::MAX as usize)
                .ok_or_else(|| {
                    EdmdError::invalid(
                        "cell count",
                        wanted_total as f64 * wanted as f64,
                        "too many cells; use a denser box",
                    )
                })?;
            let cells = wanted.min(MAX_PER_AXIS);
            n[a] = cells;
            side[a] = len / cells as f64;
            stride[a] = total;
            total *= cells;
        }
        Ok((n, side, stride, total))
    }

    fn with_layout(
        n: [usize; D],
        side: [f64; D],
        stride: [usize; D],
        total: usize,
    ) -> Result<Self, EdmdError> {
        let mut full = Vec::new();
        let mut partial = vec![Vec::new(); 2 * D];
        for code in 0..3usize.pow(D as u32) {
            let mut rest = code;
            let mut off = 0isize;
            let mut digits = [0i32; D];
            for a in 0..D {
                digits[a] = (rest % 3) as i32 - 1;
                rest /= 3;
                off += digits[a] as isize * stride[a] as isize;
            }
            full.push(off);
            for a in 0..D {
                if digits[a] != 0 {
                    partial[2 * a + (digits[a] > 0) as usize].push(off);
                }
            }
        }
        Ok(CellGrid {
            n,
            side,
            stride,
            partial_probes: partial.iter().map(|p| line_probes(p)).collect(),
            full,
            partial,
            head: vec![NONE; total],
        })
    }

    /// True if cell `c` has no face on the box boundary, so its neighbours need no wrapping.
    #[inline(always)]
    pub fn is_interior<T: Copy + Into<u32>>(&self, c: &[T; D]) -> bool {
        // 1 ≤ x ≤ n − 2 as one unsigned comparison per axis (x − 1 wraps to a huge value at 0;
        // n ≥ 3), combined without a branch.
        let mut inside = true;
        for a in 0..D {
            let x: u32 = c[a].into();
            inside &= (x as usize).wrapping_sub(1) < self.n[a] - 2;
        }
        inside
    }

    /// Each cell's first member (the rest follow the members' links).
    pub(crate) fn heads(&self) -> &[u32] {
        &self.head
    }

    /// Replaces every cell's first member (a saved state's, of a grid of the same size).
    pub(crate) fn set_heads(&mut self, heads: Vec<u32>) {
        debug_assert_eq!(heads.len(), self.head.len());
        self.head = heads;
    }

    /// Asks for the line of cell `idx`'s head (a hint).
    #[inline(always)]
    pub(crate) fn prefetch_head(&self, idx: usize) {
        crate::prefetch::prefetch_at(&self.head, idx);
    }

    /// Calls `f` with the first cell of each of the 3^(D−1) rows of three consecutive cells (along
    /// the first axis) that make up the neighbourhood of the interior cell `centre`. The loops have
    /// constant bounds, so they unroll into fixed offsets from the row starts.
    #[inline(always)]
    pub(crate) fn for_each_row(&self, centre: usize, mut f: impl FnMut(usize)) {
        for code in 0..3usize.pow(D as u32 - 1) {
            let mut rest = code;
            let mut start = centre as isize - 1;
            for a in 1..D {
                start += ((rest % 3) as isize - 1) * self.stride[a] as isize;
                rest /= 3;
            }
            f(start as usize);
        }
    }

    /// The first members of the three cells of the row that starts at cell `start` (as
    /// [`Self::for_each_row`] names it): one bounds check for the three.
    #[inline(always)]
    pub(crate) fn row(&self, start: usize) -> [u32; 3] {
        let row: &[u32; 3] = self.head[start..start + 3]
            .try_into()
            .expect("a row of three cells");
        *row
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.head.len()
    }

    /// True if the grid has no cells (never, for a valid grid).
    pub fn is_empty(&self) -> bool {
        self.head.is_empty()
    }

    /// Cell coordinates of a position inside the box (clamped to the grid).
    pub fn coords_of(&self, pos: &Vector<D>) -> [u32; D] {
        let mut c = [0u32; D];
        for a in 0..D {
            let x = (pos[a] / self.side[a]).floor();
            c[a] = x.clamp(0.0, (self.n[a] - 1) as f64) as u32;
        }
        c
    }

    /// Linear index of cell coordinates.
    #[inline(always)]
    pub fn index<T: Copy + Into<u32>>(&self, c: &[T; D]) -> usize {
        let mut idx = 0;
        for a in 0..D {
            let x: u32 = c[a].into();
            idx += x as usize * self.stride[a];
        }
        idx
    }

    /// Linear index of the neighbour of cell `c` at offset code `code` ∈ [0, 3^D) (digit `a` in base 3
    /// is the offset along axis `a`, plus one, the order of [`CellGrid::full`]), wrapping periodic
    /// axes; `None` where the offset leaves the box through a wall (`wall(a)` true).
    #[inline]
    pub fn neighbour(
        &self,
        c: &[u32; D],
        code: usize,
        wall: impl Fn(usize) -> bool,
    ) -> Option<usize> {
        let mut rest = code;
        let mut idx = 0;
        for a in 0..D {
            let n = self.n[a] as i32;
            let x = c[a] as i32 + (rest % 3) as i32 - 1;
            rest /= 3;
            if (x < 0 || x >= n) && wall(a) {
                return None;
            }
            idx += x.rem_euclid(n) as usize * self.stride[a];
        }
        Some(idx)
    }

    /// [`CellGrid::neighbour`] for every code at once: entry `code` of the first 3^D is the linear
    /// index of that neighbour, or `usize::MAX` where it lies beyond a wall. Built axis by axis
    /// (three wrapped coordinates per axis, then sums), without a division per code.
    #[inline]
    pub fn neighbours(&self, c: &[u32; D], wall: impl Fn(usize) -> bool) -> [usize; 27] {
        let mut out = [0usize; 27];
        let mut filled = 1;
        for a in 0..D {
            let n = self.n[a] as i32;
            let mut along = [0usize; 3];
            for (digit, slot) in along.iter_mut().enumerate() {
                let x = c[a] as i32 + digit as i32 - 1;
                *slot = if (x < 0 || x >= n) && wall(a) {
                    usize::MAX
                } else {
                    x.rem_euclid(n) as usize * self.stride[a]
                };
            }
            // Entry k of the first 3^a expands into k + digit·3^a (higher k first, so that no entry
            // is overwritten before it is read).
            for k in (0..filled).rev() {
                let base = out[k];
                for (digit, &add) in along.iter().enumerate() {
                    out[digit * filled + k] = if base == usize::MAX || add == usize::MAX {
                        usize::MAX
                    } else {
                        base + add
                    };
                }
            }
            filled *= 3;
        }
        out
    }

    /// First member of cell `idx`, or [`NONE`].
    #[inline(always)]
    pub fn first(&self, idx: usize) -> u32 {
        self.head[idx]
    }

    /// Adds member `i` of `items` to cell `idx`.
    #[inline]
    pub fn insert<T: CellLink>(&mut self, items: &mut [T], i: u32, idx: usize) {
        items[i as usize].set_link(self.head[idx]);
        self.head[idx] = i;
    }

    /// Removes member `i` of `items` from cell `idx` (which must hold it), walking the cell from its
    /// head to `i`'s predecessor.
    #[inline]
    pub fn remove<T: CellLink>(&mut self, items: &mut [T], i: u32, idx: usize) {
        let next = items[i as usize].link();
        let mut k = self.head[idx];
        if k == i {
            self.head[idx] = next;
            return;
        }
        loop {
            debug_assert!(k != NONE, "member {i} not in cell {idx}");
            let l = items[k as usize].link();
            if l == i {
                items[k as usize].set_link(next);
                return;
            }
            k = l;
        }
    }

    /// Empties every cell.
    pub fn clear(&mut self) {
        self.head.fill(NONE);
    }

    /// Heap bytes held by the grid.
    pub fn heap_bytes(&self) -> usize {
        4 * self.head.capacity()
    }
}

/// The first and last offset of each run of consecutive offsets (one offset for a run of one).
fn line_probes(offsets: &[isize]) -> Vec<isize> {
    let mut probes = Vec::new();
    let mut k = 0;
    while k < offsets.len() {
        let mut end = k;
        while end + 1 < offsets.len() && offsets[end + 1] == offsets[end] + 1 {
            end += 1;
        }
        probes.push(offsets[k]);
        if end > k {
            probes.push(offsets[end]);
        }
        k = end + 1;
    }
    probes
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::vector;

    #[test]
    fn small_boxes_are_rejected_by_name() {
        let e = CellGrid::<2>::new(&vector![2.9, 10.0], 1.0, 1.0).unwrap_err();
        assert!(e.to_string().contains("Lx = 2.9"), "{e}");
        assert!(CellGrid::<2>::new(&vector![3.0, 3.0], 1.0, 1.0).is_ok());
    }

    #[test]
    fn a_long_axis_gets_longer_cells_not_more_than_sixteen_bits_count() {
        // 200 000 diameters along x would be 200 000 cells of one diameter.
        let g = CellGrid::<2>::new(&vector![2e5, 10.0], 1.0, 1.0).unwrap();
        assert_eq!(g.n[0], MAX_PER_AXIS);
        assert!(g.side[0] > 1.0 && g.n[1] == 10);
        let c = g.coords_of(&vector![2e5 - 1e-9, 5.0]);
        assert_eq!(c[0] as usize, MAX_PER_AXIS - 1);
    }

    #[test]
    fn cells_are_never_smaller_than_the_diameter() {
        let g = CellGrid::<3>::new(&vector![10.5, 7.0, 3.2], 1.0, 0.5).unwrap();
        assert_eq!(g.n, [10, 7, 3]);
        assert!(g.side.iter().all(|&s| s >= 1.0));
    }

    #[test]
    fn neighbours_wrap_periodic_axes_and_stop_at_walls() {
        let g = CellGrid::<2>::new(&vector![4.0, 3.0], 1.0, 1.0).unwrap();
        // Cell (0, 2); code 0 is offset (-1, -1), code 8 is (+1, +1), code 4 the cell itself.
        let c = [0, 2];
        assert_eq!(g.neighbour(&c, 4, |_| false), Some(2 * 4));
        assert_eq!(g.neighbour(&c, 0, |_| false), Some(3 + 4));
        assert_eq!(g.neighbour(&c, 8, |_| false), Some(1));
        assert_eq!(g.neighbour(&c, 0, |a| a == 0), None);
        assert_eq!(g.neighbour(&c, 8, |a| a == 1), None);
        assert_eq!(g.neighbour(&c, 5, |a| a == 1), Some(2 * 4 + 1));
    }

    #[test]
    fn all_neighbours_at_once_match_one_by_one() {
        // Every cell of a small 3D grid (3 cells along y, so that neighbours wrap onto each other
        // there), every code, with each axis periodic or walled.
        let g = CellGrid::<3>::new(&vector![5.0, 3.0, 4.0], 1.0, 1.0).unwrap();
        for walls in 0..8u32 {
            let wall = |a: usize| walls & (1 << a) != 0;
            for idx in 0..g.len() {
                let c = [
                    (idx % g.stride[1]) as u32,
                    ((idx / g.stride[1]) % g.n[1]) as u32,
                    (idx / g.stride[2]) as u32,
                ];
                assert_eq!(g.index(&c), idx);
                let all = g.neighbours(&c, wall);
                for (code, &got) in all.iter().enumerate().take(27) {
                    let want = g.neighbour(&c, code, wall).unwrap_or(usize::MAX);
                    assert_eq!(got, want, "cell {c:?}, code {code}, walls {walls:03b}");
                }
            }
        }
    }

    /// The cells `for_each_row` visits around `c`, against the neighbourhood `full` names.
    fn rows_and_full<const D: usize>(g: &CellGrid<D>, c: [u32; D]) -> (Vec<usize>, Vec<usize>) {
        let centre = g.index(&c);
        let mut cells = vec![];
        g.for_each_row(centre, |row| cells.extend(row..row + 3));
        let mut want: Vec<usize> = g
            .full
            .iter()
            .map(|&o| (centre as isize + o) as usize)
            .collect();
        want.sort_unstable();
        (cells, want)
    }

    #[test]
    fn rows_cover_the_neighbourhood_and_probes_the_ends_of_runs() {
        let g = CellGrid::<2>::new(&vector![5.0, 4.0], 1.0, 1.0).unwrap();
        // Along x the newly adjacent cells sit one per row; along y they form one row of three.
        assert_eq!(g.partial_probes[1], g.partial[1]);
        assert_eq!(g.partial_probes[3], vec![4, 6]);
        let (cells, want) = rows_and_full(&g, [2, 2]);
        assert_eq!(cells, want);
        // In 3D: nine rows, the 27 neighbours.
        let g = CellGrid::<3>::new(&vector![5.0, 4.0, 6.0], 1.0, 1.0).unwrap();
        let (cells, want) = rows_and_full(&g, [2, 2, 3]);
        assert_eq!(cells.len(), 27);
        assert_eq!(cells, want);
    }

    #[test]
    fn insert_and_remove_keep_lists_consistent() {
        let mut g = CellGrid::<2>::new(&vector![4.0, 4.0], 1.0, 1.0).unwrap();
        let mut links = vec![NONE; 4];
        for i in 0..4 {
            g.insert(&mut links, i, 5);
        }
        g.remove(&mut links, 1, 5);
        g.remove(&mut links, 3, 5);
        let mut members = vec![];
        let mut k = g.first(5);
        while k != NONE {
            members.push(k);
            k = links[k as usize];
        }
        assert_eq!(members, vec![2, 0]);
    }
}
