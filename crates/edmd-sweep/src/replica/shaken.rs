//! The state of a bed on a vibrating floor (PHYSICS.md §8.4), from its uniform-time samples
//! ([`super::bed_meter`]): where the densest layer is, how dense, and how much denser than the layer
//! on the floor; the columns' sub-harmonic; the mean flow's horizontal mode. The thresholds are in
//! one struct, [`SHAKEN_THRESHOLDS`].
//!
//! Labelled, in this order: `convection` (a mean flow in rolls, clear of its noise), `gas` (no layer as dense as a
//! liquid), `leidenfrost` (a dense layer floating above a floor layer it outweighs), `solid` (a
//! dense bed below lift-off, Γ < 1), `undulations` (a dense bed whose columns rise and fall out of
//! step at f/2), `bouncing_bed` (a dense bed whose layer on the floor is at least 1/`inversion` as
//! dense as its densest), `undetermined` (a fluidised bed between these).

use crate::spec::Replica;

use super::bed_meter::BedSummary;

/// The thresholds of [`shaken_state`], in packing fractions, grain diameters and √(g d).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShakenThresholds {
    /// A layer at least this dense is a dense (solid-like or cluster) layer.
    pub dense: f64,
    /// Below this packing fraction everywhere, the bed is a gas.
    pub fluid: f64,
    /// A floating dense layer is a Leidenfrost state when at least this many times denser than
    /// the layer on the floor.
    pub inversion: f64,
    /// Columns whose heights swing out of step at f/2 by at least this many diameters (rms) are
    /// undulations.
    pub undulation: f64,
    /// A mean vertical flow whose horizontal mode is at least this fast, and at least
    /// `significance` times its noise, is convection.
    pub convection: f64,
    /// How many times its noise a convection amplitude must be.
    pub significance: f64,
}

/// The thresholds the runner uses.
pub const SHAKEN_THRESHOLDS: ShakenThresholds = ShakenThresholds {
    dense: 0.5,
    fluid: 0.3,
    inversion: 2.0,
    undulation: 0.5,
    convection: 0.1,
    significance: 2.0,
};

/// A shaken bed's state and the numbers it was read from.
#[derive(Debug, Clone, PartialEq)]
pub struct ShakenState {
    /// The label (see the module documentation).
    pub label: &'static str,
    /// The densest layer's packing fraction.
    pub phi_max: f64,
    /// Its height above the floor's top (2A) in diameters, measured from the first layer's centres.
    pub peak_height: f64,
    /// Its packing fraction over that of the layer on the floor (∞ where that one is empty).
    pub inversion: f64,
}

/// The state of shaken replica `r` from its uniform-time samples `bed`.
pub fn shaken_state(r: &Replica, bed: &BedSummary) -> Option<ShakenState> {
    let t = &SHAKEN_THRESHOLDS;
    let phi = &bed.packing;
    let (peak, &phi_max) = phi.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    let width = bed
        .height
        .get(1)
        .map_or(bed.height[0] * 2.0, |h| h - bed.height[0]);
    let d = r.largest_diameter();
    // Centres of the grains touching the floor's top sit at 2A + d/2.
    let first_layer = r.floor_motion().0 * 2.0 + 0.5 * d;
    let on_floor = ((first_layer / width) as usize).min(phi.len() - 1);
    let peak_height = (bed.height[peak] - first_layer) / d;
    let inversion = phi_max / phi[on_floor];
    let dense = phi_max >= t.dense;
    let rolls = bed.convection >= t.convection.max(t.significance * bed.convection_noise);
    let label = if rolls {
        "convection"
    } else if phi_max < t.fluid {
        "gas"
    } else if inversion >= t.inversion {
        "leidenfrost"
    } else if dense && r.shake_gamma < 1.0 {
        "solid"
    } else if dense && bed.undulation >= t.undulation {
        "undulations"
    } else if dense {
        "bouncing_bed"
    } else {
        "undetermined"
    };
    Some(ShakenState {
        label,
        phi_max,
        peak_height,
        inversion,
    })
}
