//! `KHR_texture_transform` on the base-colour texture: read from its
//! decimal text (one rounding to binary32, as the renderer's uniforms);
//! the library's `UvTransform` models how the shader applies it.

use super::json::{short, Obj};
use super::reader::Reader;
use crate::json_number::json_number_f32;
use crate::AssetError;
use serde_json::value::RawValue;
use std::collections::HashMap;

/// A texture transform: `uv' = offset + R(rotation) (scale * uv)` (the
/// extension's `translation * rotation * scale`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Transform {
    pub(super) offset: [f32; 2],
    pub(super) rotation: f32,
    pub(super) scale: [f32; 2],
    /// `texCoord` of the extension, which overrides the texture info's.
    pub(super) tex_coord: Option<u32>,
}

/// The member `path` of a raw JSON value, following objects.
fn raw_at<'a>(raw: &'a RawValue, path: &[&str]) -> Option<&'a RawValue> {
    let mut at = raw;
    for key in path {
        let map: HashMap<&str, &RawValue> = serde_json::from_str(at.get()).ok()?;
        at = map.get(key)?;
    }
    Some(at)
}

impl<'a> Reader<'a, '_> {
    /// The `KHR_texture_transform` of material `index`'s
    /// `baseColorTexture` (`info`), if it has one.
    pub(super) fn texture_transform(
        &self,
        index: usize,
        info: &Obj<'a>,
    ) -> Result<Option<Transform>, AssetError> {
        let Some(extensions) = info.opt_obj("extensions")? else {
            return Ok(None);
        };
        let Some(ext) = extensions.opt_obj("KHR_texture_transform")? else {
            return Ok(None);
        };
        let raw = self.raw_materials.get(index).and_then(|raw| {
            raw_at(
                raw,
                &[
                    "pbrMetallicRoughness",
                    "baseColorTexture",
                    "extensions",
                    "KHR_texture_transform",
                ],
            )
        });
        let number = |text: Option<&RawValue>, what: &str, value: &serde_json::Value| {
            text.and_then(|t| json_number_f32(t.get()))
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    ext.error(what, format!("{}, expected a finite number", short(value)))
                })
        };
        let pair = |key: &str, default: [f32; 2]| -> Result<[f32; 2], AssetError> {
            let Some(value) = ext.map.get(key) else {
                return Ok(default);
            };
            let texts: Option<Vec<&RawValue>> = raw
                .and_then(|raw| raw_at(raw, &[key]))
                .and_then(|r| serde_json::from_str(r.get()).ok());
            match texts.as_deref() {
                Some([a, b]) => Ok([number(Some(a), key, value)?, number(Some(b), key, value)?]),
                _ => Err(ext.error(
                    key,
                    format!("{}, expected an array of 2 numbers", short(value)),
                )),
            }
        };
        let offset = pair("offset", [0.0, 0.0])?;
        let scale = pair("scale", [1.0, 1.0])?;
        let rotation = match ext.map.get("rotation") {
            None => 0.0,
            Some(value) => number(
                raw.and_then(|raw| raw_at(raw, &["rotation"])),
                "rotation",
                value,
            )?,
        };
        Ok(Some(Transform {
            offset,
            rotation,
            scale,
            tex_coord: ext.opt_u32("texCoord")?,
        }))
    }
}
