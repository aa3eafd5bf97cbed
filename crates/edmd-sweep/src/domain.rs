//! The domains of the numeric spec fields, declared once: the spec's checks enforce them with a
//! message naming the field and the value, and the JSON Schema carries them (`minimum`, `maximum`, …)
//! through the `schema_with` functions below, which the spec types name in their `#[schemars]`
//! attributes. Checks that relate several fields (φ below the close packing of the chosen D, N against
//! the box) stay in `check`.

use schemars::{json_schema, Schema, SchemaGenerator};
use serde_json::{json, Map, Value};

/// An interval of allowed values (always finite), with the reason given when a value lies outside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// Lower end.
    pub min: f64,
    /// Whether the lower end itself is excluded.
    pub min_open: bool,
    /// Upper end (∞: none).
    pub max: f64,
    /// Whether the upper end itself is excluded.
    pub max_open: bool,
    /// Integers only.
    pub integer: bool,
    /// What the error message says.
    pub reason: &'static str,
}

impl Domain {
    const fn new(min: f64, min_open: bool, max: f64, max_open: bool, reason: &'static str) -> Self {
        Domain {
            min,
            min_open,
            max,
            max_open,
            integer: false,
            reason,
        }
    }

    /// `[min, max]`.
    pub const fn closed(min: f64, max: f64, reason: &'static str) -> Self {
        Domain::new(min, false, max, false, reason)
    }

    /// `(min, max)`.
    pub const fn open(min: f64, max: f64, reason: &'static str) -> Self {
        Domain::new(min, true, max, true, reason)
    }

    /// `(0, ∞)`.
    pub const fn positive(reason: &'static str) -> Self {
        Domain::new(0.0, true, f64::INFINITY, true, reason)
    }

    /// `[0, ∞)`.
    pub const fn non_negative(reason: &'static str) -> Self {
        Domain::new(0.0, false, f64::INFINITY, true, reason)
    }

    /// The integers of `[min, max]`.
    pub const fn integers(min: f64, max: f64, reason: &'static str) -> Self {
        Domain {
            integer: true,
            ..Domain::closed(min, max, reason)
        }
    }

    /// Whether `v` lies in the domain (NaN and ±∞ never do).
    pub fn contains(&self, v: f64) -> bool {
        let above = if self.min_open {
            v > self.min
        } else {
            v >= self.min
        };
        let below = if self.max_open {
            v < self.max
        } else {
            v <= self.max
        };
        v.is_finite() && above && below && (!self.integer || v.fract() == 0.0)
    }

    /// The JSON Schema of one value.
    pub fn value(&self) -> Value {
        let mut m = Map::new();
        m.insert(
            "type".into(),
            json!(if self.integer { "integer" } else { "number" }),
        );
        let (lo, hi) = if self.min_open {
            ("exclusiveMinimum", self.min)
        } else {
            ("minimum", self.min)
        };
        m.insert(lo.into(), number(hi));
        if self.max.is_finite() {
            let key = if self.max_open {
                "exclusiveMaximum"
            } else {
                "maximum"
            };
            m.insert(key.into(), number(self.max));
        }
        Value::Object(m)
    }

    /// A single value.
    pub fn one(&self) -> Schema {
        Schema::try_from(self.value()).expect("an object")
    }

    /// A value or `null` (an optional field).
    pub fn optional(&self) -> Schema {
        let mut v = self.value();
        let t = v["type"].clone();
        v["type"] = json!([t, "null"]);
        Schema::try_from(v).expect("an object")
    }

    /// A value or a non-empty list of distinct values (a grid axis).
    pub fn axis(&self) -> Schema {
        let one = self.value();
        json_schema!({
            "oneOf": [one, { "type": "array", "items": one, "minItems": 1, "uniqueItems": true }]
        })
    }

    /// A list of values.
    pub fn list(&self) -> Schema {
        let one = self.value();
        json_schema!({ "type": "array", "items": one })
    }
}

/// A whole number as a JSON integer (0.9069 stays a float; 1.0 becomes 1).
fn number(x: f64) -> Value {
    if x.fract() == 0.0 && x.abs() < 1e15 {
        json!(x as i64)
    } else {
        json!(x)
    }
}

/// Most replicas one sweep may hold (each is a file; expansion and validation are linear in them).
pub const MAX_REPLICAS: usize = 1_000_000;

/// Most samples one replica may take (every observable column is a value per sample).
pub const MAX_SAMPLES: usize = 1_000_000;

/// Restitution coefficients.
pub const RESTITUTION: Domain = Domain::closed(0.0, 1.0, "restitution must lie in [0, 1]");
/// Tangential restitution: −1 smooth, 1 perfectly rough.
pub const BETA: Domain = Domain::closed(
    -1.0,
    1.0,
    "tangential restitution must lie in [-1, 1] (-1: smooth)",
);
/// Moment-of-inertia factors q, I = q m (σ/2)²: a ring (disks) or a thin shell's 2/3 (spheres) bound
/// them physically; 1 is the ring.
pub const INERTIA: Domain = Domain::new(
    0.0,
    true,
    1.0,
    false,
    "moment-of-inertia factor must lie in (0, 1] (1/2: uniform disk, 2/5: uniform sphere)",
);
/// Gravity: g ≥ 0 (the unit is σ = m = T0 = 1); 10⁶ bounds it far above any useful column.
pub const GRAVITY: Domain = Domain::closed(0.0, 1e6, "gravity must lie in [0, 1e6]");
/// Shear rates a of the Lees–Edwards box (units √(T0/m)/σ); 10³ bounds them far above any
/// rate a gas at T0 meets (a* = a/ν0 of a steady flow is below 1).
pub const SHEAR_RATE: Domain = Domain::closed(0.0, 1e3, "shear rate must lie in [0, 1000]");
/// Wall restitution.
pub const WALL_EPS: Domain = Domain::closed(0.0, 1.0, "wall restitution must lie in [0, 1]");
/// Temperatures of a thermal floor (in units of T0).
pub const FLOOR_TEMPERATURE: Domain = Domain::new(
    0.0,
    true,
    1e12,
    false,
    "floor temperature must lie in (0, 1e12]",
);
/// The white-noise thermostat's strength ξ₀².
pub const WHITE_NOISE: Domain = Domain::new(
    0.0,
    true,
    1e12,
    false,
    "white-noise strength must lie in (0, 1e12]",
);
/// The shaking strength S = A²ω²/(g d) of a vibrating floor.
pub const SHAKE_S: Domain = Domain::new(
    0.0,
    true,
    1e6,
    false,
    "shaking strength S must lie in (0, 1e6]",
);
/// The shaking acceleration Γ = Aω²/g of a vibrating floor.
pub const SHAKE_GAMMA: Domain = Domain::new(
    0.0,
    true,
    1e6,
    false,
    "shaking acceleration Gamma must lie in (0, 1e6]",
);
/// Relative box sides.
pub const ASPECT: Domain = Domain::new(
    0.0,
    true,
    1e3,
    false,
    "relative box sides must lie in (0, 1000]",
);
/// Species of one mixture, at most.
pub const MAX_SPECIES: usize = 64;
/// Number fractions of a species.
pub const FRACTION: Domain = Domain::new(
    0.0,
    true,
    1.0,
    false,
    "a species' fraction must lie in (0, 1]",
);
/// Diameters of a species, in units of the default grain.
pub const DIAMETER: Domain = Domain::new(
    0.0,
    true,
    100.0,
    false,
    "a species' diameter must lie in (0, 100]",
);
/// Masses of a species.
pub const MASS: Domain = Domain::new(
    0.0,
    true,
    1e12,
    false,
    "a species' mass must lie in (0, 1e12]",
);
/// Packing fractions: the schema bound is the densest (2D) packing; `check` uses the one of D.
pub const PHI: Domain = Domain::open(0.0, 0.9069, "packing fraction must lie below close packing");
/// Box sides: positive, and at most 10^6 diameters (N = 10^7 disks at φ = 0.3 fill a box of 5100;
/// far larger sides leave double precision too few digits for a diameter).
pub const BOX: Domain = Domain::new(
    0.0,
    true,
    1e6,
    false,
    "box side must lie in (0, 1e6] particle diameters",
);
/// Particle numbers.
pub const N: Domain = Domain::integers(
    2.0,
    (u32::MAX / 2) as f64,
    "need at least 2 particles (and at most 2^31 − 1)",
);
/// Seeds per grid point.
pub const SEEDS: Domain = Domain::integers(
    1.0,
    MAX_REPLICAS as f64,
    "need at least one seed per grid point, and at most 10^6 (the most replicas of a sweep)",
);
/// The TC model's contact duration.
pub const TC: Domain = Domain::positive("contact duration must be positive");
/// The random rotation's largest angle.
pub const THETA_MAX_DEG: Domain = Domain::closed(0.0, 90.0, "angle must lie in [0, 90] degrees");
/// The velocity threshold of the threshold rule.
pub const DELTA: Domain = Domain::non_negative("threshold speed must be ≥ 0");
/// The thesis law's crossover speed.
pub const V0: Domain = Domain::positive("crossover speed must be positive");
/// The viscoelastic rule's reference speed.
pub const SPEED: Domain = Domain::positive("reference speed must be positive");
/// Elastic melt before cooling.
pub const MELT_TAU: Domain = Domain::non_negative("must be ≥ 0");
/// The stop condition in τ.
pub const TAU_MAX: Domain = Domain::positive("must be positive and finite");
/// The early stop on T/T0.
pub const TEMPERATURE_RATIO: Domain = Domain::open(0.0, 1.0, "must lie in (0, 1)");
/// Cells per axis of the order-parameter grid.
pub const CLASSIFY_GRID: Domain =
    Domain::integers(1.0, 1024.0, "cells per axis must lie in 1..=1024");
/// Every classifier threshold.
pub const THRESHOLD: Domain = Domain::non_negative("must be ≥ 0 and finite");
/// The linear sample interval.
pub const EVERY: Domain = Domain::positive("must be positive");
/// The start of the logarithmic sample grid.
pub const LOG_FROM: Domain = Domain::positive("must be positive");
/// Snapshot times.
pub const SNAPSHOT_AT: Domain = Domain::non_negative("snapshot times must be ≥ 0");
/// Samples per decade of the logarithmic grid (the sample count per replica is checked too).
pub const PER_DECADE: Domain =
    Domain::integers(0.0, 10000.0, "samples per decade must lie in 0..=10000");
/// The deflate level.
pub const COMPRESSION: Domain = Domain::integers(0.0, 9.0, "deflate level must lie in 0..=9");

/// `schema_with` functions for the `#[schemars]` attributes of the spec types.
macro_rules! schema_fns {
    ($($name:ident => $domain:ident . $shape:ident),* $(,)?) => {
        $(
            pub(crate) fn $name(_: &mut SchemaGenerator) -> Schema {
                $domain.$shape()
            }
        )*
    };
}

schema_fns! {
    eps_axis => RESTITUTION.axis,
    beta_axis => BETA.axis,
    inertia_optional => INERTIA.optional,
    fraction_one => FRACTION.one,
    gravity_axis => GRAVITY.axis,
    shear_rate_axis => SHEAR_RATE.axis,
    wall_eps_axis => WALL_EPS.axis,
    floor_temperature_axis => FLOOR_TEMPERATURE.optional_axis,
    white_noise_axis => WHITE_NOISE.optional_axis,
    shake_s_axis => SHAKE_S.optional_axis,
    shake_gamma_axis => SHAKE_GAMMA.optional_axis,
    diameter_one => DIAMETER.one,
    mass_optional => MASS.optional,
    phi_axis => PHI.optional_axis,
    box_axis => BOX.optional_axis,
    n_axis => N.optional_axis,
    aspect_axis => ASPECT.optional_list_axis,
    seeds_one => SEEDS.one,
    tc_one => TC.one,
    theta_one => THETA_MAX_DEG.one,
    delta_one => DELTA.one,
    eps_low_one => RESTITUTION.one,
    v0_one => V0.one,
    speed_one => SPEED.one,
    melt_optional => MELT_TAU.optional,
    tau_max_one => TAU_MAX.one,
    temperature_ratio_optional => TEMPERATURE_RATIO.optional,
    classify_grid_optional => CLASSIFY_GRID.optional,
    threshold => THRESHOLD.one,
    every_optional => EVERY.optional,
    log_from_one => LOG_FROM.one,
    snapshot_list => SNAPSHOT_AT.list,
    compression_one => COMPRESSION.one,
    per_decade_one => PER_DECADE.one,
}

impl Domain {
    /// An absent or `null` list of values, or a non-empty list of such lists (an optional grid
    /// axis whose values are lists: the box's aspect).
    pub fn optional_list_axis(&self) -> Schema {
        let one = self.value();
        let list = json!({ "type": "array", "items": one, "minItems": 1 });
        json_schema!({
            "anyOf": [list, { "type": "array", "items": list, "minItems": 1 }, { "type": "null" }]
        })
    }

    /// An absent, `null`, single or listed value (an optional grid axis).
    pub fn optional_axis(&self) -> Schema {
        let one = self.value();
        json_schema!({
            "oneOf": [one, { "type": "array", "items": one, "minItems": 1 }, { "type": "null" }]
        })
    }
}

/// The dimension axis: 2 or 3, or a non-empty list of them.
pub(crate) fn dim_axis(_: &mut SchemaGenerator) -> Schema {
    json_schema!({
        "oneOf": [
            { "enum": [2, 3] },
            { "type": "array", "items": { "enum": [2, 3] }, "minItems": 1 }
        ]
    })
}
