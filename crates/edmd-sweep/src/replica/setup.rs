//! The set-up of a replica: the engine's `InitParams` from the spec and the replica's grid point
//! (box, seed, velocities, species, walls, gravity, a vibrating floor, a thermostat, a start from a
//! given configuration).

use edmd_core::{EdmdError, InitParams, SimParams, Vector, Velocities};

use crate::spec::{Replica, Spec, VelocityKind};

/// On a vibrating floor that is not elastic, contacts slower than this times √(g d) relative to it
/// are elastic (PHYSICS.md §8.3): hops of at most 1.3·10⁻³ d on a still floor.
pub(crate) const SHAKEN_WALL_THRESHOLD: f64 = 0.05;

/// The set-up of replica `r`: box, seed, velocities, species (and the species of each slot), walls,
/// gravity and floor, and the configuration it starts from, if the spec gives one.
pub(super) fn init_params<const D: usize>(
    spec: &Spec,
    r: &Replica,
) -> Result<(InitParams<D>, Vec<usize>), EdmdError> {
    let sides = r.sides();
    let mut p = InitParams::<D>::in_box(r.n, Vector::<D>::from_fn(|a, _| sides[a]));
    p.seed = r.seed;
    p.velocities = match spec.init.velocities {
        VelocityKind::Maxwell => Velocities::Maxwell,
        VelocityKind::Uniform => Velocities::Uniform,
    };
    p.melt_tau = spec.init.melt_tau;
    // A mixture: species k takes the next N_k slots (diameter σ_k, mass m_k); PHYSICS.md §2.4.
    let species_of: Vec<usize> = r
        .species_counts()
        .iter()
        .enumerate()
        .flat_map(|(k, &c)| std::iter::repeat_n(k, c))
        .collect();
    if let Some(m) = &r.species {
        p.radii = Some(species_of.iter().map(|&k| 0.5 * m[k].diameter).collect());
        p.masses = Some(species_of.iter().map(|&k| m[k].mass_in(D)).collect());
    }
    // Walls, gravity and a thermal floor of the scene (PHYSICS.md §1.4), or its shear (§7).
    if r.gravity > 0.0 || r.wall_eps != 1.0 || r.floor_temperature > 0.0 || r.sheared() {
        p.sim = Some(SimParams {
            gravity: r.gravity,
            wall_epsilon: r.wall_eps,
            floor_temperature: r.floor_temperature,
            shear_rate: if r.sheared() { r.shear_rate } else { 0.0 },
            ..p.default_sim_params()
        });
    }
    // The white-noise thermostat (PHYSICS.md §8.1): kicks of zero total momentum, 20 per cooling
    // time of the steady state.
    if r.white_noise > 0.0 {
        p.sim = Some(SimParams {
            white_noise: r.white_noise,
            kick_interval: super::noise::kick_interval(r),
            kick_conserves_momentum: true,
            ..p.sim.unwrap_or_else(|| p.default_sim_params())
        });
    }
    // A vibrating floor (PHYSICS.md §8.3): contacts slower than 0.05 √(g d) relative to it are
    // elastic where the floor is not, so that grains that would rest on it keep hopping.
    if r.shaken() {
        let (amplitude, omega) = r.floor_motion();
        p.sim = Some(SimParams {
            floor_amplitude: amplitude,
            floor_omega: omega,
            wall_threshold: if r.wall_eps < 1.0 {
                SHAKEN_WALL_THRESHOLD * (r.gravity * r.largest_diameter()).sqrt()
            } else {
                0.0
            },
            ..p.sim.unwrap_or_else(|| p.default_sim_params())
        });
    }
    if let Some(from) = &spec.init.from {
        super::given::start_from::<D>(from, r, &mut p)?;
    }
    Ok((p, species_of))
}
