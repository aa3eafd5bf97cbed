//! Collision rules: the restitution law applied at a pair contact.
//!
//! Rules are monomorphised into the event loop (no `dyn`). The impulse along the unit contact normal
//! `n` for masses `m_i`, `m_j` and normal relative velocity `g_n < 0` is
//! `J = −(1 + ε) μ g_n` with `μ = m_i m_j / (m_i + m_j)`; momentum is conserved exactly and the
//! kinetic energy drops by `(1 − ε²) μ g_n² / 2`.
//!
//! Laws (PHYSICS.md §6.2):
//! * [`Elastic`], [`ConstantRestitution`];
//! * [`ThresholdRestitution`]: ε below a normal speed δ differs (the velocity-threshold remedy);
//! * [`ThesisRestitution`]: the seed thesis's eq. 5.1, `r(v) = 1 − (1 − r₀)(v/v₀)^{1/5}` below `v₀`,
//!   `r₀ (v/v₀)^{−1/4}` above;
//! * [`Viscoelastic`]: Schwager & Pöschel's series for Hertz contacts with viscous damping,
//!   `ε(g) = 1 − C₁ A κ^{2/5} g^{1/5} + C₂ A² κ^{4/5} g^{2/5}`.

use std::fmt::Debug;

use crate::EdmdError;

mod rule;
mod rules;
#[cfg(test)]
mod tests;

pub use rule::{Grain, LastCollision, Law, Remedy, Rough, Rule, Smooth, Spin};
pub use rules::{
    ConstantRestitution, ThesisRestitution, ThresholdRestitution, Viscoelastic, VISCOELASTIC_C1,
    VISCOELASTIC_C2, VISCOELASTIC_EPS_MIN, VISCOELASTIC_X_MAX,
};

/// A normal-restitution law.
pub trait CollisionRule: Clone + Debug + Send + Sync + 'static {
    /// Per-particle memory of the rule: `()` (no memory, no cost) for laws of the impact alone; the
    /// time of the last collision for the TC model.
    type State: Copy
        + Default
        + Debug
        + Send
        + Sync
        + 'static
        + serde::Serialize
        + serde::de::DeserializeOwned;

    /// Restitution coefficient for a collision with normal approach speed `vn > 0` (physical units)
    /// between particles of reduced mass `m_eff` and reduced radius `r_eff = r_i r_j/(r_i + r_j)`.
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64;

    /// True for rules that may rotate the post-collision relative velocity ([`Remedy::Rotation`]);
    /// the event loop skips the rotation entirely for the others.
    const ROTATES: bool = false;

    /// Whether this rule's collisions rotate the relative velocity (only asked when `ROTATES`).
    #[inline(always)]
    fn rotates(&self) -> bool {
        Self::ROTATES
    }

    /// True for rough particles ([`Rule`] of [`Rough`] grains): collisions also exchange tangential momentum and spin.
    const ROUGH: bool = false;

    /// Tangential restitution β and moment-of-inertia factor q (I = q m R²) of a rough rule.
    #[inline(always)]
    fn roughness(&self) -> (f64, f64) {
        (-1.0, 0.0)
    }

    /// Angular velocity held in a particle's state (zero for smooth particles; only z in 2D).
    #[inline(always)]
    fn spin(_state: &Self::State) -> [f64; 3] {
        [0.0; 3]
    }

    /// Sets the angular velocity held in a particle's state (no-op for smooth particles).
    #[inline(always)]
    fn set_spin(_state: &mut Self::State, _spin: [f64; 3]) {}

    /// Replaces the law and the remedy, keeping the grains' kind and every particle's memory
    /// (between two runs: the next collision uses them). A rule that is one fixed law refuses.
    fn set_law(&mut self, law: Law, remedy: Remedy) -> Result<(), crate::EdmdError> {
        let _ = (law, remedy);
        Err(crate::EdmdError::invalid(
            "rule",
            std::any::type_name::<Self>(),
            "this rule is one fixed law; build the simulation with a `Rule` to change it",
        ))
    }

    /// Rotation angle for the post-collision relative velocity (only called when `ROTATES`).
    #[inline(always)]
    fn rotation_angle(&self, _rng: &mut rand_xoshiro::Xoshiro256PlusPlus) -> f64 {
        0.0
    }

    /// The restitution of a collision at physical time `t` between particles whose rule states are
    /// `si` and `sj`, updating them. Rules without memory use [`Self::restitution`].
    #[inline(always)]
    fn restitution_at(
        &self,
        vn: f64,
        m_eff: f64,
        r_eff: f64,
        _t: f64,
        _si: &mut Self::State,
        _sj: &mut Self::State,
    ) -> f64 {
        self.restitution(vn, m_eff, r_eff)
    }
}

/// Elastic collisions (ε = 1), the equilibrium hard-sphere gas.
#[derive(Debug, Clone, Copy, Default)]
pub struct Elastic;

impl CollisionRule for Elastic {
    type State = ();

    #[inline(always)]
    fn restitution(&self, _vn: f64, _m: f64, _r: f64) -> f64 {
        1.0
    }
}

pub(crate) fn check_unit(field: &'static str, value: f64) -> Result<f64, EdmdError> {
    if (0.0..=1.0).contains(&value) {
        Ok(value)
    } else {
        Err(EdmdError::invalid(
            field,
            value,
            "restitution must lie in [0, 1]",
        ))
    }
}

pub(crate) fn check_positive(field: &'static str, value: f64) -> Result<f64, EdmdError> {
    if value > 0.0 && value.is_finite() {
        Ok(value)
    } else {
        Err(EdmdError::invalid(
            field,
            value,
            "must be positive and finite",
        ))
    }
}
