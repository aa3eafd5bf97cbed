//! [`SimParams`]: the settings of the event loop, their domains, and defaults tuned to the density.

use crate::EdmdError;

/// Settings of the event loop. Every field has a default that suits typical runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimParams {
    /// Target cell side in units of the largest diameter (≥ 1; default 1). Larger cells mean fewer
    /// crossings and more neighbours; dilute gases gain from values above 1.
    pub cell_factor: f64,
    /// Events between rebasing the clock and re-tuning the calendar, per particle (default 8).
    pub rebase_events_per_particle: f64,
    /// Normal restitution of particle–wall collisions, in [0, 1] (default 1: elastic walls).
    pub wall_epsilon: f64,
    /// Deep cooling: when the simulated temperature falls below this fraction of its starting value
    /// (checked every rebase), all velocities are scaled back up and the factor is tracked
    /// (default 1e-4; 0 disables). Reported quantities stay in physical units.
    pub rescale_below: f64,
    /// Seed of the random stream used by random collision rules (default 0).
    pub seed: u64,
    /// Gravitational acceleration towards the floor of the last axis, for gravity scenes
    /// ([`crate::GravityAxes`]); must be 0 elsewhere (default 0).
    pub gravity: f64,
    /// Wall contacts slower than this normal speed are elastic (default 0: off). Under gravity it keeps
    /// grains resting on the floor from bouncing ever faster (a collapse against the wall): their
    /// bounces keep a height of at least ~ε_w²δ²/(2g).
    pub wall_threshold: f64,
    /// Neighbour lists instead of cell crossings (0, the default, for cells): the skin `δ` in units
    /// of the largest diameter (see [`crate::sim::neighbours`]). Pays in dense packings, where particles need
    /// many collisions to move `δ/2`; ignored under gravity and where the box holds fewer than three
    /// cells of side `σ + δ`.
    pub neighbour_skin: f64,
    /// A thermal floor (0, the default, for none): the wall at 0 of the last axis re-emits every
    /// grain that hits it with a velocity drawn from its flux-weighted Maxwellian at this temperature
    /// (normal speed Rayleigh-distributed, tangential components Gaussian; spins kept). Needs walls on
    /// the last axis; it replaces that wall's restitution.
    pub floor_temperature: f64,
    /// A vibrating floor's amplitude A (0, the default, for a floor that stands still): under
    /// gravity the floor of the last axis moves as z_w(t) = A (1 − cos ωt), from its lowest point
    /// at time 0 (PHYSICS.md §8.3). Grains meet it with the wall's restitution in its own frame.
    pub floor_amplitude: f64,
    /// The vibrating floor's angular frequency ω (> 0; default 1).
    pub floor_omega: f64,
    /// The shear rate `a` of a [`crate::LeesEdwards`] scene (flow u_x = a (y − L_y/2)), ≥ 0; must
    /// be 0 elsewhere (default 0).
    pub shear_rate: f64,
    /// The white-noise thermostat's strength ξ₀² (0, the default, for none): every grain's velocity
    /// components receive independent Gaussian kicks of variance ξ₀² per unit time, all at once
    /// every [`Self::kick_interval`] (PHYSICS.md §8.1). Deep-cooling rescales and drift removal are
    /// off while it drives the gas.
    pub white_noise: f64,
    /// Time between the thermostat's kicks (> 0 where `white_noise` > 0; default 1).
    pub kick_interval: f64,
    /// Kicks of zero total momentum (the mass-weighted mean kick removed from each).
    pub kick_conserves_momentum: bool,
}

impl Default for SimParams {
    fn default() -> Self {
        SimParams {
            cell_factor: 1.0,
            rebase_events_per_particle: 8.0,
            wall_epsilon: 1.0,
            rescale_below: 1e-4,
            seed: 0,
            gravity: 0.0,
            wall_threshold: 0.0,
            neighbour_skin: 0.0,
            floor_temperature: 0.0,
            floor_amplitude: 0.0,
            floor_omega: 1.0,
            shear_rate: 0.0,
            white_noise: 0.0,
            kick_interval: 1.0,
            kick_conserves_momentum: false,
        }
    }
}

impl SimParams {
    /// Checks every field against its domain; the error names the field and the value.
    pub fn validate(&self) -> Result<(), EdmdError> {
        let checks: [(&'static str, f64, bool, &str); 13] = [
            (
                "floor_amplitude",
                self.floor_amplitude,
                self.floor_amplitude >= 0.0 && self.floor_amplitude.is_finite(),
                "must be ≥ 0 and finite (0: a floor that stands still)",
            ),
            (
                "floor_omega",
                self.floor_omega,
                self.floor_omega > 0.0 && self.floor_omega.is_finite(),
                "must be > 0 and finite",
            ),
            (
                "white_noise",
                self.white_noise,
                self.white_noise >= 0.0 && self.white_noise.is_finite(),
                "must be ≥ 0 and finite (0: no thermostat)",
            ),
            (
                "kick_interval",
                self.kick_interval,
                self.kick_interval > 0.0 && self.kick_interval.is_finite(),
                "must be > 0 and finite",
            ),
            (
                "shear_rate",
                self.shear_rate,
                self.shear_rate >= 0.0 && self.shear_rate.is_finite(),
                "must be ≥ 0 and finite (the flow is u_x = a (y − L_y/2); mirror y for the other sense)",
            ),
            (
                "floor_temperature",
                self.floor_temperature,
                self.floor_temperature >= 0.0 && self.floor_temperature.is_finite(),
                "must be ≥ 0 and finite (0: no thermal floor)",
            ),
            (
                "cell_factor",
                self.cell_factor,
                self.cell_factor >= 1.0 && self.cell_factor.is_finite(),
                "must be ≥ 1",
            ),
            (
                "wall_epsilon",
                self.wall_epsilon,
                (0.0..=1.0).contains(&self.wall_epsilon),
                "restitution must lie in [0, 1]",
            ),
            (
                "gravity",
                self.gravity,
                self.gravity >= 0.0 && self.gravity.is_finite(),
                "must be ≥ 0 and finite",
            ),
            (
                "wall_threshold",
                self.wall_threshold,
                self.wall_threshold >= 0.0 && self.wall_threshold.is_finite(),
                "must be ≥ 0 and finite",
            ),
            (
                "rescale_below",
                self.rescale_below,
                (0.0..1.0).contains(&self.rescale_below),
                "must lie in [0, 1)",
            ),
            (
                "neighbour_skin",
                self.neighbour_skin,
                self.neighbour_skin >= 0.0 && self.neighbour_skin.is_finite(),
                "must be ≥ 0 and finite",
            ),
            (
                "rebase_events_per_particle",
                self.rebase_events_per_particle,
                self.rebase_events_per_particle > 0.0,
                "must be > 0",
            ),
        ];
        match checks.into_iter().find(|c| !c.2) {
            Some((field, value, _, reason)) => Err(EdmdError::invalid(field, value, reason)),
            None => Ok(()),
        }
    }

    /// A cell factor that balances crossings against neighbour checks for a packing fraction `phi`.
    pub fn for_density<const D: usize>(phi: f64) -> Self {
        // Cells of one diameter are fastest at φ ≥ 0.3; dilute gases keep about 0.4 particles per
        // cell, so that crossings do not dominate (docs/benchmarks.md).
        let per_cell_volume = crate::geometry::ball_volume(D, 0.5);
        let side = (0.4 * per_cell_volume / phi.max(1e-12)).powf(1.0 / D as f64);
        // Neighbour lists pay in dense 3D packings only (from φ ≈ 0.38; in 2D cells win). The
        // skin: with the four-wide scans a partner costs less than a renewal's gather, and 0.65
        // takes the fewest instructions per collision (docs/benchmarks.md, "The four-wide list
        // scan").
        let neighbour_skin = if D == 3 && phi >= 0.38 { 0.65 } else { 0.0 };
        SimParams {
            cell_factor: side.max(1.0),
            neighbour_skin,
            ..Default::default()
        }
    }
}
