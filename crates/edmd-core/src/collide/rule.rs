//! The one composite rule of a scene: a restitution [`Law`], a collapse [`Remedy`] and the grains'
//! [`Grain`] kind, composed as data rather than as nested wrapper types.
//!
//! The law and the remedy are runtime values (one predictable branch per collision), so that a
//! sweep compiles the event loop once per dimension, geometry and grain kind instead of once per
//! law × remedy × roughness. Only the grain kind is a type: it fixes the layout of the per-particle
//! state (spin or none), which the inner loop must know. Whatever the law and remedy, rough grains
//! exchange spin: there is no wrapper that could forget to forward it.

use std::fmt::Debug;

use super::{check_positive, CollisionRule, ConstantRestitution, Elastic};
use super::{ThesisRestitution, ThresholdRestitution, Viscoelastic};
use crate::EdmdError;

/// A normal-restitution law, one of those of PHYSICS.md §6.2.
#[derive(Debug, Clone, Copy)]
pub enum Law {
    /// Constant ε (ε = 1: elastic).
    Constant(ConstantRestitution),
    /// ε above a normal speed δ, another ε below.
    Threshold(ThresholdRestitution),
    /// The seed thesis's law (eq. 5.1).
    Thesis(ThesisRestitution),
    /// Viscoelastic spheres.
    Viscoelastic(Viscoelastic),
}

impl Law {
    /// ε for normal approach speed `vn`, reduced mass `m_eff` and reduced radius `r_eff`.
    #[inline(always)]
    pub fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64 {
        match self {
            Law::Constant(l) => l.restitution(vn, m_eff, r_eff),
            Law::Threshold(l) => l.restitution(vn, m_eff, r_eff),
            Law::Thesis(l) => l.restitution(vn, m_eff, r_eff),
            Law::Viscoelastic(l) => l.restitution(vn, m_eff, r_eff),
        }
    }
}

impl From<Elastic> for Law {
    fn from(_: Elastic) -> Law {
        Law::Constant(ConstantRestitution::new(1.0).expect("1 is a restitution"))
    }
}

macro_rules! law_from {
    ($($variant:ident($t:ty)),*) => {$(
        impl From<$t> for Law {
            fn from(l: $t) -> Law {
                Law::$variant(l)
            }
        }
    )*};
}
law_from!(
    Constant(ConstantRestitution),
    Threshold(ThresholdRestitution),
    Thesis(ThesisRestitution),
    Viscoelastic(Viscoelastic)
);

/// What keeps inelastic collapse away (PHYSICS.md §6.4), applied on top of the law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Remedy {
    /// The law as it is.
    None,
    /// The TC model (Luding & McNamara, Granular Matter 1, 113 (1998)): a collision is dissipative
    /// only if both partners' previous collisions happened at least `tc` ago (physical time);
    /// otherwise it is elastic. `tc` stands for the duration of a real contact.
    Tc {
        /// The contact duration t_c (> 0).
        tc: f64,
    },
    /// The thesis's random rotation: after the law, the pair's relative velocity is rotated in the
    /// centre-of-mass frame by an angle uniform in [0, θ_max] about a random axis (momentum and
    /// energy stay those of the law); a rotation that would turn the pair towards each other again
    /// is taken the other way.
    Rotation {
        /// The largest angle θ_max, radians, in [0, π/2].
        theta_max: f64,
    },
}

/// The grains' kind: smooth, or rough with a tangential restitution and spin. A type, because it
/// fixes the per-particle state the event loop carries.
pub trait Grain: Copy + Debug + Send + Sync + 'static {
    /// The spin a grain carries: `()` (nothing) for smooth grains.
    type Spin: Copy
        + Default
        + Debug
        + Send
        + Sync
        + 'static
        + serde::Serialize
        + serde::de::DeserializeOwned;
    /// True for rough grains.
    const ROUGH: bool;
    /// Tangential restitution β and inertia factor q (β = −1 for smooth grains).
    fn roughness(&self) -> (f64, f64);
    /// The angular velocity held in `spin` (zero for smooth grains; only z in 2D).
    fn spin(spin: &Self::Spin) -> [f64; 3];
    /// Sets the angular velocity held in `spin` (nothing for smooth grains).
    fn set_spin(spin: &mut Self::Spin, w: [f64; 3]);
}

/// Smooth grains: no spin, no tangential impulse.
#[derive(Debug, Clone, Copy, Default)]
pub struct Smooth;

impl Grain for Smooth {
    type Spin = ();
    const ROUGH: bool = false;
    #[inline(always)]
    fn roughness(&self) -> (f64, f64) {
        (-1.0, 0.0)
    }
    #[inline(always)]
    fn spin(_: &()) -> [f64; 3] {
        [0.0; 3]
    }
    #[inline(always)]
    fn set_spin(_: &mut (), _: [f64; 3]) {}
}

/// Rough grains (the thesis's eq. 1.15; Walton's model with constant coefficients; PHYSICS.md §6.5):
/// at contact the relative velocity of the touching surface points has its normal part reversed
/// with the law's ε and its tangential part with β ∈ [−1, 1] (β = −1 smooth, β = 1 perfectly
/// rough). Moments of inertia are `I = q m R²` (q = 1/2 for uniform disks, 2/5 for spheres).
#[derive(Debug, Clone, Copy)]
pub struct Rough {
    beta: f64,
    q: f64,
}

impl Rough {
    /// Tangential restitution `beta` ∈ [−1, 1] and inertia factor `q` > 0.
    pub fn new(beta: f64, q: f64) -> Result<Rough, EdmdError> {
        if !(-1.0..=1.0).contains(&beta) {
            return Err(EdmdError::invalid(
                "beta",
                beta,
                "tangential restitution must lie in [-1, 1]",
            ));
        }
        Ok(Rough {
            beta,
            q: check_positive("inertia_factor", q)?,
        })
    }
}

/// Angular velocity of a rough particle (only the z component is used in 2D).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Spin(pub [f64; 3]);

impl Grain for Rough {
    type Spin = Spin;
    const ROUGH: bool = true;
    #[inline(always)]
    fn roughness(&self) -> (f64, f64) {
        (self.beta, self.q)
    }
    #[inline(always)]
    fn spin(spin: &Spin) -> [f64; 3] {
        spin.0
    }
    #[inline(always)]
    fn set_spin(spin: &mut Spin, w: [f64; 3]) {
        spin.0 = w;
    }
}

/// Last collision time of a particle, for the TC model (−∞ before the first).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LastCollision(pub f64);

impl Default for LastCollision {
    fn default() -> Self {
        LastCollision(f64::NEG_INFINITY)
    }
}

/// A law, a remedy and the grains' kind: the collision rule of a scene.
///
/// ```
/// use edmd_core::{ConstantRestitution, Rule};
/// let rule = Rule::new(ConstantRestitution::new(0.8)?).with_tc(1e-4)?.rough(0.5, 0.5)?;
/// # Ok::<(), edmd_core::EdmdError>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct Rule<G: Grain = Smooth> {
    law: Law,
    remedy: Remedy,
    grain: G,
}

impl Rule<Smooth> {
    /// Smooth grains colliding by `law`, without a remedy.
    pub fn new(law: impl Into<Law>) -> Rule<Smooth> {
        Rule {
            law: law.into(),
            remedy: Remedy::None,
            grain: Smooth,
        }
    }

    /// The same law and remedy for rough grains of tangential restitution `beta` and inertia
    /// factor `q`.
    pub fn rough(self, beta: f64, q: f64) -> Result<Rule<Rough>, EdmdError> {
        Ok(Rule {
            law: self.law,
            remedy: self.remedy,
            grain: Rough::new(beta, q)?,
        })
    }
}

impl<G: Grain> Rule<G> {
    /// The rule with `remedy` instead of its current one (checked as [`Rule::with_tc`] and
    /// [`Rule::with_rotation`] check).
    pub fn with_remedy(self, remedy: Remedy) -> Result<Self, EdmdError> {
        match remedy {
            Remedy::None => Ok(Rule { remedy, ..self }),
            Remedy::Tc { tc } => self.with_tc(tc),
            Remedy::Rotation { theta_max } => self.with_rotation(theta_max),
        }
    }

    /// The TC model with contact duration `tc` > 0.
    pub fn with_tc(self, tc: f64) -> Result<Self, EdmdError> {
        Ok(Rule {
            remedy: Remedy::Tc {
                tc: check_positive("t_c", tc)?,
            },
            ..self
        })
    }

    /// Random rotation by up to `theta_max` radians (in [0, π/2]).
    pub fn with_rotation(self, theta_max: f64) -> Result<Self, EdmdError> {
        if !(0.0..=std::f64::consts::FRAC_PI_2).contains(&theta_max) {
            return Err(EdmdError::invalid(
                "theta_max",
                theta_max,
                "rotation angle must lie in [0, π/2] radians",
            ));
        }
        Ok(Rule {
            remedy: Remedy::Rotation { theta_max },
            ..self
        })
    }

    /// The restitution law.
    pub fn law(&self) -> &Law {
        &self.law
    }

    /// The remedy.
    pub fn remedy(&self) -> Remedy {
        self.remedy
    }
}

impl<G: Grain> CollisionRule for Rule<G> {
    type State = (LastCollision, G::Spin);
    /// The rotation is compiled in; [`CollisionRule::rotates`] says whether it applies.
    const ROTATES: bool = true;
    const ROUGH: bool = G::ROUGH;

    #[inline(always)]
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64 {
        self.law.restitution(vn, m_eff, r_eff)
    }

    fn set_law(&mut self, law: Law, remedy: Remedy) -> Result<(), EdmdError> {
        *self = Rule { law, ..*self }.with_remedy(remedy)?;
        Ok(())
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
        if let Remedy::Tc { tc } = self.remedy {
            let fresh = t - si.0 .0 >= tc && t - sj.0 .0 >= tc;
            si.0 .0 = t;
            sj.0 .0 = t;
            if !fresh {
                return 1.0;
            }
        }
        self.law.restitution(vn, m_eff, r_eff)
    }

    #[inline(always)]
    fn rotates(&self) -> bool {
        matches!(self.remedy, Remedy::Rotation { .. })
    }

    #[inline]
    fn rotation_angle(&self, rng: &mut rand_xoshiro::Xoshiro256PlusPlus) -> f64 {
        use rand::Rng;
        match self.remedy {
            Remedy::Rotation { theta_max } => theta_max * rng.random::<f64>(),
            _ => 0.0,
        }
    }

    #[inline(always)]
    fn roughness(&self) -> (f64, f64) {
        self.grain.roughness()
    }

    #[inline(always)]
    fn spin(state: &Self::State) -> [f64; 3] {
        G::spin(&state.1)
    }

    #[inline(always)]
    fn set_spin(state: &mut Self::State, spin: [f64; 3]) {
        G::set_spin(&mut state.1, spin)
    }
}
