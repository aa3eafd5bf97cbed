//! Checks of a spec's collision rule: each replica's rule can be built, and a viscoelastic one's
//! series holds over the impact speeds a run meets.

use edmd_core::{
    ConstantRestitution, EdmdError, ThesisRestitution, ThresholdRestitution, Viscoelastic,
};

use super::{Replica, RuleSpec, Spec};

pub(super) fn base_rule_check(spec: &Spec, r: &Replica) -> Result<(), EdmdError> {
    match spec.rule {
        RuleSpec::Constant {} => ConstantRestitution::new(r.eps).map(drop),
        RuleSpec::Threshold { delta, eps_low } => {
            ThresholdRestitution::new(r.eps, eps_low, delta).map(drop)
        }
        RuleSpec::Thesis { v0 } => ThesisRestitution::new(r.eps, v0).map(drop),
        RuleSpec::Viscoelastic { speed } => viscoelastic(r.eps, speed).map(drop),
    }
}

/// The normal impact speed, in units of √(T0/m), up to which a viscoelastic rule's two-term series
/// must hold: ten times the thermal relative speed √(2T0/m_eff) = 2 of the start. Faster pairs are
/// then a Maxwellian tail of about e^-100 of the collisions.
pub const VISCOELASTIC_SPEED_RANGE: f64 = 20.0;

/// Damping such that two unit-mass, unit-diameter particles meet with ε at `speed`. The stiffness
/// only sets the unit of the damping, so Young's modulus 1 and Poisson ratio 0.3 are used. Refused
/// when the series stops decreasing below [`VISCOELASTIC_SPEED_RANGE`] (PHYSICS.md §6.2 item 5).
pub fn viscoelastic(eps: f64, speed: f64) -> Result<Viscoelastic, EdmdError> {
    let rule = Viscoelastic::from_reference(eps, speed, 0.5, 0.25, 1.0, 0.3)?;
    let limit = rule.series_limit(0.5, 0.25);
    if limit < VISCOELASTIC_SPEED_RANGE {
        return Err(EdmdError::invalid(
            "rule.speed",
            speed,
            format!(
                "with eps = {eps} the two-term viscoelastic series holds only up to normal speed {limit:.3e}, below the {VISCOELASTIC_SPEED_RANGE} a run meets; at least {:.3e}",
                speed * VISCOELASTIC_SPEED_RANGE / limit
            ),
        ));
    }
    Ok(rule)
}
