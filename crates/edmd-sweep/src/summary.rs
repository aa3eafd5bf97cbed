//! The phase table: one row per grid point (all parameters but the seed), aggregated over seeds, with
//! the theory's critical sizes for comparison.

use std::str::FromStr;

use edmd_core::theory::haff_rate;
use serde::Serialize;

use crate::classify::{critical_box_sides, Class};
use crate::record::{Record, Status};
use crate::spec::{BoundaryKind, RuleSpec, Spec};

/// One grid point of a sweep.
#[derive(Debug, Clone, Serialize)]
pub struct PointRow {
    /// Dimension.
    pub dim: usize,
    /// Boundary.
    pub boundary: String,
    /// Remedy label.
    pub remedy: String,
    /// Particle number.
    pub n: usize,
    /// Packing fraction.
    pub phi: f64,
    /// Box side.
    pub box_side: f64,
    /// Restitution.
    pub eps: f64,
    /// Tangential restitution (−1: smooth).
    pub beta: f64,
    /// The mixture (`fraction:diameter:mass+…`; empty for one species).
    pub species: String,
    /// Gravity, wall restitution, thermal floor and box aspect where they differ from the defaults
    /// (`g=0.1 wall_eps=0.9 floor_T=2 aspect=2x1`; empty for a free square or cubic box).
    pub scene: String,
    /// Sheared boxes: the shear rate a (absent elsewhere; the scene label carries it as `a=`).
    #[serde(skip_serializing_if = "is_zero")]
    pub shear_rate: f64,
    /// Seeds in the spec.
    pub seeds: usize,
    /// Seeds finished normally.
    pub done: usize,
    /// Seeds that collapsed.
    pub collapsed: usize,
    /// Seeds that stalled (pair collisions ceased before the stop, no collapse).
    pub stalled: usize,
    /// Seeds that failed to start.
    pub failed: usize,
    /// Seeds not (yet) run.
    pub missing: usize,
    /// Median τ at the end.
    pub tau_end: f64,
    /// Median log10(T/T0) at the end.
    pub log10_t_ratio: f64,
    /// log10 of Haff's law at the median final τ (constant-restitution rule only, else NaN).
    pub log10_t_haff: f64,
    /// L / L⊥ (Enskog; L⊥ halved for walled axes).
    pub l_over_l_perp: f64,
    /// L / L∥ (Enskog; L∥ halved for walled axes).
    pub l_over_l_par: f64,
    /// Fraction of seeds labelled kinetic (NaN without classification).
    pub kinetic: f64,
    /// Fraction of seeds labelled shearing.
    pub shearing: f64,
    /// Fraction of seeds labelled clustering.
    pub clustering: f64,
    /// Sheared boxes: fraction of seeds whose flow stayed homogeneous (absent elsewhere).
    #[serde(skip_serializing_if = "is_nan")]
    pub homogeneous: f64,
    /// Sheared boxes: fraction of seeds whose flow formed bands or clusters (absent elsewhere).
    #[serde(skip_serializing_if = "is_nan")]
    pub inhomogeneous: f64,
    /// Median first-passage τ of the shearing predicate, over the seeds that reached it.
    pub shear_onset_tau: f64,
    /// Median first-passage τ of the clustering predicate, over the seeds that reached it.
    pub cluster_onset_tau: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.retain(|x| !x.is_nan());
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

/// Aggregates records per grid point, in the spec's order.
pub fn phase_table(spec: &Spec, records: &[Record]) -> Vec<PointRow> {
    let replicas = spec.replicas();
    let mut keys: Vec<String> = Vec::new();
    let mut groups: Vec<Vec<&Record>> = Vec::new();
    for (r, rec) in replicas.iter().zip(records) {
        let key = r.point_key();
        match keys.iter().position(|k| *k == key) {
            Some(i) => groups[i].push(rec),
            None => {
                keys.push(key);
                groups.push(vec![rec]);
            }
        }
    }
    groups
        .into_iter()
        .map(|g| {
            let first = g[0];
            let count = |s: Status| g.iter().filter(|r| r.status == s).count();
            let ran: Vec<&&Record> = g.iter().filter(|r| r.status.has_data()).collect();
            let tau_end = median(ran.iter().map(|r| r.tau).collect());
            let ln10 = std::f64::consts::LN_10;
            let log10_t_ratio = median(ran.iter().map(|r| r.ln_temperature_ratio / ln10).collect());
            let log10_t_haff = if matches!(spec.rule, RuleSpec::Constant {})
                && first.beta == -1.0
                && first.species.is_empty()
                && first.gravity == 0.0
                && first.floor_temperature == 0.0
                && first.white_noise == 0.0
                && first.wall_eps == 1.0
                && first.boundary != BoundaryKind::LeesEdwards.name()
            {
                -haff_rate(first.dim, first.eps) * tau_end / ln10
            } else {
                f64::NAN
            };
            // The free-cooling instability's critical sizes (not defined for a sheared box).
            let sheared = first.boundary == BoundaryKind::LeesEdwards.name();
            let periodic = first.boundary == BoundaryKind::Periodic.name();
            let (lp, lq) = if sheared {
                (f64::NAN, f64::NAN)
            } else {
                critical_box_sides(first.dim, first.eps, first.phi, periodic)
            };
            // Gravity and thermal floors are not free cooling: no fractions (not_applicable).
            let classified =
                spec.classify.is_some() && g.iter().any(|r| r.class != Class::NotApplicable.name());
            // Free cooling's classes, or the sheared flow's (homogeneous, inhomogeneous).
            let frac = |c: &str, of_shear: bool| {
                if classified && of_shear == sheared {
                    g.iter().filter(|r| r.class == c).count() as f64 / g.len() as f64
                } else {
                    f64::NAN
                }
            };
            PointRow {
                kinetic: frac("kinetic", false),
                shearing: frac("shearing", false),
                clustering: frac("clustering", false),
                homogeneous: frac("homogeneous", true),
                inhomogeneous: frac("inhomogeneous", true),
                shear_onset_tau: median(g.iter().map(|r| r.shear_onset_tau).collect()),
                cluster_onset_tau: median(g.iter().map(|r| r.cluster_onset_tau).collect()),
                dim: first.dim,
                boundary: first.boundary.clone(),
                remedy: first.remedy.clone(),
                n: first.n,
                phi: first.phi,
                box_side: first.box_side,
                eps: first.eps,
                beta: first.beta,
                species: first.species.clone(),
                scene: scene_label(first),
                shear_rate: first.shear_rate,
                seeds: g.len(),
                done: count(Status::Done),
                collapsed: count(Status::Collapsed),
                stalled: count(Status::Stalled),
                failed: count(Status::Failed),
                // A corrupt file is no result: counted with the missing ones.
                missing: count(Status::Missing) + count(Status::Corrupt),
                tau_end,
                log10_t_ratio,
                log10_t_haff,
                l_over_l_perp: first.box_side / lp,
                l_over_l_par: first.box_side / lq,
            }
        })
        .collect()
}

/// Output format of the phase table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Aligned text for the terminal.
    Table,
    /// Comma-separated values with a header line.
    Csv,
    /// A JSON array of objects.
    Json,
}

impl Format {
    /// Every format, by name.
    pub const ALL: [(&'static str, Format); 3] = [
        ("table", Format::Table),
        ("csv", Format::Csv),
        ("json", Format::Json),
    ];
}

impl FromStr for Format {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Format::ALL
            .iter()
            .find(|(name, _)| *name == s)
            .map(|&(_, f)| f)
            .ok_or_else(|| format!("unknown format {s:?}: table, csv or json"))
    }
}

/// The non-default scene parameters of a record, space-separated.
fn scene_label(r: &Record) -> String {
    let mut parts = Vec::new();
    if r.gravity > 0.0 {
        parts.push(format!("g={}", r.gravity));
    }
    if r.boundary == BoundaryKind::LeesEdwards.name() {
        parts.push(format!("a={}", r.shear_rate));
    }
    if r.wall_eps != 1.0 {
        parts.push(format!("wall_eps={}", r.wall_eps));
    }
    if r.floor_temperature > 0.0 {
        parts.push(format!("floor_T={}", r.floor_temperature));
    }
    if r.white_noise > 0.0 {
        parts.push(format!("noise={}", r.white_noise));
    }
    if r.shake_s > 0.0 {
        parts.push(format!("S={}, Gamma={}", r.shake_s, r.shake_gamma));
    }
    if !r.aspect.is_empty() {
        parts.push(format!("aspect={}", r.aspect));
    }
    parts.join(" ")
}

const COLUMNS: usize = 26;
/// The sheared flow's class fractions, shown after the others when a row has them.
const SHEAR_HEADER: [&str; 2] = ["homogeneous", "inhomogeneous"];
const HEADER: [&str; COLUMNS] = [
    "D",
    "boundary",
    "remedy",
    "N",
    "phi",
    "L",
    "eps",
    "beta",
    "species",
    "scene",
    "seeds",
    "done",
    "collapsed",
    "stalled",
    "failed",
    "missing",
    "tau_end",
    "log10(T/T0)",
    "log10(Haff)",
    "L/L_perp",
    "L/L_par",
    "kinetic",
    "shearing",
    "clustering",
    "tau_shear",
    "tau_cluster",
];

/// The header and the cells of every row; the sheared flow's class fractions are two more columns
/// when any row has them.
fn table(rows: &[PointRow]) -> (Vec<&'static str>, Vec<Vec<String>>) {
    let sheared = rows.iter().any(|r| !r.homogeneous.is_nan());
    let mut header = HEADER.to_vec();
    if sheared {
        header.extend(SHEAR_HEADER);
    }
    let body = rows
        .iter()
        .map(|r| {
            let mut c = cells(r).to_vec();
            if sheared {
                for x in [r.homogeneous, r.inhomogeneous] {
                    c.push(if x.is_nan() {
                        "-".into()
                    } else {
                        format!("{x:.2}")
                    });
                }
            }
            c
        })
        .collect();
    (header, body)
}

fn cells(r: &PointRow) -> [String; COLUMNS] {
    let f = |x: f64, p: usize| {
        if x.is_nan() {
            "-".to_string()
        } else {
            format!("{x:.p$}")
        }
    };
    [
        r.dim.to_string(),
        r.boundary.clone(),
        r.remedy.clone(),
        r.n.to_string(),
        f(r.phi, 4),
        f(r.box_side, 2),
        r.eps.to_string(),
        r.beta.to_string(),
        if r.species.is_empty() {
            "-".to_string()
        } else {
            r.species.clone()
        },
        if r.scene.is_empty() {
            "-".to_string()
        } else {
            r.scene.clone()
        },
        r.seeds.to_string(),
        r.done.to_string(),
        r.collapsed.to_string(),
        r.stalled.to_string(),
        r.failed.to_string(),
        r.missing.to_string(),
        f(r.tau_end, 1),
        f(r.log10_t_ratio, 3),
        f(r.log10_t_haff, 3),
        f(r.l_over_l_perp, 2),
        f(r.l_over_l_par, 2),
        f(r.kinetic, 2),
        f(r.shearing, 2),
        f(r.clustering, 2),
        f(r.shear_onset_tau, 0),
        f(r.cluster_onset_tau, 0),
    ]
}

/// Renders the phase table.
pub fn render(rows: &[PointRow], format: Format) -> String {
    match format {
        Format::Json => serde_json::to_string_pretty(rows).expect("rows serialise") + "\n",
        Format::Csv => {
            let (header, body) = table(rows);
            let mut w = csv::Writer::from_writer(Vec::new());
            w.write_record(&header).expect("write to memory");
            for c in &body {
                w.write_record(c).expect("write to memory");
            }
            String::from_utf8(w.into_inner().expect("write to memory")).expect("UTF-8")
        }
        Format::Table => {
            let (header, body) = table(rows);
            let widths: Vec<usize> = (0..header.len())
                .map(|i| {
                    body.iter()
                        .map(|c| c[i].len())
                        .chain([header[i].len()])
                        .max()
                        .unwrap_or(0)
                })
                .collect();
            let line = |c: &[String]| {
                c.iter()
                    .zip(&widths)
                    .map(|(x, w)| format!("{x:>w$}"))
                    .collect::<Vec<_>>()
                    .join("  ")
                    .trim_end()
                    .to_string()
                    + "\n"
            };
            let head: Vec<String> = header.iter().map(|s| s.to_string()).collect();
            let mut s = line(&head);
            for c in &body {
                s += &line(c);
            }
            s
        }
    }
}

/// `skip_serializing_if` for the fractions a row does not have.
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_nan(x: &f64) -> bool {
    x.is_nan()
}
