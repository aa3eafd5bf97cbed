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

use crate::EdmdError;
use std::fmt::Debug;

/// A normal-restitution law.
pub trait CollisionRule: Clone + Debug + Send + Sync + 'static {
    /// Per-particle memory of the rule: `()` (no memory, no cost) for laws of the impact alone; the
    /// time of the last collision for the TC model.
    type State: Copy + Default + Debug + Send + Sync + 'static;

    /// Restitution coefficient for a collision with normal approach speed `vn > 0` (physical units)
    /// between particles of reduced mass `m_eff` and reduced radius `r_eff = r_i r_j/(r_i + r_j)`.
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64;

    /// True for rules that rotate the post-collision relative velocity ([`RandomRotation`]); the event
    /// loop skips the rotation entirely for the others.
    const ROTATES: bool = false;

    /// True for rough particles ([`Rough`]): collisions also exchange tangential momentum and spin.
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

fn check_unit(field: &'static str, value: f64) -> Result<f64, EdmdError> {
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

fn check_positive(field: &'static str, value: f64) -> Result<f64, EdmdError> {
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

/// Viscoelastic spheres (Schwager & Pöschel 1998; Ramírez et al. 1999): contact force
/// `F = ρ_H (ξ^{3/2} + (3/2) A ξ^{1/2} ξ̇)` with `ρ_H = 2Y√R_eff / (3(1 − ν²))`, giving
/// `ε(g) = 1 − C₁ A κ^{2/5} g^{1/5} + C₂ A² κ^{4/5} g^{2/5}` with `κ = (3/2)^{5/2} ρ_H / m_eff`,
/// clamped to [0, 1] (the two-term series holds for `A κ^{2/5} g^{1/5} ≪ 1`).
#[derive(Debug, Clone, Copy)]
pub struct Viscoelastic {
    /// `2Y/(3(1 − ν²))`, so that `ρ_H = stiffness √R_eff`.
    stiffness: f64,
    /// Damping time A.
    damping: f64,
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
}

impl CollisionRule for Viscoelastic {
    type State = ();

    #[inline]
    fn restitution(&self, vn: f64, m_eff: f64, r_eff: f64) -> f64 {
        let x = self.damping * self.kappa(m_eff, r_eff).powf(0.4) * vn.powf(0.2);
        (1.0 - VISCOELASTIC_C1 * x + VISCOELASTIC_C2 * x * x).clamp(0.0, 1.0)
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn epsilon_domain_is_checked() {
        assert!(ConstantRestitution::new(0.0).is_ok());
        assert!(ConstantRestitution::new(1.0).is_ok());
        let e = ConstantRestitution::new(1.5).unwrap_err().to_string();
        assert!(e.contains("epsilon") && e.contains("1.5"), "{e}");
        assert!(ConstantRestitution::new(f64::NAN).is_err());
        assert!(ConstantRestitution::new(-0.1).is_err());
        assert!(ThresholdRestitution::new(0.9, 1.0, 0.0)
            .unwrap_err()
            .to_string()
            .contains("delta"));
        assert!(Viscoelastic::from_material(1.0, 0.7, 0.1)
            .unwrap_err()
            .to_string()
            .contains("poisson"));
    }

    #[test]
    fn tc_model_is_elastic_within_tc() {
        let r = TcModel::new(ConstantRestitution::new(0.5).unwrap(), 1e-3).unwrap();
        let (mut a, mut b, mut c) = (
            LastCollision::default(),
            LastCollision::default(),
            LastCollision::default(),
        );
        assert_eq!(r.restitution_at(1.0, 0.5, 0.25, 1.0, &mut a, &mut b), 0.5);
        // a collided at t = 1: within t_c any collision of a is elastic, whoever the partner.
        assert_eq!(
            r.restitution_at(1.0, 0.5, 0.25, 1.0005, &mut a, &mut c),
            1.0
        );
        assert_eq!(r.restitution_at(1.0, 0.5, 0.25, 1.002, &mut b, &mut c), 0.5);
        assert!(TcModel::new(Elastic, 0.0).is_err());
    }

    #[test]
    fn threshold_switches_at_delta() {
        let r = ThresholdRestitution::new(0.7, 1.0, 0.01).unwrap();
        assert_eq!(r.restitution(0.009, 0.5, 0.25), 1.0);
        assert_eq!(r.restitution(0.01, 0.5, 0.25), 0.7);
    }

    /// PHYSICS.md §6.2 item 4: 0.9747 (v = 0.01), 0.9599 (0.1), 0.95 (0.3), 0.703 (1), 0.534 (3);
    /// continuous at v₀.
    #[test]
    fn thesis_law_values_and_continuity() {
        let r = ThesisRestitution::default();
        for (v, want) in [
            (0.01, 0.9747),
            (0.1, 0.9599),
            (0.3, 0.95),
            (1.0, 0.703),
            (3.0, 0.534),
        ] {
            assert!(
                (r.restitution(v, 0.5, 0.25) - want).abs() < 5e-4,
                "v = {v}: {}",
                r.restitution(v, 0.5, 0.25)
            );
        }
        let below = r.restitution(0.3 * (1.0 - 1e-12), 0.5, 0.25);
        let above = r.restitution(0.3 * (1.0 + 1e-12), 0.5, 0.25);
        assert!((below - above).abs() < 1e-10);
    }

    #[test]
    fn viscoelastic_constants() {
        // C₁ from its Gamma-function form: Γ(3/5) = 1.4891922488128169, Γ(21/10) = 1.0464858468535607.
        let c1 = 1.489_192_248_812_816_9 * std::f64::consts::PI.sqrt()
            / (2f64.powf(0.2) * 5f64.powf(0.4) * 1.046_485_846_853_560_7);
        assert!((c1 - VISCOELASTIC_C1).abs() < 1e-15, "{c1}");
        assert!((VISCOELASTIC_C2 - 0.79827).abs() < 1e-5);
    }

    /// Integrates the Hertz + damping contact ODE `m ξ'' = −ρ_H (ξ^{3/2} + (3/2) A ξ^{1/2} ξ')` from
    /// ξ = 0, ξ' = g until the particles separate (ξ back to 0, or the force turning attractive), and
    /// returns −ξ'/g at that moment.
    fn restitution_from_ode(rho: f64, m: f64, a: f64, g: f64) -> f64 {
        let force = |x: f64, v: f64| {
            let x = x.max(0.0);
            -(rho / m) * (x.powf(1.5) + 1.5 * a * x.sqrt() * v)
        };
        // Time scale of the contact ~ (m/ρ)^{2/5} g^{−1/5}.
        let dt = (m / rho).powf(0.4) * g.powf(-0.2) * 1e-5;
        let (mut x, mut v) = (0.0f64, g);
        loop {
            // RK4
            let (k1x, k1v) = (v, force(x, v));
            let (k2x, k2v) = (
                v + 0.5 * dt * k1v,
                force(x + 0.5 * dt * k1x, v + 0.5 * dt * k1v),
            );
            let (k3x, k3v) = (
                v + 0.5 * dt * k2v,
                force(x + 0.5 * dt * k2x, v + 0.5 * dt * k2v),
            );
            let (k4x, k4v) = (v + dt * k3v, force(x + dt * k3x, v + dt * k3v));
            let (nx, nv) = (
                x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
                v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v),
            );
            // Separation: overlap gone, or the (tensile) force would pull the spheres back.
            if nx <= 0.0 || (nv < 0.0 && nx.powf(1.5) + 1.5 * a * nx.sqrt() * nv <= 0.0) {
                return -nv / g;
            }
            x = nx;
            v = nv;
        }
    }

    /// The two-term series against a direct integration of the contact, at small speeds (where the
    /// neglected third term, ~(A κ^{2/5} g^{1/5})³, is below 1e-5).
    #[test]
    fn viscoelastic_series_matches_the_contact_ode() {
        let rule = Viscoelastic::from_material(1.0e3, 0.3, 2e-3).unwrap();
        let (m_eff, r_eff): (f64, f64) = (0.5, 0.25);
        let rho = rule.stiffness * r_eff.sqrt();
        for g in [1e-4, 1e-3, 1e-2] {
            let series = rule.restitution(g, m_eff, r_eff);
            let ode = restitution_from_ode(rho, m_eff, rule.damping, g);
            let x = rule.damping * rule.kappa(m_eff, r_eff).powf(0.4) * g.powf(0.2);
            println!("g = {g:e}: series {series:.7}, ODE {ode:.7}, expansion parameter {x:.4}");
            assert!(
                (series - ode).abs() < 1e-4,
                "g = {g}: series {series} vs ODE {ode}"
            );
        }
    }

    #[test]
    fn viscoelastic_reference_point_is_reproduced() {
        let rule = Viscoelastic::from_reference(0.9, 1.0, 0.5, 0.25, 1e4, 0.3).unwrap();
        assert!((rule.restitution(1.0, 0.5, 0.25) - 0.9).abs() < 1e-12);
        assert!(
            rule.restitution(0.1, 0.5, 0.25) > 0.9,
            "slower impacts are more elastic"
        );
    }
}
