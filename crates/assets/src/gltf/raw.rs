//! JSON objects kept as their members' raw text, in order: what the writer
//! edits is re-serialised, everything else is copied byte for byte (so
//! numbers such as `alphaCutoff` keep their decimal text and are never
//! rounded through `f64`).

use crate::AssetError;
use serde::de::{self, DeserializeOwned, MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::value::RawValue;
use std::collections::HashSet;
use std::fmt;

/// A JSON object: its members in order, each value as raw JSON text.
#[derive(Debug, Default)]
pub(super) struct RawObject(pub(super) Vec<(String, Box<RawValue>)>);

impl<'de> Deserialize<'de> for RawObject {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ObjectVisitor;
        impl<'de> Visitor<'de> for ObjectVisitor {
            type Value = RawObject;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<RawObject, A::Error> {
                let mut members = Vec::new();
                let mut seen = HashSet::new();
                while let Some(key) = map.next_key::<String>()? {
                    // Readers disagree on which duplicate wins: refuse.
                    if !seen.insert(key.clone()) {
                        return Err(de::Error::custom(format!("duplicate member {key:?}")));
                    }
                    let value: Box<RawValue> = map.next_value()?;
                    members.push((key, value));
                }
                Ok(RawObject(members))
            }
        }
        deserializer.deserialize_map(ObjectVisitor)
    }
}

impl Serialize for RawObject {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (key, value) in &self.0 {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

impl RawObject {
    pub(super) fn get(&self, key: &str) -> Option<&RawValue> {
        self.0.iter().find(|(k, _)| k == key).map(|(_, v)| &**v)
    }

    /// Sets `key` in place (keeping its position) or appends it.
    pub(super) fn set(&mut self, key: &str, value: Box<RawValue>) {
        match self.0.iter_mut().find(|(k, _)| k == key) {
            Some((_, slot)) => *slot = value,
            None => self.0.push((key.to_string(), value)),
        }
    }

    pub(super) fn remove(&mut self, key: &str) {
        self.0.retain(|(k, _)| k != key);
    }

    /// Member `key` parsed as `T` (`None` when absent); `path` names the
    /// object in the error.
    pub(super) fn parse<T: DeserializeOwned>(
        &self,
        key: &str,
        path: &str,
    ) -> Result<Option<T>, AssetError> {
        self.get(key)
            .map(|raw| parse_raw(raw, &field(path, key)))
            .transpose()
    }
}

/// `path.key`, or `key` at the top level.
pub(super) fn field(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_string()
    } else {
        format!("{path}.{key}")
    }
}

/// Raw JSON text parsed as `T`, the error naming `path`.
pub(super) fn parse_raw<T: DeserializeOwned>(raw: &RawValue, path: &str) -> Result<T, AssetError> {
    serde_json::from_str(raw.get()).map_err(|e| AssetError::gltf(path, e.to_string()))
}

/// A value as raw JSON text.
pub(super) fn to_raw<T: Serialize + ?Sized>(value: &T) -> Result<Box<RawValue>, AssetError> {
    serde_json::value::to_raw_value(value).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })
}
