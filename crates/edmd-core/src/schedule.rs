//! The sampling schedule: the points in τ at which a run observes its state.

/// Points in τ at which to sample: a linear grid, a logarithmic grid, and explicit points, merged.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Schedule {
    /// Sample every `linear` in τ, starting at 0 (none if `None`).
    pub linear: Option<f64>,
    /// Samples per decade of τ on a logarithmic grid (none if `None`).
    pub log_per_decade: Option<u32>,
    /// First τ of the logarithmic grid (default 0.1 when 0).
    pub log_start: f64,
    /// Explicit points.
    pub points: Vec<f64>,
}

impl Schedule {
    /// Every `every` in τ.
    pub fn every(every: f64) -> Self {
        Schedule {
            linear: Some(every),
            ..Default::default()
        }
    }

    /// Explicit points only.
    pub fn at(points: &[f64]) -> Self {
        Schedule {
            points: points.to_vec(),
            ..Default::default()
        }
    }

    fn contains(&self, tau: f64) -> bool {
        self.linear
            .is_some_and(|e| e > 0.0 && (tau / e).fract() == 0.0)
            || self.points.contains(&tau)
            || self
                .log_per_decade
                .is_some_and(|_| tau == self.log_start0())
    }

    fn log_start0(&self) -> f64 {
        if self.log_start > 0.0 {
            self.log_start
        } else {
            0.1
        }
    }

    /// The first point ≥ `tau`.
    pub fn first_at_or_after(&self, tau: f64) -> Option<f64> {
        if self.contains(tau) {
            Some(tau)
        } else {
            self.next_after(tau)
        }
    }

    /// The first point > `tau`.
    pub fn next_after(&self, tau: f64) -> Option<f64> {
        let mut best = f64::INFINITY;
        if let Some(e) = self.linear.filter(|&e| e > 0.0) {
            let mut k = (tau / e).floor() + 1.0;
            while k * e <= tau {
                k += 1.0;
            }
            best = best.min(k * e);
        }
        if let Some(per) = self.log_per_decade.filter(|&p| p > 0) {
            let start = self.log_start0();
            if tau < start {
                best = best.min(start);
            } else {
                let per = per as f64;
                let mut m = ((tau / start).log10() * per + 1e-9).floor() + 1.0;
                while start * 10f64.powf(m / per) <= tau {
                    m += 1.0;
                }
                best = best.min(start * 10f64.powf(m / per));
            }
        }
        for &p in &self.points {
            if p > tau && p < best {
                best = p;
            }
        }
        best.is_finite().then_some(best)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedule_merges_grids_and_never_repeats() {
        let s = Schedule {
            linear: Some(5.0),
            log_per_decade: Some(2),
            log_start: 1.0,
            points: vec![2.5],
        };
        let mut taus = vec![s.first_at_or_after(0.0).unwrap()];
        while let Some(t) = s.next_after(*taus.last().unwrap()) {
            if t > 20.0 {
                break;
            }
            taus.push(t);
        }
        let want = [0.0, 1.0, 2.5, 10f64.sqrt(), 5.0, 10.0, 15.0, 20.0];
        assert_eq!(taus.len(), want.len(), "{taus:?}");
        for (a, b) in taus.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{taus:?}");
        }
    }
}
