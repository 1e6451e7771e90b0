//! [`read_gltf_micromaps`]: the `EXT_mesh_opacity_micromap` micromaps of a
//! glTF and the primitives that use them, validated against the newest
//! draft's rules (every malformed case an [`AssetError`]).

use super::accessor::Layout;
use super::extension::{EXTENSION, MAX_GLTF_LEVEL};
use super::files::{read_file, resolve_beside};
use super::json::{short, Obj};
use super::reader::{with_reader, Reader};
use crate::{AssetError, Limits};
use micromap_index::micromap::State;
use micromap_index::micromap::{
    read_buffers, usage_counts_to_le_bytes, BufferBytes, Micromap, MicromapIndex, Overlap,
    ReadOptions, TriangleOpacity, TriangleRecord, UsageCount,
};
use std::path::Path;

/// One entry of the root `extensions.EXT_mesh_opacity_micromap.micromaps`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfMicromap {
    /// `name`, if given.
    pub name: Option<String>,
    /// The triangle records of its `triangles` buffer view.
    pub records: Vec<TriangleRecord>,
    /// The micromap each record describes (from its `data` buffer view).
    pub micromaps: Vec<Micromap>,
    /// `usageCounts`, `usageLevels`, `usageFormats`, entry by entry.
    pub usage: Vec<UsageCount>,
}

/// A primitive with `EXT_mesh_opacity_micromap`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfMicromapPrimitive {
    /// The mesh: index into the glTF's `meshes`.
    pub mesh: usize,
    /// The primitive: index into the mesh's `primitives`.
    pub primitive: usize,
    /// `micromap`: index into [`GltfMicromaps::micromaps`].
    pub micromap: usize,
    /// `micromapBaseTriangle` (default 0).
    pub base_triangle: u32,
    /// Whether `micromapIndices` was given (otherwise triangle `t` uses
    /// record `t + base_triangle`).
    pub has_index_accessor: bool,
    /// Each triangle's record (the base triangle added) or special index.
    pub indices: Vec<MicromapIndex>,
}

/// What [`read_gltf_micromaps`] reads.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct GltfMicromaps {
    /// The root micromaps, in order.
    pub micromaps: Vec<GltfMicromap>,
    /// The primitives with the extension, in the order of `meshes` and
    /// their `primitives`.
    pub primitives: Vec<GltfMicromapPrimitive>,
}

impl GltfMicromaps {
    /// Triangle `t` of `primitive` as the API sees it: its micromap or its
    /// special state (`None` past the end).
    #[must_use]
    pub fn opacity(
        &self,
        primitive: &GltfMicromapPrimitive,
        t: usize,
    ) -> Option<TriangleOpacity<'_>> {
        Some(match *primitive.indices.get(t)? {
            MicromapIndex::Record(r) => TriangleOpacity::Micromap(
                self.micromaps
                    .get(primitive.micromap)?
                    .micromaps
                    .get(r as usize)?,
            ),
            MicromapIndex::Special(state) => TriangleOpacity::Special(state),
        })
    }

    /// The primitive `(mesh, primitive)`, if it has the extension.
    #[must_use]
    pub fn primitive(&self, mesh: usize, primitive: usize) -> Option<&GltfMicromapPrimitive> {
        self.primitives
            .iter()
            .find(|p| p.mesh == mesh && p.primitive == primitive)
    }
}

/// Reads every `EXT_mesh_opacity_micromap` micromap and primitive of a
/// glTF (JSON or GLB bytes; `resolve` and `limits` as for
/// [`read_gltf_bytes`](crate::read_gltf_bytes)), checking the newest
/// draft's rules (KhronosGroup/glTF pull request 2623 at 4b95e4d3):
///
/// * the extension in `extensionsUsed` whenever it is used;
/// * root: `micromaps` with at least one entry; each with `data` and
///   `triangles` buffer views without `byteStride`, `triangles` a multiple
///   of 8 bytes; the three usage arrays non-empty and of equal length,
///   counts at least 1, levels in `0..=12`, formats 1 or 2, and for each
///   (level, format) the counts summing to the records with it; every
///   record's level in `0..=12`, its block inside `data`, no two blocks
///   overlapping ([`read_buffers`]);
/// * primitive: mode 4; `micromap` naming a micromap; optional
///   `micromapIndices`: a `SCALAR` accessor of `UNSIGNED_BYTE`,
///   `UNSIGNED_SHORT`, `UNSIGNED_INT` (special indices as the patterns of
///   -1..-4; every other value below `2^n - 4`, so `2^n - 5` is a regular
///   index here) or `SHORT`, `INT` (-4 or more), not normalized, `count`
///   the triangle count, its buffer view without `byteStride`, offsets
///   aligned to the component; each regular value plus
///   `micromapBaseTriangle` naming a record; without the accessor,
///   triangle `t` uses record `t + micromapBaseTriangle`, which must
///   exist.
///
/// A glTF without the extension gives an empty [`GltfMicromaps`]. Never
/// panics.
///
/// ```
/// use micromap_index_assets::{read_gltf_micromaps, AssetError, Limits};
/// let gltf = br#"{"asset": {"version": "2.0"}, "extensionsUsed": ["EXT_mesh_opacity_micromap"],
///   "extensions": {"EXT_mesh_opacity_micromap": {"micromaps": []}}}"#;
/// let mut no_files = |uri: &str| Err(AssetError::Uri { uri: uri.into(), message: "no files".into() });
/// let error = read_gltf_micromaps(gltf, &mut no_files, &Limits::default()).unwrap_err();
/// assert_eq!(error.to_string(), "extensions.EXT_mesh_opacity_micromap.micromaps: empty, expected at least one micromap");
/// ```
pub fn read_gltf_micromaps(
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
    limits: &Limits,
) -> Result<GltfMicromaps, AssetError> {
    // A closure: the method's lifetimes are not general enough for `with_reader`.
    #[allow(clippy::redundant_closure_for_method_calls)]
    with_reader(bytes, resolve, limits, |reader| reader.read_micromaps())
}

/// [`read_gltf_micromaps`] of the glTF file at `path`, its relative URIs
/// resolved against the file's directory as
/// [`read_gltf_file`](crate::read_gltf_file) resolves them (within
/// [`Limits::max_bytes`] and [`Limits::uri_scope`]; absolute paths
/// refused). Errors name the file.
pub fn read_gltf_micromaps_file(path: &Path, limits: &Limits) -> Result<GltfMicromaps, AssetError> {
    let within = |e: AssetError| e.within(path.display().to_string());
    let bytes = read_file(path, limits.max_bytes).map_err(within)?;
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    let mut resolve = resolve_beside(base, limits);
    read_gltf_micromaps(&bytes, &mut resolve, limits).map_err(within)
}

impl Reader<'_, '_> {
    fn read_micromaps(&mut self) -> Result<GltfMicromaps, AssetError> {
        let mut out = GltfMicromaps::default();
        let root = self.root.clone();
        let used = root
            .opt_array("extensionsUsed")?
            .unwrap_or_default()
            .iter()
            .any(|v| v.as_str() == Some(EXTENSION));
        let not_listed = |path: String| {
            AssetError::gltf(
                path,
                format!("uses {EXTENSION}, which extensionsUsed does not list"),
            )
        };
        if let Some(extensions) = root.opt_obj("extensions")? {
            if let Some(ext) = extensions.opt_obj(EXTENSION)? {
                if !used {
                    return Err(not_listed(ext.path.clone()));
                }
                let items = ext
                    .opt_array("micromaps")?
                    .ok_or_else(|| ext.error("micromaps", "missing"))?;
                if items.is_empty() {
                    return Err(ext.error("micromaps", "empty, expected at least one micromap"));
                }
                for i in 0..items.len() {
                    let entry = ext.element("micromaps", i, &ext.field("micromaps"))?;
                    out.micromaps.push(self.micromap(&entry)?);
                }
            }
        }
        let meshes = root.opt_array("meshes")?.unwrap_or_default();
        for m in 0..meshes.len() {
            let mesh = root.element("meshes", m, "meshes")?;
            let primitives = mesh.opt_array("primitives")?.unwrap_or_default();
            for p in 0..primitives.len() {
                let primitive = mesh.element("primitives", p, &mesh.field("primitives"))?;
                let Some(ext) = primitive
                    .opt_obj("extensions")?
                    .map(|e| e.opt_obj(EXTENSION))
                    .transpose()?
                    .flatten()
                else {
                    continue;
                };
                if !used {
                    return Err(not_listed(ext.path.clone()));
                }
                let found = self.micromap_primitive(&primitive, &ext, m, p, &out.micromaps)?;
                out.primitives.push(found);
            }
        }
        Ok(out)
    }

    /// One root micromap entry.
    fn micromap(&mut self, entry: &Obj<'_>) -> Result<GltfMicromap, AssetError> {
        let name = entry.opt_str("name")?.map(str::to_string);
        let mut arrays = Vec::new();
        for key in ["usageCounts", "usageLevels", "usageFormats"] {
            let items = entry
                .opt_array(key)?
                .ok_or_else(|| entry.error(key, "missing"))?;
            if items.is_empty() {
                return Err(entry.error(key, "empty, expected at least one entry"));
            }
            let values = items
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    v.as_u64()
                        .and_then(|n| u32::try_from(n).ok())
                        .ok_or_else(|| {
                            AssetError::gltf(
                                format!("{}[{i}]", entry.field(key)),
                                format!("{}, expected an integer in 0..2^32", short(v)),
                            )
                        })
                })
                .collect::<Result<Vec<u32>, _>>()?;
            arrays.push(values);
        }
        let (counts, levels, formats) = (&arrays[0], &arrays[1], &arrays[2]);
        if counts.len() != levels.len() || counts.len() != formats.len() {
            return Err(entry.error(
                "usageCounts",
                format!(
                    "usageCounts, usageLevels and usageFormats have {}, {} and {} entries, expected equal lengths",
                    counts.len(),
                    levels.len(),
                    formats.len()
                ),
            ));
        }
        for (i, ((&count, &level), &format)) in counts.iter().zip(levels).zip(formats).enumerate() {
            let bad = if count == 0 {
                Some(("usageCounts", format!("{count}, expected at least 1")))
            } else if level > MAX_GLTF_LEVEL {
                Some((
                    "usageLevels",
                    format!("{level}, expected a level in 0..={MAX_GLTF_LEVEL}"),
                ))
            } else if !(1..=2).contains(&format) {
                Some(("usageFormats", format!("{format}, expected 1 or 2")))
            } else {
                None
            };
            if let Some((key, message)) = bad {
                return Err(AssetError::gltf(
                    format!("{}[{i}]", entry.field(key)),
                    message,
                ));
            }
        }
        let usage: Vec<UsageCount> = counts
            .iter()
            .zip(levels)
            .zip(formats)
            .map(|((&count, &subdivision_level), &format)| UsageCount {
                count,
                subdivision_level,
                format,
            })
            .collect();
        let data = self.tight_view(entry, "data")?;
        let records = self.tight_view(entry, "triangles")?;
        // Decoding never holds more than the data (blocks do not overlap).
        self.budget
            .take(|| entry.field("data"), data.len() as u64)?;
        let usage_bytes = usage_counts_to_le_bytes(&usage);
        let read = read_buffers(
            &BufferBytes {
                records: &records,
                data: &data,
                usage_counts: Some(&usage_bytes),
                indices: None,
            },
            &ReadOptions {
                overlap: Overlap::Forbid,
                max_level: MAX_GLTF_LEVEL,
                base_triangle: 0,
                ..ReadOptions::default()
            },
        )
        .map_err(|e| AssetError::gltf(&entry.path, e.to_string()))?;
        Ok(GltfMicromap {
            name,
            records: read.records,
            micromaps: read.micromaps,
            usage,
        })
    }

    /// The bytes of the buffer view `entry[key]`, which must have no
    /// `byteStride`.
    fn tight_view(&mut self, entry: &Obj<'_>, key: &str) -> Result<Vec<u8>, AssetError> {
        let index = entry.usize(key)?;
        let what = entry.field(key);
        let (bytes, stride) = self.view_bytes(index, &what)?;
        if let Some(stride) = stride {
            return Err(AssetError::gltf(
                format!("bufferViews[{index}].byteStride"),
                format!("{stride}: the buffer view of {what} must not have a byteStride"),
            ));
        }
        Ok(bytes.to_vec())
    }

    fn micromap_primitive(
        &mut self,
        primitive: &Obj<'_>,
        ext: &Obj<'_>,
        m: usize,
        p: usize,
        micromaps: &[GltfMicromap],
    ) -> Result<GltfMicromapPrimitive, AssetError> {
        let mode = primitive.opt_u64("mode")?.unwrap_or(4);
        if mode != 4 {
            return Err(primitive.error(
                "mode",
                format!("{mode}: {EXTENSION} applies to TRIANGLES (4) only"),
            ));
        }
        let micromap = ext.usize("micromap")?;
        let records = micromaps
            .get(micromap)
            .ok_or_else(|| {
                ext.error(
                    "micromap",
                    format!("{micromap}, but the root has {} micromaps", micromaps.len()),
                )
            })?
            .records
            .len();
        let base_triangle = ext.opt_u32("micromapBaseTriangle")?.unwrap_or(0);
        let triangles = self.primitive_triangles(primitive)?;
        let record = |t: usize, raw: u64, path: &str| -> Result<MicromapIndex, AssetError> {
            let index = raw + u64::from(base_triangle);
            match u32::try_from(index) {
                Ok(r) if (r as usize) < records => Ok(MicromapIndex::Record(r)),
                _ => Err(AssetError::gltf(
                    path,
                    format!(
                        "triangle {t}: index {raw} + micromapBaseTriangle {base_triangle} = {index}, but micromaps[{micromap}] has {records} records"
                    ),
                )),
            }
        };
        let (has_index_accessor, indices) = match ext.opt_usize("micromapIndices")? {
            None => (
                false,
                (0..triangles)
                    .map(|t| record(t, t as u64, &ext.path))
                    .collect::<Result<Vec<_>, _>>()?,
            ),
            Some(accessor) => {
                let raw = self.index_values(accessor, &ext.field("micromapIndices"), triangles)?;
                let mut indices = Vec::with_capacity(raw.len());
                for (t, value) in raw.into_iter().enumerate() {
                    let path = format!("accessors[{accessor}]");
                    indices.push(match value {
                        -4..=-1 => MicromapIndex::Special(special(value)),
                        // Unsigned values are below 2^n - 4 once the
                        // four special patterns are taken out.
                        v if v >= 0 => record(t, v as u64, &path)?,
                        v => {
                            return Err(AssetError::gltf(
                                path,
                                format!("triangle {t}: value {v} is neither a special index (-1..-4) nor a record index"),
                            ))
                        }
                    });
                }
                (true, indices)
            }
        };
        Ok(GltfMicromapPrimitive {
            mesh: m,
            primitive: p,
            micromap,
            base_triangle,
            has_index_accessor,
            indices,
        })
    }

    /// A primitive's triangle count: index count (or `POSITION` count) / 3.
    fn primitive_triangles(&self, primitive: &Obj<'_>) -> Result<usize, AssetError> {
        let (accessor, what) = if let Some(a) = primitive.opt_usize("indices")? {
            (a, primitive.field("indices"))
        } else {
            let attributes = primitive.obj("attributes")?;
            (attributes.usize("POSITION")?, attributes.field("POSITION"))
        };
        Ok(self
            .root
            .element("accessors", accessor, &what)?
            .usize("count")?
            / 3)
    }

    /// The values of a `micromapIndices` accessor, as signed numbers: each
    /// unsigned pattern of -1..-4 becomes its negative value.
    fn index_values(
        &mut self,
        index: usize,
        what: &str,
        triangles: usize,
    ) -> Result<Vec<i64>, AssetError> {
        let accessor = self.root.element("accessors", index, what)?;
        let component_type = accessor
            .opt_u64("componentType")?
            .ok_or_else(|| accessor.error("componentType", "missing"))?;
        let (size, signed) = match component_type {
            5121 => (1, false),
            5123 => (2, false),
            5125 => (4, false),
            5122 => (2, true),
            5124 => (4, true),
            other => {
                return Err(accessor.error(
                    "componentType",
                    format!("{other}, expected 5121, 5123, 5125 (unsigned) or 5122, 5124 (signed)"),
                ))
            }
        };
        let ty = accessor.str("type")?;
        if ty != "SCALAR" {
            return Err(accessor.error("type", format!("{ty:?}, expected \"SCALAR\"")));
        }
        if accessor.opt_bool("normalized")? == Some(true) {
            return Err(accessor.error("normalized", "true, expected false or absent"));
        }
        let count = accessor.usize("count")?;
        if count != triangles {
            return Err(accessor.error(
                "count",
                format!("{count}, but the primitive has {triangles} triangles"),
            ));
        }
        let offset = accessor.opt_usize("byteOffset")?.unwrap_or(0);
        if offset % size != 0 {
            return Err(accessor.error(
                "byteOffset",
                format!("{offset}, not a multiple of the component size {size}"),
            ));
        }
        if let Some(view_index) = accessor.opt_usize("bufferView")? {
            let view =
                self.root
                    .element("bufferViews", view_index, &accessor.field("bufferView"))?;
            if let Some(stride) = view.opt_usize("byteStride")? {
                return Err(view.error(
                    "byteStride",
                    format!("{stride}: the buffer view of micromapIndices must not have one"),
                ));
            }
            let view_offset = view.opt_usize("byteOffset")?.unwrap_or(0);
            if view_offset % size != 0 {
                return Err(view.error(
                    "byteOffset",
                    format!("{view_offset}, not a multiple of the component size {size}"),
                ));
            }
        }
        let layout = Layout {
            path: accessor.path.clone(),
            count,
            component_type,
            normalized: false,
            element_size: size,
        };
        let decode = move |bytes: &[u8]| -> i64 {
            let mut raw = [0u8; 4];
            raw[..bytes.len().min(4)].copy_from_slice(&bytes[..bytes.len().min(4)]);
            let unsigned = u32::from_le_bytes(raw);
            match (signed, size) {
                (true, 2) => i64::from(unsigned as u16 as i16),
                (true, _) => i64::from(unsigned as i32),
                (false, _) => {
                    let all_ones = match size {
                        1 => 0xff,
                        2 => 0xffff,
                        _ => 0xffff_ffff,
                    };
                    let from_top = all_ones - unsigned;
                    if from_top <= 3 {
                        -(i64::from(from_top) + 1)
                    } else {
                        i64::from(unsigned)
                    }
                }
            }
        };
        self.elements(&accessor, &layout, decode)
    }
}

/// The state of special index `value` (-1..-4).
fn special(value: i64) -> State {
    match value {
        -1 => State::Transparent,
        -2 => State::Opaque,
        -3 => State::UnknownTransparent,
        _ => State::UnknownOpaque,
    }
}
