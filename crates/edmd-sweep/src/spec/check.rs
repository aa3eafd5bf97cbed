//! Validation of a spec: every field against its domain, then the checks across fields (N against
//! φ and the box, φ below close packing, the collision rule's parameters) for every replica.

use std::collections::HashSet;
use std::fmt;

use super::{close_packing, Density, Grid, OneOrMany, Remedy, Replica, Spec};
use crate::domain::{self, Domain, MAX_REPLICAS};
use crate::SweepError;

/// `field = value: reason` unless `value` lies in `domain`.
pub(super) fn within(field: &str, value: f64, domain: &Domain) -> Result<(), SweepError> {
    if domain.contains(value) {
        Ok(())
    } else {
        Err(SweepError::Spec(format!(
            "{field} = {}: {}",
            super::expand::compact(value),
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
        if !is_safe_name(&self.name) {
            return bad(
                "name",
                &format!("{:?}", self.name),
                "must be a plain file name: 1 to 100 letters, digits, '.', '_' or '-', not starting with '.' \
                 (it names the default output directory edmd-out/<name>)",
            );
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
        for (k, round) in self
            .refinement
            .iter()
            .flat_map(|r| r.rounds.iter().enumerate())
        {
            for (j, g) in round.iter().enumerate() {
                self.validate_grid(g, &format!("refinement.rounds[{k}][{j}]"))?;
            }
        }
        let total: f64 = self.grids().iter().map(grid_size).sum();
        if total > MAX_REPLICAS as f64 {
            let at = if grids.len() == 1 { "grid" } else { "grid[*]" };
            let g = &grids[0];
            return bad(
                at,
                &format!("{total:.3e} replicas"),
                &format!(
                    "more than the {MAX_REPLICAS} one sweep may hold (the product of the axes: dim {} × boundary {} × remedy {} × (n, phi or box) {} × eps {} × beta {} × seeds {}{}); split the sweep",
                    g.dim.values().len(),
                    g.boundary.values().len(),
                    g.remedy.values().len(),
                    density_pairs(g),
                    g.eps.values().len(),
                    g.beta.values().len(),
                    g.seeds,
                    if grids.len() > 1 { " for the first grid" } else { "" }
                ),
            );
        }
        self.validate_rest()
    }

    /// The checks of one grid, whose fields are named `{at}.eps` and so on.
    fn validate_grid(&self, g: &Grid, at: &str) -> Result<(), SweepError> {
        grid_axes(g, at)?;
        self.validate_scene(g, at)?;
        grid_density(g, at)?;
        grid_remedies(g, at)
    }

    fn validate_rest(&self) -> Result<(), SweepError> {
        self.rule_and_stop()?;
        self.classify_section()?;
        self.sampling()?;
        self.every_replica()
    }

    /// Every replica's box must hold a cell list and its start must be reachable; grid points must
    /// not repeat across grids.
    fn every_replica(&self) -> Result<(), SweepError> {
        let mut seen: HashSet<String> = HashSet::new();
        let mut first_of: Vec<(String, usize)> = Vec::new();
        for r in self.replicas() {
            check_replica(self, &r)?;
            if r.seed_index == 0 && r.n <= PREFLIGHT_MAX_N {
                // Once per grid point: the start and the cell grid, as the run would build them.
                crate::replica::preflight(self, &r)
                    .map_err(|e| SweepError::Spec(format!("{r}: {e}")))?;
                let key = r.point_key();
                if !seen.insert(key.clone()) {
                    let earlier = first_of.iter().find(|(k, _)| *k == key).map(|(_, i)| *i);
                    return Err(SweepError::Spec(format!(
                        "{r}: the same grid point as replica {} (grids must not overlap; use \"seeds\" for more samples of one point)",
                        earlier.unwrap_or(0)
                    )));
                }
                first_of.push((key, r.index));
            }
        }
        Ok(())
    }
}

/// The error of `{at}.{field} = {value}: {reason}`.
pub(super) fn bad(
    at: &str,
    field: &str,
    value: &dyn fmt::Display,
    reason: &str,
) -> Result<(), SweepError> {
    Err(SweepError::Spec(format!(
        "{at}.{field} = {value}: {reason}"
    )))
}

/// The grid's own axes: none empty or repeating, dimensions 2 or 3, ε, β and the inertia factor in
/// their domains.
fn grid_axes(g: &Grid, at: &str) -> Result<(), SweepError> {
    let axes: [(&str, usize); 4] = [
        ("dim", g.dim.values().len()),
        ("boundary", g.boundary.values().len()),
        ("eps", g.eps.values().len()),
        ("remedy", g.remedy.values().len()),
    ];
    for (field, len) in axes {
        if len == 0 {
            return bad(at, field, &"[]", "empty axis: the grid has no replicas");
        }
    }
    no_duplicates(at, "dim", &g.dim)?;
    no_duplicates(at, "boundary", &g.boundary)?;
    no_duplicates(at, "eps", &g.eps)?;
    no_duplicates(at, "remedy", &g.remedy)?;
    if let Some(phi) = &g.phi {
        no_duplicates(at, "phi", phi)?;
    }
    if let Some(side) = &g.box_len {
        no_duplicates(at, "box", side)?;
    }
    if let Some(ns) = &g.n {
        no_duplicates(at, "n", ns)?;
    }
    for d in g.dim.values() {
        if d != 2 && d != 3 {
            return bad(at, "dim", &d, "dimension must be 2 or 3");
        }
    }
    for e in g.eps.values() {
        within(&format!("{at}.eps"), e, &domain::RESTITUTION)?;
    }
    no_duplicates(at, "beta", &g.beta)?;
    if g.beta.values().is_empty() {
        return bad(at, "beta", &"[]", "empty axis: the grid has no replicas");
    }
    for b in g.beta.values() {
        within(&format!("{at}.beta"), b, &domain::BETA)?;
    }
    if let Some(q) = g.inertia {
        within(&format!("{at}.inertia"), q, &domain::INERTIA)?;
    }
    Ok(())
}

/// The grid's N, φ and box side (two of the three), and its seeds.
fn grid_density(g: &Grid, at: &str) -> Result<(), SweepError> {
    match (&g.n, g.phi.is_some() && g.box_len.is_some()) {
        (Some(_), true) => {
            return bad(
                at,
                "n",
                &"given",
                "omit n when both phi and box are given (N follows from them)",
            )
        }
        (None, false) => {
            return bad(
                at,
                "n",
                &"missing",
                "give n (or both phi and box, from which N follows)",
            )
        }
        (Some(ns), false) => {
            if ns.values().is_empty() {
                return bad(at, "n", &"[]", "empty axis: the grid has no replicas");
            }
            for n in ns.values() {
                within(&format!("{at}.n"), n as f64, &domain::N)?;
            }
        }
        (None, true) => {}
    }
    within(&format!("{at}.seeds"), g.seeds as f64, &domain::SEEDS)?;
    if g.phi.is_none() && g.box_len.is_none() {
        return bad(at, "phi/box", &"neither", "give phi, box, or both");
    }
    if let Some(phi) = &g.phi {
        let v = phi.values();
        if v.is_empty() {
            return bad(at, "phi", &"[]", "empty axis: the grid has no replicas");
        }
        for p in v {
            for d in g.dim.values() {
                if !(p > 0.0 && p < close_packing(d)) {
                    return bad(
                        at,
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
            return bad(at, "box", &"[]", "empty axis: the grid has no replicas");
        }
        for l in v {
            within(&format!("{at}.box"), l, &domain::BOX)?;
        }
    }
    Ok(())
}

/// The remedies' parameters.
fn grid_remedies(g: &Grid, at: &str) -> Result<(), SweepError> {
    for r in g.remedy.values() {
        match r {
            Remedy::None {} => {}
            Remedy::Tc { tc } => within(&format!("{at}.remedy.tc"), tc, &domain::TC)?,
            Remedy::Rotation { theta_max_deg } => within(
                &format!("{at}.remedy.theta_max_deg"),
                theta_max_deg,
                &domain::THETA_MAX_DEG,
            )?,
        }
    }
    Ok(())
}

/// A name that is safe as one path component: `[A-Za-z0-9_-][A-Za-z0-9._-]{0,99}`.
fn is_safe_name(name: &str) -> bool {
    let ok = |c: char| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-');
    !name.is_empty() && name.len() <= 100 && !name.starts_with('.') && name.chars().all(ok)
}

/// `{at}.{field} = [list]: v appears twice` for the first value of an axis that repeats.
pub(super) fn no_duplicates<T: Clone + PartialEq + serde::Serialize>(
    at: &str,
    field: &str,
    axis: &OneOrMany<T>,
) -> Result<(), SweepError> {
    let values = axis.values();
    for (i, v) in values.iter().enumerate() {
        if values[..i].contains(v) {
            let show = |x: &dyn erased_json::Json| x.json();
            return Err(SweepError::Spec(format!(
                "{at}.{field} = {}: {} appears twice (grid points must differ; use \"seeds\" for more samples of one point)",
                show(&values),
                show(v)
            )));
        }
    }
    Ok(())
}

mod erased_json {
    /// JSON text of a value, for messages.
    pub trait Json {
        /// The value as compact JSON.
        fn json(&self) -> String;
    }
    impl<T: serde::Serialize> Json for T {
        fn json(&self) -> String {
            serde_json::to_string(self).unwrap_or_default()
        }
    }
}

/// Number of (N, box) pairs of a grid: N × φ, N × L, or φ × L.
fn density_pairs(g: &Grid) -> f64 {
    let len = |a: Option<usize>| a.unwrap_or(0) as f64;
    let n = len(g.n.as_ref().map(|v| v.values().len()));
    let phi = len(g.phi.as_ref().map(|v| v.values().len()));
    let side = len(g.box_len.as_ref().map(|v| v.values().len()));
    if n == 0.0 {
        phi * side
    } else {
        n * phi.max(side)
    }
}

/// Replicas of a grid, computed without expanding it.
fn grid_size(g: &Grid) -> f64 {
    let axes = [
        g.dim.values().len(),
        g.boundary.values().len(),
        g.remedy.values().len(),
        g.eps.values().len(),
        g.beta.values().len(),
        g.species.as_ref().map_or(1, |a| a.0.len()),
        g.aspect.as_ref().map_or(1, |a| a.0.len()),
        g.gravity.values().len(),
        g.shear_rate.values().len(),
        g.wall_eps.values().len(),
        g.floor_temperature.as_ref().map_or(1, |f| f.values().len()),
        g.white_noise.as_ref().map_or(1, |f| f.values().len()),
        g.shake_s.as_ref().map_or(1, |f| f.values().len()),
        g.shake_gamma.as_ref().map_or(1, |f| f.values().len()),
    ];
    axes.iter().map(|&a| a as f64).product::<f64>() * density_pairs(g) * g.seeds as f64
}

impl Spec {
    /// An upper bound on the samples of one replica: the linear grid, the logarithmic grid up to
    /// `stop.tau_max`, the snapshot times (each is also a sample), τ = 0 and the end.
    pub fn samples_per_replica(&self) -> f64 {
        let tau = self.stop.tau_max;
        let s = &self.samples;
        let linear = s.every.map(|e| (tau / e).floor() + 1.0).unwrap_or(0.0);
        let log = if s.per_decade > 0 && tau >= s.log_from {
            (s.per_decade as f64 * (tau / s.log_from).log10()).floor() + 1.0
        } else {
            0.0
        };
        linear + log + self.snapshots.count_to(tau) + 2.0
    }
}

/// Replicas up to this N are built in outline when a spec is checked (`replica::preflight`: a
/// lattice start laid out, the cell grid counted); the O(N) layout of larger ones is left to the
/// run, after the memory estimate has had its say.
const PREFLIGHT_MAX_N: usize = 10_000_000;

/// Static checks of one replica that need no simulation: the box holds a cell list and the rule
/// can be built. Errors name the replica.
pub(crate) fn check_replica(spec: &Spec, r: &Replica) -> Result<(), SweepError> {
    // N follows from φ and the box when `n` is absent: it must be a number the engine can hold.
    let n_max = crate::domain::N.max;
    if let (Density::Side(l), true) = (r.density, r.n as f64 > n_max) {
        let phi = r.phi();
        return Err(SweepError::Spec(format!(
            "grid.box = {l} with phi = {:.4}: N = {:.3e} particles, more than the {n_max} one replica may hold; lower box or phi",
            phi.min(1.0),
            r.n as f64
        )));
    }
    let side = r.sides().into_iter().fold(f64::INFINITY, f64::min);
    if !(side >= 3.0) {
        return Err(SweepError::Spec(format!(
            "{r}: box side L = {side:.3} is below 3 particle diameters (the smallest cell list); raise N or lower phi"
        )));
    }
    if let Some(mixture) = &r.species {
        let counts = r.species_counts();
        for (k, (sp, &c)) in mixture.iter().zip(&counts).enumerate() {
            if c == 0 {
                return Err(SweepError::Spec(format!(
                    "{r}: species {k} (fraction {}) has no particle at N = {}; raise N or the fraction",
                    sp.fraction, r.n
                )));
            }
            if !(sp.diameter < side / 3.0) {
                return Err(SweepError::Spec(format!(
                    "{r}: species {k} has diameter {} ≥ box/3 = {:.3}; a grain must be below a third of the box",
                    sp.diameter,
                    side / 3.0
                )));
            }
        }
        let random_limit = if r.dim == 2 { 0.4 } else { 0.25 };
        if r.phi() > random_limit {
            return Err(SweepError::Spec(format!(
                "{r}: a mixture starts from random placement, which reaches phi = {random_limit} in {}D; phi = {:.4} is above it",
                r.dim,
                r.phi()
            )));
        }
    }
    let phi = r.phi();
    if !(phi < close_packing(r.dim)) {
        return Err(SweepError::Spec(format!(
            "{r}: packing fraction phi = {phi:.4} is above close packing ({:.4})",
            close_packing(r.dim)
        )));
    }
    super::check_rule::base_rule_check(spec, r).map_err(|e| SweepError::Spec(format!("{r}: {e}")))
}
