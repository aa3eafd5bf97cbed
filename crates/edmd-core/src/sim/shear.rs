//! Lees–Edwards boundaries ([`crate::LeesEdwards`]): the sliding images across the y faces.
//!
//! The image of particle k above the box (across the upper y face) sits at x_k + Δ(t), y_k + L_y
//! and moves with v_k + a L_y e_x; the one below at x_k − Δ, y_k − L_y with v_k − a L_y e_x. Seen from
//! cell column c of the upper row, the images that can touch a particle there while Δ stays in
//! [m w, (m + 1) w] (w the cell side) come from the lower row's columns c − m − 2 … c − m + 1; from
//! the lower row, the upper row's columns c + m − 1 … c + m + 2. A cell search across the face
//! visits those four columns, and when Δ reaches the next multiple of w (a *shift*) every particle
//! of the two outer rows is searched again with m + 1, so no candidate is ever missed.

use super::{Cells, Simulation};
use crate::calendar::Calendar;
use crate::sim::neighbours::NONE;
use crate::{Boundary, CollisionRule, Particle, Vector};

/// The state of the sliding images of a sheared scene: Δ(now) = `offset` + `speed` · now, taken
/// modulo L_x only together with `cell` (at each clock rebase), so that the two always agree.
/// Across a y face a particle's cell search covers four cells of the sliding row, enough until Δ
/// next crosses a multiple of the cell side: then (`next`, local time) every particle of the two
/// outer rows is searched again, with the row's stencil moved by one cell (`cell`).
#[derive(Debug, Clone, Copy, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct Shear {
    /// Δ at local time 0.
    pub offset: f64,
    /// The images' speed a L_y.
    pub speed: f64,
    /// ⌊Δ / cell side⌋ between shifts (counted by the shifts, not computed from Δ).
    pub cell: i64,
    /// Local time of the next shift (∞ without shear).
    pub next: f64,
}

/// The window of a sheared box's list builds: Δ now, Δ at the next shift (when the lists near the
/// sliding faces are renewed), the images' speed a L_y and the shift count m (Δ ∈ [m w, (m + 1) w]
/// with w the cell side).
#[derive(Debug, Clone, Copy)]
pub(super) struct ShearWindow {
    pub(super) delta: f64,
    pub(super) end: f64,
    pub(super) speed: f64,
    pub(super) cell: i64,
}

impl Shear {
    /// The sliding images of scene `B` at rate `rate` in a box whose cell columns are
    /// `side` wide, `height` the box's L_y: at rest where the scene is not sheared (`next` = ∞).
    pub(super) fn new<B: Boundary>(rate: f64, height: f64, side: f64) -> Shear {
        if !B::SHEARED {
            return Shear {
                next: f64::INFINITY,
                ..Shear::default()
            };
        }
        let speed = rate * height;
        Shear {
            offset: 0.0,
            speed,
            cell: 0,
            next: if speed > 0.0 {
                side / speed
            } else {
                f64::INFINITY
            },
        }
    }

    /// What list mode needs of the images at local time `now`: their offset, its value at the next
    /// shift, their speed and the stencil's cell (none where scene `B` is not sheared).
    #[inline(always)]
    pub(super) fn window<B: Boundary>(&self, now: f64) -> Option<ShearWindow> {
        B::SHEARED.then_some(ShearWindow {
            delta: self.offset + self.speed * now,
            end: self.offset + self.speed * self.next,
            speed: self.speed,
            cell: self.cell,
        })
    }
}

/// A pair collision as the sheared sums read it: lab velocities before and after, i's image's
/// velocity (i's own plus the slide across a face), the separation from j to i's image.
pub(super) struct PairChange<const D: usize> {
    pub masses: (f64, f64),
    pub before: (Vector<D>, Vector<D>),
    pub after: (Vector<D>, Vector<D>),
    pub image_velocity: Vector<D>,
    pub separation: Vector<D>,
    /// The rotational energy the contact removed (rough grains; else 0).
    pub spin_loss: f64,
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// `slide` (how much faster i's image moves than i) where images slide, else none: the frame
    /// in which a pair's relative velocity is the difference of the two.
    #[inline(always)]
    pub(super) fn sliding(&self, slide: Vector<D>) -> Option<Vector<D>> {
        B::SHEARED.then_some(slide)
    }

    /// Sheared scenes: the collision's share of the collisional stress tensor and of the energy
    /// dissipated (PHYSICS.md §7); nothing elsewhere.
    #[inline(always)]
    pub(super) fn add_shear_sums(&mut self, c: &PairChange<D>) {
        if !B::SHEARED {
            return;
        }
        let ((mi, mj), (vi0, vj0), (vi, vj)) = (c.masses, c.before, c.after);
        // The whole impulse on i (normal, tangential, rotated) times the separation: a-momentum
        // carried along b. Tangential and rotated impulses make it asymmetric, and the shear's
        // work is −a times the [0][1] entry (PHYSICS.md §7).
        let dp = (vi - vi0) * mi;
        for a in 0..D {
            for b in 0..D {
                self.counters.virial_tensor[a][b] += dp[a] * c.separation[b];
            }
        }
        // The kinetic energy removed, in the frame of i's image (where the pair's momentum is
        // conserved; the loss is the same in every such frame).
        let vi_after = vi + (c.image_velocity - vi0);
        self.counters.dissipated += c.spin_loss
            + 0.5 * mi * (c.image_velocity.norm_squared() - vi_after.norm_squared())
            + 0.5 * mj * (vj0.norm_squared() - vj.norm_squared());
    }

    /// List mode: whether slot i's listed partners may sit across a sliding face
    /// ([`Self::near_sliding_face`]; never where the scene is not sheared).
    #[inline(always)]
    pub(super) fn slides_near(
        &self,
        nl: &crate::sim::neighbours::NeighbourLists<D>,
        i: usize,
    ) -> bool {
        B::SHEARED && self.near_sliding_face(nl, i)
    }

    /// Cell mode at the box's edge: the search across the sliding faces where they slide
    /// ([`Self::search_cells_sheared`]); none elsewhere.
    #[inline(always)]
    pub(super) fn search_sliding_cells(
        &self,
        i: usize,
        only: Option<(usize, i32)>,
        best: (f64, u32),
    ) -> Option<(f64, u32)> {
        B::SHEARED.then(|| self.search_cells_sheared(i, only, best))
    }

    /// Whether a wrap along `axis` crosses a sliding face (y in a sheared box).
    #[inline(always)]
    pub(super) fn slides_across(&self, axis: usize) -> bool {
        B::SHEARED && axis == 1
    }

    /// The images' part of a clock rebase to local time `now`.
    pub(super) fn rebase_shear(&mut self, now: f64) {
        if B::SHEARED {
            // Whole box lengths leave Δ and the stencil's cell together, so the two stay consistent.
            let s = &mut self.shear;
            let wraps = s.cell.div_euclid(self.grid.n[0] as i64);
            s.offset += s.speed * now - wraps as f64 * self.box_len[0];
            s.cell -= wraps * self.grid.n[0] as i64;
            s.next -= now;
        }
    }

    /// Scales every velocity by `factor`, in a sheared box only its peculiar part: the flow
    /// a (y − L_y/2) is the boundary's, not the gas's heat.
    pub(super) fn scale_thermal_velocities(&mut self, factor: f64) {
        if B::SHEARED {
            let (rate, middle) = (self.params.shear_rate, self.half_box[1]);
            for p in &mut self.particles {
                let flow = rate * (p.r0[1] - middle);
                p.vel[0] -= flow;
                p.vel *= factor;
                p.vel[0] += flow;
            }
        } else {
            for p in &mut self.particles {
                p.vel *= factor;
            }
        }
    }

    /// Δ at the current time (not reduced modulo L_x; see [`super::Shear`]).
    #[inline(always)]
    pub(super) fn shear_delta(&self) -> f64 {
        self.shear.offset + self.shear.speed * self.now
    }

    /// How many sliding faces a grain's trajectory has passed upwards (negative: downwards) since
    /// it was last wrapped into the box: 0 in cell mode, where each crossing wraps at once; in list
    /// mode, where trajectories wrap lazily at list renewals, the grain's image in the box is this
    /// many L_y below, Δ times it to the left, and slower by as many a L_y.
    #[inline(always)]
    pub(super) fn faces_passed(&self, p: &Particle<D>) -> f64 {
        ((p.r0[1] + p.vel[1] * self.now) / self.box_len[1]).floor()
    }

    /// The displacement along x of the images across the y faces at the current time, in [0, L_x),
    /// and the shear rate: what a reader of the positions needs to draw the sliding images.
    pub fn shear_offset(&self) -> f64 {
        if B::SHEARED {
            self.shear_delta().rem_euclid(self.box_len[0])
        } else {
            0.0
        }
    }

    /// The shift vector and the image velocity change of partner images across y face `wrap` (+1:
    /// the image above, −1 below, 0 none) and `kx` box lengths along x: the image sits at the
    /// partner's position plus the shift, and moves with its velocity plus `wrap · a L_y` along x.
    #[inline(always)]
    fn image_shift(&self, wrap: i64, kx: i64, delta: f64) -> Vector<D> {
        let mut s = Vector::<D>::zeros();
        s[0] = kx as f64 * self.box_len[0] + wrap as f64 * delta;
        s[1] = wrap as f64 * self.box_len[1];
        s
    }

    /// The image of particle i (position `x`, velocity `v`) nearest to particle j at `y`, and that
    /// image's velocity: the shift and velocity change written as [`Self::search_cells_sheared`]
    /// writes them, so that a pair it found approaching is approaching here too.
    #[inline(always)]
    pub(super) fn sheared_image_near(
        &self,
        x: &Vector<D>,
        v: &Vector<D>,
        y: &Vector<D>,
    ) -> (Vector<D>, Vector<D>) {
        let dy = x[1] - y[1];
        // i's image across a face is j's seen from i the other way: i above j's row means j's
        // image above i, so i is reduced by the shift of j's upper image (wrap +1).
        let wrap = if dy > self.half_box[1] {
            1
        } else if dy < -self.half_box[1] {
            -1
        } else {
            0
        };
        let delta = self.shear_delta();
        let dx = x[0] - wrap as f64 * delta - y[0];
        let kx = (dx / self.box_len[0]).round() as i64;
        let mut ri = x - self.image_shift(wrap, kx, delta);
        for a in 2..D {
            let d = x[a] - y[a];
            if d > self.half_box[a] {
                ri[a] -= self.box_len[a];
            } else if d < -self.half_box[a] {
                ri[a] += self.box_len[a];
            }
        }
        let mut vi = *v;
        vi[0] -= wrap as f64 * self.shear.speed;
        (ri, vi)
    }

    /// [`Self::search_cells`] for a cell at the box's edge in a sheared scene: the rows across a y
    /// face are visited through the four sliding columns (module docs), the others as in a periodic
    /// box. `only` restricts the search to the cells newly adjacent after a crossing.
    pub(super) fn search_cells_sheared(
        &self,
        i: usize,
        only: Option<(usize, i32)>,
        mut best: (f64, u32),
    ) -> (f64, u32) {
        let pi = self.particles[i];
        let pos_i = pi.at(self.now);
        let ci = self.meta[i].cell();
        let n = self.grid.n;
        let (nx, ny) = (n[0] as i64, n[1] as i64);
        let m = self.shear.cell;
        let delta = self.shear_delta();
        let along = |a: usize, off: i64| !matches!(only, Some((axis, dir)) if axis == a && off != dir as i64);
        for oy in -1..=1i64 {
            if !along(1, oy) {
                continue;
            }
            // The columns to visit, and which of them a crossing along x newly reaches.
            let (y, wrap, first, count) = sliding_row(ci[0], ci[1] as i64 + oy, ny, m);
            let mut pi_img = pi;
            pi_img.vel[0] -= wrap as f64 * self.shear.speed;
            for k in 0..count {
                if let Some((0, dir)) = only {
                    if (dir > 0 && k != count - 1) || (dir < 0 && k != 0) {
                        continue;
                    }
                }
                let cx = first + k;
                let wx = cx.rem_euclid(nx);
                let kx = (cx - wx) / nx;
                let shift = self.image_shift(wrap, kx, delta);
                let base = wx as usize * self.grid.stride[0] + y as usize * self.grid.stride[1];
                if D == 2 {
                    best = self.scan_cell(base, i, &pi_img, &(pos_i - shift), best);
                    continue;
                }
                for oz in -1..=1i64 {
                    if !along(2, oz) {
                        continue;
                    }
                    let nz = n[2] as i64;
                    let z = ci[2] as i64 + oz;
                    let wz = z.rem_euclid(nz);
                    let mut s = shift;
                    s[2] = ((z - wz) / nz) as f64 * self.box_len[2];
                    let idx = base + wz as usize * self.grid.stride[2];
                    best = self.scan_cell(idx, i, &pi_img, &(pos_i - s), best);
                }
            }
        }
        best
    }

    /// The shift: Δ reached the next multiple of the cell side. The clock moves to it and every
    /// particle of the two outer rows is searched again with the stencil moved by one column (in
    /// list mode: its list is renewed for the next window, `sim/neighbours/list_search.rs`).
    #[cold]
    pub(super) fn shear_shift(&mut self) {
        self.now = self.shear.next;
        self.shear.cell += 1;
        self.shear.next += self.grid.side[0] / self.shear.speed;
        let (n, stride) = (self.grid.n, self.grid.stride);
        let rows = if n[1] == 1 {
            vec![0]
        } else {
            vec![0, n[1] - 1]
        };
        let layers = if D == 3 { n[D - 1] } else { 1 };
        let mut outer = Vec::new();
        for row in rows {
            for x in 0..n[0] {
                for z in 0..layers {
                    let idx = x * stride[0]
                        + row * stride[1]
                        + if D == 3 { z * stride[D - 1] } else { 0 };
                    let mut k = self.grid.first(idx);
                    while k != NONE {
                        outer.push(k as usize);
                        k = self.next_in_cell(k);
                    }
                }
            }
        }
        if self.uses_lists() {
            // The grains filed there are those whose shell centres lie within a list's reach of a
            // sliding face: their lists are gathered again for the new window.
            for i in outer {
                self.renew_list(i);
            }
        } else {
            for i in outer {
                self.predict::<Cells>(i);
            }
        }
    }

    /// A crossing of the y face by particle `i` (already moved to the row on the other side, its
    /// y wrapped): x moves by ∓Δ and v_x by ∓a L_y (`up`: through the upper face), so that the
    /// image of the particle is where it left; its x cell follows, and it counts as a new
    /// trajectory (every candidate naming it is stale).
    pub(super) fn cross_sheared_face(&mut self, i: usize, up: bool) {
        let s = if up { 1.0 } else { -1.0 };
        let now = self.now;
        let delta = self.shear_delta();
        let speed = self.shear.speed;
        let lx = self.box_len[0];
        let p: &mut Particle<D> = &mut self.particles[i];
        let x = (p.r0[0] + p.vel[0] * now - s * delta).rem_euclid(lx);
        p.vel[0] -= s * speed;
        p.r0[0] = x - p.vel[0] * now;
        p.bump();
        let mut at = p.at(now);
        at[0] = x;
        self.meta[i].cell[0] = self.grid.coords_of(&at)[0] as u16;
    }
}

impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// Peculiar velocities V = v − a (y − L_y/2) e_x (the velocities relative to the imposed flow;
    /// the velocities themselves where the scene is not sheared), in the original order. The y of a
    /// particle is taken where its trajectory is, before any wrapping into the box, so that V is
    /// continuous through the y faces.
    pub fn peculiar_velocities(&self) -> Vec<Vector<D>> {
        self.in_original_order(|s| self.thermal_velocity_now(&self.particles[s]) * self.inv_scale)
    }

    /// The shear rate a (0 where the scene is not sheared).
    pub fn shear_rate(&self) -> f64 {
        if B::SHEARED {
            self.params.shear_rate
        } else {
            0.0
        }
    }
}

/// The row `y` (possibly across a sliding face) of a stencil around column `cx`, with `ny` rows and
/// the shift count `m` (module docs): the row wrapped into the box, the face crossed (+1 above, −1
/// below, 0 none), and the first and number of (unwrapped) columns whose images can be in reach.
#[inline(always)]
pub(super) fn sliding_row(cx: u32, y: i64, ny: i64, m: i64) -> (i64, i64, i64, i64) {
    let cx = cx as i64;
    if y < 0 {
        (y + ny, -1, cx + m - 1, 4)
    } else if y >= ny {
        (y - ny, 1, cx - m - 2, 4)
    } else {
        (y, 0, cx - 1, 3)
    }
}
