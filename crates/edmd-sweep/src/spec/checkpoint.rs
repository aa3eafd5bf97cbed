//! When running replicas save their state: the spec's `checkpoint` section.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// When a running replica saves its state (docs/output.md, "Checkpoints"): a setting of the run,
/// not of its results, so it is left out of the spec's hash and of the replica files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckpointSpec {
    /// Wall-clock seconds between a replica's checkpoints (default 300); 0 turns them off (a signal
    /// still writes one).
    #[serde(default = "default_checkpoint_seconds")]
    #[schemars(extend("minimum" = 0))]
    pub every_s: f64,
    /// Also a checkpoint whenever τ passes a multiple of this (absent: by wall time only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub every_tau: Option<f64>,
    /// Keep each replica's state at `stop.tau_max` (`rNNNNN.final`), from which `edmd extend`
    /// continues it (default true).
    #[serde(default = "default_keep_final")]
    pub keep_final: bool,
}

fn default_keep_final() -> bool {
    true
}

fn default_checkpoint_seconds() -> f64 {
    300.0
}

impl Default for CheckpointSpec {
    fn default() -> Self {
        CheckpointSpec {
            every_s: default_checkpoint_seconds(),
            every_tau: None,
            keep_final: default_keep_final(),
        }
    }
}
