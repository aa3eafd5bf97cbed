//! Collision rules: the restitution law applied at a pair contact.
//!
//! Rules are monomorphised into the event loop (no `dyn`). The impulse along the unit contact normal
//! `n` for masses `m_i`, `m_j` and normal relative velocity `g_n < 0` is
//! `J = −(1 + ε) μ g_n` with `μ = m_i m_j / (m_i + m_j)`; momentum is conserved exactly and the
//! kinetic energy drops by `(1 − ε²) μ g_n² / 2`.

use crate::EdmdError;
use std::fmt::Debug;

/// A normal-restitution law.
pub trait CollisionRule: Clone + Debug + Send + Sync + 'static {
    /// Restitution coefficient for a collision with normal approach speed `vn > 0` (physical units).
    fn restitution(&self, vn: f64) -> f64;
}

/// Elastic collisions (ε = 1), the equilibrium hard-sphere gas.
#[derive(Debug, Clone, Copy, Default)]
pub struct Elastic;

impl CollisionRule for Elastic {
    #[inline(always)]
    fn restitution(&self, _vn: f64) -> f64 {
        1.0
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
        if !(0.0..=1.0).contains(&epsilon) {
            return Err(EdmdError::invalid(
                "epsilon",
                epsilon,
                "restitution must lie in [0, 1]",
            ));
        }
        Ok(ConstantRestitution { epsilon })
    }

    /// The restitution coefficient.
    pub fn epsilon(&self) -> f64 {
        self.epsilon
    }
}

impl CollisionRule for ConstantRestitution {
    #[inline(always)]
    fn restitution(&self, _vn: f64) -> f64 {
        self.epsilon
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
    }
}
