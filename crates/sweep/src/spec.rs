//! Sweep specifications: the JSON file a user writes, its validation, and its expansion into replicas.
//!
//! A spec names grid axes (each a value or a list), one collision rule, the stop condition, the sample
//! schedule, the snapshots to store and output options. Unknown fields are rejected; every check names
//! the field and the value. The full reference is `docs/sweep-spec.md` and `docs/sweep-spec.schema.json`.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::SweepError;

/// A value or a list of values (`"eps": 0.9` or `"eps": [0.9, 0.8]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum OneOrMany<T> {
    /// A single value.
    One(T),
    /// A list of values (must not be empty).
    Many(Vec<T>),
}

/// Deserialised by hand rather than with `#[serde(untagged)]`, so that an error inside a value
/// (an unknown field of a grid, say) is reported as such instead of "did not match any variant".
impl<'de, T: serde::de::DeserializeOwned> Deserialize<'de> for OneOrMany<T> {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        use serde::de::Error;
        match serde_json::Value::deserialize(d)? {
            serde_json::Value::Array(items) => items
                .into_iter()
                .map(serde_json::from_value)
                .collect::<Result<Vec<T>, _>>()
                .map(OneOrMany::Many)
                .map_err(De::Error::custom),
            v => serde_json::from_value(v)
                .map(OneOrMany::One)
                .map_err(De::Error::custom),
        }
    }
}

impl<T: Clone> OneOrMany<T> {
    /// The values as a list.
    pub fn values(&self) -> Vec<T> {
        match self {
            OneOrMany::One(v) => vec![v.clone()],
            OneOrMany::Many(v) => v.clone(),
        }
    }
}

/// Boundary conditions of the box.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum BoundaryKind {
    /// Periodic along every axis.
    Periodic,
    /// Hard specular walls along every axis.
    Walls,
    /// Periodic along x, walls along the other axes.
    Channel,
}

impl BoundaryKind {
    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryKind::Periodic => "periodic",
            BoundaryKind::Walls => "walls",
            BoundaryKind::Channel => "channel",
        }
    }

    /// H5MD `boundary` attribute per axis ("periodic" or "none").
    pub fn h5md_boundary(self, d: usize) -> Vec<&'static str> {
        (0..d)
            .map(|axis| match (self, axis) {
                (BoundaryKind::Periodic, _) | (BoundaryKind::Channel, 0) => "periodic",
                _ => "none",
            })
            .collect()
    }
}

/// A remedy against inelastic collapse, applied on top of the rule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum Remedy {
    /// No remedy.
    None,
    /// TC model: collisions within `tc` of a partner's previous collision are elastic.
    Tc {
        /// Contact duration t_c (time units of σ√(m/T0)).
        tc: f64,
    },
    /// Random rotation of the relative post-collision velocity by up to `theta_max_deg` degrees.
    Rotation {
        /// Largest rotation angle in degrees, in [0, 90].
        theta_max_deg: f64,
    },
}

impl Remedy {
    /// A short label for tables and files, e.g. `tc=0.001`.
    pub fn label(&self) -> String {
        match self {
            Remedy::None => "none".into(),
            Remedy::Tc { tc } => format!("tc={tc}"),
            Remedy::Rotation { theta_max_deg } => format!("rotation={theta_max_deg}deg"),
        }
    }
}

/// The collision law; the grid's `eps` sets its restitution (see each variant).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum RuleSpec {
    /// Constant normal restitution ε = `eps`.
    #[default]
    Constant,
    /// ε = `eps` above the normal speed `delta`, `eps_low` (default 1) below it.
    Threshold {
        /// Normal-speed threshold δ.
        delta: f64,
        /// Restitution below δ (default 1).
        #[serde(default = "one")]
        eps_low: f64,
    },
    /// The thesis's eq. 5.1 with r0 = `eps` and the given `v0` (default 0.3).
    Thesis {
        /// Crossover speed v0.
        #[serde(default = "default_v0")]
        v0: f64,
    },
    /// Viscoelastic spheres, damping chosen so that ε = `eps` at normal speed `speed` (default 1)
    /// for two equal particles.
    Viscoelastic {
        /// Reference normal speed.
        #[serde(default = "one")]
        speed: f64,
    },
}

fn one() -> f64 {
    1.0
}
fn default_v0() -> f64 {
    0.3
}

/// Initial velocity distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum VelocityKind {
    /// Maxwell–Boltzmann (default).
    #[default]
    Maxwell,
    /// Each component uniform in (−1, 1), as in the thesis.
    Uniform,
}

/// How the initial state is made.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InitSpec {
    /// Velocity distribution.
    #[serde(default)]
    pub velocities: VelocityKind,
    /// Elastic collisions per particle run before the inelastic rule starts (default 0 for a random
    /// start, 20 for a lattice start at high density).
    #[serde(default)]
    pub melt_tau: Option<f64>,
}

impl Default for InitSpec {
    fn default() -> Self {
        InitSpec {
            velocities: VelocityKind::Maxwell,
            melt_tau: None,
        }
    }
}

/// When a replica ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopSpec {
    /// Pair collisions per particle τ = C/N at which the run ends.
    pub tau_max: f64,
    /// End earlier, at the first sample where T/T0 falls below this value.
    #[serde(default)]
    pub temperature_ratio: Option<f64>,
    /// End earlier, once the replica's class is settled (needs a `classify` section).
    #[serde(default)]
    pub classified: bool,
}

/// Order parameters and the regime classifier (PHYSICS.md §5).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClassifySpec {
    /// Cells per axis of the order-parameter grid (default: about 16 particles per cell).
    #[serde(default)]
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

/// When observables are sampled (the union of a linear and a logarithmic grid in τ).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    /// Sample every this many collisions per particle (none if absent).
    #[serde(default)]
    pub every: Option<f64>,
    /// Samples per decade of τ on a logarithmic grid (default 10; 0 for none).
    #[serde(default = "default_per_decade")]
    pub per_decade: u32,
    /// First τ of the logarithmic grid (default 0.1).
    #[serde(default = "default_log_from")]
    pub log_from: f64,
}

fn default_per_decade() -> u32 {
    10
}
fn default_log_from() -> f64 {
    0.1
}

impl Default for SampleSpec {
    fn default() -> Self {
        SampleSpec {
            every: None,
            per_decade: default_per_decade(),
            log_from: default_log_from(),
        }
    }
}

/// Which particle snapshots (positions, velocities) are stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SnapshotSpec {
    /// τ values at which to store a snapshot (default `[0]`).
    #[serde(default = "default_snapshot_at")]
    pub at: Vec<f64>,
    /// Also store the final state (default true).
    #[serde(default = "default_true", rename = "final")]
    pub last: bool,
}

fn default_snapshot_at() -> Vec<f64> {
    vec![0.0]
}
fn default_true() -> bool {
    true
}

impl Default for SnapshotSpec {
    fn default() -> Self {
        SnapshotSpec {
            at: default_snapshot_at(),
            last: true,
        }
    }
}

/// Output options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Deflate level of the replica files' datasets, 0 (none) to 9 (default 4).
    #[serde(default = "default_compression")]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    /// Dimension, 2 (disks) or 3 (spheres) (default 2).
    #[serde(default = "default_dim")]
    pub dim: OneOrMany<usize>,
    /// Boundary conditions (default periodic).
    #[serde(default = "default_boundary")]
    pub boundary: OneOrMany<BoundaryKind>,
    /// Restitution coefficients ε (the rule says how ε is used).
    pub eps: OneOrMany<f64>,
    /// Packing fractions φ (with `n`, or with `box` for N to follow).
    #[serde(default)]
    pub phi: Option<OneOrMany<f64>>,
    /// Box sides L in particle diameters (square or cubic box; with `n`, or with `phi`).
    #[serde(default, rename = "box")]
    pub box_len: Option<OneOrMany<f64>>,
    /// Particle numbers N (omit when both `phi` and `box` are given: N = round(φ L^D / v₁)).
    #[serde(default)]
    pub n: Option<OneOrMany<usize>>,
    /// Independent seeds per grid point (default 1).
    #[serde(default = "default_seeds")]
    pub seeds: u32,
    /// Collapse remedies (default none).
    #[serde(default = "default_remedy")]
    pub remedy: OneOrMany<Remedy>,
}

fn default_dim() -> OneOrMany<usize> {
    OneOrMany::One(2)
}
fn default_boundary() -> OneOrMany<BoundaryKind> {
    OneOrMany::One(BoundaryKind::Periodic)
}
fn default_seeds() -> u32 {
    1
}
fn default_remedy() -> OneOrMany<Remedy> {
    OneOrMany::One(Remedy::None)
}

/// A sweep specification.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spec {
    /// Name of the sweep (used in tables and file attributes).
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
}

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

    /// Box side L (square or cubic box).
    pub fn side(&self) -> f64 {
        match self.density {
            Density::Side(l) => l,
            Density::Phi(phi) => {
                (self.n as f64 * ball_volume(self.dim) / phi).powf(1.0 / self.dim as f64)
            }
        }
    }

    /// Packing fraction φ.
    pub fn phi(&self) -> f64 {
        match self.density {
            Density::Phi(phi) => phi,
            Density::Side(l) => self.n as f64 * ball_volume(self.dim) / l.powi(self.dim as i32),
        }
    }

    /// The grid point (every parameter but the seed) as a key for grouping.
    pub fn point_key(&self) -> String {
        format!(
            "{}|{}|{}|{}|{}|{}",
            self.dim,
            self.boundary.name(),
            self.eps,
            self.density_label(),
            self.n,
            self.remedy.label()
        )
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
            "replica {} (D={}, {}, eps={}, {}, N={}, seed #{}, remedy {})",
            self.index,
            self.dim,
            self.boundary.name(),
            self.eps,
            self.density_label(),
            self.n,
            self.seed_index,
            self.remedy.label()
        )
    }
}

/// Volume of a ball of diameter 1 in `d` dimensions.
pub fn ball_volume(d: usize) -> f64 {
    if d == 2 {
        std::f64::consts::PI / 4.0
    } else {
        std::f64::consts::PI / 6.0
    }
}

/// Densest packing fraction of equal disks (hexagonal) or spheres (fcc).
pub fn close_packing(d: usize) -> f64 {
    if d == 2 {
        std::f64::consts::PI / (2.0 * 3f64.sqrt())
    } else {
        std::f64::consts::PI / (3.0 * 2f64.sqrt())
    }
}

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
    /// Parses and validates a spec from JSON text.
    pub fn from_json(text: &str) -> Result<Spec, SweepError> {
        let spec: Spec = serde_json::from_str(text).map_err(|e| SweepError::Spec(e.to_string()))?;
        spec.validate()?;
        Ok(spec)
    }

    /// The canonical JSON form (every default filled in); equal specs give equal text.
    pub fn canonical_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("a spec always serialises")
    }

    /// Hash of the canonical form, stored in every output file.
    pub fn hash(&self) -> String {
        format!("{:016x}", stable_hash(self.canonical_json().as_bytes()))
    }

    /// Checks every field; the error names the field and the value.
    pub fn validate(&self) -> Result<(), SweepError> {
        let bad = |field: &str, value: &dyn fmt::Display, reason: &str| {
            Err(SweepError::Spec(format!("{field} = {value}: {reason}")))
        };
        if self.name.trim().is_empty() {
            return bad("name", &"\"\"", "must not be empty");
        }
        let grids = self.grid.values();
        if grids.is_empty() {
            return bad("grid", &"[]", "no grid: the sweep has no replicas");
        }
        for g in &grids {
            self.validate_grid(g)?;
        }
        self.validate_rest()
    }

    fn validate_grid(&self, g: &Grid) -> Result<(), SweepError> {
        let bad = |field: &str, value: &dyn fmt::Display, reason: &str| {
            Err(SweepError::Spec(format!("{field} = {value}: {reason}")))
        };
        let axes: [(&str, usize); 4] = [
            ("grid.dim", g.dim.values().len()),
            ("grid.boundary", g.boundary.values().len()),
            ("grid.eps", g.eps.values().len()),
            ("grid.remedy", g.remedy.values().len()),
        ];
        for (field, len) in axes {
            if len == 0 {
                return bad(field, &"[]", "empty axis: the grid has no replicas");
            }
        }
        for d in g.dim.values() {
            if d != 2 && d != 3 {
                return bad("grid.dim", &d, "dimension must be 2 or 3");
            }
        }
        for e in g.eps.values() {
            if !(0.0..=1.0).contains(&e) {
                return bad("grid.eps", &e, "restitution must lie in [0, 1]");
            }
        }
        match (&g.n, g.phi.is_some() && g.box_len.is_some()) {
            (Some(_), true) => {
                return bad(
                    "grid.n",
                    &"given",
                    "omit n when both phi and box are given (N follows from them)",
                )
            }
            (None, false) => {
                return bad(
                    "grid.n",
                    &"missing",
                    "give n (or both phi and box, from which N follows)",
                )
            }
            (Some(ns), false) => {
                if ns.values().is_empty() {
                    return bad("grid.n", &"[]", "empty axis: the grid has no replicas");
                }
                for n in ns.values() {
                    if n < 2 {
                        return bad("grid.n", &n, "need at least 2 particles");
                    }
                    if n > u32::MAX as usize / 2 {
                        return bad("grid.n", &n, "too many particles");
                    }
                }
            }
            (None, true) => {}
        }
        if g.seeds == 0 {
            return bad("grid.seeds", &0, "need at least one seed per grid point");
        }
        if g.phi.is_none() && g.box_len.is_none() {
            return bad("grid.phi/grid.box", &"neither", "give phi, box, or both");
        }
        if let Some(phi) = &g.phi {
            let v = phi.values();
            if v.is_empty() {
                return bad("grid.phi", &"[]", "empty axis: the grid has no replicas");
            }
            for p in v {
                for d in g.dim.values() {
                    if !(p > 0.0 && p < close_packing(d)) {
                        return bad(
                            "grid.phi",
                            &p,
                            &format!(
                                "packing fraction must lie in (0, {:.4}), the close packing in {d}D",
                                close_packing(d)
                            ),
                        );
                    }
                }
            }
        }
        if let Some(side) = &g.box_len {
            let v = side.values();
            if v.is_empty() {
                return bad("grid.box", &"[]", "empty axis: the grid has no replicas");
            }
            for l in v {
                if !(l > 0.0 && l.is_finite()) {
                    return bad("grid.box", &l, "box side must be positive");
                }
            }
        }
        for r in g.remedy.values() {
            match r {
                Remedy::None => {}
                Remedy::Tc { tc } => {
                    if !(tc > 0.0 && tc.is_finite()) {
                        return bad("grid.remedy.tc", &tc, "contact duration must be positive");
                    }
                }
                Remedy::Rotation { theta_max_deg } => {
                    if !(0.0..=90.0).contains(&theta_max_deg) {
                        return bad(
                            "grid.remedy.theta_max_deg",
                            &theta_max_deg,
                            "angle must lie in [0, 90] degrees",
                        );
                    }
                }
            }
        }
        Ok(())
    }

    fn validate_rest(&self) -> Result<(), SweepError> {
        let bad = |field: &str, value: &dyn fmt::Display, reason: &str| {
            Err(SweepError::Spec(format!("{field} = {value}: {reason}")))
        };
        match self.rule {
            RuleSpec::Constant => {}
            RuleSpec::Threshold { delta, eps_low } => {
                if !(delta >= 0.0 && delta.is_finite()) {
                    return bad("rule.delta", &delta, "threshold speed must be ≥ 0");
                }
                if !(0.0..=1.0).contains(&eps_low) {
                    return bad("rule.eps_low", &eps_low, "restitution must lie in [0, 1]");
                }
            }
            RuleSpec::Thesis { v0 } => {
                if !(v0 > 0.0 && v0.is_finite()) {
                    return bad("rule.v0", &v0, "crossover speed must be positive");
                }
            }
            RuleSpec::Viscoelastic { speed } => {
                if !(speed > 0.0 && speed.is_finite()) {
                    return bad("rule.speed", &speed, "reference speed must be positive");
                }
            }
        }
        if let Some(m) = self.init.melt_tau {
            if !(m >= 0.0 && m.is_finite()) {
                return bad("init.melt_tau", &m, "must be ≥ 0");
            }
        }
        let s = &self.stop;
        if !(s.tau_max > 0.0 && s.tau_max.is_finite()) {
            return bad("stop.tau_max", &s.tau_max, "must be positive and finite");
        }
        if let Some(t) = s.temperature_ratio {
            if !(t > 0.0 && t < 1.0) {
                return bad("stop.temperature_ratio", &t, "must lie in (0, 1)");
            }
        }
        if s.classified && self.classify.is_none() {
            return bad(
                "stop.classified",
                &true,
                "needs a \"classify\" section (order parameters)",
            );
        }
        if let Some(c) = &self.classify {
            if let Some(g) = c.grid {
                if !(1..=1024).contains(&g) {
                    return bad("classify.grid", &g, "cells per axis must lie in 1..=1024");
                }
            }
            let t = &c.thresholds;
            for (field, v) in [
                ("classify.thresholds.haff_tau0", t.haff_tau0),
                ("classify.thresholds.haff", t.haff),
                ("classify.thresholds.kinetic_flow", t.kinetic_flow),
                ("classify.thresholds.kinetic_density", t.kinetic_density),
                ("classify.thresholds.shear_s_perp", t.shear_s_perp),
                ("classify.thresholds.cluster_density", t.cluster_density),
                ("classify.thresholds.cluster_f2x", t.cluster_f2x),
                (
                    "classify.thresholds.cluster_f2x_min_per_cell",
                    t.cluster_f2x_min_per_cell,
                ),
                ("classify.thresholds.cluster_s_rho", t.cluster_s_rho),
                ("classify.thresholds.settle_window", t.settle_window),
            ] {
                if !(v >= 0.0 && v.is_finite()) {
                    return bad(field, &v, "must be ≥ 0 and finite");
                }
            }
        }
        if let Some(e) = self.samples.every {
            if !(e > 0.0 && e.is_finite()) {
                return bad("samples.every", &e, "must be positive");
            }
        }
        if !(self.samples.log_from > 0.0 && self.samples.log_from.is_finite()) {
            return bad(
                "samples.log_from",
                &self.samples.log_from,
                "must be positive",
            );
        }
        for &t in &self.snapshots.at {
            if !(t >= 0.0 && t.is_finite()) {
                return bad("snapshots.at", &t, "snapshot times must be ≥ 0");
            }
        }
        if self.output.compression > 9 {
            return bad(
                "output.compression",
                &self.output.compression,
                "deflate level must lie in 0..=9",
            );
        }
        // Every replica's box must hold a cell list and its start must be reachable.
        for r in self.replicas() {
            crate::replica::check(self, &r)?;
        }
        Ok(())
    }

    /// The replicas in expansion order: grid by grid; within a grid dim, boundary, remedy, n, density,
    /// eps, seed (seed fastest).
    pub fn replicas(&self) -> Vec<Replica> {
        let mut out = Vec::new();
        for g in self.grid.values() {
            self.expand(&g, &mut out);
        }
        out
    }

    fn expand(&self, g: &Grid, out: &mut Vec<Replica>) {
        let ns = g.n.as_ref().map(|n| n.values()).unwrap_or_default();
        let phis = g.phi.as_ref().map(|p| p.values()).unwrap_or_default();
        let sides = g.box_len.as_ref().map(|l| l.values()).unwrap_or_default();
        for dim in g.dim.values() {
            // (N, box) pairs: N × φ, N × L, or N = round(φ L^D / v₁) for φ × L.
            let pairs: Vec<(usize, Density)> = match (phis.is_empty(), sides.is_empty()) {
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
                            let n = (p * l.powi(dim as i32) / ball_volume(dim)).round();
                            ((n as usize).max(2), Density::Side(l))
                        })
                    })
                    .collect(),
            };
            for boundary in g.boundary.values() {
                for remedy in g.remedy.values() {
                    for &(n, density) in &pairs {
                        for eps in g.eps.values() {
                            for seed_index in 0..g.seeds {
                                let mut r = Replica {
                                    index: out.len(),
                                    dim,
                                    boundary,
                                    eps,
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

    /// The seed of a replica's initial state. It derives from the sweep seed and the parameters that
    /// define the initial state (D, boundary, box, N, seed number), not from ε or the remedy: replicas
    /// that differ only in ε start from the same state (common random numbers), which sharpens
    /// comparisons across ε. It does not depend on the replica's index, the thread count or the shard.
    pub fn replica_seed(&self, r: &Replica) -> u64 {
        let key = format!(
            "{}|{}|{}|{}|{}|{}",
            self.seed,
            r.dim,
            r.boundary.name(),
            r.density_label(),
            r.n,
            r.seed_index
        );
        stable_hash(key.as_bytes())
    }
}

/// Which replicas a shard runs: `K/N` takes every replica whose index is `K` modulo `N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, 0-based.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

impl Shard {
    /// Parses `K/N` with 0 ≤ K < N.
    pub fn parse(s: &str) -> Result<Shard, SweepError> {
        let err = || {
            SweepError::Usage(format!(
                "--shard {s}: expected K/N with 0 <= K < N, e.g. 0/4"
            ))
        };
        let (k, n) = s.split_once('/').ok_or_else(err)?;
        let k: usize = k.trim().parse().map_err(|_| err())?;
        let n: usize = n.trim().parse().map_err(|_| err())?;
        if n == 0 || k >= n {
            return Err(err());
        }
        Ok(Shard { k, n })
    }

    /// Whether the shard runs replica `index`.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.k
    }
}
