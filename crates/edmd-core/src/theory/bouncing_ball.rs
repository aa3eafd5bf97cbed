//! A completely inelastic ball on a vibrating floor (PHYSICS.md §8.2): the ball rides the floor
//! z_w = A sin(ωt) until the floor's downward acceleration exceeds g, flies on a parabola, lands
//! and sticks. With Γ = Aω²/g:
//! * it lifts off at the phase ωt = asin(1/Γ) (never for Γ ≤ 1);
//! * a flight of exactly one period, from a take-off at the phase θ with cos θ = π/Γ back to the
//!   same phase, needs sin θ ≥ 1/Γ (the floor already falling faster than the ball would): from
//!   Γ = √(1 + π²) ≈ 3.297 on it is the ball's periodic motion, landing and leaving at once;
//! * that motion is the fixed point of the take-off phase map θ → θ'. Implicit differentiation of
//!   the landing condition sin θ + cos θ (τ − θ) − (τ − θ)²/(2Γ) = sin τ at τ = θ + 2π gives
//!   dθ'/dθ = 1 − Γ sin θ, which passes −1 (the period doubles) where Γ sin θ = 2, i.e.
//!   Γ = √(4 + π²) ≈ 3.724.

use std::f64::consts::PI;

/// The phase ωt at which a ball resting on the floor lifts off (None for Γ ≤ 1).
pub fn lift_off_phase(gamma: f64) -> Option<f64> {
    (gamma > 1.0).then(|| (1.0 / gamma).asin())
}

/// Γ from which a completely inelastic ball flies exactly one period: √(1 + π²).
pub fn one_period_gamma() -> f64 {
    (1.0 + PI * PI).sqrt()
}

/// The take-off phase of the one-period motion at Γ ≥ √(1 + π²): cos θ = π/Γ.
pub fn one_period_take_off(gamma: f64) -> Option<f64> {
    (gamma >= one_period_gamma()).then(|| (PI / gamma).acos())
}

/// Γ at which the one-period motion doubles its period: √(4 + π²).
pub fn period_doubling_gamma() -> f64 {
    (4.0 + PI * PI).sqrt()
}
