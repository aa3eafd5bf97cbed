//! The refinement a spec records: the axes `edmd refine` bisects and the points of each round.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::Grid;

/// A grid axis that `edmd refine` bisects: linear for ε, φ and β, logarithmic for N, the box and
/// a vibrating floor's shaking strength S.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum RefineAxis {
    /// Restitution ε (linear midpoints).
    Eps,
    /// Packing fraction φ (linear).
    Phi,
    /// Box side L (geometric midpoints).
    Box,
    /// Particle number N (geometric, rounded to an integer).
    N,
    /// Tangential restitution β (linear).
    Beta,
    /// A vibrating floor's shaking strength S (geometric).
    #[serde(rename = "shake_s")]
    ShakeS,
}

impl RefineAxis {
    /// Every axis, in the order `--axes` lists them by default.
    pub const ALL: [RefineAxis; 6] = [
        RefineAxis::Eps,
        RefineAxis::Phi,
        RefineAxis::Box,
        RefineAxis::N,
        RefineAxis::Beta,
        RefineAxis::ShakeS,
    ];

    /// The name of the axis: its field in a grid.
    pub fn name(self) -> &'static str {
        match self {
            RefineAxis::Eps => "eps",
            RefineAxis::Phi => "phi",
            RefineAxis::Box => "box",
            RefineAxis::N => "n",
            RefineAxis::Beta => "beta",
            RefineAxis::ShakeS => "shake_s",
        }
    }

    /// Whether the axis is bisected in its logarithm (N and the box).
    pub fn logarithmic(self) -> bool {
        matches!(self, RefineAxis::Box | RefineAxis::N | RefineAxis::ShakeS)
    }

    /// Parses an axis name.
    pub fn parse(s: &str) -> Option<RefineAxis> {
        RefineAxis::ALL.into_iter().find(|a| a.name() == s.trim())
    }
}

/// The refinement of a sweep: the axes it bisects and the points of each round, each a grid of
/// single values (with the grid's seeds).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Refinement {
    /// The axes bisected.
    pub axes: Vec<RefineAxis>,
    /// The points added in each round.
    pub rounds: Vec<Vec<Grid>>,
}
