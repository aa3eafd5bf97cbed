//! The points of a sweep as refinement sees them: each grid point once, known by the normal form of
//! its parameters, with the classes its seeds were given.

use std::collections::{HashMap, HashSet};

use serde_json::{Map, Value};

use crate::classify::Class;
use crate::record::Record;
use crate::spec::{Grid, OneOrMany, RefineAxis, Spec};

/// The grid fields that are axes (a list is several values); `species` and `aspect` are axes when
/// they hold a list of lists.
const AXIS_FIELDS: [&str; 15] = [
    "dim",
    "boundary",
    "remedy",
    "n",
    "phi",
    "box",
    "eps",
    "beta",
    "gravity",
    "shear_rate",
    "wall_eps",
    "floor_temperature",
    "white_noise",
    "shake_s",
    "shake_gamma",
];
const LIST_AXIS_FIELDS: [&str; 2] = ["species", "aspect"];

/// One grid point: a grid of single values, its normal form and its seeds' classes.
#[derive(Debug, Clone)]
pub struct Point {
    /// The point as a grid of single values (with its grid's seeds).
    pub grid: Grid,
    /// Its normal form ([`normal_form`]): every field a single value, without the seeds, with β
    /// explicit. Two points are the same point exactly when their normal forms are equal.
    pub json: Map<String, Value>,
    /// The classes of its seeds that ran and were classified.
    pub classes: Vec<String>,
}

impl Point {
    /// The value of `axis` at this point (None when the grid does not give the axis: N of a φ × L
    /// grid, the box of an N × φ grid).
    pub fn coordinate(&self, axis: RefineAxis) -> Option<f64> {
        self.json.get(axis.name()).and_then(Value::as_f64)
    }

    /// The line through this point along `axis`: every other field, as canonical JSON.
    pub(super) fn line_key(&self, axis: RefineAxis) -> String {
        let mut m = self.json.clone();
        m.remove(axis.name());
        serde_json::to_string(&m).expect("a map serialises")
    }

    /// The fields fixed along the line through this point along `axis` (β of smooth grains left out,
    /// as specs leave it out).
    pub fn line(&self, axis: RefineAxis) -> Map<String, Value> {
        let mut m = self.json.clone();
        m.remove(axis.name());
        if m.get("beta").and_then(Value::as_f64) == Some(SMOOTH_BETA) {
            m.remove("beta");
        }
        m
    }

    /// The key of this point's normal form.
    pub(super) fn key(&self) -> String {
        serde_json::to_string(&self.json).expect("a map serialises")
    }

    /// The majority class and its share of the classified seeds (None without any).
    pub fn majority(&self) -> Option<(&str, f64)> {
        let mut counts: Vec<(&str, usize)> = Vec::new();
        for c in &self.classes {
            match counts.iter_mut().find(|(k, _)| *k == c.as_str()) {
                Some((_, n)) => *n += 1,
                None => counts.push((c.as_str(), 1)),
            }
        }
        // Most seeds first; a tie goes to the class first in table order.
        counts.sort_by_key(|&(c, n)| (std::cmp::Reverse(n), class_rank(c)));
        counts
            .first()
            .map(|&(c, n)| (c, n as f64 / self.classes.len() as f64))
    }

    /// Whether the seeds are split: no class holds two thirds of them.
    pub(super) fn split(&self) -> bool {
        self.majority().is_some_and(|(_, share)| share < 2.0 / 3.0)
    }
}

/// The position of a class name in the table order (unknown names last).
pub(super) fn class_rank(name: &str) -> usize {
    Class::ALL
        .iter()
        .position(|c| c.name() == name)
        .unwrap_or(Class::ALL.len())
}

/// Whether a record's class is a regime a refinement can bracket: the free-cooling classes, the
/// sheared flow's, or a collapse; not stalled, failed, missing or not applicable.
fn is_regime(class: &str) -> bool {
    [
        Class::Kinetic,
        Class::Shearing,
        Class::Clustering,
        Class::Collapsed,
        Class::Homogeneous,
        Class::Inhomogeneous,
    ]
    .iter()
    .any(|c| c.name() == class)
}

/// The single-value grids of a grid, in no particular order (the replicas keep the spec's order).
fn point_grids(g: &Grid) -> Vec<Map<String, Value>> {
    let Value::Object(base) = serde_json::to_value(g).expect("a grid serialises") else {
        unreachable!("a grid is an object")
    };
    // Fields a grid leaves unset (n of a φ × L grid) are not part of its points.
    let base: Map<String, Value> = base.into_iter().filter(|(_, v)| !v.is_null()).collect();
    let mut points = vec![base.clone()];
    for (field, value) in &base {
        let is_axis = AXIS_FIELDS.contains(&field.as_str())
            || (LIST_AXIS_FIELDS.contains(&field.as_str())
                && value
                    .as_array()
                    .and_then(|a| a.first())
                    .is_some_and(Value::is_array));
        let Some(values) = value.as_array().filter(|_| is_axis) else {
            continue;
        };
        points = points
            .into_iter()
            .flat_map(|p| {
                values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.insert(field.clone(), v.clone());
                    q
                })
            })
            .collect();
    }
    points
}

pub(super) fn to_grid(json: &Map<String, Value>) -> Grid {
    serde_json::from_value(Value::Object(json.clone())).expect("a point of a valid grid parses")
}

/// β of smooth grains, the value a grid without `beta` has.
const SMOOTH_BETA: f64 = -1.0;

/// The normal form of a point's JSON: parsed into a grid and written again (so that a default
/// written out and one left out agree, as do `1` and `1.0`), without the seeds (the same point may
/// be run with other seeds by another grid), and with β explicit (β = −1 is left out of a written
/// grid, but it is a coordinate of the β axis).
pub(super) fn normal_form(json: &Map<String, Value>) -> Map<String, Value> {
    let grid = to_grid(json);
    let Value::Object(mut m) = serde_json::to_value(&grid).expect("a grid serialises") else {
        unreachable!("a grid is an object")
    };
    m.retain(|_, v| !v.is_null());
    m.remove("seeds");
    m.entry("beta").or_insert(Value::from(SMOOTH_BETA));
    m
}

/// Every point of a sweep (the grids', then the refinement's, each once) with its seeds' classes.
pub fn points(spec: &Spec, records: &[Record]) -> Vec<Point> {
    let mut classes: HashMap<String, Vec<String>> = HashMap::new();
    for (r, rec) in spec.replicas().iter().zip(records) {
        let entry = classes.entry(r.point_key()).or_default();
        // A shaken bed's regime is its state (`replica/shaken.rs`), not a free-cooling class.
        let regime = if rec.shaken_state.is_empty() {
            &rec.class
        } else {
            &rec.shaken_state
        };
        if rec.status.has_data() && (is_regime(regime) || !rec.shaken_state.is_empty()) {
            entry.push(regime.clone());
        }
    }
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    for g in spec.grids() {
        for json in point_grids(&g) {
            let normal = normal_form(&json);
            let key = serde_json::to_string(&normal).expect("a map serialises");
            if !seen.insert(key) {
                continue;
            }
            let grid = to_grid(&json);
            let one = Spec {
                grid: OneOrMany::One(grid.clone()),
                refinement: None,
                ..spec.clone()
            };
            let point_key = one.replicas().first().map(|r| r.point_key());
            let classes = point_key
                .and_then(|k| classes.get(&k).cloned())
                .unwrap_or_default();
            out.push(Point {
                grid,
                json: normal,
                classes,
            });
        }
    }
    out
}
