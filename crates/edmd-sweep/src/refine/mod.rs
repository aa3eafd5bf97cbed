//! Refinement of a phase diagram: where neighbouring grid points disagree on the regime, add the
//! midpoint (docs/sweep-spec.md, "Refinement").
//!
//! A sweep's points are its grids' single-value combinations (a refinement's points are such grids
//! already). Along each refined axis, the points that agree on every other parameter form a *line*;
//! sorted along the axis, two consecutive points of a line are a *pair*. A pair is bisected when the
//! majority classes of its ends differ, or when an end's seeds are split (no class holds two thirds
//! of them). Midpoints are linear in ε, φ and β, geometric in N and the box side, and rounded to ten
//! significant digits (N to an integer), so that a refined point equals the point of the finer grid
//! `(m − 1)·2^r + 1` values per axis that bisects the same interval r times. Replica seeds depend on
//! the point's parameters, not on its number: a refined point runs exactly the replicas the finer
//! grid would run there.

use std::collections::HashSet;

use serde::Serialize;
use serde_json::{Map, Value};

use crate::record::Record;
use crate::spec::{Grid, OneOrMany, RefineAxis, Refinement, Spec};
use crate::SweepError;

mod points;
use points::{class_rank, normal_form, to_grid};
pub use points::{points, Point};

/// `x` rounded to ten significant digits.
pub fn tidy(x: f64) -> f64 {
    format!("{x:.9e}")
        .parse()
        .expect("a formatted float parses")
}

/// The midpoint of `a` and `b` along `axis` (None when it equals an end: the axis is resolved).
pub fn midpoint(axis: RefineAxis, a: f64, b: f64) -> Option<f64> {
    let m = match axis {
        RefineAxis::N => (a * b).sqrt().round(),
        RefineAxis::Box => tidy((a * b).sqrt()),
        _ => tidy(0.5 * (a + b)),
    };
    (m != a && m != b).then_some(m)
}

/// The lines along `axis`: points sharing every other field, each sorted along the axis, in the
/// order of their first point.
fn lines(points: &[Point], axis: RefineAxis) -> Vec<Vec<&Point>> {
    let mut keys: Vec<String> = Vec::new();
    let mut out: Vec<Vec<&Point>> = Vec::new();
    for p in points.iter().filter(|p| p.coordinate(axis).is_some()) {
        let key = p.line_key(axis);
        match keys.iter().position(|k| *k == key) {
            Some(i) => out[i].push(p),
            None => {
                keys.push(key);
                out.push(vec![p]);
            }
        }
    }
    for line in &mut out {
        line.sort_by(|a, b| {
            a.coordinate(axis)
                .unwrap()
                .total_cmp(&b.coordinate(axis).unwrap())
        });
    }
    out
}

/// The points of the next round: the midpoints of the pairs to bisect along each axis, in axis,
/// line and axis order, at most `budget` replicas' worth (each point costs its seeds).
pub fn plan(points: &[Point], axes: &[RefineAxis], budget: usize) -> Vec<Grid> {
    let mut existing: HashSet<String> = points.iter().map(Point::key).collect();
    let mut out = Vec::new();
    let mut spent = 0;
    for &axis in axes {
        for line in lines(points, axis) {
            for pair in line.windows(2) {
                let (p, q) = (pair[0], pair[1]);
                let (Some(mp), Some(mq)) = (p.majority(), q.majority()) else {
                    continue;
                };
                if mp.0 == mq.0 && !p.split() && !q.split() {
                    continue;
                }
                let (a, b) = (p.coordinate(axis).unwrap(), q.coordinate(axis).unwrap());
                let Some(m) = midpoint(axis, a, b) else {
                    continue;
                };
                let mut json = p.json.clone();
                let value = if axis == RefineAxis::N {
                    Value::from(m as u64)
                } else {
                    Value::from(m)
                };
                json.insert(axis.name().into(), value);
                let json = normal_form(&json);
                let key = serde_json::to_string(&json).expect("a map serialises");
                if existing.contains(&key) {
                    continue;
                }
                let mut seeded = json.clone();
                seeded.insert("seeds".into(), Value::from(p.grid.seeds));
                let grid = to_grid(&seeded);
                let cost = grid.seeds as usize;
                if spent + cost > budget {
                    return out;
                }
                spent += cost;
                existing.insert(key);
                out.push(grid);
            }
        }
    }
    out
}

/// A change of regime along one line of the grid, bracketed by two neighbouring points.
#[derive(Debug, Clone, Serialize)]
pub struct Crossing {
    /// The axis along which the label changes.
    pub axis: RefineAxis,
    /// The two regimes, in table order.
    pub regimes: [String; 2],
    /// The majority class at the lower end.
    pub below: String,
    /// The majority class at the upper end.
    pub above: String,
    /// The lower end of the bracketing pair.
    pub lower: f64,
    /// The upper end.
    pub upper: f64,
    /// The estimate: the pair's midpoint (geometric for N and the box).
    pub at: f64,
    /// Its uncertainty: half the pair's width, (upper − lower)/2.
    pub half_width: f64,
    /// The fields fixed along the line (every grid field but the axis and the seeds).
    pub line: Map<String, Value>,
}

/// The boundary: every change of majority class between neighbouring points along each axis.
pub fn boundary(points: &[Point], axes: &[RefineAxis]) -> Vec<Crossing> {
    let mut out = Vec::new();
    for &axis in axes {
        for line in lines(points, axis) {
            let labelled: Vec<(&Point, &str)> = line
                .iter()
                .filter_map(|p| p.majority().map(|(c, _)| (*p, c)))
                .collect();
            for pair in labelled.windows(2) {
                let ((p, cp), (q, cq)) = (pair[0], pair[1]);
                if cp == cq {
                    continue;
                }
                let (lower, upper) = (p.coordinate(axis).unwrap(), q.coordinate(axis).unwrap());
                let at = if axis.logarithmic() {
                    (lower * upper).sqrt()
                } else {
                    0.5 * (lower + upper)
                };
                let mut regimes = [cp.to_string(), cq.to_string()];
                regimes.sort_by_key(|c| class_rank(c));
                out.push(Crossing {
                    axis,
                    regimes,
                    below: cp.into(),
                    above: cq.into(),
                    lower,
                    upper,
                    at,
                    half_width: 0.5 * (upper - lower),
                    line: p.line(axis),
                });
            }
        }
    }
    out
}

/// `OUT/boundary.json`: what a refinement found and what it cost.
#[derive(Debug, Clone, Serialize)]
pub struct BoundaryFile {
    /// The sweep's name.
    pub sweep: String,
    /// The axes refined.
    pub axes: Vec<RefineAxis>,
    /// Rounds run.
    pub rounds: usize,
    /// Replicas of the sweep (grid and refinement).
    pub replicas: usize,
    /// Of them, added by the refinement.
    pub refinement_replicas: usize,
    /// Replicas of the full grid of the same resolution (each refined axis bisected `rounds`
    /// times everywhere).
    pub full_grid_replicas: usize,
    /// The regime changes found.
    pub crossings: Vec<Crossing>,
}

/// The boundary file of a refined sweep whose replicas have `records`.
pub fn boundary_file(spec: &Spec, records: &[Record], axes: &[RefineAxis]) -> BoundaryFile {
    let pts = points(spec, records);
    BoundaryFile {
        sweep: spec.name.clone(),
        axes: axes.to_vec(),
        rounds: rounds(spec),
        replicas: records.len(),
        refinement_replicas: refinement_replicas(spec),
        full_grid_replicas: full_grid_replicas(spec, axes, rounds(spec)),
        crossings: boundary(&pts, axes),
    }
}

/// Replicas of a full grid as fine as `rounds` bisections of each refined axis of the spec's grids.
pub fn full_grid_replicas(spec: &Spec, axes: &[RefineAxis], rounds: usize) -> usize {
    spec.grid
        .values()
        .iter()
        .map(|g| {
            let base = Spec {
                grid: OneOrMany::One(g.clone()),
                refinement: None,
                ..spec.clone()
            }
            .replicas()
            .len() as f64;
            let Value::Object(json) = serde_json::to_value(g).expect("a grid serialises") else {
                unreachable!("a grid is an object")
            };
            let factor: f64 = axes
                .iter()
                .filter_map(|a| json.get(a.name()).and_then(Value::as_array))
                .map(|v| {
                    let m = v.len() as f64;
                    ((m - 1.0) * 2f64.powi(rounds as i32) + 1.0) / m
                })
                .product();
            (base * factor).round() as usize
        })
        .sum()
}

/// The refinement's axes: those asked for, or else every refinable axis that varies in a grid of
/// the spec. Refused: an axis no grid varies, or other axes than an earlier round used.
pub fn choose_axes(
    spec: &Spec,
    asked: Option<&[RefineAxis]>,
) -> Result<Vec<RefineAxis>, SweepError> {
    let varies = |a: RefineAxis| {
        spec.grid.values().iter().any(|g| {
            let json = serde_json::to_value(g).expect("a grid serialises");
            json.get(a.name())
                .and_then(Value::as_array)
                .is_some_and(|v| v.len() > 1)
        })
    };
    if let Some(a) = asked {
        if let Some(twice) = a.iter().find(|x| a.iter().filter(|y| y == x).count() > 1) {
            return Err(SweepError::Usage(format!(
                "--axes: {} is named more than once; name each axis once",
                twice.name()
            )));
        }
    }
    let axes: Vec<RefineAxis> = match asked {
        Some(a) => a.to_vec(),
        None => match &spec.refinement {
            Some(r) => r.axes.clone(),
            None => RefineAxis::ALL.into_iter().filter(|&a| varies(a)).collect(),
        },
    };
    if axes.is_empty() {
        return Err(SweepError::Usage(
            "refine: no grid of the spec varies eps, phi, box, n or beta; nothing to refine".into(),
        ));
    }
    for &a in &axes {
        if !varies(a) {
            return Err(SweepError::Usage(format!(
                "--axes {}: no grid of the spec has two or more values of {} to bisect",
                a.name(),
                a.name()
            )));
        }
    }
    if let Some(r) = &spec.refinement {
        if !r.rounds.is_empty() && r.axes != axes {
            let names = |v: &[RefineAxis]| v.iter().map(|a| a.name()).collect::<Vec<_>>().join(",");
            return Err(SweepError::Usage(format!(
                "--axes {}: this sweep was refined along {} (see its spec.json); refine it along the same axes, or refine a copy of the original spec",
                names(&axes),
                names(&r.axes)
            )));
        }
    }
    Ok(axes)
}

/// The spec with one more round of points.
pub fn with_round(spec: &Spec, axes: &[RefineAxis], round: Vec<Grid>) -> Spec {
    let mut out = spec.clone();
    let r = out.refinement.get_or_insert_with(|| Refinement {
        axes: axes.to_vec(),
        rounds: Vec::new(),
    });
    r.axes = axes.to_vec();
    r.rounds.push(round);
    out
}

/// Replicas the refinement has added so far.
pub fn refinement_replicas(spec: &Spec) -> usize {
    spec.refinement.as_ref().map_or(0, |r| {
        r.rounds.iter().flatten().map(|g| g.seeds as usize).sum()
    })
}

/// Rounds the refinement has run.
pub fn rounds(spec: &Spec) -> usize {
    spec.refinement.as_ref().map_or(0, |r| r.rounds.len())
}
