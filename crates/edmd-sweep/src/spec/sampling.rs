//! When a replica samples its observables (`samples`) and stores particle snapshots (`snapshots`).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::domain;

/// When observables are sampled (the union of a linear and a logarithmic grid in τ).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SampleSpec {
    /// Sample every this many collisions per particle (none if absent).
    #[serde(default)]
    #[schemars(schema_with = "domain::every_optional")]
    pub every: Option<f64>,
    /// Samples per decade of τ on a logarithmic grid (default 10; 0 for none).
    #[serde(default = "default_per_decade")]
    #[schemars(schema_with = "domain::per_decade_one")]
    pub per_decade: u32,
    /// First τ of the logarithmic grid (default 0.1).
    #[serde(default = "default_log_from")]
    #[schemars(schema_with = "domain::log_from_one")]
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

/// Which particle snapshots (positions, velocities) are stored: the `at` list, a linear grid
/// (`every`) and a logarithmic grid (`per_decade` from `log_from`), merged, and the final state.
/// A movie of a replica (`python -m edmd_analysis movie`) is drawn from them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SnapshotSpec {
    /// τ values at which to store a snapshot (default `[0]`).
    #[serde(default = "default_snapshot_at")]
    #[schemars(schema_with = "domain::snapshot_list")]
    pub at: Vec<f64>,
    /// Also store a snapshot every this many collisions per particle, from τ = 0 (none if absent).
    #[serde(default)]
    #[schemars(schema_with = "domain::every_optional")]
    pub every: Option<f64>,
    /// Snapshots per decade of τ on a logarithmic grid from `log_from` (default 0: none).
    #[serde(default)]
    #[schemars(schema_with = "domain::per_decade_one")]
    pub per_decade: u32,
    /// First τ of the logarithmic snapshot grid (default 1).
    #[serde(default = "default_snapshot_log_from")]
    #[schemars(schema_with = "domain::log_from_one")]
    pub log_from: f64,
    /// Also store the final state (default true).
    #[serde(default = "default_true", rename = "final")]
    pub last: bool,
}

fn default_snapshot_at() -> Vec<f64> {
    vec![0.0]
}
fn default_snapshot_log_from() -> f64 {
    1.0
}
fn default_true() -> bool {
    true
}

impl Default for SnapshotSpec {
    fn default() -> Self {
        SnapshotSpec {
            at: default_snapshot_at(),
            every: None,
            per_decade: 0,
            log_from: default_snapshot_log_from(),
            last: true,
        }
    }
}

impl SnapshotSpec {
    /// The snapshot times besides the final state, as a schedule (the `at` points and both grids).
    pub fn schedule(&self) -> edmd_core::Schedule {
        edmd_core::Schedule {
            linear: self.every,
            log_per_decade: (self.per_decade > 0).then_some(self.per_decade),
            log_start: self.log_from,
            points: self.at.clone(),
        }
    }

    /// An upper bound on the snapshots up to `tau_max` besides the final state.
    pub fn count_to(&self, tau_max: f64) -> f64 {
        let at = self.at.iter().filter(|&&t| t <= tau_max).count() as f64;
        let linear = self.every.map_or(0.0, |e| (tau_max / e).floor() + 1.0);
        let log = if self.per_decade > 0 && tau_max >= self.log_from {
            (self.per_decade as f64 * (tau_max / self.log_from).log10()).floor() + 1.0
        } else {
            0.0
        };
        at + linear + log
    }
}
