//! The steady uniform shear flow of the Enskog gas of inelastic smooth hard disks or spheres,
//! closed with an anisotropic Maxwellian (PHYSICS.md §7.2).
//!
//! The velocity distribution is taken to be the Gaussian whose second moment is the kinetic
//! pressure tensor, f ∝ exp(−m V·Θ⁻¹·V/2) with P^k = nΘ (Jenkins & Richman 1988 for disks; the
//! "generalized Grad" closure of Lutsko 2004). Unlike Grad's linear closure ([`super::ShearFlow`])
//! it keeps every order in the anisotropy, so the cooling grows with it and P_zz differs from
//! P_yy. The Enskog collision operator is evaluated exactly for that distribution: the partner
//! sits one diameter away along n, so its velocity carries the stream difference a σ n_y e_x.
//! For each direction n the normal relative speed u = g·n is Gaussian with mean
//! μ = −a σ n_x n_y and variance s = 2 n·Θ·n/m, and the collisional moments reduce to integrals
//! over the unit sphere of its truncated moments M_k = ⟨u^k Θ(u)⟩:
//!
//! ```text
//! Λ_ij  = m χ n² σ^{d−1} ∮ dn [ −e (n_i b_j + b_i n_j) (M3 − μ M2)/s + e² n_i n_j M3 ],
//!         b = Θ n/m,  e = (1 + α)/2
//! P^c_ij = (1 + α) m χ n² σ^d / 4 ∮ dn n_i n_j M2
//! ```
//!
//! The steady state solves a (δ_ix P^k_yj + δ_jx P^k_yi) = Λ_ij at T = 1; every other temperature
//! follows by scaling (a ∝ √T, P ∝ T). Units σ = m = 1.

use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};

use super::{chi, ShearFlow};

/// The sheared Enskog gas at restitution α and packing fraction φ in `d` dimensions.
#[derive(Debug, Clone, PartialEq)]
pub struct EnskogShear {
    d: usize,
    alpha: f64,
    phi: f64,
    chi: f64,
    density: f64,
    /// Quadrature of the unit sphere: directions and weights (summing to its area).
    nodes: Vec<([f64; 3], f64)>,
}

/// The steady uniform shear flow at unit temperature (σ = m = 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearSteadyState {
    /// Dimension.
    pub d: usize,
    /// Number density n.
    pub density: f64,
    /// The shear rate a that sustains T = 1; at rate a' the steady temperature is (a'/a)².
    pub shear_rate: f64,
    /// The kinetic pressure tensor over nT (zeros beyond `d`).
    pub kinetic: [[f64; 3]; 3],
    /// The collisional (transfer) pressure tensor over nT.
    pub collisional: [[f64; 3]; 3],
}

impl ShearSteadyState {
    /// P*_ij = P_ij/(nT), kinetic plus collisional.
    pub fn pressure(&self, i: usize, j: usize) -> f64 {
        self.kinetic[i][j] + self.collisional[i][j]
    }

    /// a* = a/ν0 with the Boltzmann gas's ν0 = p/η0 at the same n and T (no χ: the density's
    /// effect on the rate is part of the result).
    pub fn reduced_shear_rate(&self) -> f64 {
        self.shear_rate / ShearFlow::nu0_per_sqrt_t(self.d, self.density, 1.0)
    }

    /// η* = η/η0 = −P*_xy/a*, with the Boltzmann gas's elastic viscosity η0.
    pub fn reduced_viscosity(&self) -> f64 {
        -self.pressure(0, 1) / self.reduced_shear_rate()
    }

    /// The steady temperature a shear rate `a` sustains: (a/a_{T=1})².
    pub fn steady_temperature(&self, a: f64) -> f64 {
        (a / self.shear_rate).powi(2)
    }
}

/// ⟨u² Θ(u)⟩ and ⟨u³ Θ(u)⟩ of a Gaussian u of mean `mu` and variance `s`.
fn truncated_moments(mu: f64, s: f64) -> (f64, f64) {
    let r = s.sqrt();
    let z = mu / r;
    let cdf = 0.5 * libm::erfc(-z / std::f64::consts::SQRT_2);
    let pdf = (-0.5 * z * z).exp() / (2.0 * PI).sqrt();
    let m2 = (mu * mu + s) * cdf + mu * r * pdf;
    let m3 = (mu * mu * mu + 3.0 * mu * s) * cdf + (mu * mu + 2.0 * s) * r * pdf;
    (m2, m3)
}

/// Gauss–Legendre nodes and weights on [−1, 1] (Newton on the Legendre recurrence).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    (0..n)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            loop {
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let k = k as f64;
                    (p0, p1) = (p1, ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k);
                }
                let dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    return (x, 2.0 / ((1.0 - x * x) * dp * dp));
                }
            }
        })
        .collect()
}

/// Directions and weights covering the unit circle (d = 2: `m` equal angles) or sphere (d = 3:
/// `m`/2 Gauss–Legendre polar nodes times `m` equal azimuths). The integrands are smooth and
/// periodic, so both converge geometrically.
fn sphere_nodes(d: usize, m: usize) -> Vec<([f64; 3], f64)> {
    let w = 2.0 * PI / m as f64;
    let angle = |k: usize| 2.0 * PI * k as f64 / m as f64;
    if d == 2 {
        return (0..m)
            .map(|k| ([angle(k).cos(), angle(k).sin(), 0.0], w))
            .collect();
    }
    let mut nodes = Vec::with_capacity(m * m / 2);
    for (c, wc) in gauss_legendre(m / 2) {
        let s = (1.0 - c * c).sqrt();
        for k in 0..m {
            nodes.push(([s * angle(k).cos(), s * angle(k).sin(), c], wc * w));
        }
    }
    nodes
}

impl EnskogShear {
    /// The gas of disks (`d` = 2) or spheres (`d` = 3) at restitution `alpha` ∈ [0, 1] and packing
    /// fraction `phi`, with the reference χ(φ) of [`super::chi`].
    pub fn new(d: usize, alpha: f64, phi: f64) -> Self {
        Self::with_nodes(d, alpha, phi, 64)
    }

    fn with_nodes(d: usize, alpha: f64, phi: f64, m: usize) -> Self {
        assert!(d == 2 || d == 3, "dimension {d}");
        let unit = if d == 2 { PI / 4.0 } else { PI / 6.0 };
        EnskogShear {
            d,
            alpha,
            phi,
            chi: chi(d, phi),
            density: phi / unit,
            nodes: sphere_nodes(d, m),
        }
    }

    /// The collisional moment Λ of m V V and the collisional pressure tensor P^c of a gas whose
    /// velocities are Gaussian with covariance `theta` (= P^k/n), sheared at rate `a`.
    pub fn collisional_moments(
        &self,
        theta: &[[f64; 3]; 3],
        a: f64,
    ) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
        let (d, e) = (self.d, 0.5 * (1.0 + self.alpha));
        let (mut lambda, mut transfer) = ([[0.0; 3]; 3], [[0.0; 3]; 3]);
        for (n, w) in &self.nodes {
            let mut b = [0.0; 3];
            for i in 0..d {
                for j in 0..d {
                    b[i] += theta[i][j] * n[j];
                }
            }
            let s = 2.0 * (0..d).map(|i| n[i] * b[i]).sum::<f64>();
            let mu = -a * n[0] * n[1];
            let (m2, m3) = truncated_moments(mu, s);
            let cross = e * (m3 - mu * m2) / s;
            for i in 0..d {
                for j in 0..d {
                    lambda[i][j] +=
                        w * (e * e * n[i] * n[j] * m3 - cross * (n[i] * b[j] + b[i] * n[j]));
                    transfer[i][j] += w * n[i] * n[j] * m2;
                }
            }
        }
        let scale = self.chi * self.density * self.density;
        for i in 0..d {
            for j in 0..d {
                lambda[i][j] *= scale;
                transfer[i][j] *= scale * 0.5 * e;
            }
        }
        (lambda, transfer)
    }

    /// The kinetic tensor Θ at T = 1 from the unknowns [Θ_xx, (Θ_yy in 3D), Θ_xy].
    fn theta(&self, x: &[f64]) -> [[f64; 3]; 3] {
        let mut t = [[0.0; 3]; 3];
        t[0][0] = x[0];
        if self.d == 2 {
            t[1][1] = 2.0 - x[0];
        } else {
            t[1][1] = x[1];
            t[2][2] = 3.0 - x[0] - x[1];
        }
        t[0][1] = x[self.d - 1];
        t[1][0] = x[self.d - 1];
        t
    }

    /// The steady balance's residual (Λ − shear term)/n² in xx, yy, (zz), xy for the unknowns
    /// x = [Θ_xx, (Θ_yy), Θ_xy, a].
    fn residual(&self, x: &[f64]) -> DVector<f64> {
        let (theta, a) = (self.theta(x), x[self.d]);
        let (lambda, _) = self.collisional_moments(&theta, a);
        let n = self.density;
        let r = |i: usize, j: usize| {
            let shear = a
                * n
                * (if i == 0 { theta[1][j] } else { 0.0 } + if j == 0 { theta[1][i] } else { 0.0 });
            (lambda[i][j] - shear) / (n * n)
        };
        let mut out = vec![r(0, 0), r(1, 1)];
        if self.d == 3 {
            out.push(r(2, 2));
        }
        out.push(r(0, 1));
        DVector::from_vec(out)
    }

    /// The steady state, by Newton's method from Grad's linear solution (3–6 steps); `None` for
    /// elastic grains (no steady state) or if Newton does not converge.
    pub fn solve(&self) -> Option<ShearSteadyState> {
        if self.alpha >= 1.0 {
            return None;
        }
        let d = self.d;
        let grad = ShearFlow::new(d, self.alpha);
        let rate = grad.reduced_shear_rate() * ShearFlow::nu0_per_sqrt_t(d, self.density, self.chi);
        let mut x = vec![grad.pxx()];
        if d == 3 {
            x.push(grad.pyy());
        }
        x.extend([grad.pxy(), rate]);
        for _ in 0..50 {
            let r0 = self.residual(&x);
            let mut jac = DMatrix::zeros(x.len(), x.len());
            for k in 0..x.len() {
                let mut xp = x.clone();
                let h = 1e-7 * x[k].abs().max(1e-3);
                xp[k] += h;
                jac.set_column(k, &((self.residual(&xp) - &r0) / h));
            }
            let dx = jac.lu().solve(&(-r0))?;
            for (xi, di) in x.iter_mut().zip(dx.iter()) {
                *xi += di;
            }
            if !x.iter().all(|v| v.is_finite()) {
                return None;
            }
            if dx.amax() < 1e-12 {
                let theta = self.theta(&x);
                let (_, transfer) = self.collisional_moments(&theta, x[d]);
                let mut collisional = [[0.0; 3]; 3];
                for i in 0..d {
                    for j in 0..d {
                        collisional[i][j] = transfer[i][j] / self.density;
                    }
                }
                return Some(ShearSteadyState {
                    d,
                    density: self.density,
                    shear_rate: x[d],
                    kinetic: theta,
                    collisional,
                });
            }
        }
        None
    }

    /// Packing fraction φ.
    pub fn phi(&self) -> f64 {
        self.phi
    }
}

#[cfg(test)]
mod tests;
