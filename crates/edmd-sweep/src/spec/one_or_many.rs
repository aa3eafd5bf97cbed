//! `OneOrMany`: a spec value that is a single value or a list of them (a grid axis).

use std::borrow::Cow;

use schemars::{json_schema, JsonSchema, Schema, SchemaGenerator};
use serde::{Deserialize, Serialize};

/// A value or a list of values (`"eps": 0.9` or `"eps": [0.9, 0.8]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum OneOrMany<T> {
    /// A single value.
    One(T),
    /// A list of values (must not be empty).
    Many(Vec<T>),
}

/// Deserialised by hand rather than with `#[serde(untagged)]`, so that an error inside a value
/// (an unknown field of a grid, say) is reported as such instead of "did not match any variant".
impl<'de, T: serde::de::DeserializeOwned> Deserialize<'de> for OneOrMany<T> {
    fn deserialize<De: serde::Deserializer<'de>>(d: De) -> Result<Self, De::Error> {
        use serde::de::Error;
        let item = |index: Option<usize>, v: serde_json::Value| {
            serde_path_to_error::deserialize::<_, T>(v)
                .map_err(|e| De::Error::custom(nested_error(index, e)))
        };
        match serde_json::Value::deserialize(d)? {
            serde_json::Value::Array(items) => items
                .into_iter()
                .enumerate()
                .map(|(i, v)| item(Some(i), v))
                .collect::<Result<Vec<T>, _>>()
                .map(OneOrMany::Many),
            v => item(None, v).map(OneOrMany::One),
        }
    }
}

/// Marks the start and end of a field path carried inside an error message (a value inside a
/// `OneOrMany` is deserialised on its own, so serde's path stops at the `OneOrMany`).
pub(super) const PATH_MARK: char = '\u{1}';

/// `MARK [i].field MARK message`: the path below a `OneOrMany` (item index, fields, and any path
/// carried by a nested `OneOrMany`), then the message without serde_json's position, which would
/// point at the end of the enclosing value rather than at the field.
fn nested_error(index: Option<usize>, e: serde_path_to_error::Error<serde_json::Error>) -> String {
    let mut path = index.map(|i| format!("[{i}]")).unwrap_or_default();
    let inner_path = e.path().to_string();
    if inner_path != "." && !inner_path.is_empty() {
        path = format!("{path}.{inner_path}");
    }
    let inner = e.into_inner();
    let mut message = inner.to_string();
    if inner.line() > 0 {
        let at = format!(" at line {} column {}", inner.line(), inner.column());
        message = message.trim_end_matches(at.as_str()).to_string();
    }
    if let Some((deeper, rest)) = split_path(&message) {
        path += &deeper;
        message = rest;
    }
    format!("{PATH_MARK}{path}{PATH_MARK}{message}")
}

/// Splits `MARK path MARK message` into the path and the message (without positions).
pub(super) fn split_path(message: &str) -> Option<(String, String)> {
    let rest = message.strip_prefix(PATH_MARK)?;
    let (path, message) = rest.split_once(PATH_MARK)?;
    let message = match message.rfind(" at line ") {
        Some(k) if message[k..].contains(" column ") => &message[..k],
        _ => message,
    };
    Some((path.to_string(), message.to_string()))
}

/// In the schema: a value or a non-empty list of distinct values.
impl<T: JsonSchema> JsonSchema for OneOrMany<T> {
    fn schema_name() -> Cow<'static, str> {
        format!("OneOrMany_{}", T::schema_name()).into()
    }

    fn inline_schema() -> bool {
        true
    }

    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        let one = generator.subschema_for::<T>();
        json_schema!({ "oneOf": [one, { "type": "array", "items": one, "minItems": 1, "uniqueItems": true }] })
    }
}

impl<T: Clone> OneOrMany<T> {
    /// The values as a list.
    pub fn values(&self) -> Vec<T> {
        match self {
            OneOrMany::One(v) => vec![v.clone()],
            OneOrMany::Many(v) => v.clone(),
        }
    }
}
