//! `grid.species`: the grains of a mixture, one mixture or a list of them (an axis).

use std::borrow::Cow;
use std::sync::Arc;

use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::{Deserialize, Serialize};

/// One species of a mixture.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Species {
    /// Number fraction, in (0, 1]; the fractions of a mixture sum to 1.
    #[schemars(schema_with = "crate::domain::fraction_one")]
    pub fraction: f64,
    /// Diameter σ in units of the default grain (σ = 1).
    #[schemars(schema_with = "crate::domain::diameter_one")]
    pub diameter: f64,
    /// Mass (default σ^D: every species of one material).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(schema_with = "crate::domain::mass_optional")]
    pub mass: Option<f64>,
}

impl Species {
    /// The mass of a grain, σ^D unless given.
    pub fn mass_in(&self, dim: usize) -> f64 {
        self.mass.unwrap_or(self.diameter.powi(dim as i32))
    }
}

/// A mixture: its species in order (species k of the files is the k-th here).
pub type Mixture = Arc<Vec<Species>>;

/// A grid value that is itself a list: one list (`[a, b]`) or several (`[[a, b], [c]]`), an axis.
#[derive(Debug, Clone, PartialEq)]
pub struct ListAxis<T>(pub Vec<Arc<Vec<T>>>);

/// One mixture (`[{…}, {…}]`) or several (`[[{…}, {…}], [{…}]]`), an axis of the grid.
pub type SpeciesAxis = ListAxis<Species>;

/// Relative box sides, one list of D numbers or several (an axis).
pub type AspectAxis = ListAxis<f64>;

impl<T: Serialize> Serialize for ListAxis<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self.0.as_slice() {
            [one] => one.as_slice().serialize(s),
            many => many
                .iter()
                .map(|m| m.as_slice())
                .collect::<Vec<_>>()
                .serialize(s),
        }
    }
}

impl<'de, T: serde::de::DeserializeOwned> Deserialize<'de> for ListAxis<T> {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        use serde::de::Error;
        let v = serde_json::Value::deserialize(d)?;
        let nested = matches!(&v, serde_json::Value::Array(items) if items.first().is_some_and(|x| x.is_array()));
        let parse = |v: serde_json::Value, at: String| {
            serde_path_to_error::deserialize::<_, Vec<T>>(v)
                .map(Arc::new)
                .map_err(|e| {
                    let path = e.path().to_string();
                    De::Error::custom(
                        format!(
                            "{}{}{}{}",
                            super::one_or_many::PATH_MARK,
                            at,
                            if path == "." { String::new() } else { path },
                            super::one_or_many::PATH_MARK
                        ) + &strip_position(&e.into_inner().to_string()),
                    )
                })
        };
        if nested {
            let serde_json::Value::Array(items) = v else {
                unreachable!()
            };
            items
                .into_iter()
                .enumerate()
                .map(|(i, m)| parse(m, format!("[{i}]")))
                .collect::<Result<Vec<_>, _>>()
                .map(ListAxis)
        } else {
            parse(v, String::new()).map(|m| ListAxis(vec![m]))
        }
    }
}

fn strip_position(message: &str) -> String {
    match message.rfind(" at line ") {
        Some(k) if message[k..].contains(" column ") => message[..k].to_string(),
        _ => message.to_string(),
    }
}

impl<T: JsonSchema> JsonSchema for ListAxis<T> {
    fn schema_name() -> Cow<'static, str> {
        format!("ListAxis_{}", T::schema_name()).into()
    }

    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        let item = generator.subschema_for::<T>();
        let list = json_schema!({ "type": "array", "items": item, "minItems": 1 });
        json_schema!({
            "description": "One list or a list of lists (an axis).",
            "oneOf": [list, { "type": "array", "items": list, "minItems": 1 }]
        })
    }
}

/// Particles per species of a mixture of `n` grains: ⌊x_k N⌋ each, the remainder given one by one
/// to the largest fractional parts (the earlier species on ties), so that the split is deterministic
/// and sums to N.
pub fn counts(mixture: &[Species], n: usize) -> Vec<usize> {
    let exact: Vec<f64> = mixture.iter().map(|s| s.fraction * n as f64).collect();
    let mut out: Vec<usize> = exact.iter().map(|x| x.floor() as usize).collect();
    let mut left = n.saturating_sub(out.iter().sum());
    let mut order: Vec<usize> = (0..mixture.len()).collect();
    order.sort_by(|&a, &b| {
        (exact[b] - exact[b].floor())
            .total_cmp(&(exact[a] - exact[a].floor()))
            .then(a.cmp(&b))
    });
    for &k in order.iter().cycle() {
        if left == 0 {
            break;
        }
        out[k] += 1;
        left -= 1;
    }
    out
}

/// `0.5:1:1+0.5:1.4:1.96` (fraction:diameter:mass per species), the label of a mixture in tables.
pub fn label(mixture: &[Species], dim: usize) -> String {
    mixture
        .iter()
        .map(|s| {
            format!(
                "{}:{}:{}",
                short(s.fraction),
                short(s.diameter),
                short(s.mass_in(dim))
            )
        })
        .collect::<Vec<_>>()
        .join("+")
}

/// A number with at most 9 significant digits (σ^D of 1.4 is 1.9599999999999997 in binary).
fn short(x: f64) -> String {
    let s = format!("{:.9e}", x);
    s.parse::<f64>().map(|v| v.to_string()).unwrap_or(s)
}
