//! Event-time predictions: pair contact, cell crossing and wall contact.
//!
//! The contact time of two spheres with relative position `r`, relative velocity `v` and contact
//! distance `σ` is the smaller root of `|r + v t|² = σ²`. With `b = r·v < 0` (approaching) and
//! `c = |r|² − σ² > 0` it is computed in the cancellation-free form `t = c / (−b + √(b² − v²c))`,
//! with the discriminant written as `v²σ² − |r × v|²`.
//! A pair that overlaps by round-off (`c ≤ 0`) while approaching collides now (`t = 0`); no time is
//! ever negative.

use crate::Vector;

/// An approach speed `|b|/|r|` below this fraction of the particles' speeds is round-off: the
/// impulse it calls for would not change the velocities, and a contact would repeat forever. Such a
/// pair is treated as not approaching. (Any real contact that this skips has a normal speed below
/// 1e-13 of the particle speeds; its neglect can deepen an overlap by ~1e-13 σ per mean free time.)
pub const APPROACH_TOLERANCE: f64 = 1e-13;

/// True if the pair with `b = r·v`, `dr2 = |r|²` and `speed2 = |v_i|² + |v_j|²` approaches by more
/// than round-off. The event loop and the collision use this same test, so they always agree.
#[inline(always)]
pub fn approaching(b: f64, dr2: f64, speed2: f64) -> bool {
    b < 0.0 && b * b > APPROACH_TOLERANCE * APPROACH_TOLERANCE * dr2 * speed2
}

/// Time until contact, or `∞` if the pair never touches (from the current positions); `speed2` is
/// `|v_i|² + |v_j|²` (see [`approaching`]).
///
/// One data-dependent branch: a receding pair (`b ≥ 0`, about half the neighbours a search meets)
/// returns at once, which spares it the root and the division. For the others every quantity is
/// computed and the result chosen by [`select`], without a branch: whether an approaching pair
/// meets is a coin flip too, and a branch on it would mispredict as often.
#[inline(always)]
pub fn pair_time<const D: usize>(dr: &Vector<D>, dv: &Vector<D>, sigma: f64, speed2: f64) -> f64 {
    let b = dr.dot(dv);
    if !(b < 0.0) {
        return f64::INFINITY;
    }
    let dr2 = dr.norm_squared();
    let c = dr2 - sigma * sigma;
    // b² − v²c = v²σ² − |r × v|²: the cross-product form keeps its digits for grazing approaches
    // from afar, where b² and v²c nearly cancel.
    let mut cross2 = 0.0;
    for a in 0..D {
        for k in a + 1..D {
            let w = dr[a] * dv[k] - dr[k] * dv[a];
            cross2 += w * w;
        }
    }
    let disc = dv.norm_squared() * sigma * sigma - cross2;
    let t = c / (disc.max(0.0).sqrt() - b);
    let t = if c <= 0.0 { 0.0 } else { t };
    select(approaching(b, dr2, speed2) & (disc > 0.0), t, f64::INFINITY)
}

/// `if cond { a } else { b }` without a branch. Written as a plain `if`, the compiler turns the
/// choice into a branch around the division that computes `a`: cheaper when predicted, but for
/// neighbours it mispredicts about as often as not.
#[inline(always)]
#[allow(unsafe_code)]
pub(crate) fn select(cond: bool, a: f64, b: f64) -> f64 {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: SSE2 is part of the x86_64 baseline; the operations only move bits.
    unsafe {
        use std::arch::x86_64::*;
        let m = _mm_castsi128_pd(_mm_set1_epi64x(-(cond as i64)));
        _mm_cvtsd_f64(_mm_or_pd(
            _mm_and_pd(m, _mm_set_sd(a)),
            _mm_andnot_pd(m, _mm_set_sd(b)),
        ))
    }
    #[cfg(not(target_arch = "x86_64"))]
    if cond {
        a
    } else {
        b
    }
}

/// Time until coordinate `x` moving at `v` reaches `target`: `∞` at rest, `0` if already past it.
#[inline(always)]
pub fn reach_time(x: f64, v: f64, target: f64) -> f64 {
    if v == 0.0 {
        return f64::INFINITY;
    }
    ((target - x) / v).max(0.0)
}

/// Under gravity `g > 0` (pulling towards −x): time until `x(t) = x + u t − g t²/2` next comes down
/// through `target` (0 if it is already at or below it and not rising); cancellation-free.
#[inline]
pub fn fall_time(x: f64, u: f64, g: f64, target: f64) -> f64 {
    let h = x - target;
    let disc = u * u + 2.0 * g * h;
    if (h <= 0.0 && u <= 0.0) || disc < 0.0 {
        // At or below the target and not rising, or (by round-off) below it without the speed to
        // rise above it: it crosses now.
        return 0.0;
    }
    let s = disc.sqrt();
    if u <= 0.0 {
        2.0 * h / (s - u)
    } else {
        (u + s) / g
    }
}

/// Under gravity `g ≥ 0`: time until `x(t) = x + u t − g t²/2` first rises to `target ≥ x`; `∞` if
/// its apex stays below (0 if already above it while rising).
#[inline]
pub fn rise_time(x: f64, u: f64, g: f64, target: f64) -> f64 {
    let d = target - x;
    if u <= 0.0 {
        return f64::INFINITY;
    }
    if d <= 0.0 {
        return 0.0;
    }
    let disc = u * u - 2.0 * g * d;
    if disc < 0.0 {
        return f64::INFINITY;
    }
    2.0 * d / (u + disc.sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::vector;

    #[test]
    fn head_on_contact() {
        let t = pair_time(&vector![3.0, 0.0], &vector![-1.0, 0.0], 1.0, 2.0);
        assert!((t - 2.0).abs() < 1e-15);
    }

    #[test]
    fn receding_and_missing_pairs_never_collide() {
        assert_eq!(
            pair_time(&vector![3.0, 0.0], &vector![1.0, 0.0], 1.0, 2.0),
            f64::INFINITY
        );
        assert_eq!(
            pair_time(&vector![3.0, 2.0], &vector![-1.0, 0.0], 1.0, 2.0),
            f64::INFINITY
        );
    }

    #[test]
    fn overlap_while_approaching_collides_now() {
        assert_eq!(
            pair_time(
                &vector![0.999_999_999, 0.0, 0.0],
                &vector![-1.0, 0.0, 0.0],
                1.0,
                2.0
            ),
            0.0
        );
        // Overlapping but separating: no event.
        assert_eq!(
            pair_time(&vector![0.99, 0.0], &vector![1.0, 0.0], 1.0, 2.0),
            f64::INFINITY
        );
    }

    #[test]
    fn grazing_root_is_accurate() {
        // Near-tangent approach: the naive (−b − √disc)/v² loses digits here, the stable form does not.
        let (y, v): (f64, f64) = (1.0 - 1e-9, 1e-3);
        let t = pair_time(&vector![1e3, y], &vector![-v, 0.0], 1.0, 2.0);
        let exact = (1e3 - (1.0 - y * y).sqrt()) / v;
        assert!(((t - exact) / exact).abs() < 1e-12, "{t} vs {exact}");
    }

    #[test]
    fn round_off_approach_in_contact_is_no_approach() {
        // In contact, moving together: the approach speed 1e-20 is far below round-off.
        let (dr, dv) = (vector![1.0, 0.0], vector![-1e-20, 1.0]);
        assert_eq!(pair_time(&dr, &dv, 1.0, 2.0), f64::INFINITY);
        assert_eq!(pair_time(&dr, &vector![-1e-6, 1.0], 1.0, 2.0), 0.0);
    }

    #[test]
    fn ballistic_times() {
        // Dropped from 5 onto 0 with g = 2: t = √5.
        assert!((fall_time(5.0, 0.0, 2.0, 0.0) - 5f64.sqrt()).abs() < 1e-15);
        // Thrown up at 2 with g = 2: reaches 0.75 at t = 0.5, never reaches 1.1 (apex 1).
        assert!((rise_time(0.0, 2.0, 2.0, 0.75) - 0.5).abs() < 1e-15);
        assert_eq!(rise_time(0.0, 2.0, 2.0, 1.1), f64::INFINITY);
        // Thrown up at 2 from 1, falls back to 0 at t = 1 + √2.
        assert!((fall_time(1.0, 2.0, 2.0, 0.0) - (1.0 + 2f64.sqrt())).abs() < 1e-14);
        // Just bounced off the floor (at or a hair below the contact height): back after 2u/g.
        assert!((fall_time(0.5, 1.0, 2.0, 0.5) - 1.0).abs() < 1e-15);
        assert!((fall_time(0.5 - 1e-16, 1.0, 2.0, 0.5) - 1.0).abs() < 1e-15);
        assert_eq!(fall_time(0.5 - 1e-16, -1.0, 2.0, 0.5), 0.0);
        // Without gravity they reduce to straight lines.
        assert_eq!(fall_time(3.0, -2.0, 0.0, 1.0), 1.0);
        assert_eq!(rise_time(1.0, 2.0, 0.0, 3.0), 1.0);
        assert_eq!(fall_time(3.0, 2.0, 0.0, 1.0), f64::INFINITY);
    }

    #[test]
    fn reach_time_is_never_negative() {
        assert_eq!(reach_time(1.0 + 1e-16, 1.0, 1.0), 0.0);
        assert_eq!(reach_time(0.5, 0.0, 1.0), f64::INFINITY);
        assert_eq!(reach_time(1.5, 0.0, 1.0), f64::INFINITY);
        assert_eq!(reach_time(0.5, -2.0, 0.0), 0.25);
    }
}
