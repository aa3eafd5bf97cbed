//! The state of a bed on a vibrating floor (PHYSICS.md §8.4), from its density profile averaged
//! over the second half of the samples: where the densest layer is, how dense, and how much denser
//! than the layer on the floor. The thresholds are in one struct, [`SHAKEN_THRESHOLDS`].
//!
//! Labelled: `gas` (no layer as dense as a liquid), `leidenfrost` (a dense layer floating above a
//! floor layer it outweighs), `bouncing_bed` (a dense bed whose layer on the floor is at least
//! 1/`inversion` as dense as its densest; `solid` below lift-off, Γ < 1), `undetermined` (a
//! fluidised bed between these).
//! Undulations and convection need the centre of mass's spectrum and the velocity field; they are
//! not labelled yet.

use crate::spec::Replica;

use super::Series;

/// The thresholds of [`shaken_state`], in packing fractions and grain diameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShakenThresholds {
    /// A layer at least this dense is a dense (solid-like or cluster) layer.
    pub dense: f64,
    /// Below this packing fraction everywhere, the bed is a gas.
    pub fluid: f64,
    /// A floating dense layer is a Leidenfrost state when at least this many times denser than
    /// the layer on the floor.
    pub inversion: f64,
}

/// The thresholds the runner uses.
pub const SHAKEN_THRESHOLDS: ShakenThresholds = ShakenThresholds {
    dense: 0.5,
    fluid: 0.3,
    inversion: 2.0,
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

/// The state of shaken replica `r` from its density profiles in `bins` bins (None unless shaken
/// and sampled, or without a profile).
pub fn shaken_state(r: &Replica, s: &Series, bins: usize) -> Option<ShakenState> {
    let late = &s.density_profile[s.density_profile.len() / 2..];
    if !r.shaken() || bins == 0 || late.is_empty() {
        return None;
    }
    let t = &SHAKEN_THRESHOLDS;
    let width = r.sides()[r.dim - 1] / bins as f64;
    let grain = r.grain_volume() / r.n as f64;
    let phi: Vec<f64> = (0..bins)
        .map(|b| late.iter().map(|row| row[b]).sum::<f64>() / late.len() as f64 * grain)
        .collect();
    let (peak, &phi_max) = phi.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    let d = r.largest_diameter();
    // Centres of the grains touching the floor's top sit at 2A + d/2.
    let first_layer = r.floor_motion().0 * 2.0 + 0.5 * d;
    let on_floor = ((first_layer / width) as usize).min(bins - 1);
    let peak_height = ((peak as f64 + 0.5) * width - first_layer) / d;
    let inversion = phi_max / phi[on_floor];
    let label = if phi_max < t.fluid {
        "gas"
    } else if inversion >= t.inversion {
        "leidenfrost"
    } else if phi_max >= t.dense && r.shake_gamma < 1.0 {
        "solid"
    } else if phi_max >= t.dense {
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
