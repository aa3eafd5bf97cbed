//! Neighbour lists in a sheared box ([`crate::LeesEdwards`]): lazily wrapped trajectories, lists
//! gathered across the sliding faces for a window of the offset Δ, and the scan's exact sheared
//! image (PHYSICS.md §7).
//!
//! A trajectory that passes a y face stays unwrapped (it is the same motion as its image) until its
//! list is renewed, when [`wrapped_now_sheared`] replaces it by its image in the box. A shell centre
//! within a list's reach of a y face gathers its neighbours across the face through the four
//! columns of `sim/shear.rs`, keeping an image that comes within reach for any Δ up to the next
//! shift; at the shift every such list is gathered again (`Simulation::shear_shift`).

use super::space::Space;
use super::NeighbourLists;
use super::NONE;
use crate::calendar::Calendar;
use crate::sim::shear::{sliding_row, ShearWindow};
use crate::sim::Simulation;
use crate::{Boundary, CollisionRule, Particle, Vector};

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Whether a listed partner of `i` may sit across a sliding face of a sheared box: its shell
    /// centre lies within a list's reach of a y face (or the box is so thin that reach plus skin
    /// exceeds half of it). Otherwise its partners are not across one (their centres within reach,
    /// in the box; the grains within their shells, less than half the box apart along y), and the
    /// periodic images along x and z that [`Self::scan_list`] takes are the ones
    /// `sheared_image_near` takes, to the bit.
    #[inline(always)]
    pub(in crate::sim) fn near_sliding_face(&self, nl: &NeighbourLists<D>, i: usize) -> bool {
        let y = nl.centre[i][1];
        nl.max_reach + nl.skin >= self.half_box[1]
            || !(y > nl.max_reach && y < self.box_len[1] - nl.max_reach)
    }

    /// [`Self::consider`] across the sliding faces of a sheared box: the partner's image is the one
    /// [`Self::collide`] takes (`sheared_image_near`), with its sliding velocity.
    #[inline(always)]
    pub(in crate::sim) fn consider_sheared(
        &self,
        pi: &crate::state::Particle<D>,
        pos_i: &Vector<D>,
        j: u32,
        best: &mut (f64, u32),
        limit: &mut f64,
    ) {
        let now = self.now;
        let pj = &self.particles[j as usize];
        let pos_j = pj.at(now);
        let (ri, vi) = self.sheared_image_near(pos_i, &pi.vel, &pos_j);
        let v2 = vi.norm_squared() + pj.vel.norm_squared();
        self.keep_if_earlier(
            &(ri - pos_j),
            &(vi - pj.vel),
            pi.radius + pj.radius,
            v2,
            j,
            best,
            limit,
        );
    }
}

/// `lists::wrapped_now` in a sheared box: a trajectory past a sliding face is replaced by its image in
/// the box (y ∓ L_y, x ∓ Δ, v_x ∓ a L_y: the same motion), which names the grain anew; x and z
/// wrap by whole box lengths.
pub(in crate::sim) fn wrapped_now_sheared<const D: usize>(
    p: &mut Particle<D>,
    now: f64,
    box_len: &Vector<D>,
    w: &ShearWindow,
) -> Vector<D> {
    let mut pos = p.at(now);
    let k = (pos[1] / box_len[1]).floor();
    let mut moved = k != 0.0;
    if moved {
        pos[1] -= k * box_len[1];
        pos[0] -= k * w.delta;
        p.vel[0] -= k * w.speed;
        p.bump();
    }
    for a in 0..D {
        let l = box_len[a];
        if pos[a] < 0.0 || pos[a] >= l {
            pos[a] -= (pos[a] / l).floor() * l;
            if pos[a] >= l {
                pos[a] -= l;
            }
            moved = true;
        }
    }
    if moved {
        p.r0 = pos - p.vel * now;
    }
    pos
}

impl<const D: usize> NeighbourLists<D> {
    /// [`Self::gather`] for a centre in a row along a sliding face of a sheared box: the row across
    /// the face is visited through its four columns that can hold images within reach while Δ stays
    /// in the window (`sim/shear.rs`), and an image counts if it comes within reach for some Δ up
    /// to the window's end (the x gap then closes by up to `end − delta`). Scalar: few grains live
    /// in the two outer rows.
    pub(in crate::sim) fn gather_sheared<B: Boundary>(
        &mut self,
        space: &Space<'_, D, B>,
        w: &ShearWindow,
        ci: &[u32; D],
        i: usize,
        later_only: bool,
        mut found: impl FnMut(&mut Self, u32),
    ) {
        let (particles, grid) = (space.particles, space.grid);
        let n = grid.n;
        let (nx, ny) = (n[0] as i64, n[1] as i64);
        let centre = self.centre[i];
        let ri = particles[i].radius;
        let slide = (w.end - w.delta).max(0.0);
        let far = self.max_reach * self.max_reach * (1.0 + 1e-9);
        for oy in -1..=1i64 {
            let (y, wrap, first, count) = sliding_row(ci[0], ci[1] as i64 + oy, ny, w.cell);
            for cx in first..first + count {
                let wx = cx.rem_euclid(nx);
                let mut shift = Vector::<D>::zeros();
                shift[0] = ((cx - wx) / nx) as f64 * space.box_len[0] + wrap as f64 * w.delta;
                shift[1] = wrap as f64 * space.box_len[1];
                let layers: &[i64] = if D == 3 { &[-1, 0, 1] } else { &[0] };
                for &oz in layers {
                    let mut idx = wx as usize * grid.stride[0] + y as usize * grid.stride[1];
                    if D == 3 {
                        let nz = n[2] as i64;
                        let z = ci[2] as i64 + oz;
                        let wz = z.rem_euclid(nz);
                        shift[2] = ((z - wz) / nz) as f64 * space.box_len[2];
                        idx += wz as usize * grid.stride[2];
                    }
                    // The cell's box as seen from i, its x extent stretched by the slide: skipped
                    // when farther than the largest reach (about half the stencil).
                    let lo = [
                        wx as f64 * grid.side[0] + shift[0],
                        y as f64 * grid.side[1] + shift[1],
                        if D == 3 {
                            (ci[2] as i64 + oz).rem_euclid(n[2] as i64) as f64 * grid.side[2]
                                + shift[2]
                        } else {
                            0.0
                        },
                    ];
                    let mut gap2 = 0.0;
                    for a in 0..D {
                        let (mut from, mut to) = (lo[a], lo[a] + grid.side[a]);
                        if a == 0 && wrap > 0 {
                            to += slide;
                        } else if a == 0 && wrap < 0 {
                            from -= slide;
                        }
                        let g = (from - centre[a]).max(centre[a] - to).max(0.0);
                        gap2 += g * g;
                    }
                    if gap2 > far {
                        continue;
                    }
                    let mut k = grid.first(idx);
                    while k != NONE {
                        let j = k as usize;
                        k = self.links[j];
                        if j == i || (later_only && j < i) {
                            continue;
                        }
                        let mut d = centre - (self.centre[j] + shift);
                        // The image slides by wrap · (Δ' − Δ) along x for Δ' up to the window's
                        // end: the nearest the gap gets.
                        let moved = d[0] - wrap as f64 * slide;
                        d[0] = if d[0].min(moved) <= 0.0 && d[0].max(moved) >= 0.0 {
                            0.0
                        } else {
                            d[0].abs().min(moved.abs())
                        };
                        let reach = ri + particles[j].radius + self.skin;
                        if d.norm_squared() < reach * reach {
                            found(self, j as u32);
                        }
                    }
                }
            }
        }
    }
}
