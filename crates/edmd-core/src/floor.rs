//! A floor that vibrates, z_w(t) = A sin(ωt + φ₀), under gravity (PHYSICS.md §8.2): the first
//! contact of a grain's parabolic flight with it, found exactly.
//!
//! The gap between the grain's lowest point and the floor, h(t) = z₀ + v₀t − gt²/2 − R − A sin(ωt + φ₀),
//! has h'' = −g + Aω² sin(ωt + φ₀) in [−g − Aω², −g + Aω²]. A contact can only happen while the
//! flight's lowest point is inside the floor's band [−A, A]: between the time it comes down to A
//! and the time it would pass −A (both roots of a quadratic). That window is cut at the inflection
//! times (sin(ωt + φ₀) = g/(Aω²)) into pieces on which h is concave or convex. On a concave piece
//! that starts at h ≥ 0 a root exists exactly when h < 0 at its end; on a convex piece, exactly
//! when h < 0 at its minimum (where h' = 0, h' being monotone there). The first piece with a root
//! brackets the first contact, which a safeguarded Newton iteration then refines to round-off. So
//! no grazing contact is missed and no grain passes through the floor, whatever Aω against the
//! grain's speed.

use std::f64::consts::PI;

/// A vibrating floor: amplitude A, angular frequency ω and phase φ₀ at local time 0 (kept reduced
/// to [0, 2π) by its owner, so that long runs lose no precision in sin(ωt + φ₀)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// Amplitude A ≥ 0.
    pub amplitude: f64,
    /// Angular frequency ω > 0.
    pub omega: f64,
    /// Phase φ₀ at local time 0.
    pub phase: f64,
}

/// A grain's vertical flight: the height z₀ of its lowest point (centre minus radius) and its
/// vertical speed v₀ at local time 0, under gravity g ≥ 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flight {
    /// Height of the grain's lowest point at time 0.
    pub z0: f64,
    /// Vertical speed at time 0.
    pub v0: f64,
    /// Gravity g ≥ 0.
    pub g: f64,
}

impl Floor {
    /// The floor's height at time t.
    pub fn height(&self, t: f64) -> f64 {
        self.amplitude * (self.omega * t + self.phase).sin()
    }

    /// The floor's speed at time t.
    pub fn speed(&self, t: f64) -> f64 {
        self.amplitude * self.omega * (self.omega * t + self.phase).cos()
    }
}

impl Flight {
    /// The lowest point's height at time t.
    pub fn height(&self, t: f64) -> f64 {
        self.z0 + t * (self.v0 - 0.5 * self.g * t)
    }

    /// The gap h(t) and its slope h'(t), from one evaluation of the floor's phase (`sin_cos`: the
    /// root search's Newton steps need both, and the transcendental functions are its cost).
    fn gap_and_slope(&self, floor: &Floor, t: f64) -> (f64, f64) {
        let (sin, cos) = (floor.omega * t + floor.phase).sin_cos();
        (
            self.height(t) - floor.amplitude * sin,
            self.v0 - self.g * t - floor.amplitude * floor.omega * cos,
        )
    }

    /// The first time t in (0, horizon] at which the flight meets the floor from above, or None.
    /// The grain must start on or above the floor (h(0) ≥ 0).
    pub fn first_contact(&self, floor: &Floor, horizon: f64) -> Option<f64> {
        let gap = |t: f64| self.height(t) - floor.height(t);
        let (start, end) = self.band_window(floor.amplitude, horizon)?;
        // The pieces between consecutive cuts (start, the inflections, end), in order; no
        // allocation, as this runs at every flight that can reach the floor.
        let mut a = start;
        let cuts = Inflections::new(floor, self.g, start, end).chain(std::iter::once(end));
        for b in cuts {
            if b <= a {
                continue;
            }
            let mid = 0.5 * (a + b);
            let curvature = -self.g
                + floor.amplitude * floor.omega.powi(2) * (floor.omega * mid + floor.phase).sin();
            let low = if curvature < 0.0 {
                b // concave: the smallest value is at an end, and h(a) ≥ 0
            } else {
                self.lowest_on(floor, a, b)
            };
            if gap(low) < 0.0 {
                return Some(self.refine(floor, a, low));
            }
            a = b;
        }
        None
    }

    /// [start, end] ∩ (0, horizon]: the times at which the lowest point lies in [−A, A]; None if
    /// it never comes down to A in time.
    fn band_window(&self, amplitude: f64, horizon: f64) -> Option<(f64, f64)> {
        let start = if self.z0 <= amplitude {
            0.0
        } else {
            self.first_time_at(amplitude)?
        };
        let end = self
            .first_time_at(-amplitude)
            .unwrap_or(f64::INFINITY)
            .min(horizon);
        (start < end).then_some((start, end))
    }

    /// The first time t > 0 at which the height comes down to `level` (from above), or None.
    fn first_time_at(&self, level: f64) -> Option<f64> {
        let (a, b, c) = (-0.5 * self.g, self.v0, self.z0 - level);
        if a == 0.0 {
            return (b < 0.0).then(|| -c / b).filter(|&t| t >= 0.0);
        }
        // a t² + b t + c = 0 with a < 0: the larger root is where the parabola falls through.
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        let (r1, r2) = (q / a, if q != 0.0 { c / q } else { 0.0 });
        let t = r1.max(r2);
        (t >= 0.0).then_some(t)
    }

    /// On [a, b], where the gap is convex (h' increasing) and h(a) ≥ 0: a time at which it is
    /// below the floor, if there is one, else any time (where it is not). Bisects h' = 0 for the
    /// minimum, but stops as soon as a probe is below the floor or the two tangents at the
    /// bracket's ends, which bound a convex function from below, meet above it.
    fn lowest_on(&self, floor: &Floor, a: f64, b: f64) -> f64 {
        let (mut lo, mut hi) = (a, b);
        let (mut h_lo, mut s_lo) = self.gap_and_slope(floor, lo);
        if s_lo >= 0.0 {
            return a;
        }
        let (mut h_hi, mut s_hi) = self.gap_and_slope(floor, hi);
        if s_hi <= 0.0 || h_hi < 0.0 {
            return b;
        }
        for _ in 0..200 {
            // The tangents h_lo + s_lo (t − lo) and h_hi + s_hi (t − hi) meet at their lowest.
            let meet = (h_hi - h_lo + s_lo * lo - s_hi * hi) / (s_lo - s_hi);
            if h_lo + s_lo * (meet - lo) >= 0.0 {
                return hi; // no root: the gap there is ≥ 0
            }
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            let (h_mid, s_mid) = self.gap_and_slope(floor, mid);
            if h_mid < 0.0 {
                return mid;
            }
            if s_mid < 0.0 {
                (lo, h_lo, s_lo) = (mid, h_mid, s_mid);
            } else {
                (hi, h_hi, s_hi) = (mid, h_mid, s_mid);
            }
        }
        hi
    }

    /// The root in [lo, hi] with h(lo) ≥ 0 > h(hi): Newton steps kept inside the bracket, bisection
    /// where a step would leave it, to round-off.
    fn refine(&self, floor: &Floor, mut lo: f64, mut hi: f64) -> f64 {
        let mut t = hi;
        for _ in 0..200 {
            let (h, slope) = self.gap_and_slope(floor, t);
            if h < 0.0 {
                hi = t;
            } else {
                lo = t;
            }
            let newton = t - h / slope;
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if next <= lo || next >= hi || (hi - lo) <= 4.0 * f64::EPSILON * hi.abs() {
                break;
            }
            t = next;
        }
        // The last time on or above the floor (every `hi` is below it): the grain never ends
        // below the floor.
        lo
    }
}

/// The inflection times of the gap in (start, end), in order: sin(ωt + φ₀) = g/(Aω²) (none when
/// Γ = Aω²/g ≤ 1: the gap is concave throughout).
struct Inflections {
    /// The two phases s and π − s within a period, as times of period k = 0 (before `- phase/ω`).
    offsets: [f64; 2],
    omega: f64,
    phase: f64,
    /// The period and which of its two inflections comes next.
    k: f64,
    which: usize,
    start: f64,
    end: f64,
}

impl Inflections {
    fn new(floor: &Floor, g: f64, start: f64, end: f64) -> Self {
        let peak = floor.amplitude * floor.omega.powi(2);
        let w = floor.omega;
        let none = peak <= g || !end.is_finite();
        let s = if none { 0.0 } else { (g / peak).asin() };
        Inflections {
            offsets: [s, PI - s],
            omega: w,
            phase: floor.phase,
            // Every period from the one holding `start`.
            k: ((w * start + floor.phase - PI) / (2.0 * PI)).floor() - 1.0,
            which: 0,
            start,
            end: if none { f64::NEG_INFINITY } else { end },
        }
    }
}

impl Iterator for Inflections {
    type Item = f64;

    fn next(&mut self) -> Option<f64> {
        loop {
            let t = (2.0 * PI * self.k - self.phase + self.offsets[self.which]) / self.omega;
            if t >= self.end || self.end == f64::NEG_INFINITY {
                return None;
            }
            self.which ^= 1;
            if self.which == 0 {
                self.k += 1.0;
            }
            if t > self.start {
                return Some(t);
            }
        }
    }
}
