//! The checks of [`super::Simulation::new`]: the box and parameters against the scene, and each
//! particle against the box.

use crate::{Boundary, EdmdError, ParticleInit, Vector};

/// The checks of [`super::Simulation::new`] on each particle (radius, mass, inside the box, a finite
/// velocity); returns the largest diameter.
pub(super) fn particles<const D: usize, B: Boundary>(
    particles: &[ParticleInit<D>],
    box_len: &Vector<D>,
) -> Result<f64, EdmdError> {
    let mut max_d: f64 = 0.0;
    for (i, p) in particles.iter().enumerate() {
        if !(p.radius > 0.0 && p.radius.is_finite()) {
            return Err(EdmdError::invalid(
                "radius",
                p.radius,
                format!("particle {i}: radius must be positive"),
            ));
        }
        if !(p.mass > 0.0 && p.mass.is_finite()) {
            return Err(EdmdError::invalid(
                "mass",
                p.mass,
                format!("particle {i}: mass must be positive"),
            ));
        }
        for a in 0..D {
            let (lo, hi) = if B::is_wall(a) {
                (p.radius, box_len[a] - p.radius)
            } else {
                (0.0, box_len[a])
            };
            let x = p.pos[a];
            if !(x >= lo && x <= hi) || (!B::is_wall(a) && x >= hi) {
                return Err(EdmdError::invalid(
                    "position",
                    x,
                    format!("particle {i}, axis {a}: outside [{lo}, {hi}]"),
                ));
            }
            if !p.vel[a].is_finite() {
                return Err(EdmdError::invalid(
                    "velocity",
                    p.vel[a],
                    format!("particle {i}: not finite"),
                ));
            }
        }
        max_d = max_d.max(2.0 * p.radius);
    }
    Ok(max_d)
}
