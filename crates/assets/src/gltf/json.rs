//! Walking the glTF's JSON: objects with their paths, typed fields, and
//! values for error messages.

use crate::AssetError;
use serde_json::{Map, Value};

/// A JSON object and its path (`meshes[0].primitives[1]`).
#[derive(Clone)]
pub(super) struct Obj<'a> {
    pub(super) map: &'a Map<String, Value>,
    pub(super) path: String,
}

impl<'a> Obj<'a> {
    pub(super) fn field(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    pub(super) fn error(&self, key: &str, message: impl Into<String>) -> AssetError {
        AssetError::gltf(self.field(key), message)
    }

    pub(super) fn opt_u64(&self, key: &str) -> Result<Option<u64>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(value) => value.as_u64().map(Some).ok_or_else(|| {
                self.error(
                    key,
                    format!("{}, expected a non-negative integer", short(value)),
                )
            }),
        }
    }

    pub(super) fn opt_usize(&self, key: &str) -> Result<Option<usize>, AssetError> {
        match self.opt_u64(key)? {
            None => Ok(None),
            Some(n) => usize::try_from(n)
                .map(Some)
                .map_err(|_| self.error(key, format!("{n} is too large"))),
        }
    }

    pub(super) fn usize(&self, key: &str) -> Result<usize, AssetError> {
        self.opt_usize(key)?
            .ok_or_else(|| self.error(key, "missing"))
    }

    pub(super) fn opt_u32(&self, key: &str) -> Result<Option<u32>, AssetError> {
        match self.opt_u64(key)? {
            None => Ok(None),
            Some(n) => u32::try_from(n)
                .map(Some)
                .map_err(|_| self.error(key, format!("{n} is too large"))),
        }
    }

    pub(super) fn opt_bool(&self, key: &str) -> Result<Option<bool>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(value) => value
                .as_bool()
                .map(Some)
                .ok_or_else(|| self.error(key, format!("{}, expected a boolean", short(value)))),
        }
    }

    pub(super) fn opt_str(&self, key: &str) -> Result<Option<&'a str>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(value) => value
                .as_str()
                .map(Some)
                .ok_or_else(|| self.error(key, format!("{}, expected a string", short(value)))),
        }
    }

    pub(super) fn str(&self, key: &str) -> Result<&'a str, AssetError> {
        self.opt_str(key)?.ok_or_else(|| self.error(key, "missing"))
    }

    pub(super) fn opt_obj(&self, key: &str) -> Result<Option<Obj<'a>>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(Value::Object(map)) => Ok(Some(Obj {
                map,
                path: self.field(key),
            })),
            Some(value) => Err(self.error(key, format!("{}, expected an object", short(value)))),
        }
    }

    pub(super) fn obj(&self, key: &str) -> Result<Obj<'a>, AssetError> {
        self.opt_obj(key)?.ok_or_else(|| self.error(key, "missing"))
    }

    pub(super) fn opt_array(&self, key: &str) -> Result<Option<&'a [Value]>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(Value::Array(items)) => Ok(Some(items)),
            Some(value) => Err(self.error(key, format!("{}, expected an array", short(value)))),
        }
    }

    /// `self[key][index]`, an object; `what` names the reference for the
    /// error (`meshes[0].primitives[1].material`).
    pub(super) fn element(
        &self,
        key: &str,
        index: usize,
        what: &str,
    ) -> Result<Obj<'a>, AssetError> {
        let items = self.opt_array(key)?.unwrap_or_default();
        match items.get(index) {
            Some(Value::Object(map)) => Ok(Obj {
                map,
                path: format!("{}[{index}]", self.field(key)),
            }),
            Some(value) => Err(AssetError::gltf(
                format!("{}[{index}]", self.field(key)),
                format!("{}, expected an object", short(value)),
            )),
            None => Err(AssetError::gltf(
                what,
                format!("{key}[{index}] does not exist ({} {key})", items.len()),
            )),
        }
    }
}

/// A JSON value for an error message: its kind and, if short, its text.
pub(super) fn short(value: &Value) -> String {
    let text = value.to_string();
    let kind = match value {
        Value::Null => return "null".to_string(),
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    };
    if text.len() <= 40 {
        format!("{kind} {text}")
    } else {
        kind.to_string()
    }
}
