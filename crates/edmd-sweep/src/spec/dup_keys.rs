//! Duplicate keys anywhere in a spec's JSON are refused with their path, before the spec is read.
//!
//! serde's derive refuses a repeated field of a struct, but values read through an intermediate
//! `serde_json::Value` (a grid, a list of species) keep the last of two equal keys silently:
//! `"eps": [1, 0.95], "eps": 0.5` would run one replica. One pass over the text sees every object.

use std::collections::HashSet;
use std::fmt;

use serde::de::{DeserializeSeed, Deserializer, MapAccess, SeqAccess, Visitor};

/// Walks one JSON value, at `path`, failing on the first object with a repeated key.
struct Walk<'a> {
    path: &'a str,
}

impl<'de> DeserializeSeed<'de> for Walk<'_> {
    type Value = ();

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<(), D::Error> {
        d.deserialize_any(self)
    }
}

impl<'de> Visitor<'de> for Walk<'_> {
    type Value = ();

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("a JSON value")
    }

    fn visit_bool<E>(self, _: bool) -> Result<(), E> {
        Ok(())
    }
    fn visit_i64<E>(self, _: i64) -> Result<(), E> {
        Ok(())
    }
    fn visit_u64<E>(self, _: u64) -> Result<(), E> {
        Ok(())
    }
    fn visit_f64<E>(self, _: f64) -> Result<(), E> {
        Ok(())
    }
    fn visit_str<E>(self, _: &str) -> Result<(), E> {
        Ok(())
    }
    fn visit_unit<E>(self) -> Result<(), E> {
        Ok(())
    }

    fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<(), A::Error> {
        let mut k = 0;
        loop {
            let path = format!("{}[{k}]", self.path);
            if seq.next_element_seed(Walk { path: &path })?.is_none() {
                return Ok(());
            }
            k += 1;
        }
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<(), A::Error> {
        let mut seen = HashSet::new();
        while let Some(key) = map.next_key::<String>()? {
            let path = if self.path.is_empty() {
                key.clone()
            } else {
                format!("{}.{key}", self.path)
            };
            if !seen.insert(key.clone()) {
                return Err(serde::de::Error::custom(format!(
                    "{path}: duplicate key `{key}` (a key may appear once in an object)"
                )));
            }
            map.next_value_seed(Walk { path: &path })?;
        }
        Ok(())
    }
}

/// Fails with `path: duplicate key` at the first object that repeats a key. Text that is not JSON
/// passes: the spec's own parse reports it.
pub(super) fn check(text: &str) -> Result<(), String> {
    let mut de = serde_json::Deserializer::from_str(text);
    match (Walk { path: "" }).deserialize(&mut de) {
        Err(e) if e.to_string().contains("duplicate key") => {
            let s = e.to_string();
            // serde_json appends " at line L column C": keep the path and reason.
            Err(s.split(" at line ").next().unwrap_or(&s).to_string())
        }
        _ => Ok(()),
    }
}
