//! The list scan's cheap test four partners at a time, on x86-64 processors with AVX2 (chosen at
//! run time: [`crate::sim::neighbours::wide_scan_available`]).
//!
//! [`Simulation::scan_list`] tests partners two at a time in SSE2 registers, which the x86-64
//! baseline guarantees; gathering each pair's seven numbers into lanes and unpacking them costs more
//! instructions than the test itself (docs/benchmarks.md, "The 3D instruction budget by function").
//! Here the partners' records are read into lanes for four partners at once, and the test runs on
//! four lanes: in 3D, where a record is one line, by two 32-byte loads per partner and a 4×4
//! transpose (some processors microcode gathers; docs/benchmarks.md, "Sphere records by loads and
//! a transpose"); in 2D by AVX2 gathers, one instruction per coordinate. Every lane computes exactly
//! the operations of the portable test, in the same order and without fused multiply-adds, so it
//! keeps exactly the same partners; those go through the same exact test
//! ([`Simulation::consider`]) one by one in list order. Trajectories are bit-identical to the
//! portable scan's (`tests/engine/oracle.rs`, `wide_scan_changes_no_event`).

#[cfg(target_arch = "x86_64")]
use std::arch::x86_64::*;

use super::space::{rootless_test, smaller, Space};
use super::NeighbourLists;
use crate::calendar::Calendar;
use crate::predict::APPROACH_TOLERANCE;
use crate::sim::Simulation;
use crate::state::Particle;
use crate::{Boundary, CollisionRule};

#[cfg(target_arch = "x86_64")]
impl<const D: usize, B: Boundary, R: CollisionRule, C: Calendar> Simulation<D, B, R, C> {
    /// [`Simulation::scan_list`] with the cheap test on four partners at once (module docs);
    /// `SAME`: every particle has the same radius ([`NeighbourLists::same_radius`]).
    ///
    /// # Safety
    /// The processor must support AVX2, and `n` times the particle record's length in `f64` words
    /// must fit an `i32` ([`crate::sim::neighbours::wide_scan_available`]).
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    pub(in crate::sim) unsafe fn scan_list_wide<
        const WRAP: bool,
        const SHEAR: bool,
        const SAME: bool,
    >(
        &self,
        nl: &NeighbourLists<D>,
        i: usize,
        mut best: (f64, u32),
        horizon: f64,
    ) -> (f64, u32) {
        const LANES: usize = 4;
        let now = self.now;
        let pi = self.particles[i];
        let pos_i = pi.at(now);
        let vi2 = pi.vel.norm_squared();
        let mut limit = smaller(best.0 - now, horizon - now);
        let words = (std::mem::size_of::<Particle<D>>() / 8) as i32;
        let base = self.particles.as_ptr().cast::<f64>();
        // SAFETY (all intrinsics below): AVX2 is enabled by the caller's contract; the loads and
        // gathers read within the records of the padded list's entries, all slots (below n, whose
        // word offsets fit an i32 by the contract; a 3D record is the eight words the two loads
        // read).
        let now_v = _mm256_set1_pd(now);
        let ri = _mm256_set1_pd(pi.radius);
        let ri2 = _mm256_set1_pd(pi.radius + pi.radius);
        let mut factor = _mm256_set1_pd(bound_factor(limit));
        let zero = _mm256_setzero_pd();
        let stride = _mm_set1_epi32(words);
        let own: [Image; D] =
            std::array::from_fn(|a| Image::new(pos_i[a], self.box_len[a], self.half_box[a]));
        // The last group's entries past the list's end are `i` itself, which the test never keeps
        // (no separation, no approach: b = 0 and, in a sheared box, no gap across the face).
        for group in nl.of_padded(i).chunks_exact(LANES) {
            let slots = _mm_loadu_si128(group.as_ptr().cast::<__m128i>());
            let at = _mm_mullo_epi32(slots, stride);
            let (mut r0s, mut vels, mut radii) = ([zero; D], [zero; D], zero);
            group_lanes::<D, SAME>(base, group, at, words, (&mut r0s, &mut vels, &mut radii));
            // Separation, relative velocity and the partner's velocity per axis, for the exact
            // times; b = r·v and |r|²; in a sheared box whether the pair lies across a sliding face.
            let Lanes {
                ds,
                dvs,
                b,
                dr2,
                across,
            } = separations::<D, B, WRAP, SHEAR>(&r0s, &vels, &own, now_v, &pi.vel);
            // Where every radius is `i`'s, σ is `i`'s two radii for every partner, to the bit.
            let sigma = if SAME { ri2 } else { _mm256_add_pd(ri, radii) };
            let room = _mm256_sub_pd(_mm256_mul_pd(sigma, sigma), dr2);
            // `rootless_test` (b < 0 and room ≥ 2 b limit (1 + 1e-9)), a trace looser: the lanes
            // it keeps go through the test itself below.
            let fits = _mm256_cmp_pd::<_CMP_GE_OQ>(room, _mm256_mul_pd(b, factor));
            let keep = _mm256_or_pd(
                _mm256_and_pd(_mm256_cmp_pd::<_CMP_LT_OQ>(b, zero), fits),
                across,
            );
            let mut kept = _mm256_movemask_pd(keep) as u32;
            if kept == 0 {
                continue;
            }
            if SHEAR {
                while kept != 0 {
                    let k = kept.trailing_zeros() as usize;
                    kept &= kept - 1;
                    self.consider_sheared(&pi, &pos_i, group[k], &mut best, &mut limit);
                }
                continue;
            }
            // The group's exact times on four lanes (`pair_time`'s operations), then, lane by
            // lane in list order, the test and the update of `keep_if_earlier`.
            let times = pair_times::<D>(&ds, &dvs, &vels, b, dr2, sigma, room, vi2);
            let mut lane_b = [0.0; LANES];
            let mut lane_room = [0.0; LANES];
            let mut lane_t = [0.0; LANES];
            _mm256_storeu_pd(lane_b.as_mut_ptr(), b);
            _mm256_storeu_pd(lane_room.as_mut_ptr(), room);
            _mm256_storeu_pd(lane_t.as_mut_ptr(), times);
            while kept != 0 {
                let k = kept.trailing_zeros() as usize;
                kept &= kept - 1;
                if rootless_test(lane_b[k], lane_room[k], limit) {
                    let t = now + lane_t[k];
                    if t < best.0 {
                        best = (t, group[k]);
                        limit = smaller(limit, t - now);
                        factor = _mm256_set1_pd(bound_factor(limit));
                    }
                }
            }
        }
        best
    }
}

/// A group's separations (partner minus own) and relative velocities per axis, with b = r·v, |r|²
/// and, in a sheared box, the lanes whose pair lies across a sliding face.
#[cfg(target_arch = "x86_64")]
struct Lanes<const D: usize> {
    ds: [__m256d; D],
    dvs: [__m256d; D],
    b: __m256d,
    dr2: __m256d,
    across: __m256d,
}

/// The separations of the group whose origins and velocities are `r0s`, `vels`, from the own
/// particle (`own`, velocity `vel_i`) at the time in `now_v`. They are taken partner minus own, the
/// negatives of `pair_time`'s, exactly (x − y = −(y − x) in floating point): every product of two
/// of them, and so b, |r|² and the exact time, is the same to the bit, and the own values can be
/// read from memory by the subtraction itself.
///
/// # Safety
/// The processor must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code)]
#[inline]
unsafe fn separations<const D: usize, B: Boundary, const WRAP: bool, const SHEAR: bool>(
    r0s: &[__m256d; D],
    vels: &[__m256d; D],
    own: &[Image; D],
    now_v: __m256d,
    vel_i: &crate::Vector<D>,
) -> Lanes<D> {
    let zero = _mm256_setzero_pd();
    let sign = _mm256_set1_pd(-0.0);
    let mut b = zero;
    let mut dr2 = zero;
    let mut across = zero;
    let mut ds = [zero; D];
    let mut dvs = [zero; D];
    for a in 0..D {
        let (r0, vel) = (r0s[a], vels[a]);
        let pos = _mm256_add_pd(r0, _mm256_mul_pd(vel, now_v));
        let d = if WRAP && !B::is_wall(a) {
            if SHEAR && a == 1 {
                let raw = _mm256_andnot_pd(sign, _mm256_sub_pd(own[a].at, pos));
                across = _mm256_cmp_pd::<_CMP_GT_OQ>(raw, own[a].half);
            }
            own[a].separation_from(pos)
        } else {
            _mm256_sub_pd(pos, own[a].at)
        };
        let dv = _mm256_sub_pd(vel, _mm256_set1_pd(vel_i[a]));
        (ds[a], dvs[a]) = (d, dv);
        if a == 0 {
            b = _mm256_mul_pd(d, dv);
            dr2 = _mm256_mul_pd(d, d);
        } else {
            b = _mm256_add_pd(b, _mm256_mul_pd(d, dv));
            dr2 = _mm256_add_pd(dr2, _mm256_mul_pd(d, d));
        }
    }
    Lanes {
        ds,
        dvs,
        b,
        dr2,
        across,
    }
}

/// The records of a group of four partners on four lanes: the trajectories' origins and the
/// velocities per axis, and (unless every radius is the same, `SAME`) the radii. In 3D, where a
/// record is one line, by two loads per record and a 4×4 transpose; in 2D by gathers.
///
/// # Safety
/// The processor must support AVX2; the group's slots index records of `words` words from `base`
/// (`at` their word offsets), which must fit an `i32`.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code)]
#[inline]
unsafe fn group_lanes<const D: usize, const SAME: bool>(
    base: *const f64,
    group: &[u32],
    at: __m128i,
    words: i32,
    (r0s, vels, radii): (&mut [__m256d; D], &mut [__m256d; D], &mut __m256d),
) {
    // Offsets, in words, of the fields of a record (`Particle` is `repr(C)`).
    let (r0_at, vel_at, radius_at) = (0, D, 2 * D);
    if D == 3 {
        // Sphere records are one line each, [x y z vx | vy vz radius link]: two loads per
        // partner and a 4×4 transpose give the same lanes as six gathers, in fewer µops
        // where gathers are microcoded.
        let rec = |k: usize| base.add(group[k] as usize * words as usize);
        let recs = [rec(0), rec(1), rec(2), rec(3)];
        let [t0, t1, t2, t3] = pairs_of_lanes(recs, 0);
        r0s[0] = _mm256_permute2f128_pd::<0x20>(t0, t2);
        r0s[2] = _mm256_permute2f128_pd::<0x31>(t0, t2);
        r0s[1] = _mm256_permute2f128_pd::<0x20>(t1, t3);
        vels[0] = _mm256_permute2f128_pd::<0x31>(t1, t3);
        let [u0, u1, u2, u3] = pairs_of_lanes(recs, 4);
        vels[1] = _mm256_permute2f128_pd::<0x20>(u0, u2);
        vels[2] = _mm256_permute2f128_pd::<0x20>(u1, u3);
        if !SAME {
            *radii = _mm256_permute2f128_pd::<0x31>(u0, u2);
        }
    } else {
        for a in 0..D {
            r0s[a] = _mm256_i32gather_pd::<8>(base.add(r0_at + a), at);
            vels[a] = _mm256_i32gather_pd::<8>(base.add(vel_at + a), at);
        }
        if !SAME {
            *radii = _mm256_i32gather_pd::<8>(base.add(radius_at), at);
        }
    }
}

/// The first half of a 4×4 transpose: the four words at `offset` of each of the four records `p`,
/// unpacked in pairs, `[w0 of p0, p1 | w2 of p0, p1]`, `[w1 of p0, p1 | w3 of p0, p1]`, then the
/// same of p2 and p3; one `vperm2f128` of two of them makes a word's four lanes.
///
/// # Safety
/// AVX2; each `p[k] + offset` starts four readable words.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code)]
#[inline]
unsafe fn pairs_of_lanes(p: [*const f64; 4], offset: usize) -> [__m256d; 4] {
    let [a0, a1, a2, a3] = p.map(|q| _mm256_loadu_pd(q.add(offset)));
    [
        _mm256_unpacklo_pd(a0, a1),
        _mm256_unpackhi_pd(a0, a1),
        _mm256_unpacklo_pd(a2, a3),
        _mm256_unpackhi_pd(a2, a3),
    ]
}

/// The test of a list renewal's search on four candidates at once: hands `found`, in the order of
/// `candidates[..len]`, each whose shell centre lies within `σ_ij + δ` of slot `i`'s (with nearest
/// images if `WRAP`), by the operations of the one-by-one test (`NeighbourLists::gather`). Slot `i`
/// itself, and with `later_only` every slot below it, is masked off here, so that the walk that
/// lists the candidates needs no test per occupant. `SAME`: every particle has the same radius
/// ([`NeighbourLists::same_radius`]), so the reach is one number and no radius is read.
///
/// # Safety
/// As [`Simulation::scan_list_wide`]; every entry of `candidates` is a slot, and its length is a
/// multiple of four.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code, clippy::too_many_arguments)]
pub(in crate::sim) unsafe fn within_reach_wide<
    const D: usize,
    B: Boundary,
    const WRAP: bool,
    const SAME: bool,
>(
    nl: &mut NeighbourLists<D>,
    space: &Space<'_, D, B>,
    candidates: &[u32],
    len: usize,
    i: usize,
    later_only: bool,
    found: &mut impl FnMut(&mut NeighbourLists<D>, u32),
) {
    const LANES: usize = 4;
    let centre = nl.centre[i];
    let words = (std::mem::size_of::<Particle<D>>() / 8) as i32;
    let records = space.particles.as_ptr().cast::<f64>();
    // SAFETY (all intrinsics below): AVX2 by the contract; the gathers read the centres and the
    // radii of slots (below n, whose word offsets fit an i32).
    let ri = _mm256_set1_pd(space.particles[i].radius);
    let skin = _mm256_set1_pd(nl.skin);
    // (ri + ri) + δ is the one-by-one test's `ri + rj + δ` where every rj is ri, to the bit.
    let same_reach = _mm256_add_pd(_mm256_add_pd(ri, ri), skin);
    let same_reach2 = _mm256_mul_pd(same_reach, same_reach);
    let stride = _mm_set1_epi32(words);
    let centre_stride = _mm_set1_epi32(D as i32);
    let own_slot = _mm_set1_epi32(i as i32);
    let own: [Image; D] =
        std::array::from_fn(|a| Image::new(centre[a], space.box_len[a], space.half_box[a]));
    let (whole, tail) = (len / LANES, (1u32 << (len % LANES)) - 1);
    for (g, group) in candidates.chunks_exact(LANES).enumerate() {
        let slots = _mm_loadu_si128(group.as_ptr().cast::<__m128i>());
        // Lanes past the end, slot `i` itself and, for `later_only`, the slots below it.
        let skip = if later_only {
            _mm_xor_si128(_mm_cmpgt_epi32(slots, own_slot), _mm_set1_epi32(-1))
        } else {
            _mm_cmpeq_epi32(slots, own_slot)
        };
        let lanes = if g < whole { 0b1111 } else { tail };
        let lanes = lanes & !(_mm_movemask_ps(_mm_castsi128_ps(skip)) as u32);
        let at = _mm_mullo_epi32(slots, centre_stride);
        // Taken anew for each group: `found` may change the lists (never the centres).
        let centres = nl.centre.as_ptr().cast::<f64>();
        let mut d2 = _mm256_setzero_pd();
        // Separations taken partner minus own, the exact negatives of the one-by-one test's: the
        // same squares.
        for (a, own) in own.iter().enumerate() {
            let cj = _mm256_i32gather_pd::<8>(centres.add(a), at);
            let d = if WRAP && !B::is_wall(a) {
                own.separation_from(cj)
            } else {
                _mm256_sub_pd(cj, own.at)
            };
            d2 = if a == 0 {
                _mm256_mul_pd(d, d)
            } else {
                _mm256_add_pd(d2, _mm256_mul_pd(d, d))
            };
        }
        let reach2 = if SAME {
            same_reach2
        } else {
            let radius =
                _mm256_i32gather_pd::<8>(records.add(2 * D), _mm_mullo_epi32(slots, stride));
            let reach = _mm256_add_pd(_mm256_add_pd(ri, radius), skin);
            _mm256_mul_pd(reach, reach)
        };
        let near = _mm256_cmp_pd::<_CMP_LT_OQ>(d2, reach2);
        let mut kept = _mm256_movemask_pd(near) as u32 & lanes;
        while kept != 0 {
            let k = kept.trailing_zeros() as usize;
            kept &= kept - 1;
            found(nl, group[k]);
        }
    }
}

/// One own coordinate along one axis on four lanes, with its two periodic images, for
/// [`Image::separation_from`]: built once per search instead of once per group.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
struct Image {
    /// The own coordinate.
    at: __m256d,
    /// It moved down and up by the box side.
    down: __m256d,
    up: __m256d,
    /// The half side and its negative.
    half: __m256d,
    minus_half: __m256d,
}

#[cfg(target_arch = "x86_64")]
impl Image {
    /// The coordinate `own` along an axis of side `len` and half side `half` (unused along a
    /// wall axis).
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    #[inline]
    unsafe fn new(own: f64, len: f64, half: f64) -> Self {
        let (at, len) = (_mm256_set1_pd(own), _mm256_set1_pd(len));
        Image {
            at,
            down: _mm256_sub_pd(at, len),
            up: _mm256_add_pd(at, len),
            half: _mm256_set1_pd(half),
            minus_half: _mm256_set1_pd(-half),
        }
    }

    /// `other − image_near(own, other)` on four lanes: `other` minus `own` moved by the side
    /// towards it where they lie more than half a side apart, by the operations of `image_near`
    /// with the sign flipped (exactly the negative of `image_near(own, other) − other`).
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[target_feature(enable = "avx2")]
    #[allow(unsafe_code)]
    #[inline]
    unsafe fn separation_from(&self, other: __m256d) -> __m256d {
        // raw = other − own = −(own − other). `image_near` moves own by `up − down`: len − 0 = len
        // where own − other > half, 0 − len = −len where < −half, 0 − 0 = 0 elsewhere; own − len,
        // own − (−len) = own + len and own − 0 = own are those results exactly, so own is replaced
        // by its two moved copies (built once per search) where they apply.
        let raw = _mm256_sub_pd(other, self.at);
        let below = _mm256_cmp_pd::<_CMP_LT_OQ>(raw, self.minus_half);
        let above = _mm256_cmp_pd::<_CMP_GT_OQ>(raw, self.half);
        let moved = _mm256_blendv_pd(self.at, self.down, below);
        let moved = _mm256_blendv_pd(moved, self.up, above);
        _mm256_sub_pd(other, moved)
    }
}

/// [`pair_time`](crate::predict::pair_time) on four lanes, by its operations in its order: the
/// separations `ds`, relative velocities `dvs` and partner velocities `vels` per axis, `b = r·v`,
/// `dr2 = |r|²`, the contact distances `sigma`, `room = σ² − |r|²` and the own speed squared `vi2`.
///
/// # Safety
/// The processor must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(unsafe_code, clippy::too_many_arguments)]
#[inline]
unsafe fn pair_times<const D: usize>(
    ds: &[__m256d; D],
    dvs: &[__m256d; D],
    vels: &[__m256d; D],
    b: __m256d,
    dr2: __m256d,
    sigma: __m256d,
    room: __m256d,
    vi2: f64,
) -> __m256d {
    let zero = _mm256_setzero_pd();
    // c = |r|² − σ², the negative of `room` (both from the same σ²).
    let c = _mm256_sub_pd(zero, room);
    let mut cross2 = zero;
    let mut dv2 = zero;
    let mut vj2 = zero;
    for a in 0..D {
        for k in a + 1..D {
            let w = _mm256_sub_pd(_mm256_mul_pd(ds[a], dvs[k]), _mm256_mul_pd(ds[k], dvs[a]));
            cross2 = _mm256_add_pd(cross2, _mm256_mul_pd(w, w));
        }
        dv2 = _mm256_add_pd(dv2, _mm256_mul_pd(dvs[a], dvs[a]));
        vj2 = _mm256_add_pd(vj2, _mm256_mul_pd(vels[a], vels[a]));
    }
    let disc = _mm256_sub_pd(_mm256_mul_pd(_mm256_mul_pd(dv2, sigma), sigma), cross2);
    let root = _mm256_sqrt_pd(_mm256_max_pd(disc, zero));
    let t = _mm256_div_pd(c, _mm256_sub_pd(root, b));
    let t = _mm256_blendv_pd(t, zero, _mm256_cmp_pd::<_CMP_LE_OQ>(c, zero));
    // `approaching(b, dr2, speed2)` and a real root.
    let speed2 = _mm256_add_pd(_mm256_set1_pd(vi2), vj2);
    let tol2 = _mm256_set1_pd(APPROACH_TOLERANCE * APPROACH_TOLERANCE);
    let slow = _mm256_mul_pd(_mm256_mul_pd(tol2, dr2), speed2);
    let approach = _mm256_and_pd(
        _mm256_cmp_pd::<_CMP_LT_OQ>(b, zero),
        _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_mul_pd(b, b), slow),
    );
    let hit = _mm256_and_pd(approach, _mm256_cmp_pd::<_CMP_GT_OQ>(disc, zero));
    _mm256_blendv_pd(_mm256_set1_pd(f64::INFINITY), t, hit)
}

/// The factor `f` of the four-wide form `room ≥ b f` of [`rootless_test`] for `limit`: `2 limit
/// (1 + 1e-9)`, a relative 1e-12 larger. For b < 0 the bound b f then lies below the test's own
/// `(2 b limit)(1 + 1e-9)` by far more than their few roundings, so the four-wide form keeps every
/// partner the test keeps (and the test decides); at limit 0 or ∞ both bounds are equal.
#[inline(always)]
fn bound_factor(limit: f64) -> f64 {
    2.0 * limit * (1.0 + 1e-9) * (1.0 + 1e-12)
}
