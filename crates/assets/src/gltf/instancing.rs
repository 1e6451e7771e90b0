//! `EXT_mesh_gpu_instancing` on a node with a mesh: the mesh is drawn once
//! per instance, at the node's world transform times the instance's
//! `TRANSLATION * ROTATION * SCALE` (each attribute optional, identity when
//! absent), for renderers ([`MaskPrimitive::instances`](super::MaskPrimitive::instances)).
//! The accessors are read as every other accessor (byte offsets, strides,
//! sparse substitution, the byte budget); a malformed extension is a
//! reason, which `nodes` makes the node tree's (a warning, never an error:
//! bakes do not depend on it).

use super::accessor::component_name;
use super::json::Obj;
use super::nodes::{trs, Affine, InstanceTransforms};
use super::reader::{bytes_of, Reader, INSTANCING, INSTANCING_KHR};

/// The attributes that make the instance transform, in the order their
/// counts are compared (custom attributes after them).
const TRS: [&str; 3] = ["TRANSLATION", "ROTATION", "SCALE"];

/// A reader's error as the reason the node tree is not applied.
fn reason(e: impl std::fmt::Display) -> String {
    e.to_string()
}

impl<'a> Reader<'a, '_> {
    /// The instance transforms (binary64, row-major 3x4) of `node`'s
    /// `EXT_mesh_gpu_instancing` (or its `KHR_` spelling), in accessor
    /// order; `None` without the extension. Refused, with the reason:
    /// both spellings on one node, no `attributes` or none in it (the
    /// schema asks for at least one; without one the instance count is not
    /// defined), an attribute that is not an accessor index, attributes of
    /// different counts (custom `_NAME` attributes included), a count of
    /// 0, `TRANSLATION` or `SCALE` other than `VEC3` of `FLOAT`,
    /// `ROTATION` other than `VEC4` of `FLOAT` or normalized `BYTE` or
    /// `SHORT` (`max(c / 127, -1)`, `max(c / 32767, -1)`), a value that is
    /// not finite, a zero quaternion (others are normalised, as a node's),
    /// and the byte budget.
    pub(super) fn gpu_instances(&mut self, node: &Obj<'a>) -> InstanceTransforms {
        let Some(extensions) = node.opt_obj("extensions").map_err(reason)? else {
            return Ok(None);
        };
        let ext = extensions.opt_obj(INSTANCING).map_err(reason)?;
        let khr = extensions.opt_obj(INSTANCING_KHR).map_err(reason)?;
        let ext = match (ext, khr) {
            (None, None) => return Ok(None),
            (Some(ext), None) | (None, Some(ext)) => ext,
            (Some(_), Some(_)) => {
                return Err(format!(
                    "{}: both {INSTANCING} and {INSTANCING_KHR}",
                    node.field("extensions")
                ))
            }
        };
        let attributes = ext.opt_obj("attributes").map_err(reason)?;
        let Some(attributes) = attributes.filter(|a| !a.map.is_empty()) else {
            return Err(format!(
                "{}: no attributes, so no instance count (at least one is required)",
                ext.field("attributes")
            ));
        };
        // Every attribute's count, checked equal before anything is
        // decoded: the transform's first, then the custom ones.
        let names = TRS
            .into_iter()
            .filter(|name| attributes.map.contains_key(*name))
            .chain(
                attributes
                    .map
                    .keys()
                    .map(String::as_str)
                    .filter(|name| !TRS.contains(name)),
            );
        let mut count: Option<(usize, &str)> = None;
        for name in names {
            let index = attributes.usize(name).map_err(reason)?;
            let accessor = self
                .root
                .element("accessors", index, &attributes.field(name))
                .map_err(reason)?;
            let n = accessor.usize("count").map_err(reason)?;
            match count {
                None => count = Some((n, name)),
                Some((first, first_name)) if first != n => {
                    return Err(format!(
                        "{}: {first_name} has {first} instances but {name} has {n} (all attributes must have the same count)",
                        attributes.path
                    ))
                }
                Some(_) => {}
            }
        }
        let count = count.map_or(0, |(n, _)| n);
        if count == 0 {
            return Err(format!("{}: a count of 0 instances", attributes.path));
        }
        let float3 = |reader: &mut Self, name: &str| -> Result<Option<Vec<[f64; 3]>>, String> {
            let Some(index) = attributes.opt_usize(name).map_err(reason)? else {
                return Ok(None);
            };
            let what = attributes.field(name);
            let (accessor, layout) = reader.layout(index, &what, "VEC3", 3).map_err(reason)?;
            if layout.component_type != 5126 || layout.normalized {
                return Err(reason(accessor.error(
                    "componentType",
                    format!(
                        "{} ({}{}), expected FLOAT for {name}",
                        layout.component_type,
                        if layout.normalized { "normalized " } else { "" },
                        component_name(layout.component_type)
                    ),
                )));
            }
            let values = reader
                .elements(&accessor, &layout, |c| {
                    let f = |i: usize| f32::from_le_bytes([c[i], c[i + 1], c[i + 2], c[i + 3]]);
                    [f(0), f(4), f(8)].map(f64::from)
                })
                .map_err(reason)?;
            finite(&values, &layout.path)?;
            Ok(Some(values))
        };
        let translations = float3(self, "TRANSLATION")?;
        let scales = float3(self, "SCALE")?;
        let rotations = match attributes.opt_usize("ROTATION").map_err(reason)? {
            None => None,
            Some(index) => Some(self.rotations(index, &attributes.field("ROTATION"))?),
        };
        self.budget
            .take(
                || format!("{} ({count} instance transforms)", attributes.path),
                bytes_of(count as u64, std::mem::size_of::<Affine>() as u64 + 48),
            )
            .map_err(reason)?;
        let mut transforms = Vec::new();
        transforms.try_reserve_exact(count).map_err(|_| {
            format!(
                "{}: {count} instances do not fit in memory",
                attributes.path
            )
        })?;
        for k in 0..count {
            let t = translations.as_ref().map_or([0.0; 3], |v| v[k]);
            let q = rotations.as_ref().map_or([0.0, 0.0, 0.0, 1.0], |v| v[k]);
            let s = scales.as_ref().map_or([1.0; 3], |v| v[k]);
            transforms.push(trs(t, q, s).ok_or_else(|| {
                format!(
                    "{}: element {k} is a zero quaternion",
                    attributes.field("ROTATION")
                )
            })?);
        }
        Ok(Some(transforms))
    }

    /// The quaternions of `ROTATION` accessor `index`.
    fn rotations(&mut self, index: usize, what: &str) -> Result<Vec<[f64; 4]>, String> {
        let (accessor, layout) = self.layout(index, what, "VEC4", 4).map_err(reason)?;
        let convert: fn(&[u8]) -> f64 = match (layout.component_type, layout.normalized) {
            (5126, false) => |c| f64::from(f32::from_le_bytes([c[0], c[1], c[2], c[3]])),
            (5120, true) => |c| (f64::from(c[0] as i8) / 127.0).max(-1.0),
            (5122, true) => |c| (f64::from(i16::from_le_bytes([c[0], c[1]])) / 32767.0).max(-1.0),
            (other, normalized) => {
                return Err(reason(accessor.error(
                    "componentType",
                    format!(
                        "{other} ({}{}), expected FLOAT or normalized BYTE or SHORT for ROTATION",
                        if normalized { "normalized " } else { "" },
                        component_name(other)
                    ),
                )))
            }
        };
        let size = layout.element_size / 4;
        let values = self
            .elements(&accessor, &layout, |c| {
                [0, 1, 2, 3].map(|k| convert(&c[k * size..(k + 1) * size]))
            })
            .map_err(reason)?;
        finite(&values, &layout.path)?;
        Ok(values)
    }
}

/// Every value finite, or the first element that is not.
fn finite<const N: usize>(values: &[[f64; N]], path: &str) -> Result<(), String> {
    match values.iter().position(|v| v.iter().any(|x| !x.is_finite())) {
        None => Ok(()),
        Some(i) => Err(format!(
            "{path}: element {i} is {:?}, not finite",
            values[i]
        )),
    }
}
