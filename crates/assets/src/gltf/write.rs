//! [`write_gltf_micromaps`]: a glTF written back with
//! `EXT_mesh_opacity_micromap` on the baked primitives, everything else
//! kept (members the writer does not touch are copied as their raw text).

use super::embed::{embed_into_bin, exactly, load_uri};
use super::extension::{EXTENSION, MAX_GLTF_LEVEL};
use super::glb::{split_glb, GLB_BIN, GLB_JSON};
use super::raw::{field, parse_raw, to_raw, RawObject};
use crate::{AssetError, Limits};
use micromap_index::micromap::{
    Api, IndexWidth, MicromapBuffers, MicromapIndex, TriangleRecord, UsageCount,
};
use serde_json::value::RawValue;
use serde_json::{json, Value};
use std::fmt::Write as _;

/// The container [`write_gltf_micromaps`] writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GltfContainer {
    /// A `.glb` that stands alone: the micromap bytes are appended to
    /// buffer 0, the `BIN` chunk (an input buffer 0 with a URI is loaded
    /// into the chunk; an input without buffers gets one), and so are the
    /// input's other buffers and every image it names by a URI (images get
    /// a buffer view and a `mimeType`).
    Glb,
    /// A `.gltf` that stands alone with the files next to it: the micromap
    /// bytes are a new last buffer, the file `<stem>.micromap.bin`; the
    /// input's buffers and every image it names by a URI are gathered, as
    /// a `.glb`'s chunk gathers them, into buffer 0, the file `<stem>.bin`
    /// (images get a buffer view and a `mimeType`), so the output's folder
    /// can be moved.
    Json {
        /// The output's file name without `.gltf` (no directory part).
        stem: String,
    },
}

/// What [`write_gltf_micromaps`] adds to an asset.
#[derive(Clone, Copy, Debug)]
pub struct GltfMicromapWrite<'a> {
    /// The baked buffers: one geometry per entry of `primitives`.
    pub buffers: &'a MicromapBuffers,
    /// The `(mesh, primitive)` each geometry of `buffers` belongs to.
    pub primitives: &'a [(usize, usize)],
}

/// The files [`write_gltf_micromaps`] makes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfFiles {
    /// The `.gltf` or `.glb` itself.
    pub main: Vec<u8>,
    /// Files next to it, by name (only for [`GltfContainer::Json`]).
    pub sidecars: Vec<(String, Vec<u8>)>,
}

/// Writes the glTF `input` (JSON or GLB bytes) back as `container` with one
/// new `EXT_mesh_opacity_micromap` micromap holding every record of
/// `write.buffers`, and on each primitive of `write.primitives` the
/// extension pointing at it, following the newest draft (KhronosGroup/glTF
/// pull request 2623 at 4b95e4d3, `../shared/gltf-micromap-extension.md`):
///
/// * `EXT_mesh_opacity_micromap` in `extensionsUsed`, removed from
///   `extensionsRequired` (the draft: SHOULD NOT be required);
/// * the micromap's `data` and `triangles` buffer views without
///   `byteStride`; `usageCounts`/`usageLevels`/`usageFormats` one entry per
///   (level, format) of the records, counting them; every level at most
///   [`MAX_GLTF_LEVEL`] (a higher one is refused);
/// * per primitive: `micromapIndices`, an unsigned `SCALAR` accessor of
///   the narrowest width ([`IndexWidth::narrowest`] for glTF) over its own
///   buffer view, special indices as two's-complement patterns; or, when
///   the primitive's triangles use consecutive records `b, b + 1, ...`, no
///   accessor and `micromapBaseTriangle: b` (omitted when 0);
/// * a bake without any record (every triangle a special index) still
///   gets one level-0 record, which the draft's `minItems` require;
/// * an existing root `micromaps` array is kept and the new micromap
///   appended to it; the input's own extension must then read
///   ([`read_gltf_micromaps`](crate::read_gltf_micromaps)), or it is
///   refused.
///
/// Every primitive must exist, be `TRIANGLES`, and have as many triangles
/// (index count, or `POSITION` count, divided by 3) as its geometry.
/// `resolve` loads a percent-decoded relative URI (only for a GLB output
/// from an input whose buffer 0 is a file). Never panics; every refusal is
/// an [`AssetError`].
///
/// ```
/// use micromap_index::micromap::{MicromapBuffers, State, TriangleOpacity};
/// use micromap_index_assets::{write_gltf_micromaps, GltfContainer, GltfMicromapWrite};
/// let gltf = br#"{"asset":{"version":"2.0"},"accessors":[{"count":3,"componentType":5126,"type":"VEC3"}],
///   "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#;
/// let buffers = MicromapBuffers::build([TriangleOpacity::Special(State::Opaque)], Default::default()).unwrap();
/// let write = GltfMicromapWrite { buffers: &buffers, primitives: &[(0, 0)] };
/// let mut no_files = |_: &str| unreachable!();
/// let files = write_gltf_micromaps(gltf, &mut no_files, &write, &GltfContainer::Glb).unwrap();
/// assert!(files.main.starts_with(b"glTF") && files.sidecars.is_empty());
/// ```
pub fn write_gltf_micromaps(
    input: &[u8],
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
    write: &GltfMicromapWrite<'_>,
    container: &GltfContainer,
) -> Result<GltfFiles, AssetError> {
    let mut warnings = Vec::new();
    let (json, bin) = if input.starts_with(b"glTF") {
        split_glb(input, &mut warnings)?
    } else {
        (input, None)
    };
    let json = json.strip_prefix(b"\xef\xbb\xbf").unwrap_or(json);
    // The input's own micromaps are kept: they must be valid, or the
    // output would not be.
    if json
        .windows(EXTENSION.len())
        .any(|w| w == EXTENSION.as_bytes())
    {
        super::read_gltf_micromaps(input, resolve, &Limits::default())
            .map_err(|e| e.within(format!("the input's own {EXTENSION}")))?;
    }
    let mut root: RawObject = serde_json::from_slice(json).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })?;
    let buffers = write.buffers;
    if buffers.geometry_count() != write.primitives.len() {
        return Err(AssetError::gltf(
            EXTENSION,
            format!(
                "{} geometries for {} primitives",
                buffers.geometry_count(),
                write.primitives.len()
            ),
        ));
    }

    // The records and usage to write: a bake of special indices only gets
    // one unused level-0 record, since the micromap needs one.
    let (records, data, usage) = if buffers.records().is_empty() {
        let format = 2;
        (
            vec![TriangleRecord {
                data_offset: 0,
                subdivision_level: 0,
                format,
            }],
            vec![0u8],
            vec![UsageCount {
                count: 1,
                subdivision_level: 0,
                format: u32::from(format),
            }],
        )
    } else {
        (
            buffers.records().to_vec(),
            buffers.data().to_vec(),
            buffers.usage_counts().to_vec(),
        )
    };
    if let Some(r) = records
        .iter()
        .find(|r| u32::from(r.subdivision_level) > MAX_GLTF_LEVEL)
    {
        return Err(AssetError::gltf(
            EXTENSION,
            format!(
                "a micromap of level {}: the extension allows levels 0..={MAX_GLTF_LEVEL} only, refused",
                r.subdivision_level
            ),
        ));
    }

    let mut accessors: Vec<Box<RawValue>> = root.parse("accessors", "")?.unwrap_or_default();
    let mut views: Vec<Box<RawValue>> = root.parse("bufferViews", "")?.unwrap_or_default();
    let mut gltf_buffers: Vec<RawObject> = root.parse("buffers", "")?.unwrap_or_default();
    let mut sidecars = Vec::new();

    let mut images = root.parse::<Vec<RawObject>>("images", "")?;

    // Buffer 0's bytes (from its URI or the GLB's BIN chunk), its URI
    // dropped: every output gathers the input's buffers and images there,
    // so the output stands alone.
    let byte_length = |buffer: &RawObject, b: usize| -> Result<usize, AssetError> {
        buffer
            .parse::<usize>("byteLength", &format!("buffers[{b}]"))?
            .ok_or_else(|| AssetError::gltf(format!("buffers[{b}].byteLength"), "missing"))
    };
    let mut first_buffer = |buffers: &mut Vec<RawObject>| -> Result<Vec<u8>, AssetError> {
        if buffers.is_empty() {
            buffers.push(RawObject::default());
            return Ok(Vec::new());
        }
        let length = byte_length(&buffers[0], 0)?;
        let bytes = match buffers[0].parse::<String>("uri", "buffers[0]")? {
            None => bin
                .ok_or_else(|| {
                    AssetError::gltf("buffers[0].uri", "missing, and there is no GLB BIN chunk")
                })?
                .to_vec(),
            Some(uri) => load_uri(&uri, resolve)?,
        };
        buffers[0].remove("uri");
        exactly(bytes, length, "buffers[0]")
    };
    let names_anything = !gltf_buffers.is_empty()
        || images
            .as_deref()
            .unwrap_or_default()
            .iter()
            .any(|image| image.get("uri").is_some());

    // The host buffer the micromap bytes are appended to.
    let (host_index, mut host) = match container {
        GltfContainer::Glb => {
            let mut host = first_buffer(&mut gltf_buffers)?;
            embed_into_bin(
                &mut host,
                &mut gltf_buffers,
                &mut views,
                images.as_deref_mut().unwrap_or_default(),
                resolve,
            )?;
            (0, host)
        }
        GltfContainer::Json { stem } => {
            // As a GLB's chunk, but in the file `<stem>.bin` beside the
            // output: a folder that can be moved, with no URI out of it.
            if names_anything {
                let mut resources = first_buffer(&mut gltf_buffers)?;
                embed_into_bin(
                    &mut resources,
                    &mut gltf_buffers,
                    &mut views,
                    images.as_deref_mut().unwrap_or_default(),
                    resolve,
                )?;
                let name = format!("{stem}.bin");
                gltf_buffers[0].set("byteLength", to_raw(&resources.len())?);
                gltf_buffers[0].set("uri", to_raw(&percent_encode(&name))?);
                sidecars.push((name, resources));
            }
            gltf_buffers.push(RawObject::default());
            (gltf_buffers.len() - 1, Vec::new())
        }
    };

    let mut add_view =
        |host: &mut Vec<u8>, bytes: &[u8], name: &str| -> Result<usize, AssetError> {
            // 4-byte alignment: enough for every accessor component and record.
            host.resize(host.len().next_multiple_of(4), 0);
            let offset = host.len();
            host.extend_from_slice(bytes);
            views.push(to_raw(&json!({
                "buffer": host_index,
                "byteOffset": offset,
                "byteLength": bytes.len(),
                "name": name,
            }))?);
            Ok(views.len() - 1)
        };
    let data_view = add_view(&mut host, &data, "EXT_mesh_opacity_micromap data")?;
    let records_view = add_view(
        &mut host,
        &micromap_index::micromap::records_to_le_bytes(&records),
        "EXT_mesh_opacity_micromap triangles",
    )?;

    // The root extension: the new micromap appended to any already there.
    let mut extensions: RawObject = root.parse("extensions", "")?.unwrap_or_default();
    let mut ours: RawObject = extensions
        .parse(EXTENSION, "extensions")?
        .unwrap_or_default();
    let mut micromaps: Vec<Box<RawValue>> = ours
        .parse("micromaps", &format!("extensions.{EXTENSION}"))?
        .unwrap_or_default();
    let micromap = micromaps.len();
    micromaps.push(to_raw(&json!({
        "data": data_view,
        "triangles": records_view,
        "usageCounts": usage.iter().map(|u| u.count).collect::<Vec<_>>(),
        "usageLevels": usage.iter().map(|u| u.subdivision_level).collect::<Vec<_>>(),
        "usageFormats": usage.iter().map(|u| u.format).collect::<Vec<_>>(),
    }))?);
    ours.set("micromaps", to_raw(&micromaps)?);
    extensions.set(EXTENSION, to_raw(&ours)?);

    // Each primitive: checked against its geometry, then given the extension.
    let mut meshes: Vec<Box<RawValue>> = root.parse("meshes", "")?.unwrap_or_default();
    for (g, &(m, p)) in write.primitives.iter().enumerate() {
        let mesh_path = format!("meshes[{m}]");
        let raw_mesh = meshes
            .get(m)
            .ok_or_else(|| AssetError::gltf(&mesh_path, "does not exist"))?;
        let mut mesh: RawObject = parse_raw(raw_mesh, &mesh_path)?;
        let mut primitives: Vec<Box<RawValue>> =
            mesh.parse("primitives", &mesh_path)?.unwrap_or_default();
        let path = format!("{mesh_path}.primitives[{p}]");
        let raw_primitive = primitives
            .get(p)
            .ok_or_else(|| AssetError::gltf(&path, "does not exist"))?;
        let mut primitive: RawObject = parse_raw(raw_primitive, &path)?;
        if let Some(mode) = primitive.parse::<u64>("mode", &path)? {
            if mode != 4 {
                return Err(AssetError::gltf(
                    field(&path, "mode"),
                    format!("{mode}: the extension applies to TRIANGLES (4) only"),
                ));
            }
        }
        let indices = buffers
            .geometry_indices(g)
            .map_err(|e| AssetError::gltf(&path, e.to_string()))?;
        let triangles = triangle_count(&primitive, &path, &accessors)?;
        if triangles != indices.len() {
            return Err(AssetError::gltf(
                &path,
                format!(
                    "{triangles} triangles, but its geometry has {} micromap indices",
                    indices.len()
                ),
            ));
        }
        let mut extension = json!({ "micromap": micromap });
        match consecutive_base(indices) {
            Some(base) if base as usize + indices.len() <= records.len() => {
                if base > 0 {
                    extension["micromapBaseTriangle"] = Value::from(base);
                }
            }
            _ => {
                let max = indices
                    .iter()
                    .filter_map(|i| match i {
                        MicromapIndex::Record(r) => Some(*r),
                        MicromapIndex::Special(_) => None,
                    })
                    .max();
                let width = IndexWidth::narrowest(max, Api::Gltf);
                let bytes = buffers
                    .index_bytes(g, width)
                    .map_err(|e| AssetError::gltf(&path, e.to_string()))?;
                let view = add_view(
                    &mut host,
                    &bytes,
                    &format!("EXT_mesh_opacity_micromap indices of {path}"),
                )?;
                accessors.push(to_raw(&json!({
                    "bufferView": view,
                    "componentType": match width {
                        IndexWidth::U8 => 5121,
                        IndexWidth::U16 => 5123,
                        IndexWidth::U32 => 5125,
                    },
                    "count": indices.len(),
                    "type": "SCALAR",
                }))?);
                extension["micromapIndices"] = Value::from(accessors.len() - 1);
            }
        }
        let mut primitive_extensions: RawObject =
            primitive.parse("extensions", &path)?.unwrap_or_default();
        primitive_extensions.set(EXTENSION, to_raw(&extension)?);
        primitive.set("extensions", to_raw(&primitive_extensions)?);
        primitives[p] = to_raw(&primitive)?;
        mesh.set("primitives", to_raw(&primitives)?);
        meshes[m] = to_raw(&mesh)?;
    }

    let host_length = host.len();
    gltf_buffers[host_index].set("byteLength", to_raw(&host_length)?);
    if let GltfContainer::Json { stem } = container {
        let name = format!("{stem}.micromap.bin");
        gltf_buffers[host_index].set("uri", to_raw(&percent_encode(&name))?);
        sidecars.push((name, std::mem::take(&mut host)));
    }
    if let Some(images) = &images {
        root.set("images", to_raw(images)?);
    }
    root.set("meshes", to_raw(&meshes)?);
    root.set("accessors", to_raw(&accessors)?);
    root.set("bufferViews", to_raw(&views)?);
    root.set("buffers", to_raw(&gltf_buffers)?);
    root.set("extensions", to_raw(&extensions)?);

    let mut used: Vec<Value> = root.parse("extensionsUsed", "")?.unwrap_or_default();
    if !used.iter().any(|v| v.as_str() == Some(EXTENSION)) {
        used.push(Value::from(EXTENSION));
    }
    root.set("extensionsUsed", to_raw(&used)?);
    if let Some(mut required) = root.parse::<Vec<Value>>("extensionsRequired", "")? {
        required.retain(|v| v.as_str() != Some(EXTENSION));
        if required.is_empty() {
            root.remove("extensionsRequired");
        } else {
            root.set("extensionsRequired", to_raw(&required)?);
        }
    }

    let json = serde_json::to_vec(&root).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })?;
    let main = match container {
        GltfContainer::Json { .. } => json,
        GltfContainer::Glb => glb(json, host)?,
    };
    Ok(GltfFiles { main, sidecars })
}

/// A primitive's triangle count: its index count, or its `POSITION` count,
/// over 3 (the reader drops a remainder).
fn triangle_count(
    primitive: &RawObject,
    path: &str,
    accessors: &[Box<RawValue>],
) -> Result<usize, AssetError> {
    let accessor = if let Some(a) = primitive.parse::<usize>("indices", path)? {
        a
    } else {
        let attributes: RawObject = primitive
            .parse("attributes", path)?
            .ok_or_else(|| AssetError::gltf(field(path, "attributes"), "missing"))?;
        attributes
            .parse::<usize>("POSITION", &field(path, "attributes"))?
            .ok_or_else(|| {
                AssetError::gltf(
                    field(path, "attributes.POSITION"),
                    "missing (and no indices)",
                )
            })?
    };
    let accessor_path = format!("accessors[{accessor}]");
    let raw = accessors
        .get(accessor)
        .ok_or_else(|| AssetError::gltf(&accessor_path, "does not exist"))?;
    let object: RawObject = parse_raw(raw, &accessor_path)?;
    let count: usize = object
        .parse("count", &accessor_path)?
        .ok_or_else(|| AssetError::gltf(field(&accessor_path, "count"), "missing"))?;
    Ok(count / 3)
}

/// `Some(b)` when the indices are the records `b, b + 1, ...` in order
/// (then the extension needs no index accessor).
fn consecutive_base(indices: &[MicromapIndex]) -> Option<u32> {
    let base = match indices.first() {
        None => return Some(0),
        Some(MicromapIndex::Record(b)) => *b,
        Some(MicromapIndex::Special(_)) => return None,
    };
    indices
        .iter()
        .enumerate()
        .all(|(t, i)| u64::try_from(t).ok().map(|t| t + u64::from(base)) == index_value(*i))
        .then_some(base)
}

fn index_value(index: MicromapIndex) -> Option<u64> {
    match index {
        MicromapIndex::Record(r) => Some(u64::from(r)),
        MicromapIndex::Special(_) => None,
    }
}

/// A file name as a URI path segment: bytes outside RFC 3986's unreserved
/// set percent-encoded.
fn percent_encode(name: &str) -> String {
    let mut out = String::new();
    for byte in name.bytes() {
        if byte.is_ascii_alphanumeric() || matches!(byte, b'-' | b'.' | b'_' | b'~') {
            out.push(byte as char);
        } else {
            let _ = write!(out, "%{byte:02X}");
        }
    }
    out
}

/// A GLB of `json` (padded with spaces) and the `BIN` chunk `bin` (padded
/// with zeros), each chunk a multiple of 4 bytes.
fn glb(mut json: Vec<u8>, mut bin: Vec<u8>) -> Result<Vec<u8>, AssetError> {
    json.resize(json.len().next_multiple_of(4), b' ');
    bin.resize(bin.len().next_multiple_of(4), 0);
    let total = 12 + 8 + json.len() as u64 + 8 + bin.len() as u64;
    let too_large = || AssetError::Glb {
        message: format!("{total} bytes, over the 4 GiB a GLB can hold"),
    };
    let total32 = u32::try_from(total).map_err(|_| too_large())?;
    let chunk32 = |n: usize| u32::try_from(n).map_err(|_| too_large());
    let mut out = Vec::with_capacity(total32 as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&chunk32(json.len())?.to_le_bytes());
    out.extend_from_slice(&GLB_JSON.to_le_bytes());
    out.extend_from_slice(&json);
    out.extend_from_slice(&chunk32(bin.len())?.to_le_bytes());
    out.extend_from_slice(&GLB_BIN.to_le_bytes());
    out.extend_from_slice(&bin);
    Ok(out)
}
