//! The checks of a spec's sections beside its grids: the rule's parameters, the melt and the stop,
//! the classifier, and the sample and snapshot schedules. Errors name the field.

use super::check::within;
use super::{RuleSpec, Spec};
use crate::domain;
use crate::domain::MAX_SAMPLES;
use crate::SweepError;

impl Spec {
    /// The rule's parameters, the melt and the stop.
    pub(super) fn rule_and_stop(&self) -> Result<(), SweepError> {
        match self.rule {
            RuleSpec::Constant {} => {}
            RuleSpec::Threshold { delta, eps_low } => {
                within("rule.delta", delta, &domain::DELTA)?;
                within("rule.eps_low", eps_low, &domain::RESTITUTION)?;
            }
            RuleSpec::Thesis { v0 } => within("rule.v0", v0, &domain::V0)?,
            RuleSpec::Viscoelastic { speed } => within("rule.speed", speed, &domain::SPEED)?,
        }
        if let Some(m) = self.init.melt_tau {
            within("init.melt_tau", m, &domain::MELT_TAU)?;
        }
        let s = &self.stop;
        within("stop.tau_max", s.tau_max, &domain::TAU_MAX)?;
        if let Some(t) = s.temperature_ratio {
            within("stop.temperature_ratio", t, &domain::TEMPERATURE_RATIO)?;
        }
        if s.classified && self.classify.is_none() {
            return Err(SweepError::Spec(
                "stop.classified = true: needs a \"classify\" section (order parameters)".into(),
            ));
        }
        Ok(())
    }

    /// The classifier's grid and thresholds.
    pub(super) fn classify_section(&self) -> Result<(), SweepError> {
        let Some(c) = &self.classify else {
            return Ok(());
        };
        if let Some(g) = c.grid {
            within("classify.grid", g as f64, &domain::CLASSIFY_GRID)?;
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
            within(field, v, &domain::THRESHOLD)?;
        }
        Ok(())
    }

    /// The sample and snapshot schedules, the compression, and the samples a replica would hold.
    pub(super) fn sampling(&self) -> Result<(), SweepError> {
        if let Some(e) = self.samples.every {
            within("samples.every", e, &domain::EVERY)?;
        }
        within("samples.log_from", self.samples.log_from, &domain::LOG_FROM)?;
        for &t in &self.snapshots.at {
            within("snapshots.at", t, &domain::SNAPSHOT_AT)?;
        }
        if let Some(e) = self.snapshots.every {
            within("snapshots.every", e, &domain::EVERY)?;
        }
        within(
            "snapshots.per_decade",
            self.snapshots.per_decade as f64,
            &domain::PER_DECADE,
        )?;
        within(
            "snapshots.log_from",
            self.snapshots.log_from,
            &domain::LOG_FROM,
        )?;
        if let Some(c) = &self.checkpoint {
            if !(c.every_s >= 0.0 && c.every_s.is_finite()) {
                return Err(SweepError::Spec(format!(
                    "checkpoint.every_s = {}: must be a finite number of seconds, 0 or more",
                    c.every_s
                )));
            }
            if let Some(t) = c.every_tau.filter(|t| !(*t > 0.0 && t.is_finite())) {
                return Err(SweepError::Spec(format!(
                    "checkpoint.every_tau = {t}: must be finite and above 0"
                )));
            }
        }
        within(
            "output.compression",
            self.output.compression as f64,
            &domain::COMPRESSION,
        )?;
        let samples = self.samples_per_replica();
        if samples > MAX_SAMPLES as f64 {
            let tau = self.stop.tau_max;
            let snaps = &self.snapshots;
            let field = match (self.samples.every, snaps.every) {
                (_, Some(e)) if tau / e > 0.5 * samples => format!("snapshots.every = {e}"),
                (Some(e), _) if tau / e > 0.5 * samples => format!("samples.every = {e}"),
                _ if snaps.count_to(tau) > 0.5 * samples => {
                    format!("snapshots.per_decade = {}", snaps.per_decade)
                }
                _ => format!("samples.per_decade = {}", self.samples.per_decade),
            };
            return Err(SweepError::Spec(format!(
                "{field}: {samples:.3e} samples per replica (to tau_max = {}), more than the {MAX_SAMPLES} a replica may hold",
                self.stop.tau_max
            )));
        }
        Ok(())
    }
}
