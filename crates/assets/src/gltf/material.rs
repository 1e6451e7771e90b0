//! Materials: `alphaCutoff` and `baseColorFactor`, each read from its
//! decimal text with one rounding to binary32.

use super::json::{short, Obj};
use crate::json_number::json_number_f32;
use crate::AssetError;
use micromap_index::bake::{Comparison, Cutoff};
use serde::Deserialize;
use serde_json::value::RawValue;

/// Material fields read from their decimal text (one rounding to binary32).
#[derive(Deserialize)]
pub(super) struct RawRoot<'a> {
    #[serde(borrow, default)]
    materials: Option<&'a RawValue>,
}

#[derive(Deserialize)]
pub(super) struct RawMaterial<'a> {
    #[serde(borrow, default, rename = "alphaCutoff")]
    alpha_cutoff: Option<&'a RawValue>,
    #[serde(borrow, default, rename = "pbrMetallicRoughness")]
    pbr: Option<&'a RawValue>,
}

#[derive(Deserialize)]
pub(super) struct RawPbr<'a> {
    #[serde(borrow, default, rename = "baseColorFactor")]
    base_color_factor: Option<&'a RawValue>,
}

/// The raw text of each material (empty if `materials` is not an array,
/// which the structured reading reports).
pub(super) fn raw_materials(json: &[u8]) -> Result<Vec<&RawValue>, AssetError> {
    let root: RawRoot<'_> = serde_json::from_slice(json).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })?;
    Ok(root
        .materials
        .and_then(|raw| serde_json::from_str::<Vec<&RawValue>>(raw.get()).ok())
        .unwrap_or_default())
}

/// `alphaCutoff` (as glTF's `alpha >= cutoff`) and `baseColorFactor[3]`
/// of `material`, from their decimal text in `raw` (the material's raw
/// text, from [`raw_materials`]).
pub(super) fn material_numbers(
    raw: Option<&RawValue>,
    material: &Obj<'_>,
) -> Result<(Cutoff, f32), AssetError> {
    // The structured reading has checked the types; the raw reading gives
    // the text of the same members.
    let raw: Option<RawMaterial<'_>> = raw.and_then(|raw| serde_json::from_str(raw.get()).ok());
    let cutoff = match material.map.get("alphaCutoff") {
        None => 0.5,
        Some(value) => {
            let parsed = raw
                .as_ref()
                .and_then(|raw| raw.alpha_cutoff)
                .and_then(|text| json_number_f32(text.get()));
            match parsed {
                Some(cutoff) if cutoff >= 0.0 => cutoff,
                _ => {
                    return Err(material.error(
                        "alphaCutoff",
                        format!("{}, expected a number >= 0", short(value)),
                    ))
                }
            }
        }
    };
    let pbr = material.opt_obj("pbrMetallicRoughness")?;
    let factor = match pbr.as_ref().and_then(|pbr| pbr.map.get("baseColorFactor")) {
        None => 1.0,
        Some(value) => {
            let field = pbr
                .as_ref()
                .map(|pbr| pbr.field("baseColorFactor"))
                .unwrap_or_default();
            let texts: Option<Vec<&RawValue>> = raw
                .as_ref()
                .and_then(|raw| raw.pbr)
                .and_then(|pbr| serde_json::from_str::<RawPbr<'_>>(pbr.get()).ok())
                .and_then(|pbr| pbr.base_color_factor)
                .and_then(|factor| serde_json::from_str(factor.get()).ok());
            let numbers: Option<Vec<f32>> = texts.and_then(|texts| {
                texts
                    .iter()
                    .map(|text| json_number_f32(text.get()))
                    .collect()
            });
            match numbers.as_deref() {
                Some(&[_, _, _, alpha]) => alpha,
                _ => {
                    return Err(AssetError::gltf(
                        field,
                        format!("{}, expected an array of 4 numbers", short(value)),
                    ))
                }
            }
        }
    };
    // Not NaN: checked above.
    let cutoff = Cutoff::new(cutoff, Comparison::AtLeast)
        .map_err(|e| material.error("alphaCutoff", e.to_string()))?;
    Ok((cutoff, factor))
}
