//! Placement: random sequential addition through a cell grid, and centred lattices.

use rand::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::sim::neighbours::{CellGrid, NONE};
use crate::{Boundary, EdmdError, Vector};

/// Random sequential addition, checking overlaps through a cell grid: O(N) for moderate φ.
pub(super) fn random_positions<const D: usize, B: Boundary>(
    radii: &[f64],
    box_len: &Vector<D>,
    phi: f64,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<Vec<Vector<D>>, EdmdError> {
    const ATTEMPTS: usize = 10_000;
    let max_d = 2.0 * radii.iter().cloned().fold(0.0, f64::max);
    let mut grid = CellGrid::<D>::new(box_len, max_d, max_d)?;
    // Largest particles first: they are the hardest to fit.
    let mut order: Vec<usize> = (0..radii.len()).collect();
    order.sort_by(|&a, &b| radii[b].total_cmp(&radii[a]));
    let mut placed = vec![Vector::<D>::zeros(); radii.len()];
    let mut links = vec![NONE; radii.len()];
    for (count, &i) in order.iter().enumerate() {
        let r = radii[i];
        let mut ok = false;
        for _ in 0..ATTEMPTS {
            let mut x = Vector::<D>::zeros();
            for a in 0..D {
                x[a] = if B::is_wall(a) {
                    r + rng.random::<f64>() * (box_len[a] - 2.0 * r)
                } else {
                    rng.random::<f64>() * box_len[a]
                };
            }
            if !overlaps_any::<D, B>(&grid, &links, &placed, radii, box_len, &x, r) {
                placed[i] = x;
                let idx = grid.index(&grid.coords_of(&x));
                grid.insert(&mut links, i as u32, idx);
                ok = true;
                break;
            }
        }
        if !ok {
            return Err(EdmdError::TooDense {
                method: "random",
                phi,
                max: count as f64 / radii.len() as f64 * phi,
            });
        }
    }
    Ok(placed)
}

fn overlaps_any<const D: usize, B: Boundary>(
    grid: &CellGrid<D>,
    links: &[u32],
    placed: &[Vector<D>],
    radii: &[f64],
    box_len: &Vector<D>,
    x: &Vector<D>,
    r: f64,
) -> bool {
    let c = grid.coords_of(x);
    for code in 0..3usize.pow(D as u32) {
        let mut rest = code;
        let mut idx = 0;
        let mut inside = true;
        for a in 0..D {
            let off = (rest % 3) as i32 - 1;
            rest /= 3;
            let n = grid.n[a] as i32;
            let y = c[a] as i32 + off;
            if (y < 0 || y >= n) && B::is_wall(a) {
                inside = false;
                break;
            }
            idx += y.rem_euclid(n) as usize * grid.stride[a];
        }
        if !inside {
            continue;
        }
        let mut k = grid.first(idx);
        while k != NONE {
            let mut dr = x - placed[k as usize];
            for a in 0..D {
                if !B::is_wall(a) {
                    dr[a] -= box_len[a] * (dr[a] / box_len[a]).round();
                }
            }
            let s = r + radii[k as usize];
            if dr.norm_squared() < s * s {
                return true;
            }
            k = links[k as usize];
        }
    }
    false
}

/// A centred lattice (two sites per cell: corner and body centre; hexagonal in 2D at the right
/// aspect, body-centred cubic in 3D) with the cell counts that maximise the nearest-neighbour
/// distance; vacancies are spread at random when there are more sites than particles.
pub(super) fn lattice_positions<const D: usize, B: Boundary>(
    n: usize,
    box_len: &Vector<D>,
    radius: f64,
    phi: f64,
    rng: &mut Xoshiro256PlusPlus,
) -> Result<Vec<Vector<D>>, EdmdError> {
    // On a walled axis the sites span [r, L − r] and the last body-centre site touches the far end.
    let span = |a: usize| {
        if B::is_wall(a) {
            box_len[a] - 2.0 * radius
        } else {
            box_len[a]
        }
    };
    let spacing = |a: usize, cells: usize| {
        if B::is_wall(a) {
            span(a) / (cells as f64 - 0.5)
        } else {
            span(a) / cells as f64
        }
    };
    let min_dist = |cells: &[usize; D]| {
        let mut sq = 0.0;
        let mut best = f64::INFINITY;
        for a in 0..D {
            let s = spacing(a, cells[a]);
            sq += s * s;
            // A walled axis with one cell has no same-sublattice neighbour along it.
            if !(B::is_wall(a) && cells[a] == 1) {
                best = f64::min(best, s);
            }
        }
        best.min(0.5 * sq.sqrt())
    };
    let target = n.div_ceil(2);
    let guess = (target as f64).powf(1.0 / D as f64);
    let hi = (guess * 4.0).ceil() as usize + 2;
    let mut best: Option<([usize; D], f64)> = None;
    let mut cells = [1usize; D];
    // Enumerate the first D − 1 counts; the last is the smallest that fits the particles.
    let outer = hi.pow(D as u32 - 1);
    for code in 0..outer {
        let mut rest = code;
        let mut prod = 1usize;
        for a in 0..D - 1 {
            cells[a] = rest % hi + 1;
            rest /= hi;
            prod *= cells[a];
        }
        cells[D - 1] = target.div_ceil(prod).max(1);
        let d = min_dist(&cells);
        if best.is_none_or(|b| d > b.1) {
            best = Some((cells, d));
        }
    }
    let (cells, dist) = best.expect("at least one lattice");
    if dist < 2.0 * radius * (1.0 + 1e-9) {
        // φ scales as (σ/dist)^D at fixed sites: the largest φ this lattice reaches.
        let max = phi * (dist / (2.0 * radius)).powi(D as i32);
        return Err(EdmdError::TooDense {
            method: "lattice",
            phi,
            max,
        });
    }
    let mut sites: Vec<Vector<D>> = Vec::with_capacity(2 * cells.iter().product::<usize>());
    let total: usize = cells.iter().product();
    for code in 0..total {
        let mut rest = code;
        let mut idx = [0usize; D];
        for a in 0..D {
            idx[a] = rest % cells[a];
            rest /= cells[a];
        }
        for b in 0..2 {
            let mut x = Vector::<D>::zeros();
            for a in 0..D {
                let u = idx[a] as f64 + 0.5 * b as f64;
                x[a] = if B::is_wall(a) {
                    // The far site can land one ulp beyond L − r.
                    (radius + u * spacing(a, cells[a])).min(box_len[a] - radius)
                } else {
                    (u + 0.25) * spacing(a, cells[a])
                };
            }
            sites.push(x);
        }
    }
    // Keep a random subset of n sites.
    for i in 0..n {
        let j = rng.random_range(i..sites.len());
        sites.swap(i, j);
    }
    sites.truncate(n);
    Ok(sites)
}
