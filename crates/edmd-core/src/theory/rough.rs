//! Two-temperature cooling of rough grains (Huthmann & Zippelius 1997; Luding, Huthmann, McNamara &
//! Zippelius 1998), derived for any dimension in PHYSICS.md §6.6: with Maxwellian velocities and
//! spins at temperatures T (translational, Σ m v²/(d N)) and R (rotational, Σ I ω²/(d_rot N)), the
//! mean energy changes per collision are linear in T and R, so per τ = C/N the temperatures obey the
//! linear system
//!
//! ```text
//! dT/dτ = −(2/d)     [ (1 − ε²) T + 2(d−1) (η(1−η) T − (η²/q) R) ]
//! dR/dτ =  (2/d_rot) 2(d−1) [ (η²/q) T − (η/q)(1 − η/q) R ],      η = q(1 + β) / (2(1 + q))
//! ```
//!
//! solved here exactly (the matrix exponential of a 2 × 2 system). The Maxwellian closure puts R/T
//! 2.4–5.3 % too high at ε = 0.9; [`super::RoughSonine`] adds the first Sonine correction (§6.7).

/// The two-temperature theory of a gas of equal rough grains: ε, β and the inertia factor q
/// (I = q m R²) in dimension `d` (2 or 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughCooling {
    d: usize,
    eps: f64,
    beta: f64,
    q: f64,
    /// N/(N − 1) of a gas of N grains with zero total momentum (1 for N → ∞): pairs meet with
    /// ⟨g²⟩ = 2⟨v²⟩·N/(N − 1), so every translational term is larger by this factor.
    momentum_factor: f64,
}

impl RoughCooling {
    /// The theory for ε, β ∈ [−1, 1] and inertia factor `q` in `d` dimensions (N → ∞).
    pub fn new(d: usize, eps: f64, beta: f64, q: f64) -> Self {
        RoughCooling {
            d,
            eps,
            beta,
            q,
            momentum_factor: 1.0,
        }
    }

    /// The same theory for exactly `n` grains whose total momentum is zero.
    pub fn with_particles(self, n: usize) -> Self {
        RoughCooling {
            momentum_factor: n as f64 / (n as f64 - 1.0),
            ..self
        }
    }

    /// Rotational degrees of freedom per grain: 1 for disks, 3 for spheres.
    pub fn rotational_dof(&self) -> f64 {
        if self.d == 2 {
            1.0
        } else {
            3.0
        }
    }

    /// η = q(1 + β)/(2(1 + q)): the tangential impulse is −m η g_t per unit mass (equal grains).
    pub fn eta(&self) -> f64 {
        self.q * (1.0 + self.beta) / (2.0 * (1.0 + self.q))
    }

    /// The matrix M of d(T, R)/dτ = M (T, R).
    pub fn matrix(&self) -> [[f64; 2]; 2] {
        let (d, q, eta) = (self.d as f64, self.q, self.eta());
        let k = 2.0 * (d - 1.0);
        let f = self.momentum_factor;
        // η/q and 1 − η/q = ((1 − β) + 2q)/(2(1 + q)) written without differences of near-equal
        // numbers, which lose every digit of q when q is small (and with them R/T).
        let eta_q = (1.0 + self.beta) / (2.0 * (1.0 + q));
        let rest_q = ((1.0 - self.beta) + 2.0 * q) / (2.0 * (1.0 + q));
        let a = (1.0 - self.eps) * (1.0 + self.eps) + k * eta * (1.0 - eta);
        let b = k * eta * eta_q;
        let c = k * eta_q * rest_q;
        let dr = self.rotational_dof();
        [
            [-2.0 / d * a * f, 2.0 / d * b],
            [2.0 / dr * b * f, -2.0 / dr * c],
        ]
    }

    /// The eigenvalues of [`Self::matrix`], slower decay first (both real: the off-diagonal terms
    /// have one sign).
    fn eigenvalues(&self) -> (f64, f64) {
        let m = self.matrix();
        let s = 0.5 * (m[0][0] + m[1][1]);
        let w = (0.25 * (m[0][0] - m[1][1]).powi(2) + m[0][1] * m[1][0]).sqrt();
        (s + w, s - w)
    }

    /// The homogeneous cooling state's ratio R/T, reached after a transient of a few τ from any start
    /// (the eigenvector of the slower mode); 0 for smooth grains (β = −1).
    pub fn stationary_ratio(&self) -> f64 {
        let m = self.matrix();
        if m[1][0] == 0.0 {
            return 0.0;
        }
        // The slower eigenvector: m10 T + (m11 − λ) R = 0 with λ = s + w, s the mean of the diagonal,
        // δ = (m00 − m11)/2 and w = √(δ² + m01 m10). λ − m11 = δ + w, which cancels when δ < 0 (small
        // inertia: the rotational mode relaxes much faster); there it is m01 m10/(w − δ), so that
        // R/T = (w − δ)/m01 with no difference of near-equal numbers.
        // The ratio is that of the matrix scaled to unit size: no product underflows at tiny q.
        let scale = m.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
        let [[m00, m01], [m10, m11]] = m.map(|row| row.map(|x| x / scale));
        let delta = 0.5 * (m00 - m11);
        let w = (delta * delta + m01 * m10).sqrt();
        if delta >= 0.0 {
            m10 / (delta + w)
        } else {
            (w - delta) / m01
        }
    }

    /// The asymptotic cooling rate −d ln T/dτ of both temperatures in that state.
    /// For smooth grains (β = −1) it is the rate of T alone (spins keep their values).
    pub fn cooling_rate(&self) -> f64 {
        let m = self.matrix();
        if m[1][0] == 0.0 {
            return -m[0][0];
        }
        -self.eigenvalues().0
    }

    /// (T, R) at τ from (T₀, R₀) at τ = 0: exp(Mτ) = e^{sτ} [cosh(wτ) 1 + sinh(wτ)/w (M − s 1)].
    pub fn temperatures(&self, t0: f64, r0: f64, tau: f64) -> (f64, f64) {
        let m = self.matrix();
        let s = 0.5 * (m[0][0] + m[1][1]);
        let w = (0.25 * (m[0][0] - m[1][1]).powi(2) + m[0][1] * m[1][0]).sqrt();
        // e^{sτ}cosh(wτ) and e^{sτ}sinh(wτ)/w from e^{(s±w)τ}: the factors e^{sτ} and cosh(wτ)
        // apart under- and overflow (0 · ∞) long before their product does.
        let (fast, slow) = (((s - w) * tau).exp(), ((s + w) * tau).exp());
        let ch = 0.5 * (slow + fast);
        let sh = if w * tau == 0.0 {
            tau * (s * tau).exp()
        } else {
            0.5 * (slow - fast) / w
        };
        let t = ch * t0 + sh * ((m[0][0] - s) * t0 + m[0][1] * r0);
        let r = ch * r0 + sh * (m[1][0] * t0 + (m[1][1] - s) * r0);
        (t, r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// At ε = β = 1 the ratio is exactly the equipartition value of N grains, N/(N − 1) (spins
    /// carry no momentum constraint), for every inertia factor down to the smallest representable
    /// ones; finite and positive everywhere else.
    #[test]
    fn stationary_ratio_is_stable_at_small_inertia() {
        for d in [2, 3] {
            for q in [1.0, 0.4, 1e-2, 1e-4, 1e-6, 1e-9, 1e-12, 1e-300] {
                let r = RoughCooling::new(d, 1.0, 1.0, q)
                    .with_particles(64)
                    .stationary_ratio();
                assert!((r / (64.0 / 63.0) - 1.0).abs() < 1e-9, "d {d} q {q}: {r}");
                for (eps, beta) in [(0.5, 1.0), (0.9, 0.0), (0.1, -0.9)] {
                    let r = RoughCooling::new(d, eps, beta, q).stationary_ratio();
                    assert!(
                        r.is_finite() && r > 0.0,
                        "d {d} q {q} eps {eps} beta {beta}: {r}"
                    );
                }
            }
        }
    }

    /// ε = β = 1 conserves d T + d_rot R: the ratio is 1 (equipartition) and nothing cools.
    #[test]
    fn elastic_perfectly_rough_grains_equipartition() {
        for (d, q) in [(2, 0.5), (3, 0.4), (2, 0.25)] {
            let th = RoughCooling::new(d, 1.0, 1.0, q);
            assert!((th.stationary_ratio() - 1.0).abs() < 1e-12, "d {d} q {q}");
            assert!(th.cooling_rate().abs() < 1e-12);
            let (t, r) = th.temperatures(1.0, 0.0, 30.0);
            let e = d as f64 * t + th.rotational_dof() * r;
            assert!((e - d as f64).abs() < 1e-12, "energy {e}");
            assert!((r / t - 1.0).abs() < 1e-6, "relaxed by τ = 30: {}", r / t);
        }
    }

    /// 3D reduces to Huthmann & Zippelius's closed form R/T = X + √(X² + 1), X = (A − C)/(2B), with
    /// A = (1 − ε²)/4 + η(1 − η), B = η²/q, C = (η/q)(1 − η/q).
    #[test]
    fn three_dimensions_match_the_closed_form() {
        for (eps, beta) in [(0.9, 0.0), (0.7, -0.5), (0.95, 0.6), (0.5, 1.0)] {
            let q = 0.4;
            let th = RoughCooling::new(3, eps, beta, q);
            let eta = th.eta();
            let a = (1.0 - eps * eps) / 4.0 + eta * (1.0 - eta);
            let b = eta * eta / q;
            let c = eta / q * (1.0 - eta / q);
            let x = (a - c) / (2.0 * b);
            let closed = x + (x * x + 1.0).sqrt();
            assert!((th.stationary_ratio() / closed - 1.0).abs() < 1e-12);
        }
    }

    /// Smooth grains: spins are untouched and T follows the Maxwellian Haff rate (2/d)(1 − ε²).
    #[test]
    fn smooth_grains_cool_by_haff() {
        let th = RoughCooling::new(2, 0.8, -1.0, 0.5);
        assert_eq!(th.stationary_ratio(), 0.0);
        assert!((th.cooling_rate() - (1.0 - 0.64)).abs() < 1e-12);
        let (t, r) = th.temperatures(1.0, 0.3, 10.0);
        assert!((t - (-(1.0 - 0.64) * 10.0f64).exp()).abs() < 1e-12);
        assert!((r - 0.3).abs() < 1e-12);
    }

    /// The exact solution obeys the differential system (central difference) and relaxes to the
    /// stationary ratio.
    #[test]
    fn solution_solves_the_system() {
        let th = RoughCooling::new(2, 0.9, 0.0, 0.5).with_particles(100);
        let m = th.matrix();
        let h = 1e-5;
        for tau in [0.5, 3.0, 20.0] {
            let (t, r) = th.temperatures(1.0, 0.0, tau);
            let (tp, rp) = th.temperatures(1.0, 0.0, tau + h);
            let (tm, rm) = th.temperatures(1.0, 0.0, tau - h);
            let dt = (tp - tm) / (2.0 * h);
            let dr = (rp - rm) / (2.0 * h);
            assert!((dt - (m[0][0] * t + m[0][1] * r)).abs() < 1e-7 * t.abs().max(1e-3));
            assert!((dr - (m[1][0] * t + m[1][1] * r)).abs() < 1e-7 * t.abs().max(1e-3));
        }
        let (t, r) = th.temperatures(1.0, 0.0, 60.0);
        assert!((r / t / th.stationary_ratio() - 1.0).abs() < 1e-9);
    }
}
