//! Initial states: random non-overlapping placement in O(N), centred lattices for dense states, and
//! velocities (uniform in (−v, v) as in the thesis, or Maxwellian) with zero total momentum and the
//! exact target temperature.

use rand::SeedableRng;
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::calendar::{Calendar, PaulCalendar};
use crate::{
    Boundary, CollisionRule, EdmdError, Elastic, ParticleInit, SimParams, Simulation, Stop, Vector,
};

mod place;
#[cfg(test)]
mod tests;
mod velocities;

use place::{lattice_positions, random_positions};
pub use velocities::draw_velocities;

/// Particle number from which [`InitParams::default_sim_params`] widens a neighbour-list skin.
pub const LARGE_LIST_N: usize = 500_000;
/// The skin (in largest diameters) of list-mode systems of [`LARGE_LIST_N`] particles or more.
pub const LARGE_LIST_SKIN: f64 = 0.7;

/// How particles are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Placement {
    /// Random sequential addition through the cell grid (2D up to φ ≈ 0.45, 3D up to ≈ 0.3).
    Random,
    /// A centred lattice (2D up to φ ≈ 0.9, 3D up to ≈ 0.68), then melted elastically.
    Lattice,
    /// Random below φ = 0.4 (2D) or 0.25 (3D), lattice above (mixtures: always random).
    Auto,
}

/// Velocity distribution before momentum removal and temperature scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Velocities {
    /// Each component uniform in (−1, 1), as in the thesis (kurtosis 1.4 in 2D instead of 2).
    Uniform,
    /// Maxwell–Boltzmann.
    Maxwell,
}

/// Parameters of an initial state of monodisperse (or, with `radii`, polydisperse) particles.
#[derive(Debug, Clone, PartialEq)]
pub struct InitParams<const D: usize> {
    /// Number of particles.
    pub n: usize,
    /// Box sides.
    pub box_len: Vector<D>,
    /// Radius of every particle (default 0.5, i.e. σ = 1), unless `radii` is set.
    pub radius: f64,
    /// Per-particle radii (polydisperse); overrides `radius`.
    pub radii: Option<Vec<f64>>,
    /// Mass of a particle of radius `radius` (default 1); with `radii`, masses scale as r^D.
    pub mass: f64,
    /// Per-particle masses (a mixture of materials); overrides `mass` and the r^D scaling.
    pub masses: Option<Vec<f64>>,
    /// Placement method (default `Auto`).
    pub placement: Placement,
    /// Velocity distribution (default `Maxwell`).
    pub velocities: Velocities,
    /// Target temperature T0 (default 1).
    pub temperature: f64,
    /// Seed of the random stream.
    pub seed: u64,
    /// Elastic collisions per particle run after placement (default 0 for random placement, 20 for a
    /// lattice); counters are reset afterwards.
    pub melt_tau: Option<f64>,
    /// Event-loop settings (default: tuned to the density).
    pub sim: Option<SimParams>,
    /// A configuration to start from (positions, velocities, radii, masses) instead of placing
    /// particles and drawing velocities; no melt unless `melt_tau` asks for one.
    pub given: Option<Vec<ParticleInit<D>>>,
    /// Angular velocities of the given configuration (original order, physical units, z only in
    /// 2D), set once the rule is in place; ignored by smooth rules.
    pub given_spins: Option<Vec<[f64; 3]>>,
}

impl<const D: usize> InitParams<D> {
    /// `n` particles of diameter 1 at packing fraction `phi` in a square (cubic) box.
    pub fn with_packing(n: usize, phi: f64) -> Result<Self, EdmdError> {
        if n == 0 {
            return Err(EdmdError::invalid("N", n, "need at least one particle"));
        }
        if !(phi > 0.0 && phi < 1.0) {
            return Err(EdmdError::invalid(
                "phi",
                phi,
                "packing fraction must lie in (0, 1)",
            ));
        }
        let side = (n as f64 * unit_volume::<D>(0.5) / phi).powf(1.0 / D as f64);
        Ok(Self::in_box(n, Vector::<D>::repeat(side)))
    }

    /// `n` particles of diameter 1 in a given box.
    pub fn in_box(n: usize, box_len: Vector<D>) -> Self {
        InitParams {
            n,
            box_len,
            radius: 0.5,
            radii: None,
            mass: 1.0,
            masses: None,
            placement: Placement::Auto,
            velocities: Velocities::Maxwell,
            temperature: 1.0,
            seed: 0,
            melt_tau: None,
            sim: None,
            given: None,
            given_spins: None,
        }
    }

    /// The event-loop settings `build` uses when `sim` is not set: tuned to the density, with the
    /// random stream of random collision rules (and of a thermal floor) derived from the seed.
    pub fn default_sim_params(&self) -> SimParams {
        let mut params = SimParams {
            seed: self.seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 1,
            ..SimParams::for_density::<D>(self.packing_fraction())
        };
        // Large list-mode systems take a wider skin: there a list renewal's 3^D-cell gather misses
        // the caches, so fewer renewals pay for the longer lists (docs/benchmarks.md).
        if params.neighbour_skin > 0.0 && self.n >= LARGE_LIST_N {
            params.neighbour_skin = LARGE_LIST_SKIN;
        }
        params
    }

    /// Packing fraction of the state.
    pub fn packing_fraction(&self) -> f64 {
        let vol: f64 = match &self.radii {
            Some(r) => r.iter().map(|&r| unit_volume::<D>(r)).sum(),
            None => self.n as f64 * unit_volume::<D>(self.radius),
        };
        vol / self.box_len.iter().product::<f64>()
    }

    fn validate(&self) -> Result<(), EdmdError> {
        if let Some(g) = self.given.as_ref().filter(|g| g.len() != self.n) {
            return Err(EdmdError::invalid(
                "N",
                self.n,
                format!("the given configuration holds {} particles", g.len()),
            ));
        }
        if self.n < 2 {
            return Err(EdmdError::invalid(
                "N",
                self.n,
                "need at least two particles (momentum is set to zero)",
            ));
        }
        if !(self.radius > 0.0 && self.radius.is_finite()) {
            return Err(EdmdError::invalid(
                "radius",
                self.radius,
                "must be positive",
            ));
        }
        if let Some(r) = &self.radii {
            if r.len() != self.n {
                return Err(EdmdError::invalid(
                    "radii",
                    r.len(),
                    format!("need one radius per particle (N = {})", self.n),
                ));
            }
            if let Some(bad) = r.iter().find(|&&r| !(r > 0.0 && r.is_finite())) {
                return Err(EdmdError::invalid(
                    "radii",
                    bad,
                    "every radius must be positive",
                ));
            }
        }
        if let Some(m) = &self.masses {
            if m.len() != self.n {
                return Err(EdmdError::invalid(
                    "masses",
                    m.len(),
                    format!("need one mass per particle (N = {})", self.n),
                ));
            }
            if let Some(bad) = m.iter().find(|&&m| !(m > 0.0 && m.is_finite())) {
                return Err(EdmdError::invalid(
                    "masses",
                    bad,
                    "every mass must be positive",
                ));
            }
        }
        if !(self.mass > 0.0 && self.mass.is_finite()) {
            return Err(EdmdError::invalid("mass", self.mass, "must be positive"));
        }
        if !(self.temperature > 0.0 && self.temperature.is_finite()) {
            return Err(EdmdError::invalid(
                "temperature",
                self.temperature,
                "must be positive",
            ));
        }
        if let Some(m) = self.melt_tau {
            if !(m >= 0.0 && m.is_finite()) {
                return Err(EdmdError::invalid("melt_tau", m, "must be ≥ 0"));
            }
        }
        let phi = self.packing_fraction();
        if !(phi < 1.0) {
            return Err(EdmdError::invalid(
                "phi",
                phi,
                "packing fraction must be below 1",
            ));
        }
        Ok(())
    }

    /// Whether the start is a lattice: asked for, or (automatic placement) equal grains denser
    /// than random placement reaches, φ > 0.4 (2D) or 0.25 (3D). A mixture is placed at random
    /// (a lattice needs equal radii; its φ, counted from whole grains, can lie a hair above the
    /// limit it was asked at).
    fn on_lattice(&self, phi: f64) -> bool {
        match self.placement {
            Placement::Random => false,
            Placement::Lattice => true,
            Placement::Auto => self.radii.is_none() && phi > if D == 2 { 0.4 } else { 0.25 },
        }
    }

    /// The checks of [`Self::build`] that need no simulation, in a fraction of its time: the
    /// parameters, a lattice start's reach (the lattice is laid out, with no melt) and the cell
    /// grid of the box. A start that passes can still fail only in random placement (too dense for
    /// the random start's tries). Used to refuse a spec before anything runs.
    pub fn preflight<B: Boundary>(&self) -> Result<(), EdmdError> {
        self.validate()?;
        if let Some(given) = &self.given {
            // A given configuration is checked whole: inside the box, finite, no overlap.
            let params = self.sim.unwrap_or_else(|| self.default_sim_params());
            return Simulation::<D, B, Elastic>::new(self.box_len, given.to_vec(), Elastic, params)
                .map(|_| ());
        }
        let phi = self.packing_fraction();
        let lattice = self.on_lattice(phi);
        if lattice {
            if self.radii.is_some() {
                return Err(EdmdError::invalid(
                    "placement",
                    "lattice",
                    "lattice starts need equal radii; use random placement",
                ));
            }
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(self.seed);
            lattice_positions::<D, B>(self.n, &self.box_len, self.radius, phi, &mut rng)?;
        }
        let max_d = 2.0
            * self
                .radii
                .as_ref()
                .map_or(self.radius, |r| r.iter().copied().fold(0.0, f64::max));
        let params = self.sim.unwrap_or_else(|| self.default_sim_params());
        crate::sim::check_scene::<D, B>(self.n, &self.box_len, &params)?;
        let skin = params.neighbour_skin * max_d;
        if !lattice {
            // Random placement files the grains in a grid of one diameter.
            crate::CellGrid::<D>::check(&self.box_len, max_d, max_d)?;
        }
        let lists = skin > 0.0
            && crate::sim::lists_possible::<B>()
            && crate::CellGrid::<D>::check(&self.box_len, max_d + skin, max_d * params.cell_factor)
                .is_ok();
        if !lists {
            crate::CellGrid::<D>::check(&self.box_len, max_d, max_d * params.cell_factor)?;
        }
        Ok(())
    }

    /// Builds the simulation: places particles, draws velocities, melts a lattice elastically, sets
    /// zero momentum and the exact temperature, and resets the counters.
    pub fn build<B: Boundary, R: CollisionRule>(
        &self,
        rule: R,
    ) -> Result<Simulation<D, B, R>, EdmdError> {
        self.build_with_calendar::<B, R, PaulCalendar>(rule)
    }

    /// [`Self::build`] with a chosen event calendar (e.g. [`crate::HeapCalendar`] as an oracle).
    pub fn build_with_calendar<B: Boundary, R: CollisionRule, C: Calendar>(
        &self,
        rule: R,
    ) -> Result<Simulation<D, B, R, C>, EdmdError> {
        self.validate()?;
        if let Some(given) = &self.given {
            return self.build_given(given, rule);
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(self.seed);
        let radii: Vec<f64> = self
            .radii
            .clone()
            .unwrap_or_else(|| vec![self.radius; self.n]);
        let phi = self.packing_fraction();
        let lattice = self.on_lattice(phi);
        let positions = if lattice {
            if self.radii.is_some() {
                return Err(EdmdError::invalid(
                    "placement",
                    "lattice",
                    "lattice starts need equal radii; use random placement",
                ));
            }
            lattice_positions::<D, B>(self.n, &self.box_len, self.radius, phi, &mut rng)?
        } else {
            random_positions::<D, B>(&radii, &self.box_len, phi, &mut rng)?
        };
        let masses: Vec<f64> = match &self.masses {
            Some(m) => m.clone(),
            None => radii
                .iter()
                .map(|&r| self.mass * (r / self.radius).powi(D as i32))
                .collect(),
        };
        // A sheared box starts at rest in the lab (PHYSICS.md §7): the flow builds up from the
        // sliding faces, so the peculiar T(0) is T0 + a² L_y²/(12 d).
        let velocities = draw_velocities::<D>(&masses, self.velocities, self.temperature, &mut rng);
        let params = self.sim.unwrap_or_else(|| self.default_sim_params());
        let particles: Vec<ParticleInit<D>> = (positions.into_iter().zip(velocities))
            .zip(radii.into_iter().zip(masses))
            .map(|((pos, vel), (radius, mass))| ParticleInit {
                pos,
                vel,
                radius,
                mass,
            })
            .collect();
        let melt = self.melt_tau.unwrap_or(if lattice { 20.0 } else { 0.0 });
        let sim = if melt > 0.0 {
            let mut sim =
                Simulation::<D, B, Elastic, C>::new(self.box_len, particles, Elastic, params)?;
            sim.run(Stop::Tau(melt));
            sim.with_rule(rule)
        } else {
            Simulation::<D, B, R, C>::new(self.box_len, particles, rule, params)?
        };
        let mut sim = sim;
        let t = sim.temperature();
        if melt > 0.0 && t > 0.0 {
            sim.scale_velocities((self.temperature / t).sqrt());
        }
        sim.reset_counters();
        Ok(sim)
    }
}

impl<const D: usize> InitParams<D> {
    /// [`Self::build_with_calendar`] from a given configuration: its particles as they are, melted
    /// elastically only if `melt_tau` asks (then scaled back to its temperature).
    fn build_given<B: Boundary, R: CollisionRule, C: Calendar>(
        &self,
        given: &[ParticleInit<D>],
        rule: R,
    ) -> Result<Simulation<D, B, R, C>, EdmdError> {
        let params = self.sim.unwrap_or_else(|| self.default_sim_params());
        let melt = self.melt_tau.unwrap_or(0.0);
        let particles = given.to_vec();
        let mut sim = if melt > 0.0 {
            let mut sim =
                Simulation::<D, B, Elastic, C>::new(self.box_len, particles, Elastic, params)?;
            let t0 = sim.temperature();
            sim.run(Stop::Tau(melt));
            let t = sim.temperature();
            if t > 0.0 && t0 > 0.0 {
                sim.scale_velocities((t0 / t).sqrt());
            }
            sim.with_rule(rule)
        } else {
            Simulation::<D, B, R, C>::new(self.box_len, particles, rule, params)?
        };
        if let Some(spins) = &self.given_spins {
            sim.set_spins(spins)?;
        }
        sim.reset_counters();
        Ok(sim)
    }
}

/// Volume of a D-ball of radius r.
pub fn unit_volume<const D: usize>(r: f64) -> f64 {
    crate::geometry::ball_volume(D, r)
}
