//! The steady uniform shear flow of a dilute gas of inelastic smooth hard disks or spheres
//! (PHYSICS.md §7.1): Grad's moment solution of the Boltzmann equation (Brey, Ruiz-Montero & Moreno
//! 1997; Montanero, Garzó, Santos & Brey 1999; Santos, Garzó & Dufty 2004).
//!
//! In the steady state the shear's heating, −a P_xy, balances the collisional cooling, (d/2) ζ n T.
//! With the collision frequency ν0 = p/η0 of the elastic Navier–Stokes viscosity η0, Grad's closure
//! of the pressure tensor's balance gives, in reduced units (a* = a/ν0, P* = P/(nT)):
//!
//! ```text
//! ζ* = (d + 2)(1 − α²)/(4d)                       reduced cooling rate
//! β  = (1 + α)(2d + 3 − 3α)/(4d)                  reduced relaxation rate of the anisotropy
//! P*_yy = P*_zz = 1 − ζ*/β,   P*_xx = 1 + (d − 1) ζ*/β
//! η* = −P*_xy/a* = (β − ζ*)/β²,   a*² = d ζ* β² / (2 (β − ζ*))
//! ```
//!
//! Elastic grains (α = 1) have no steady state (ζ* = 0, a* = 0): they heat up.

use std::f64::consts::PI;

/// The dilute steady uniform shear flow at restitution α in `d` dimensions (Grad's solution).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearFlow {
    /// Dimension.
    pub d: usize,
    /// Normal restitution α.
    pub alpha: f64,
}

impl ShearFlow {
    /// The dilute flow of disks (`d` = 2) or spheres (`d` = 3) at restitution `alpha` in [0, 1].
    pub fn new(d: usize, alpha: f64) -> Self {
        ShearFlow { d, alpha }
    }

    fn df(&self) -> f64 {
        self.d as f64
    }

    /// ζ* = ζ/ν0, the reduced cooling rate of the local-equilibrium estimate.
    pub fn zeta(&self) -> f64 {
        let d = self.df();
        (d + 2.0) * (1.0 - self.alpha * self.alpha) / (4.0 * d)
    }

    /// β, the reduced rate at which collisions relax the pressure tensor's anisotropy (1 elastic).
    pub fn beta(&self) -> f64 {
        let (d, a) = (self.df(), self.alpha);
        (1.0 + a) * (2.0 * d + 3.0 - 3.0 * a) / (4.0 * d)
    }

    /// The steady reduced shear rate a* = a/ν0.
    pub fn reduced_shear_rate(&self) -> f64 {
        let (z, b) = (self.zeta(), self.beta());
        (self.df() * z * b * b / (2.0 * (b - z))).sqrt()
    }

    /// The reduced viscosity η* = η/η0 = −P*_xy/a*.
    pub fn reduced_viscosity(&self) -> f64 {
        let (z, b) = (self.zeta(), self.beta());
        (b - z) / (b * b)
    }

    /// P*_xx = P_xx/(nT) along the flow.
    pub fn pxx(&self) -> f64 {
        1.0 + (self.df() - 1.0) * self.zeta() / self.beta()
    }

    /// P*_yy = P_yy/(nT) along the gradient (and P*_zz in 3D: Grad's closure makes them equal).
    pub fn pyy(&self) -> f64 {
        1.0 - self.zeta() / self.beta()
    }

    /// P*_xy = P_xy/(nT) = −a* η*.
    pub fn pxy(&self) -> f64 {
        -self.reduced_shear_rate() * self.reduced_viscosity()
    }

    /// ν0/√T at number density `n` (diameter σ = 1, mass m = 1), with the pair correlation `chi` at
    /// contact (1 for the Boltzmann gas; Enskog's χ to carry the collision rate of a denser gas):
    /// ν0 = p/η0 = 8 π^{(d−1)/2} χ n σ^{d−1} √(T/m) / ((d + 2) Γ(d/2)).
    pub fn nu0_per_sqrt_t(d: usize, n: f64, chi: f64) -> f64 {
        let gamma_half_d = if d == 2 { 1.0 } else { 0.5 * PI.sqrt() };
        8.0 * PI.powf((d as f64 - 1.0) / 2.0) * chi * n / ((d as f64 + 2.0) * gamma_half_d)
    }

    /// The steady temperature a shear rate `a` sustains at number density `n` (σ = m = 1):
    /// a = a* ν0(T), so √T = a / (a* ν0/√T).
    pub fn steady_temperature(&self, a: f64, n: f64, chi: f64) -> f64 {
        (a / (self.reduced_shear_rate() * Self::nu0_per_sqrt_t(self.d, n, chi))).powi(2)
    }
}

#[cfg(test)]
mod tests {
    use super::ShearFlow;

    /// The closed forms against their defining balances, and against values worked by hand.
    #[test]
    fn grad_solution_satisfies_its_balances() {
        for d in [2, 3] {
            for alpha in [0.5, 0.7, 0.9, 0.99] {
                let f = ShearFlow::new(d, alpha);
                let (a, b, z) = (f.reduced_shear_rate(), f.beta(), f.zeta());
                // Trace: P*_xx + (d − 1) P*_yy = d.
                assert!((f.pxx() + (d as f64 - 1.0) * f.pyy() - d as f64).abs() < 1e-14);
                // Energy: −2 a* P*_xy = d ζ*.
                assert!((-2.0 * a * f.pxy() - d as f64 * z).abs() < 1e-14);
                // xy: a* P*_yy = −β P*_xy; xx: 2 a* P*_xy = −β (P*_xx − 1) − ζ*.
                assert!((a * f.pyy() + b * f.pxy()).abs() < 1e-14);
                assert!((2.0 * a * f.pxy() + b * (f.pxx() - 1.0) + z).abs() < 1e-14);
            }
        }
        // By hand, 3D α = 0.9: ζ* = 5·0.19/12 = 0.0791667, β = 1.9·2.1/4 = 0.9975.
        let f = ShearFlow::new(3, 0.9);
        assert!((f.zeta() - 0.95 / 12.0).abs() < 1e-15);
        assert!((f.beta() - 0.9975).abs() < 1e-15);
        // The table of PHYSICS.md §7.1.
        for (d, alpha, a, eta, pxx, pyy) in [
            (2, 0.9, 0.3271, 0.8881, 1.0930, 0.9070),
            (2, 0.7, 0.5930, 0.7252, 1.2449, 0.7551),
            (3, 0.9, 0.3587, 0.9229, 1.1587, 0.9206),
            (3, 0.7, 0.6310, 0.8006, 1.4348, 0.7826),
        ] {
            let f = ShearFlow::new(d, alpha);
            for (got, want) in [
                (f.reduced_shear_rate(), a),
                (f.reduced_viscosity(), eta),
                (f.pxx(), pxx),
                (f.pyy(), pyy),
            ] {
                assert!(
                    (got - want).abs() < 6e-5,
                    "d {d}, alpha {alpha}: {got} against {want}"
                );
            }
        }
        // Elastic limit: β = 1, no cooling, no steady shear.
        let e = ShearFlow::new(2, 1.0);
        assert_eq!(
            (e.beta(), e.zeta(), e.reduced_shear_rate()),
            (1.0, 0.0, 0.0)
        );
        // ν0 of 3D: p/η0 with η0 = (5/16) √(mT/π)/σ²: ν0/√T = 16 √π n/5.
        let n = 0.3;
        let nu = ShearFlow::nu0_per_sqrt_t(3, n, 1.0);
        assert!((nu - 16.0 * std::f64::consts::PI.sqrt() * n / 5.0).abs() < 1e-14);
        // 2D: η0 = (1/(2σ)) √(mT/π), so ν0/√T = 2 √π n.
        let nu = ShearFlow::nu0_per_sqrt_t(2, n, 1.0);
        assert!((nu - 2.0 * std::f64::consts::PI.sqrt() * n).abs() < 1e-14);
    }
}
