//! Rough particles: tangential restitution β and spin (PHYSICS.md §6.5).

use super::{check_positive, CollisionRule};
use crate::EdmdError;

/// Rough particles (the thesis's eq. 1.15; Walton's model with constant coefficients): at contact the
/// relative velocity of the touching surface points, `g_c = g − (R_i ω_i + R_j ω_j) × n`, has its
/// normal part reversed with ε (the inner rule) and its tangential part `g_t` with β ∈ [−1, 1]:
/// β = −1 is smooth (no spin exchange), β = 1 perfectly rough (energy-conserving when ε = 1). The
/// tangential impulse is `P_t = −(1 + β) μ_t g_t` with `1/μ_t = 1/m_i + 1/m_j + R_i²/I_i + R_j²/I_j`;
/// linear and angular momentum are conserved and the energy drops by
/// `(1 − ε²) μ g_n²/2 + (1 − β²) μ_t g_t²/2`. Moments of inertia are `I = q m R²` (q = 1/2 for
/// uniform disks, 2/5 for uniform spheres). Only rough scenes carry spin.
#[derive(Debug, Clone, Copy)]
pub struct Rough<R> {
    inner: R,
    beta: f64,
    q: f64,
}

impl<R: CollisionRule> Rough<R> {
    /// Rough particles with tangential restitution `beta` ∈ [−1, 1] and inertia factor `q` > 0.
    pub fn new(inner: R, beta: f64, q: f64) -> Result<Self, EdmdError> {
        if !(-1.0..=1.0).contains(&beta) {
            return Err(EdmdError::invalid(
                "beta",
                beta,
                "tangential restitution must lie in [-1, 1]",
            ));
        }
        Ok(Rough {
            inner,
            beta,
            q: check_positive("inertia_factor", q)?,
        })
    }

    /// Uniform disks (q = 1/2).
    pub fn disks(inner: R, beta: f64) -> Result<Self, EdmdError> {
        Self::new(inner, beta, 0.5)
    }

    /// Uniform spheres (q = 2/5).
    pub fn spheres(inner: R, beta: f64) -> Result<Self, EdmdError> {
        Self::new(inner, beta, 0.4)
    }
}

/// Angular velocity of a rough particle (only the z component is used in 2D).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Spin(pub [f64; 3]);

impl<R: CollisionRule> CollisionRule for Rough<R> {
    type State = (R::State, Spin);
    const ROTATES: bool = R::ROTATES;
    const ROUGH: bool = true;

    #[inline(always)]
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64 {
        self.inner.restitution(vn, m_eff, r_eff)
    }

    #[inline(always)]
    fn restitution_at(
        &self,
        vn: f64,
        m_eff: f64,
        r_eff: f64,
        t: f64,
        si: &mut Self::State,
        sj: &mut Self::State,
    ) -> f64 {
        self.inner
            .restitution_at(vn, m_eff, r_eff, t, &mut si.0, &mut sj.0)
    }

    #[inline(always)]
    fn roughness(&self) -> (f64, f64) {
        (self.beta, self.q)
    }

    #[inline(always)]
    fn spin(state: &Self::State) -> [f64; 3] {
        state.1 .0
    }

    #[inline(always)]
    fn set_spin(state: &mut Self::State, spin: [f64; 3]) {
        state.1 .0 = spin;
    }

    #[inline(always)]
    fn rotation_angle(&self, rng: &mut rand_xoshiro::Xoshiro256PlusPlus) -> f64 {
        self.inner.rotation_angle(rng)
    }
}
