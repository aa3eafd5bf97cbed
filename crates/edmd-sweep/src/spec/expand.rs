//! Expansion of a spec into replicas and their seeds.

use std::fmt;
use std::sync::Arc;

use super::species::{self, Mixture};
use super::{BoundaryKind, Grid, Remedy, Spec};

/// How the box of a replica is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Density {
    /// Packing fraction φ.
    Phi(f64),
    /// Box side L.
    Side(f64),
}

/// One simulation of the sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Replica {
    /// Position in the sweep's expansion order (stable for a given spec).
    pub index: usize,
    /// Dimension.
    pub dim: usize,
    /// Boundary.
    pub boundary: BoundaryKind,
    /// Restitution.
    pub eps: f64,
    /// Tangential restitution (−1: smooth grains, no spin).
    pub beta: f64,
    /// Moment-of-inertia factor q (I = q m (σ/2)²) of rough grains.
    pub inertia: f64,
    /// The species of a mixture (`None`: one species, σ = 1, m = 1).
    pub species: Option<Mixture>,
    /// Relative box sides (`None`: square or cubic).
    pub aspect: Option<Arc<Vec<f64>>>,
    /// Gravity along −(last axis) (0: none).
    pub gravity: f64,
    /// Shear rate of a Lees–Edwards box (0: none).
    pub shear_rate: f64,
    /// Wall restitution (1: elastic).
    pub wall_eps: f64,
    /// Temperature of a thermal floor (0: none).
    pub floor_temperature: f64,
    /// The white-noise thermostat's strength ξ₀² (0: none).
    pub white_noise: f64,
    /// A vibrating floor's shaking strength S = A²ω²/(g d) (0: a floor that stands still).
    pub shake_s: f64,
    /// A vibrating floor's peak acceleration Γ = Aω²/g (0: a floor that stands still).
    pub shake_gamma: f64,
    /// Box as given.
    pub density: Density,
    /// Particle number.
    pub n: usize,
    /// Seed number within the grid point, 0-based.
    pub seed_index: u32,
    /// Remedy.
    pub remedy: Remedy,
    /// Seed of the initial state, derived from the sweep seed and the state's parameters.
    pub seed: u64,
}

impl Replica {
    /// File name of the replica's H5MD file.
    pub fn file_name(&self) -> String {
        format!("r{:05}.h5", self.index)
    }

    /// Box side L: every side of a square or cubic box, the unit of `aspect` otherwise.
    pub fn side(&self) -> f64 {
        match self.density {
            Density::Side(l) => l,
            Density::Phi(phi) => {
                (self.grain_volume() / (phi * self.aspect_volume())).powf(1.0 / self.dim as f64)
            }
        }
    }

    /// The box sides, L·aspect[a].
    pub fn sides(&self) -> Vec<f64> {
        let l = self.side();
        match &self.aspect {
            None => vec![l; self.dim],
            Some(a) => a.iter().map(|x| l * x).collect(),
        }
    }

    /// Π aspect[a] (1 for a square or cubic box).
    fn aspect_volume(&self) -> f64 {
        self.aspect.as_ref().map_or(1.0, |a| a.iter().product())
    }

    /// Packing fraction φ.
    pub fn phi(&self) -> f64 {
        match self.density {
            Density::Phi(phi) => phi,
            Density::Side(l) => {
                self.grain_volume() / (l.powi(self.dim as i32) * self.aspect_volume())
            }
        }
    }

    /// Whether the scene has gravity, a thermal floor, shear or a thermostat (not free cooling: no
    /// free-cooling classification).
    pub fn driven_or_stratified(&self) -> bool {
        self.gravity > 0.0
            || self.floor_temperature > 0.0
            || self.sheared()
            || self.white_noise > 0.0
    }

    /// The largest grain diameter (1 for one species).
    pub fn largest_diameter(&self) -> f64 {
        self.species
            .as_ref()
            .map_or(1.0, |m| m.iter().map(|s| s.diameter).fold(0.0, f64::max))
    }

    /// Whether the floor vibrates.
    pub fn shaken(&self) -> bool {
        self.shake_s > 0.0
    }

    /// A vibrating floor's amplitude A = S d/Γ and angular frequency ω = √(Γ g/A), d the largest
    /// diameter; (0, 1) for a floor that stands still.
    pub fn floor_motion(&self) -> (f64, f64) {
        if !self.shaken() {
            return (0.0, 1.0);
        }
        let amplitude = self.shake_s * self.largest_diameter() / self.shake_gamma;
        (
            amplitude,
            (self.shake_gamma * self.gravity / amplitude).sqrt(),
        )
    }

    /// Whether the box is a Lees–Edwards box (sheared at `shear_rate`, possibly 0).
    pub fn sheared(&self) -> bool {
        self.boundary == BoundaryKind::LeesEdwards
    }

    /// `""` for a free periodic or walled box; `, g=0.1, wall_eps=0.9, floor_T=2, aspect=2x1` for
    /// whatever differs from the defaults.
    pub fn scene_label(&self) -> String {
        let mut out = String::new();
        if self.gravity > 0.0 {
            out += &format!(", g={}", self.gravity);
        }
        if self.sheared() {
            out += &format!(", a={}", self.shear_rate);
        }
        if self.wall_eps != 1.0 {
            out += &format!(", wall_eps={}", self.wall_eps);
        }
        if self.floor_temperature > 0.0 {
            out += &format!(", floor_T={}", self.floor_temperature);
        }
        if self.white_noise > 0.0 {
            out += &format!(", noise={}", self.white_noise);
        }
        if self.shaken() {
            out += &format!(", S={}, Gamma={}", self.shake_s, self.shake_gamma);
        }
        if let Some(a) = &self.aspect {
            out += &format!(", aspect={}", aspect_label(a));
        }
        out
    }

    /// The volume of all grains: N v₁ for one species, Σ N_k v(σ_k) for a mixture.
    pub fn grain_volume(&self) -> f64 {
        match &self.species {
            None => self.n as f64 * ball_volume(self.dim),
            Some(m) => species::counts(m, self.n)
                .iter()
                .zip(m.iter())
                .map(|(&c, s)| {
                    c as f64 * edmd_core::geometry::ball_volume(self.dim, 0.5 * s.diameter)
                })
                .sum(),
        }
    }

    /// Particles per species (one entry, N, without a mixture).
    pub fn species_counts(&self) -> Vec<usize> {
        match &self.species {
            None => vec![self.n],
            Some(m) => species::counts(m, self.n),
        }
    }

    /// `""` without a mixture, `, species=0.5:1:1+0.5:1.4:1.96` with one.
    pub fn species_label(&self) -> String {
        match &self.species {
            None => String::new(),
            Some(m) => format!(", species={}", species::label(m, self.dim)),
        }
    }

    /// Whether the grains are rough (β > −1: they carry spin).
    pub fn rough(&self) -> bool {
        self.beta > -1.0
    }

    /// The grid point (every parameter but the seed) as a key for grouping.
    pub fn point_key(&self) -> String {
        format!(
            "{}|{}|{}|{}|{}|{}{}{}{}",
            self.dim,
            self.boundary.name(),
            self.eps,
            self.density_label(),
            self.n,
            self.remedy.label(),
            self.rough_label(),
            self.species_label(),
            self.scene_label()
        )
    }

    /// `""` for smooth grains, `, beta=0.5` (and the inertia factor when not uniform) for rough ones.
    pub fn rough_label(&self) -> String {
        if !self.rough() {
            return String::new();
        }
        let uniform = if self.dim == 2 { 0.5 } else { 0.4 };
        if self.inertia == uniform {
            format!(", beta={}", self.beta)
        } else {
            format!(", beta={}, inertia={}", self.beta, self.inertia)
        }
    }

    /// `phi=0.25` or `L=56.7`.
    pub fn density_label(&self) -> String {
        match self.density {
            Density::Phi(p) => format!("phi={p}"),
            Density::Side(l) => format!("L={l}"),
        }
    }
}

impl fmt::Display for Replica {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "replica {} (D={}, {}, eps={}{}{}{}, {}, N={}, seed #{}, remedy {})",
            self.index,
            self.dim,
            self.boundary.name(),
            self.eps,
            self.rough_label(),
            self.species_label(),
            self.scene_label(),
            self.density_label(),
            self.n,
            self.seed_index,
            self.remedy.label()
        )
    }
}

/// `2x1` (the relative sides joined by `x`).
pub fn aspect_label(a: &[f64]) -> String {
    a.iter().map(|&x| compact(x)).collect::<Vec<_>>().join("x")
}

/// `x` as Rust writes it (`0.25`, `1000`, `1.6666666666666667`) where that needs no run of zeros,
/// else in exponent form (`1e-7`, `1e300`): a message never carries a 300-digit decimal.
pub fn compact(x: f64) -> String {
    if x == 0.0 || (1e-5..1e16).contains(&x.abs()) || !x.is_finite() {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// Volume of a particle of diameter 1 in `d` dimensions.
pub fn ball_volume(d: usize) -> f64 {
    edmd_core::geometry::ball_volume(d, 0.5)
}

pub use edmd_core::geometry::close_packing;

/// SplitMix64 finaliser: a well-mixed 64-bit hash step.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A stable 64-bit hash of bytes (FNV-1a, then mixed); the same on every platform and version.
pub fn stable_hash(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    mix(h)
}

impl Spec {
    /// The replicas in expansion order: grid by grid (the refinement's points last, in round order);
    /// within a grid dim, species, aspect, boundary,
    /// remedy, n, density, eps, beta, gravity, shear_rate, wall_eps, floor_temperature, white_noise,
    /// shake_s, shake_gamma, seed (seed fastest).
    pub fn replicas(&self) -> Vec<Replica> {
        let mut out = Vec::new();
        for g in self.grids() {
            self.expand(&g, &mut out);
        }
        out
    }

    fn expand(&self, g: &Grid, out: &mut Vec<Replica>) {
        let ns = g.n.as_ref().map(|n| n.values()).unwrap_or_default();
        let phis = g.phi.as_ref().map(|p| p.values()).unwrap_or_default();
        let sides = g.box_len.as_ref().map(|l| l.values()).unwrap_or_default();
        let mixtures: Vec<Option<Mixture>> = match &g.species {
            None => vec![None],
            Some(axis) => axis.0.iter().cloned().map(Some).collect(),
        };
        let aspects: Vec<Option<Arc<Vec<f64>>>> = match &g.aspect {
            None => vec![None],
            Some(axis) => axis.0.iter().cloned().map(Some).collect(),
        };
        let floors = g
            .floor_temperature
            .as_ref()
            .map_or(vec![0.0], |f| f.values());
        let noises = g.white_noise.as_ref().map_or(vec![0.0], |f| f.values());
        // The scene axes varying inside beta: gravity, shear rate, wall restitution, floor
        // temperature, white noise, the floor's shaking (S, then Γ).
        let shakes: Vec<(f64, f64)> = match (&g.shake_s, &g.shake_gamma) {
            (Some(s), Some(gamma)) => s
                .values()
                .into_iter()
                .flat_map(|s| gamma.values().into_iter().map(move |gamma| (s, gamma)))
                .collect(),
            _ => vec![(0.0, 0.0)],
        };
        let mut scenes = Vec::new();
        for gravity in g.gravity.values() {
            for shear_rate in g.shear_rate.values() {
                for wall_eps in g.wall_eps.values() {
                    for &floor in &floors {
                        for &noise in &noises {
                            for &shake in &shakes {
                                scenes.push((gravity, shear_rate, wall_eps, floor, noise, shake));
                            }
                        }
                    }
                }
            }
        }
        for dim in g.dim.values() {
            let inertia = g.inertia.unwrap_or(if dim == 2 { 0.5 } else { 0.4 });
            for mixture in &mixtures {
                let v_mean = mean_grain_volume(dim, mixture.as_ref());
                for aspect in &aspects {
                    let aspect_volume: f64 = aspect.as_ref().map_or(1.0, |a| a.iter().product());
                    let pairs = size_pairs(&ns, &phis, &sides, dim, (aspect_volume, v_mean));
                    for boundary in g.boundary.values() {
                        for remedy in g.remedy.values() {
                            for &(n, density) in &pairs {
                                for eps in g.eps.values() {
                                    for beta in g.beta.values() {
                                        for &(
                                            gravity,
                                            shear_rate,
                                            wall_eps,
                                            floor_temperature,
                                            white_noise,
                                            (shake_s, shake_gamma),
                                        ) in &scenes
                                        {
                                            for seed_index in 0..g.seeds {
                                                let mut r = Replica {
                                                    index: out.len(),
                                                    dim,
                                                    boundary,
                                                    eps,
                                                    beta,
                                                    inertia,
                                                    species: mixture.clone(),
                                                    aspect: aspect.clone(),
                                                    gravity,
                                                    shear_rate,
                                                    wall_eps,
                                                    floor_temperature,
                                                    white_noise,
                                                    shake_s,
                                                    shake_gamma,
                                                    density,
                                                    n,
                                                    seed_index,
                                                    remedy,
                                                    seed: 0,
                                                };
                                                r.seed = self.replica_seed(&r);
                                                out.push(r);
                                            }
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
    }

    /// The seed of a replica's initial state. It derives from the sweep seed and the parameters that
    /// define the initial state (D, boundary, box, N, seed number), not from ε, β or the remedy: replicas
    /// that differ only in ε (or β) start from the same state (common random numbers), which sharpens
    /// comparisons across ε. It does not depend on the replica's index, the thread count or the shard.
    pub fn replica_seed(&self, r: &Replica) -> u64 {
        let key = format!(
            "{}|{}|{}|{}|{}|{}{}{}",
            self.seed,
            r.dim,
            r.boundary.name(),
            r.density_label(),
            r.n,
            r.seed_index,
            r.species_label(),
            r.aspect
                .as_ref()
                .map(|a| format!(", aspect={}", aspect_label(a)))
                .unwrap_or_default()
        );
        stable_hash(key.as_bytes())
    }
}

/// The mean grain volume: v₁ for one species, Σ x_k v(σ_k) for a mixture.
fn mean_grain_volume(dim: usize, mixture: Option<&Mixture>) -> f64 {
    match mixture {
        None => ball_volume(dim),
        Some(m) => m
            .iter()
            .map(|s| s.fraction * edmd_core::geometry::ball_volume(dim, 0.5 * s.diameter))
            .sum(),
    }
}

/// The (N, box) pairs of a grid: N × φ, N × L, or N = round(φ L^D Π aspect / v̄) for φ × L, from
/// the aspect's volume Π aspect and the mean grain volume v̄.
fn size_pairs(
    ns: &[usize],
    phis: &[f64],
    sides: &[f64],
    dim: usize,
    (aspect_volume, v_mean): (f64, f64),
) -> Vec<(usize, Density)> {
    match (phis.is_empty(), sides.is_empty()) {
        (false, true) => ns
            .iter()
            .flat_map(|&n| phis.iter().map(move |&p| (n, Density::Phi(p))))
            .collect(),
        (true, false) => ns
            .iter()
            .flat_map(|&n| sides.iter().map(move |&l| (n, Density::Side(l))))
            .collect(),
        _ => phis
            .iter()
            .flat_map(|&p| {
                sides.iter().map(move |&l| {
                    let n = (p * l.powi(dim as i32) * aspect_volume / v_mean).round();
                    ((n as usize).max(2), Density::Side(l))
                })
            })
            .collect(),
    }
}
