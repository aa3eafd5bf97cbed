//! Laws of the impact alone: constant, threshold, the thesis's law and viscoelastic spheres.

use super::{check_positive, check_unit, CollisionRule};
use crate::EdmdError;

/// Constant normal restitution ε ∈ [0, 1].
#[derive(Debug, Clone, Copy)]
pub struct ConstantRestitution {
    epsilon: f64,
}

impl ConstantRestitution {
    /// A rule with restitution `epsilon`; errors unless `0 ≤ ε ≤ 1`.
    pub fn new(epsilon: f64) -> Result<Self, EdmdError> {
        Ok(ConstantRestitution {
            epsilon: check_unit("epsilon", epsilon)?,
        })
    }

    /// The restitution coefficient.
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }
}

impl CollisionRule for ConstantRestitution {
    type State = ();

    #[inline(always)]
    fn restitution(&self, _vn: f64, _m: f64, _r: f64) -> f64 {
        self.epsilon
    }
}

/// ε above a normal approach speed δ, `epsilon_low` (usually 1 or close to it) below: the velocity
/// threshold that keeps slow, repeated contacts from collapsing (PHYSICS.md §6.2 item 2).
#[derive(Debug, Clone, Copy)]
pub struct ThresholdRestitution {
    epsilon: f64,
    epsilon_low: f64,
    delta: f64,
}

impl ThresholdRestitution {
    /// `epsilon` for `vn ≥ delta`, `epsilon_low` below; both in [0, 1], `delta > 0`.
    pub fn new(epsilon: f64, epsilon_low: f64, delta: f64) -> Result<Self, EdmdError> {
        Ok(ThresholdRestitution {
            epsilon: check_unit("epsilon", epsilon)?,
            epsilon_low: check_unit("epsilon_low", epsilon_low)?,
            delta: check_positive("delta", delta)?,
        })
    }
}

impl CollisionRule for ThresholdRestitution {
    type State = ();

    #[inline(always)]
    fn restitution(&self, vn: f64, _m: f64, _r: f64) -> f64 {
        if vn < self.delta {
            self.epsilon_low
        } else {
            self.epsilon
        }
    }
}

/// The seed thesis's velocity-dependent law (its eq. 5.1, "steel"): `r(v) = 1 − (1 − r₀)(v/v₀)^{1/5}`
/// for `v ≤ v₀` and `r₀ (v/v₀)^{−1/4}` above; continuous at `v₀`. Defaults `v₀ = 0.3`, `r₀ = 0.95`.
#[derive(Debug, Clone, Copy)]
pub struct ThesisRestitution {
    r0: f64,
    v0: f64,
}

impl Default for ThesisRestitution {
    fn default() -> Self {
        ThesisRestitution { r0: 0.95, v0: 0.3 }
    }
}

impl ThesisRestitution {
    /// The law with restitution `r0` at speed `v0`.
    pub fn new(r0: f64, v0: f64) -> Result<Self, EdmdError> {
        Ok(ThesisRestitution {
            r0: check_unit("r0", r0)?,
            v0: check_positive("v0", v0)?,
        })
    }
}

impl CollisionRule for ThesisRestitution {
    type State = ();

    #[inline]
    fn restitution(&self, vn: f64, _m: f64, _r: f64) -> f64 {
        let x = vn / self.v0;
        if x <= 1.0 {
            1.0 - (1.0 - self.r0) * x.powf(0.2)
        } else {
            self.r0 * x.powf(-0.25)
        }
    }
}

/// `C₁ = Γ(3/5)√π / (2^{1/5} 5^{2/5} Γ(21/10))` of the viscoelastic series.
pub const VISCOELASTIC_C1: f64 = 1.153_448_858_095_288_4;
/// `C₂ = (3/5) C₁²`.
pub const VISCOELASTIC_C2: f64 = 0.6 * VISCOELASTIC_C1 * VISCOELASTIC_C1;
/// Where the two-term series `1 − C₁x + C₂x²` has its minimum, `x* = C₁/(2C₂) = 1/(1.2 C₁)`:
/// beyond it the series rises back towards 1, which the true ε(g) never does.
pub const VISCOELASTIC_X_MAX: f64 = VISCOELASTIC_C1 / (2.0 * VISCOELASTIC_C2);
/// The series' value at [`VISCOELASTIC_X_MAX`], `1 − C₁²/(4C₂) = 7/12`: the smallest ε it gives.
pub const VISCOELASTIC_EPS_MIN: f64 =
    1.0 - VISCOELASTIC_C1 * VISCOELASTIC_C1 / (4.0 * VISCOELASTIC_C2);

/// Viscoelastic spheres (Schwager & Pöschel 1998; Ramírez et al. 1999): contact force
/// `F = ρ_H (ξ^{3/2} + (3/2) A ξ^{1/2} ξ̇)` with `ρ_H = 2Y√R_eff / (3(1 − ν²))`, giving
/// `ε(g) = 1 − C₁ A κ^{2/5} g^{1/5} + C₂ A² κ^{4/5} g^{2/5}` with `κ = (3/2)^{5/2} ρ_H / m_eff`.
/// The two-term series holds for `x = A κ^{2/5} g^{1/5} ≪ 1`; past its minimum at
/// `x* =` [`VISCOELASTIC_X_MAX`] it would rise back to 1, so ε is held at the minimum
/// ([`VISCOELASTIC_EPS_MIN`]) there: the law never increases with speed. Sweeps refuse a damping
/// whose series ends below the impact speeds a run meets ([`Viscoelastic::series_limit`]).
#[derive(Debug, Clone, Copy)]
pub struct Viscoelastic {
    /// `2Y/(3(1 − ν²))`, so that `ρ_H = stiffness √R_eff`.
    pub(super) stiffness: f64,
    /// Damping time A.
    pub(super) damping: f64,
}

impl Viscoelastic {
    /// From material constants: Young's modulus `young`, Poisson ratio `poisson` ∈ (−1, 0.5] and the
    /// damping constant `a` (time units) of Schwager & Pöschel.
    pub fn from_material(young: f64, poisson: f64, a: f64) -> Result<Self, EdmdError> {
        check_positive("young", young)?;
        if !(poisson > -1.0 && poisson <= 0.5) {
            return Err(EdmdError::invalid(
                "poisson",
                poisson,
                "Poisson ratio must lie in (−1, 0.5]",
            ));
        }
        if !(a >= 0.0 && a.is_finite()) {
            return Err(EdmdError::invalid("damping", a, "must be ≥ 0"));
        }
        Ok(Viscoelastic {
            stiffness: 2.0 * young / (3.0 * (1.0 - poisson * poisson)),
            damping: a,
        })
    }

    /// From the seed PhD thesis's contact `F = K δ^{3/2} + T K δ^{1/2} δ̇` with `K = 2E√r_eff/(3(1 − ν²))`:
    /// its damping time `T` maps to `A = 2T/3` (PHYSICS.md §6.2 item 5).
    pub fn from_phd_damping(young: f64, poisson: f64, t: f64) -> Result<Self, EdmdError> {
        Self::from_material(young, poisson, 2.0 * t / 3.0)
    }

    /// The damping that gives restitution `epsilon` at impact speed `speed` for a pair with reduced
    /// mass `m_eff` and reduced radius `r_eff`, at the stiffness of `young`, `poisson`.
    pub fn from_reference(
        epsilon: f64,
        speed: f64,
        m_eff: f64,
        r_eff: f64,
        young: f64,
        poisson: f64,
    ) -> Result<Self, EdmdError> {
        check_unit("epsilon", epsilon)?;
        check_positive("speed", speed)?;
        let mut rule = Self::from_material(young, poisson, 0.0)?;
        // ε(A) = 1 − C₁ x + C₂ x², x = A κ^{2/5} g^{1/5}: the smaller root.
        let disc = VISCOELASTIC_C1 * VISCOELASTIC_C1 - 4.0 * VISCOELASTIC_C2 * (1.0 - epsilon);
        if disc < 0.0 {
            return Err(EdmdError::invalid(
                "epsilon",
                epsilon,
                "too small for the two-term viscoelastic series",
            ));
        }
        let x = (VISCOELASTIC_C1 - disc.sqrt()) / (2.0 * VISCOELASTIC_C2);
        let kappa = rule.kappa(m_eff, r_eff);
        rule.damping = x / (kappa.powf(0.4) * speed.powf(0.2));
        Ok(rule)
    }

    /// κ = (3/2)^{5/2} ρ_H / m_eff for a pair.
    pub fn kappa(&self, m_eff: f64, r_eff: f64) -> f64 {
        1.5f64.powf(2.5) * self.stiffness * r_eff.sqrt() / m_eff
    }

    /// The damping constant A.
    pub fn damping(&self) -> f64 {
        self.damping
    }

    /// The largest normal speed at which the two-term series still decreases, for a pair of
    /// reduced mass `m_eff` and reduced radius `r_eff`: `(x*/(A κ^{2/5}))^5` (∞ without damping).
    pub fn series_limit(&self, m_eff: f64, r_eff: f64) -> f64 {
        (VISCOELASTIC_X_MAX / (self.damping * self.kappa(m_eff, r_eff).powf(0.4))).powi(5)
    }
}

impl CollisionRule for Viscoelastic {
    type State = ();

    #[inline]
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64 {
        let x = self.damping * self.kappa(m_eff, r_eff).powf(0.4) * vn.powf(0.2);
        if x >= VISCOELASTIC_X_MAX {
            VISCOELASTIC_EPS_MIN
        } else {
            (1.0 - VISCOELASTIC_C1 * x + VISCOELASTIC_C2 * x * x).min(1.0)
        }
    }
}
