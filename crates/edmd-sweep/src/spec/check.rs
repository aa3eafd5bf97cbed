//! Validation of a spec: every field against its domain, then the checks across fields (N against
//! φ and the box, φ below close packing, the collision rule's parameters) for every replica.

use std::fmt;

use edmd_core::{
    ConstantRestitution, EdmdError, ThesisRestitution, ThresholdRestitution, Viscoelastic,
};

use super::{close_packing, Grid, Remedy, Replica, RuleSpec, Spec};
use crate::SweepError;

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
