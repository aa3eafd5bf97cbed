//! `BoundaryKind`: the boundary conditions a spec names, and their names in files.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Boundary conditions of the box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum BoundaryKind {
    /// Periodic along every axis.
    Periodic,
    /// Hard specular walls along every axis.
    Walls,
    /// Periodic along x, walls along the other axes.
    Channel,
    /// Periodic, with the images across the y faces sliding along x (Lees–Edwards): the uniform
    /// shear flow at `grid.shear_rate`.
    #[serde(rename = "lees-edwards")]
    LeesEdwards,
}

impl BoundaryKind {
    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryKind::Periodic => "periodic",
            BoundaryKind::Walls => "walls",
            BoundaryKind::Channel => "channel",
            BoundaryKind::LeesEdwards => "lees-edwards",
        }
    }

    /// Whether every axis is periodic (the sheared box is: its y images slide, H5MD calls it periodic
    /// and the file stores the sliding offset beside the box).
    pub fn periodic(self) -> bool {
        matches!(self, BoundaryKind::Periodic | BoundaryKind::LeesEdwards)
    }

    /// H5MD `boundary` attribute per axis ("periodic" or "none").
    pub fn h5md_boundary(self, d: usize) -> Vec<&'static str> {
        (0..d)
            .map(|axis| match (self, axis) {
                (BoundaryKind::Periodic | BoundaryKind::LeesEdwards, _)
                | (BoundaryKind::Channel, 0) => "periodic",
                _ => "none",
            })
            .collect()
    }
}
