//! The checks of [`super::Simulation::new`]: the box and parameters against the scene, and each
//! particle against the box.

use crate::cells::NONE;
use crate::{Boundary, EdmdError, ParticleInit, SimParams, Vector};

/// The checks of [`super::Simulation::new`] on the box and the parameters against scene `B`.
pub(super) fn scene<const D: usize, B: Boundary>(
    n: usize,
    box_len: &Vector<D>,
    params: &SimParams,
) -> Result<(), EdmdError> {
    if n == 0 {
        return Err(EdmdError::invalid("N", 0, "need at least one particle"));
    }
    if n >= NONE as usize {
        return Err(EdmdError::invalid("N", n, "at most 2^32 − 2 particles"));
    }
    for a in 0..D {
        if !(box_len[a] > 0.0 && box_len[a].is_finite()) {
            return Err(EdmdError::invalid(
                crate::error::AXIS_NAMES[a],
                box_len[a],
                "box side must be positive and finite",
            ));
        }
    }
    params.validate()?;
    if params.gravity != 0.0 && !B::GRAVITY {
        return Err(EdmdError::invalid(
            "gravity",
            params.gravity,
            "this scene has no gravity: use a GravityAxes scene",
        ));
    }
    if params.shear_rate != 0.0 && !B::SHEARED {
        return Err(EdmdError::invalid(
            "shear_rate",
            params.shear_rate,
            "this scene is not sheared: use the LeesEdwards scene",
        ));
    }
    if params.floor_temperature > 0.0 && !B::is_wall(D - 1) {
        return Err(EdmdError::invalid(
            "floor_temperature",
            params.floor_temperature,
            "a thermal floor needs walls on the last axis",
        ));
    }
    if B::GRAVITY && !B::is_wall(D - 1) {
        return Err(EdmdError::invalid(
            "scene",
            B::NAME,
            "gravity needs walls (a floor) on the last axis",
        ));
    }
    Ok(())
}

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
