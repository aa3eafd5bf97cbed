//! The regime classifier: a pure function of a replica's order-parameter time series (PHYSICS.md §5.2).
//!
//! At every sample τ ≥ τ₀ three predicates are evaluated:
//! * **clustering**: δ²ρ − δ²ρ(0) ≥ `cluster_density`, or f₂ₓ ≥ `cluster_f2x` with at least
//!   `cluster_f2x_min_per_cell` particles per cell, or S_ρ(k₁) ≥ `cluster_s_rho` at
//!   `sustain` consecutive samples;
//! * **shearing**: S⊥(k₁) ≥ `shear_s_perp`. (PHYSICS.md §5.2 reads "f_flow ≥ 0.1, or S⊥ ≥ 20 and
//!   growing". S⊥ alone is used because it needs no grid, and its level in a stable box is known:
//!   1/(1 − (L/L⊥)²), below 20 unless L > 0.975 L⊥, so a 20 sustained over the window means a growing
//!   or grown shear mode. f_flow depends on the grid and, in small boxes, has a noise floor of about
//!   4 S⊥/N that reaches 0.1 below L⊥; it is reported and used by the kinetic predicate.)
//! * **kinetic**: ΔH < `haff`, f_flow < `kinetic_flow` and δ²ρ − δ²ρ(0) < `kinetic_density`.
//!
//! The class is the most advanced regime whose predicate held without a break over `settle_window` in
//! τ at some time of the run (clustering before shearing); failing that, the predicate that holds at
//! the last sample (with a note that it was not sustained), else kinetic (with a note when the last
//! sample is not kinetic either: a departure from Haff's law without sustained structure). Because a sustained class never reverts, a replica stopped once
//! clustering is sustained (`stop.classified`) gets the label the full run would give. First-passage τ of the shearing and
//! clustering predicates are reported. A kinetic label gets a note saying whether linear theory
//! predicts stability (L < L⊥) or whether the run ended before the onset time 3/r⊥.

use edmd_core::theory::{critical_sizes, Transport};
use serde::{Deserialize, Serialize};

/// Thresholds of the classifier, with the defaults of PHYSICS.md §5.2.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Thresholds {
    /// Start of the Haff-deviation window τ₀ (default 5).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub haff_tau0: f64,
    /// ΔH above which the gas has left the homogeneous cooling state (default 0.1).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub haff: f64,
    /// f_flow below which the gas is kinetic (default 0.05).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub kinetic_flow: f64,
    /// δ²ρ − δ²ρ(0) below which the gas is kinetic (default 0.05).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub kinetic_density: f64,
    /// S⊥(k₁) at and above which the gas shears (default 20).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub shear_s_perp: f64,
    /// δ²ρ − δ²ρ(0) at and above which the gas clusters (default 0.15).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub cluster_density: f64,
    /// f₂ₓ at and above which the gas clusters (default 0.05) …
    #[schemars(schema_with = "crate::domain::threshold")]
    pub cluster_f2x: f64,
    /// … if the grid has at least this many particles per cell (default 16).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub cluster_f2x_min_per_cell: f64,
    /// S_ρ(k₁) at and above which, sustained, the gas clusters (default 10).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub cluster_s_rho: f64,
    /// Consecutive samples that make S_ρ "sustained" (default 3).
    pub sustain: usize,
    /// τ window over which a class must hold before `stop.classified` ends a replica (default 50).
    #[schemars(schema_with = "crate::domain::threshold")]
    pub settle_window: f64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Thresholds {
            haff_tau0: 5.0,
            haff: 0.1,
            kinetic_flow: 0.05,
            kinetic_density: 0.05,
            shear_s_perp: 20.0,
            cluster_density: 0.15,
            cluster_f2x: 0.05,
            cluster_f2x_min_per_cell: 16.0,
            cluster_s_rho: 10.0,
            sustain: 3,
            settle_window: 50.0,
        }
    }
}

/// A replica's class.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Class {
    /// Homogeneous cooling (Haff's law).
    Kinetic,
    /// Vortices / shear bands, no clusters.
    Shearing,
    /// Density clusters.
    Clustering,
    /// Inelastic collapse ended the run.
    Collapsed,
    /// Pair collisions ceased before the stop (no collapse): not classified.
    Stalled,
    /// The replica could not start.
    Failed,
    /// Not a freely cooling gas (gravity or a thermal floor): the classes do not apply; the note
    /// says why.
    NotApplicable,
    /// A sheared gas whose density stays uniform: the uniform shear flow.
    Homogeneous,
    /// A sheared gas that formed bands or clusters (density contrast of a profile at or above
    /// `cluster_density`).
    Inhomogeneous,
}

impl Class {
    /// Every class, in table order.
    pub const ALL: [Class; 9] = [
        Class::Kinetic,
        Class::Shearing,
        Class::Clustering,
        Class::Collapsed,
        Class::Stalled,
        Class::Failed,
        Class::NotApplicable,
        Class::Homogeneous,
        Class::Inhomogeneous,
    ];

    /// The name used in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Class::Kinetic => "kinetic",
            Class::Shearing => "shearing",
            Class::Clustering => "clustering",
            Class::Collapsed => "collapsed",
            Class::Stalled => "stalled",
            Class::Failed => "failed",
            Class::NotApplicable => "not_applicable",
            Class::Homogeneous => "homogeneous",
            Class::Inhomogeneous => "inhomogeneous",
        }
    }
}

/// Order parameters over time (one entry per sample).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OrderSeries {
    /// τ of each sample.
    pub tau: Vec<f64>,
    /// ln T.
    pub ln_temperature: Vec<f64>,
    /// Noise-corrected flow-energy fraction.
    pub f_flow: Vec<f64>,
    /// Transverse velocity structure factor at k₁.
    pub s_perp: Vec<f64>,
    /// Poisson-corrected density contrast (raw; the classifier subtracts the first value).
    pub delta_rho2: Vec<f64>,
    /// Fraction of particles in cells above twice the mean count.
    pub f_2x: Vec<f64>,
    /// Density structure factor at k₁.
    pub s_rho: Vec<f64>,
}

/// What linear theory says about the replica's box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Theory {
    /// Haff cooling rate k(ε) per unit τ (None: fit it on [τ₀, τ₀ + 10]).
    pub haff_rate: Option<f64>,
    /// Box side over the critical shear size (walls: over L⊥/2).
    pub l_over_l_perp: f64,
    /// Box side over the critical clustering size (walls: over L∥/2).
    pub l_over_l_par: f64,
    /// Particles per cell of the order-parameter grid.
    pub per_cell: f64,
}

impl Theory {
    /// Linear growth rate r⊥ of the slowest shear mode per unit τ: k(ε)(1 − (L⊥/L)²).
    pub fn r_perp(&self, k: f64) -> f64 {
        k * (1.0 - self.l_over_l_perp.powi(-2))
    }
}

/// The critical box sides (L⊥, L∥) of the Enskog linear stability analysis (PHYSICS.md §3.1) for a
/// periodic box, or halved for a walled one (a wall reflects the longest mode into half a
/// wavelength). Infinite for elastic gases. The summary and the classifier both take them here.
pub fn critical_box_sides(dim: usize, eps: f64, phi: f64, periodic: bool) -> (f64, f64) {
    if !(eps < 1.0) {
        return (f64::INFINITY, f64::INFINITY);
    }
    let (lp, lq) = critical_sizes(dim, eps, phi, 1.0, Transport::Enskog);
    if periodic {
        (lp, lq)
    } else {
        (lp * 0.5, lq * 0.5)
    }
}

/// The classifier's verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Classification {
    /// The class.
    pub class: Class,
    /// First τ at which the shearing predicate held (NaN if never).
    pub shear_onset: f64,
    /// First τ at which the clustering predicate held (NaN if never).
    pub cluster_onset: f64,
    /// Haff deviation ΔH at every sample (NaN before τ₀).
    pub haff_deviation: Vec<f64>,
    /// Caveats: "too short to tell", weak departures, …
    pub note: String,
}

/// Haff deviation ΔH(τ) = ln T(τ) − ln T(τ₀) + k (τ − τ₀) at every sample, and the k used.
pub fn haff_deviation(s: &OrderSeries, tau0: f64, rate: Option<f64>) -> (Vec<f64>, f64) {
    let interp = |t: f64| -> Option<f64> {
        let i = s.tau.iter().position(|&x| x >= t)?;
        if s.tau[i] == t || i == 0 {
            return Some(s.ln_temperature[i]);
        }
        let (t0, t1) = (s.tau[i - 1], s.tau[i]);
        let w = (t - t0) / (t1 - t0);
        Some(s.ln_temperature[i - 1] * (1.0 - w) + s.ln_temperature[i] * w)
    };
    let k = rate.unwrap_or_else(|| {
        // Least-squares slope of ln T over [τ₀, τ₀ + 10].
        let pts: Vec<(f64, f64)> = s
            .tau
            .iter()
            .zip(&s.ln_temperature)
            .filter(|(&t, _)| t >= tau0 && t <= tau0 + 10.0)
            .map(|(&t, &l)| (t, l))
            .collect();
        if pts.len() < 2 {
            return f64::NAN;
        }
        let n = pts.len() as f64;
        let (mt, ml) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let cov: f64 = pts.iter().map(|p| (p.0 - mt) * (p.1 - ml)).sum();
        let var: f64 = pts.iter().map(|p| (p.0 - mt).powi(2)).sum();
        -cov / var
    });
    let Some(ln0) = interp(tau0) else {
        return (vec![f64::NAN; s.tau.len()], k);
    };
    let dh = s
        .tau
        .iter()
        .zip(&s.ln_temperature)
        .map(|(&t, &l)| {
            if t < tau0 {
                f64::NAN
            } else {
                l - ln0 + k * (t - tau0)
            }
        })
        .collect();
    (dh, k)
}

/// Per-sample predicates.
struct Predicates {
    kinetic: Vec<bool>,
    shearing: Vec<bool>,
    clustering: Vec<bool>,
}

fn predicates(s: &OrderSeries, dh: &[f64], th: &Thresholds, per_cell: f64) -> Predicates {
    let n = s.tau.len();
    let d0 = s.delta_rho2.first().copied().unwrap_or(0.0);
    let mut p = Predicates {
        kinetic: vec![false; n],
        shearing: vec![false; n],
        clustering: vec![false; n],
    };
    let mut rho_run = 0usize;
    for i in 0..n {
        let contrast = s.delta_rho2[i] - d0;
        rho_run = if s.s_rho[i] >= th.cluster_s_rho {
            rho_run + 1
        } else {
            0
        };
        p.clustering[i] = contrast >= th.cluster_density
            || (s.f_2x[i] >= th.cluster_f2x && per_cell >= th.cluster_f2x_min_per_cell)
            || rho_run >= th.sustain;
        p.shearing[i] = s.s_perp[i] >= th.shear_s_perp;
        let dhi = if dh[i].is_nan() { 0.0 } else { dh[i] };
        p.kinetic[i] =
            dhi < th.haff && s.f_flow[i] < th.kinetic_flow && contrast < th.kinetic_density;
    }
    p
}

/// Classifies a replica that ran (status done); collapsed and failed replicas are passed through by
/// the caller.
pub fn classify(s: &OrderSeries, th: &Thresholds, theory: &Theory) -> Classification {
    let (dh, k) = haff_deviation(s, th.haff_tau0, theory.haff_rate);
    let n = s.tau.len();
    if n == 0 {
        return Classification {
            class: Class::Failed,
            shear_onset: f64::NAN,
            cluster_onset: f64::NAN,
            haff_deviation: dh,
            note: "no samples".into(),
        };
    }
    let p = predicates(s, &dh, th, theory.per_cell);
    let first = |v: &[bool]| {
        v.iter()
            .position(|&b| b)
            .map(|i| s.tau[i])
            .unwrap_or(f64::NAN)
    };
    let (shear_onset, cluster_onset) = (first(&p.shearing), first(&p.clustering));
    let last = n - 1;
    let tau_end = s.tau[last];
    let mut note = String::new();
    let window = th.settle_window;
    let class = if sustained(&s.tau, &p.clustering, window).is_some() {
        Class::Clustering
    } else if sustained(&s.tau, &p.shearing, window).is_some() {
        Class::Shearing
    } else if p.clustering[last] {
        note = format!("clustering at the end, held for less than the window of {window} in tau");
        Class::Clustering
    } else if p.shearing[last] {
        note = format!("shearing at the end, held for less than the window of {window} in tau");
        Class::Shearing
    } else {
        if !p.kinetic[last] {
            note = format!(
                "departure from Haff's law without sustained shear or clusters (Delta H = {:.3}, f_flow = {:.3}, S_perp = {:.1})",
                dh[last], s.f_flow[last], s.s_perp[last]
            );
        }
        Class::Kinetic
    };
    if class == Class::Kinetic && note.is_empty() {
        let r = theory.r_perp(k);
        note = if theory.l_over_l_perp <= 1.0 {
            format!(
                "linearly stable: L/L_perp = {:.2} < 1",
                theory.l_over_l_perp
            )
        } else if r * tau_end < 3.0 {
            format!(
                "too short to tell: ended at tau = {tau_end:.0}, before the linear onset 3/r_perp = {:.0}",
                3.0 / r
            )
        } else {
            format!(
                "kinetic beyond the linear onset 3/r_perp = {:.0} (L/L_perp = {:.2})",
                3.0 / r,
                theory.l_over_l_perp
            )
        };
    }
    Classification {
        class,
        shear_onset,
        cluster_onset,
        haff_deviation: dh,
        note,
    }
}

/// The τ at which a predicate first began a run that lasted at least `window` in τ.
fn sustained(tau: &[f64], holds: &[bool], window: f64) -> Option<f64> {
    let mut start: Option<usize> = None;
    for (i, &h) in holds.iter().enumerate() {
        if h {
            let s = *start.get_or_insert(i);
            if tau[i] - tau[s] >= window {
                return Some(tau[s]);
            }
        } else {
            start = None;
        }
    }
    None
}

/// Whether a running replica's class is settled, so that `stop.classified` may end it: clustering
/// has held over `settle_window` in τ. Clustering is the last class in the order kinetic → shearing →
/// clustering, so the label is then final: the run to τ_max would give the same. Shearing is never
/// settled early: a shearing gas may still cluster later (even below L∥, through nonlinear
/// shear-driven compression).
pub fn settled(s: &OrderSeries, th: &Thresholds, theory: &Theory) -> Option<Class> {
    if s.tau.len() < 2 {
        return None;
    }
    let (dh, _) = haff_deviation(s, th.haff_tau0, theory.haff_rate);
    let p = predicates(s, &dh, th, theory.per_cell);
    sustained(&s.tau, &p.clustering, th.settle_window).map(|_| Class::Clustering)
}
