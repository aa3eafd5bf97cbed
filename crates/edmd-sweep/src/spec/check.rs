//! Validation of a spec: every field against its domain, then the checks across fields (N against
//! φ and the box, φ below close packing, the collision rule's parameters) for every replica.

use std::fmt;

use edmd_core::{
    ConstantRestitution, EdmdError, ThesisRestitution, ThresholdRestitution, Viscoelastic,
};

use super::{close_packing, Grid, Remedy, Replica, RuleSpec, Spec};
use crate::domain::{self, Domain};
use crate::SweepError;

/// `field = value: reason` unless `value` lies in `domain`.
fn within(field: &str, value: f64, domain: &Domain) -> Result<(), SweepError> {
    if domain.contains(value) {
        Ok(())
    } else {
        Err(SweepError::Spec(format!(
            "{field} = {value}: {}",
            domain.reason
        )))
    }
}

impl Spec {
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
        for (k, g) in grids.iter().enumerate() {
            let at = match &self.grid {
                super::OneOrMany::One(_) => "grid".to_string(),
                super::OneOrMany::Many(_) => format!("grid[{k}]"),
            };
            self.validate_grid(g, &at)?;
        }
        self.validate_rest()
    }

    /// The checks of one grid, whose fields are named `{at}.eps` and so on.
    fn validate_grid(&self, g: &Grid, at: &str) -> Result<(), SweepError> {
        let bad = |field: &str, value: &dyn fmt::Display, reason: &str| {
            Err(SweepError::Spec(format!(
                "{at}.{field} = {value}: {reason}"
            )))
        };
        let within =
            |field: &str, value: f64, d: &Domain| within(&format!("{at}.{field}"), value, d);
        let axes: [(&str, usize); 4] = [
            ("dim", g.dim.values().len()),
            ("boundary", g.boundary.values().len()),
            ("eps", g.eps.values().len()),
            ("remedy", g.remedy.values().len()),
        ];
        for (field, len) in axes {
            if len == 0 {
                return bad(field, &"[]", "empty axis: the grid has no replicas");
            }
        }
        for d in g.dim.values() {
            if d != 2 && d != 3 {
                return bad("dim", &d, "dimension must be 2 or 3");
            }
        }
        for e in g.eps.values() {
            within("eps", e, &domain::RESTITUTION)?;
        }
        match (&g.n, g.phi.is_some() && g.box_len.is_some()) {
            (Some(_), true) => {
                return bad(
                    "n",
                    &"given",
                    "omit n when both phi and box are given (N follows from them)",
                )
            }
            (None, false) => {
                return bad(
                    "n",
                    &"missing",
                    "give n (or both phi and box, from which N follows)",
                )
            }
            (Some(ns), false) => {
                if ns.values().is_empty() {
                    return bad("n", &"[]", "empty axis: the grid has no replicas");
                }
                for n in ns.values() {
                    within("n", n as f64, &domain::N)?;
                }
            }
            (None, true) => {}
        }
        within("seeds", g.seeds as f64, &domain::SEEDS)?;
        if g.phi.is_none() && g.box_len.is_none() {
            return bad("phi/box", &"neither", "give phi, box, or both");
        }
        if let Some(phi) = &g.phi {
            let v = phi.values();
            if v.is_empty() {
                return bad("phi", &"[]", "empty axis: the grid has no replicas");
            }
            for p in v {
                for d in g.dim.values() {
                    if !(p > 0.0 && p < close_packing(d)) {
                        return bad(
                            "phi",
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
                return bad("box", &"[]", "empty axis: the grid has no replicas");
            }
            for l in v {
                within("box", l, &domain::BOX)?;
            }
        }
        for r in g.remedy.values() {
            match r {
                Remedy::None => {}
                Remedy::Tc { tc } => within("remedy.tc", tc, &domain::TC)?,
                Remedy::Rotation { theta_max_deg } => within(
                    "remedy.theta_max_deg",
                    theta_max_deg,
                    &domain::THETA_MAX_DEG,
                )?,
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
            return bad(
                "stop.classified",
                &true,
                "needs a \"classify\" section (order parameters)",
            );
        }
        if let Some(c) = &self.classify {
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
        }
        if let Some(e) = self.samples.every {
            within("samples.every", e, &domain::EVERY)?;
        }
        within("samples.log_from", self.samples.log_from, &domain::LOG_FROM)?;
        for &t in &self.snapshots.at {
            within("snapshots.at", t, &domain::SNAPSHOT_AT)?;
        }
        within(
            "output.compression",
            self.output.compression as f64,
            &domain::COMPRESSION,
        )?;
        // Every replica's box must hold a cell list and its start must be reachable.
        for r in self.replicas() {
            check_replica(self, &r)?;
        }
        Ok(())
    }
}

/// Static checks of one replica that need no simulation: the box holds a cell list and the rule
/// can be built. Errors name the replica.
pub(crate) fn check_replica(spec: &Spec, r: &Replica) -> Result<(), SweepError> {
    let side = r.side();
    if !(side >= 3.0) {
        return Err(SweepError::Spec(format!(
            "{r}: box side L = {side:.3} is below 3 particle diameters (the smallest cell list); raise N or lower phi"
        )));
    }
    let phi = r.phi();
    if !(phi < close_packing(r.dim)) {
        return Err(SweepError::Spec(format!(
            "{r}: packing fraction phi = {phi:.4} is above close packing ({:.4})",
            close_packing(r.dim)
        )));
    }
    base_rule_check(spec, r).map_err(|e| SweepError::Spec(format!("{r}: {e}")))
}

fn base_rule_check(spec: &Spec, r: &Replica) -> Result<(), EdmdError> {
    match spec.rule {
        RuleSpec::Constant => ConstantRestitution::new(r.eps).map(drop),
        RuleSpec::Threshold { delta, eps_low } => {
            ThresholdRestitution::new(r.eps, eps_low, delta).map(drop)
        }
        RuleSpec::Thesis { v0 } => ThesisRestitution::new(r.eps, v0).map(drop),
        RuleSpec::Viscoelastic { speed } => viscoelastic(r.eps, speed).map(drop),
    }
}

/// Damping such that two unit-mass, unit-diameter particles meet with ε at `speed`. The stiffness
/// only sets the unit of the damping, so Young's modulus 1 and Poisson ratio 0.3 are used.
pub fn viscoelastic(eps: f64, speed: f64) -> Result<Viscoelastic, EdmdError> {
    Viscoelastic::from_reference(eps, speed, 0.5, 0.25, 1.0, 0.3)
}
