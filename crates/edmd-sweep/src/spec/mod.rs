//! Sweep specifications: the JSON file a user writes, its validation, and its expansion into replicas.
//!
//! A spec names grid axes (each a value or a list), one collision rule, the stop condition, the sample
//! schedule, the snapshots to store and output options. Unknown fields are rejected; every check names
//! the field and the value. The full reference is `docs/sweep-spec.md` and `docs/sweep-spec.schema.json`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::domain;
use crate::SweepError;

mod boundary;
mod check;
mod check_rule;
mod check_scene;
mod check_sections;
mod checkpoint;
mod dup_keys;
mod expand;
mod one_or_many;
mod refinement;
mod sampling;
mod shard;
mod species;

pub use crate::domain::{MAX_REPLICAS, MAX_SAMPLES};
pub use boundary::BoundaryKind;
pub use checkpoint::CheckpointSpec;

pub use check_rule::viscoelastic;
pub use expand::{aspect_label, ball_volume, close_packing, stable_hash, Density, Replica};
pub use one_or_many::OneOrMany;
pub use refinement::{RefineAxis, Refinement};
pub use sampling::{SampleSpec, SnapshotSpec};
pub use shard::Shard;
pub use species::{
    counts as species_counts, label as species_label, AspectAxis, ListAxis, Mixture, Species,
    SpeciesAxis,
};

/// The largest spec file read (1 MiB): a spec is a few hundred bytes; this bounds what a wrong path
/// (`/dev/zero`, a trajectory file) can make the reader allocate.
pub const MAX_SPEC_BYTES: usize = 1 << 20;

/// A remedy against inelastic collapse, applied on top of the rule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Remedy {
    /// No remedy.
    // An empty struct variant rather than a unit one: serde checks unknown fields only on struct
    // variants, and `{"kind": "none", "tc": 1}` must be refused as the schema refuses it.
    None {},
    /// TC model: collisions within `tc` of a partner's previous collision are elastic.
    Tc {
        /// Contact duration t_c (time units of σ√(m/T0)).
        #[schemars(schema_with = "domain::tc_one")]
        tc: f64,
    },
    /// Random rotation of the relative post-collision velocity by up to `theta_max_deg` degrees.
    Rotation {
        /// Largest rotation angle in degrees, in [0, 90].
        #[schemars(schema_with = "domain::theta_one")]
        theta_max_deg: f64,
    },
}

impl Remedy {
    /// A short label for tables and files, e.g. `tc=0.001`.
    pub fn label(&self) -> String {
        match self {
            Remedy::None {} => "none".into(),
            Remedy::Tc { tc } => format!("tc={tc}"),
            Remedy::Rotation { theta_max_deg } => format!("rotation={theta_max_deg}deg"),
        }
    }
}

/// The collision law; the grid's `eps` sets its restitution (see each variant).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum RuleSpec {
    /// Constant normal restitution ε = `eps`.
    // An empty struct variant, so that unknown fields are refused (see `Remedy::None`).
    Constant {},
    /// ε = `eps` above the normal speed `delta`, `eps_low` (default 1) below it.
    Threshold {
        /// Normal-speed threshold δ.
        #[schemars(schema_with = "domain::delta_one")]
        delta: f64,
        /// Restitution below δ (default 1).
        #[serde(default = "one")]
        #[schemars(schema_with = "domain::eps_low_one")]
        eps_low: f64,
    },
    /// The thesis's eq. 5.1 with r0 = `eps` and the given `v0` (default 0.3).
    Thesis {
        /// Crossover speed v0.
        #[serde(default = "default_v0")]
        #[schemars(schema_with = "domain::v0_one")]
        v0: f64,
    },
    /// Viscoelastic spheres, damping chosen so that ε = `eps` at normal speed `speed` (default 1)
    /// for two equal particles.
    Viscoelastic {
        /// Reference normal speed.
        #[serde(default = "one")]
        #[schemars(schema_with = "domain::speed_one")]
        speed: f64,
    },
}

impl Default for RuleSpec {
    fn default() -> Self {
        RuleSpec::Constant {}
    }
}

fn one() -> f64 {
    1.0
}
fn default_v0() -> f64 {
    0.3
}

/// Initial velocity distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema, Default)]
#[serde(rename_all = "lowercase")]
pub enum VelocityKind {
    /// Maxwell–Boltzmann (default).
    #[default]
    Maxwell,
    /// Each component uniform in (−1, 1), as in the thesis.
    Uniform,
}

/// How the initial state is made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct InitSpec {
    /// Velocity distribution.
    #[serde(default)]
    pub velocities: VelocityKind,
    /// Elastic collisions per particle run before the inelastic rule starts (default 0 for a random
    /// start, 20 for a lattice start at high density).
    #[serde(default)]
    #[schemars(schema_with = "domain::melt_optional")]
    pub melt_tau: Option<f64>,
    /// Start from a configuration in a file instead of placing particles (docs/sweep-spec.md,
    /// "Starting from a configuration").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<FromSpec>,
}

/// A configuration to start every replica from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FromSpec {
    /// An edmd replica file or H5MD file (`.h5`), or a plain-text file of D positions, D velocities
    /// and optionally a radius and a mass per line; relative to the working directory.
    pub file: String,
    /// Of a replica file: the snapshot nearest this τ (default: the last).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tau: Option<f64>,
}

impl Default for InitSpec {
    fn default() -> Self {
        InitSpec {
            velocities: VelocityKind::Maxwell,
            melt_tau: None,
            from: None,
        }
    }
}

/// When a replica ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// Pair collisions per particle τ = C/N at which the run ends.
    #[schemars(schema_with = "domain::tau_max_one")]
    pub tau_max: f64,
    /// End earlier, at the first sample where T/T0 falls below this value.
    #[serde(default)]
    #[schemars(schema_with = "domain::temperature_ratio_optional")]
    pub temperature_ratio: Option<f64>,
    /// End earlier, once the replica's class is settled (needs a `classify` section).
    #[serde(default)]
    pub classified: bool,
}

/// Order parameters and the regime classifier (PHYSICS.md §5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ClassifySpec {
    /// Cells per axis of the order-parameter grid (default: about 16 particles per cell).
    #[serde(default)]
    #[schemars(schema_with = "domain::classify_grid_optional")]
    pub grid: Option<usize>,
    /// Thresholds of the classifier.
    #[serde(default)]
    pub thresholds: crate::classify::Thresholds,
}

impl ClassifySpec {
    /// Cells per axis for `n` particles in `d` dimensions: the spec's `grid`, or else about 16
    /// particles per cell (8 per axis for N = 1024 disks), at least 2.
    pub fn grid_for(&self, n: usize, d: usize) -> usize {
        self.grid
            .unwrap_or_else(|| ((n as f64 / 16.0).powf(1.0 / d as f64).round() as usize).max(2))
    }
}

/// Output options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Deflate level of the replica files' datasets, 0 (none) to 9 (default 4).
    #[serde(default = "default_compression")]
    #[schemars(schema_with = "domain::compression_one")]
    pub compression: u8,
    /// The H5MD author name written into every file (default "edmd user").
    #[serde(default = "default_author")]
    pub author: String,
}

fn default_compression() -> u8 {
    4
}
fn default_author() -> String {
    "edmd user".into()
}

impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            compression: default_compression(),
            author: default_author(),
        }
    }
}

/// The grid of replicas: the Cartesian product of its axes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("anyOf" = [
    { "required": ["n", "phi"], "not": { "required": ["box"] } },
    { "required": ["n", "box"], "not": { "required": ["phi"] } },
    { "required": ["phi", "box"], "not": { "required": ["n"] } }
]))]
pub struct Grid {
    /// Dimension, 2 (disks) or 3 (spheres) (default 2).
    #[serde(default = "default_dim")]
    #[schemars(schema_with = "domain::dim_axis")]
    pub dim: OneOrMany<usize>,
    /// Boundary conditions (default periodic).
    #[serde(default = "default_boundary")]
    pub boundary: OneOrMany<BoundaryKind>,
    /// Restitution coefficients ε (the rule says how ε is used).
    #[schemars(schema_with = "domain::eps_axis")]
    pub eps: OneOrMany<f64>,
    /// Packing fractions φ (with `n`, or with `box` for N to follow).
    #[serde(default)]
    #[schemars(schema_with = "domain::phi_axis")]
    pub phi: Option<OneOrMany<f64>>,
    /// Box sides L in particle diameters (square or cubic box; with `n`, or with `phi`).
    #[serde(default, rename = "box")]
    #[schemars(schema_with = "domain::box_axis")]
    pub box_len: Option<OneOrMany<f64>>,
    /// Particle numbers N (omit when both `phi` and `box` are given: N = round(φ L^D / v₁)).
    #[serde(default)]
    #[schemars(schema_with = "domain::n_axis")]
    pub n: Option<OneOrMany<usize>>,
    /// Independent seeds per grid point (default 1).
    #[serde(default = "default_seeds")]
    #[schemars(schema_with = "domain::seeds_one")]
    pub seeds: u32,
    /// Collapse remedies (default none).
    #[serde(default = "default_remedy")]
    pub remedy: OneOrMany<Remedy>,
    /// Tangential restitution β of rough grains, in [−1, 1] (default −1: smooth, no spin).
    #[serde(default = "default_beta", skip_serializing_if = "is_smooth")]
    #[schemars(schema_with = "domain::beta_axis")]
    pub beta: OneOrMany<f64>,
    /// Moment-of-inertia factor q of rough grains, I = q m (σ/2)² (default: uniform, 1/2 for disks
    /// and 2/5 for spheres).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "domain::inertia_optional")]
    pub inertia: Option<f64>,
    /// Species of a mixture, `[{"fraction": x, "diameter": σ, "mass": m}, …]` (mass default σ^D),
    /// or a list of such mixtures (an axis); default one species of diameter 1 and mass 1. φ counts
    /// every species; N is split by the fractions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub species: Option<SpeciesAxis>,
    /// Relative box sides: D positive numbers (default all 1), or a list of such lists (an axis).
    /// Side a is `box`·aspect[a]; with `phi` the box holds N grains at φ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "domain::aspect_axis")]
    pub aspect: Option<AspectAxis>,
    /// Gravity g ≥ 0 along −y (2D) or −z (3D), towards the floor at 0 (default 0); needs walls on
    /// that axis (`"walls"` or `"channel"`).
    #[serde(default = "default_zero", skip_serializing_if = "is_zero")]
    #[schemars(schema_with = "domain::gravity_axis")]
    pub gravity: OneOrMany<f64>,
    /// Shear rate a ≥ 0 of a `"lees-edwards"` box (default 0): the images across the y faces slide
    /// along x at a L_y, driving the uniform shear flow u_x = a (y − L_y/2) (PHYSICS.md §7).
    #[serde(default = "default_zero", skip_serializing_if = "is_zero")]
    #[schemars(schema_with = "domain::shear_rate_axis")]
    pub shear_rate: OneOrMany<f64>,
    /// Normal restitution of the walls, in [0, 1] (default 1: elastic).
    #[serde(default = "default_one", skip_serializing_if = "is_one")]
    #[schemars(schema_with = "domain::wall_eps_axis")]
    pub wall_eps: OneOrMany<f64>,
    /// A thermal floor at this temperature (the wall at 0 of the last axis re-emits grains from its
    /// flux-weighted Maxwellian; PHYSICS.md §1.4); default none. Needs walls on that axis.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "domain::floor_temperature_axis")]
    pub floor_temperature: Option<OneOrMany<f64>>,
    /// The white-noise thermostat's strength ξ₀² (PHYSICS.md §8.1): every grain's velocity
    /// components receive Gaussian kicks of variance ξ₀² per unit time, so that the gas reaches a
    /// steady temperature; default none. Periodic or walled boxes without gravity, shear or floor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "domain::white_noise_axis")]
    pub white_noise: Option<OneOrMany<f64>>,
    /// A vibrating floor's shaking strength S = A²ω²/(g d) (PHYSICS.md §8.2–8.3), d the largest
    /// diameter; with `shake_gamma` it sets the amplitude A = S d/Γ and the angular frequency
    /// ω = √(Γ g/A). Gravity scenes only; default none (a floor that stands still).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "domain::shake_s_axis")]
    pub shake_s: Option<OneOrMany<f64>>,
    /// A vibrating floor's peak acceleration Γ = Aω²/g, given with `shake_s`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "domain::shake_gamma_axis")]
    pub shake_gamma: Option<OneOrMany<f64>>,
}

fn default_dim() -> OneOrMany<usize> {
    OneOrMany::One(2)
}
fn default_boundary() -> OneOrMany<BoundaryKind> {
    OneOrMany::One(BoundaryKind::Periodic)
}
fn default_beta() -> OneOrMany<f64> {
    OneOrMany::One(-1.0)
}
/// Smooth grains leave `beta` out of the canonical spec, so that specs written before rough grains
/// keep their hash.
fn is_smooth(beta: &OneOrMany<f64>) -> bool {
    *beta == default_beta()
}
fn default_zero() -> OneOrMany<f64> {
    OneOrMany::One(0.0)
}
fn is_zero(v: &OneOrMany<f64>) -> bool {
    *v == default_zero()
}
fn default_one() -> OneOrMany<f64> {
    OneOrMany::One(1.0)
}
fn is_one(v: &OneOrMany<f64>) -> bool {
    *v == default_one()
}
fn default_seeds() -> u32 {
    1
}
fn default_remedy() -> OneOrMany<Remedy> {
    OneOrMany::One(Remedy::None {})
}

/// A sweep specification: the JSON file given to `edmd run` (reference: docs/sweep-spec.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(
    title = "edmd sweep spec",
    extend("$id" = "https://github.com/edmd-project/edmd/docs/sweep-spec.schema.json"),
    extend("if" = { "required": ["stop"], "properties": { "stop": { "required": ["classified"], "properties": { "classified": { "const": true } } } } }),
    extend("then" = { "required": ["classify"] })
)]
pub struct Spec {
    /// Name of the sweep (used in tables and file attributes, and as the default output directory
    /// `edmd-out/<name>`): a plain file name of letters, digits, `.`, `_` and `-`, not starting with
    /// `.`, at most 100 characters.
    #[schemars(extend("pattern" = "^[A-Za-z0-9_-][A-Za-z0-9._-]{0,99}$"))]
    pub name: String,
    /// Free text describing the sweep.
    #[serde(default)]
    pub description: String,
    /// Sweep seed; a replica's random stream derives from it and the replica's parameters.
    #[serde(default)]
    pub seed: u64,
    /// The grid of replicas, or a list of grids whose replicas are concatenated.
    pub grid: OneOrMany<Grid>,
    /// The collision rule (default constant restitution).
    #[serde(default)]
    pub rule: RuleSpec,
    /// Initial state.
    #[serde(default)]
    pub init: InitSpec,
    /// Stop condition.
    pub stop: StopSpec,
    /// Sample schedule of the observables.
    #[serde(default)]
    pub samples: SampleSpec,
    /// Snapshot schedule of positions and velocities.
    #[serde(default)]
    pub snapshots: SnapshotSpec,
    /// Output options.
    #[serde(default)]
    pub output: OutputSpec,
    /// Order parameters and classification at every sample (absent: neither is computed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub classify: Option<ClassifySpec>,
    /// The points `edmd refine` added, round by round (written by it into OUT/spec.json; absent in
    /// a spec a person writes). Their replicas follow the grid's, in round order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement: Option<Refinement>,
    /// When running replicas save their state (absent: every 300 s of wall time).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkpoint: Option<CheckpointSpec>,
}

impl Spec {
    /// The JSON Schema of specs, generated from these types (committed as
    /// `docs/sweep-spec.schema.json`; a test fails when the two drift apart).
    pub fn json_schema_text() -> String {
        let schema = schemars::schema_for!(Spec);
        serde_json::to_string_pretty(&schema).expect("a schema serialises") + "\n"
    }

    /// Parses and validates a spec from JSON text (at most [`MAX_SPEC_BYTES`]). A malformed value is
    /// reported with the path of its field (`grid.eps: invalid type: string "x", expected f64`).
    pub fn from_json(text: &str) -> Result<Spec, SweepError> {
        if text.len() > MAX_SPEC_BYTES {
            return Err(SweepError::Spec(format!(
                "the file is larger than {MAX_SPEC_BYTES} bytes, the most a spec may hold (a spec is a few hundred bytes of JSON)"
            )));
        }
        dup_keys::check(text).map_err(SweepError::Spec)?;
        let mut de = serde_json::Deserializer::from_str(text);
        let spec: Spec = serde_path_to_error::deserialize(&mut de).map_err(|e| {
            let mut path = e.path().to_string();
            let mut message = e.into_inner().to_string();
            if let Some((below, rest)) = one_or_many::split_path(&message) {
                path += &below;
                message = rest;
            }
            let path = path.trim_start_matches('.');
            if path.is_empty() {
                SweepError::Spec(message)
            } else {
                SweepError::Spec(format!("{path}: {message}"))
            }
        })?;
        de.end().map_err(|e| SweepError::Spec(e.to_string()))?;
        spec.validate()?;
        Ok(spec)
    }

    /// The canonical JSON form (every default filled in); equal specs give equal text.
    pub fn canonical_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a spec always serialises")
    }

    /// Hash of the canonical form of the spec without its refinement ([`Spec::base`]), stored in
    /// every output file: a refinement adds replicas without changing those before it.
    pub fn hash(&self) -> String {
        format!(
            "{:016x}",
            stable_hash(self.base().canonical_json().as_bytes())
        )
    }

    /// The spec as its author wrote it: without the points `edmd refine` added. Replica files carry
    /// this one, so that a replica's file does not depend on the round that ran it.
    pub fn base(&self) -> Spec {
        Spec {
            refinement: None,
            checkpoint: None,
            ..self.clone()
        }
    }

    /// The grids whose replicas make the sweep: the spec's, then the refinement's points round by
    /// round.
    pub fn grids(&self) -> Vec<Grid> {
        let mut out = self.grid.values();
        if let Some(r) = &self.refinement {
            out.extend(r.rounds.iter().flatten().cloned());
        }
        out
    }
}
