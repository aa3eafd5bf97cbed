//! Rules that keep inelastic collapse away: the TC model and random rotation (PHYSICS.md §6.4).

use super::{check_positive, CollisionRule};
use crate::EdmdError;

/// The TC model (Luding & McNamara, Granular Matter 1, 113 (1998)): a collision is dissipative
/// only if both partners' previous collisions happened more than `t_c` ago; otherwise it is elastic.
/// `t_c` stands for the duration of a real contact and must be ≪ the mean free time. Composes with
/// any rule; its state is each particle's last collision time (physical time).
#[derive(Debug, Clone, Copy)]
pub struct TcModel<R> {
    inner: R,
    tc: f64,
}

impl<R: CollisionRule> TcModel<R> {
    /// `inner` applied only when both partners have been free for at least `tc` (> 0).
    pub fn new(inner: R, tc: f64) -> Result<Self, EdmdError> {
        Ok(TcModel {
            inner,
            tc: check_positive("t_c", tc)?,
        })
    }

    /// The contact duration t_c.
    pub fn tc(&self) -> f64 {
        self.tc
    }
}

/// Last collision time of a particle under the TC model (−∞ before the first).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LastCollision(pub f64);

impl Default for LastCollision {
    fn default() -> Self {
        LastCollision(f64::NEG_INFINITY)
    }
}

impl<R: CollisionRule<State = ()>> CollisionRule for TcModel<R> {
    type State = LastCollision;
    const ROTATES: bool = R::ROTATES;

    #[inline(always)]
    fn rotation_angle(&self, rng: &mut rand_xoshiro::Xoshiro256PlusPlus) -> f64 {
        self.inner.rotation_angle(rng)
    }

    #[inline(always)]
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64 {
        self.inner.restitution(vn, m_eff, r_eff)
    }

    #[inline]
    fn restitution_at(
        &self,
        vn: f64,
        m_eff: f64,
        r_eff: f64,
        t: f64,
        si: &mut LastCollision,
        sj: &mut LastCollision,
    ) -> f64 {
        let fresh = t - si.0 >= self.tc && t - sj.0 >= self.tc;
        si.0 = t;
        sj.0 = t;
        if fresh {
            self.inner.restitution(vn, m_eff, r_eff)
        } else {
            1.0
        }
    }
}

/// Random rotation remedy (the thesis's): after the collision law, the relative velocity of the pair is
/// rotated in the centre-of-mass frame by an angle uniform in [0, θ_max] about a random axis, so that
/// momentum and energy are exactly those of the law (rotating the two lab-frame velocities separately
/// would not conserve momentum). A rotation that would turn the pair towards each other again is
/// taken the other way. Composes with any rule; with [`ThresholdRestitution`] it is the thesis's
/// combination.
#[derive(Debug, Clone, Copy)]
pub struct RandomRotation<R> {
    inner: R,
    theta_max: f64,
}

impl<R: CollisionRule> RandomRotation<R> {
    /// `inner` followed by a rotation by up to `theta_max` radians (in [0, π/2]).
    pub fn new(inner: R, theta_max: f64) -> Result<Self, EdmdError> {
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&theta_max) {
            return Err(EdmdError::invalid(
                "theta_max",
                theta_max,
                "rotation angle must lie in [0, π/2] radians",
            ));
        }
        Ok(RandomRotation { inner, theta_max })
    }
}

impl<R: CollisionRule> CollisionRule for RandomRotation<R> {
    type State = R::State;
    const ROTATES: bool = true;

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
        si: &mut R::State,
        sj: &mut R::State,
    ) -> f64 {
        self.inner.restitution_at(vn, m_eff, r_eff, t, si, sj)
    }

    #[inline]
    fn rotation_angle(&self, rng: &mut rand_xoshiro::Xoshiro256PlusPlus) -> f64 {
        use rand::Rng;
        self.theta_max * rng.random::<f64>()
    }
}
