//! Typed errors returned by constructors and validation (never by the event loop).

use thiserror::Error;

/// Everything that can go wrong when a simulation is set up.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EdmdError {
    /// A parameter is outside its domain.
    #[error("invalid {field} = {value}: {reason}")]
    InvalidParameter {
        /// Name of the parameter, as the user spells it.
        field: &'static str,
        /// The offending value, formatted.
        value: String,
        /// What the value must satisfy.
        reason: String,
    },
    /// The requested packing fraction cannot be reached by the chosen start.
    #[error("{method} start cannot reach packing fraction phi = {phi:.4} (at most {max:.4} for these parameters)")]
    TooDense {
        /// Placement method (`random` or `lattice`).
        method: &'static str,
        /// Requested packing fraction.
        phi: f64,
        /// Largest reachable packing fraction.
        max: f64,
    },
    /// The box is too small for a cell list of at least three cells along an axis.
    #[error(
        "box side {axis} = {len} holds fewer than 3 cells of side {cell} (the largest diameter): enlarge the box or lower N's density"
    )]
    BoxTooSmall {
        /// Axis name (`Lx`, `Ly`, `Lz`).
        axis: &'static str,
        /// The box side.
        len: f64,
        /// The smallest allowed cell side.
        cell: f64,
    },
    /// Two particles of a given state overlap.
    #[error("particles {i} and {j} overlap by {overlap:.3e} of their contact distance")]
    Overlap {
        /// First particle.
        i: usize,
        /// Second particle.
        j: usize,
        /// Overlap depth relative to the contact distance.
        overlap: f64,
    },
}

impl EdmdError {
    /// Shorthand for [`EdmdError::InvalidParameter`].
    pub fn invalid(
        field: &'static str,
        value: impl std::fmt::Display,
        reason: impl Into<String>,
    ) -> Self {
        EdmdError::InvalidParameter {
            field,
            value: value.to_string(),
            reason: reason.into(),
        }
    }
}

/// Axis names used in messages.
pub(crate) const AXIS_NAMES: [&str; 3] = ["Lx", "Ly", "Lz"];
