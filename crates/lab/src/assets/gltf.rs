//! [`read_gltf_file`] and [`read_gltf_bytes`]: the alpha-tested triangles of
//! a glTF 2.0 asset, with their UVs, cutoffs, samplers and images.

use super::{check_limit, decode_alpha_image, json_number_f32, AlphaImage, AssetError, Limits};
use serde::Deserialize;
use serde_json::value::RawValue;
use serde_json::{Map, Value};
use std::borrow::Cow;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::fmt::Write as _;
use std::io::Read;
use std::path::Path;
use std::rc::Rc;

/// glTF's `REPEAT` wrap mode (the default of `wrapS` and `wrapT`).
pub const REPEAT: u32 = 10497;
/// glTF's `CLAMP_TO_EDGE` wrap mode.
pub const CLAMP_TO_EDGE: u32 = 33071;
/// glTF's `MIRRORED_REPEAT` wrap mode.
pub const MIRRORED_REPEAT: u32 = 33648;
/// glTF's `NEAREST` filter.
pub const NEAREST: u32 = 9728;
/// glTF's `LINEAR` filter.
pub const LINEAR: u32 = 9729;

/// A glTF sampler with its raw codes (`samplers[i]`, or the defaults when a
/// texture has none).
///
/// Wrap modes: [`REPEAT`] (10497), [`CLAMP_TO_EDGE`] (33071),
/// [`MIRRORED_REPEAT`] (33648). Filters: [`NEAREST`] (9728), [`LINEAR`]
/// (9729), and for `min_filter` also the mipmap modes 9984..=9987. The
/// reader checks that each code is one of these.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct GltfSampler {
    /// `wrapS`, the wrap mode along `u`; default [`REPEAT`].
    pub wrap_s: u32,
    /// `wrapT`, the wrap mode along `v`; default [`REPEAT`].
    pub wrap_t: u32,
    /// `magFilter`, if given.
    pub mag_filter: Option<u32>,
    /// `minFilter`, if given.
    pub min_filter: Option<u32>,
}

impl Default for GltfSampler {
    /// glTF's defaults: wrap [`REPEAT`] both ways, filters unspecified.
    fn default() -> Self {
        GltfSampler {
            wrap_s: REPEAT,
            wrap_t: REPEAT,
            mag_filter: None,
            min_filter: None,
        }
    }
}

/// One triangle primitive of a glTF mesh whose material is alpha-tested
/// (`alphaMode: "MASK"`) with a base colour texture.
#[derive(Clone, Debug, PartialEq)]
pub struct MaskPrimitive {
    /// The mesh: index into the glTF's `meshes`.
    pub mesh: usize,
    /// The primitive: index into the mesh's `primitives`.
    pub primitive: usize,
    /// The material: index into the glTF's `materials`.
    pub material: usize,
    /// `material.alphaCutoff` (default 0.5), rounded once from its decimal
    /// text to binary32. A texel is opaque where
    /// `alpha * alpha_factor >= alpha_cutoff`.
    pub alpha_cutoff: f32,
    /// `pbrMetallicRoughness.baseColorFactor[3]` (default 1), rounded once
    /// from its decimal text; it multiplies the texture's alpha.
    pub alpha_factor: f32,
    /// The texture: index into the glTF's `textures`.
    pub texture: usize,
    /// The decoded image: index into [`GltfAsset::images`] (not into the
    /// glTF's `images`; [`GltfAsset::image_info`] maps back).
    pub image: usize,
    /// The texture's sampler, or the defaults.
    pub sampler: GltfSampler,
    /// `baseColorTexture.texCoord`: the triangles are `TEXCOORD_<tex_coord>`.
    pub tex_coord: u32,
    /// The UVs of each triangle, in order, with the indices applied (or
    /// vertices `3i, 3i + 1, 3i + 2` without indices). Integer UVs
    /// (`KHR_mesh_quantization`) are converted as glTF says: normalized
    /// `c / 255`, `c / 65535`, `max(c / 127, -1)`, `max(c / 32767, -1)`,
    /// each one binary32 division; others as the integer's value.
    pub triangles: Vec<[[f32; 2]; 3]>,
}

/// Where a decoded image of [`GltfAsset::images`] came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GltfImageInfo {
    /// Its index into the glTF's `images`.
    pub index: usize,
    /// `images[index].uri` as written (percent-encoded), `data:` URIs cut
    /// to their header (`data:image/png;base64,...`), if it has one.
    pub uri: Option<String>,
    /// `images[index].bufferView`, if it has one.
    pub buffer_view: Option<usize>,
    /// `images[index].mimeType`, if given (the format is detected from the
    /// bytes, not from this).
    pub mime_type: Option<String>,
    /// `images[index].name`, if given.
    pub name: Option<String>,
}

/// What [`read_gltf_file`] and [`read_gltf_bytes`] read from a glTF.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct GltfAsset {
    /// Every alpha-tested triangle primitive, in the order of `meshes` and
    /// their `primitives`.
    pub primitives: Vec<MaskPrimitive>,
    /// The images the primitives use, each decoded once
    /// ([`decode_alpha_image`]), in order of first use.
    pub images: Vec<AlphaImage>,
    /// For each of [`GltfAsset::images`], where it came from.
    pub image_info: Vec<GltfImageInfo>,
    /// What was skipped or is not applied, one line each: primitives that
    /// are not triangles, materials that are not `MASK` (counted), `MASK`
    /// materials without a base colour texture, `COLOR_0` (its alpha is not
    /// multiplied in), `KHR_texture_transform` (not applied to the UVs),
    /// oddities of the GLB container.
    pub warnings: Vec<String>,
}

/// Reads a `.gltf` (JSON, with buffers and images in files next to it or in
/// `data:` URIs) or a `.glb` (told apart by the GLB magic `glTF`, not by
/// name), resolving relative URIs against the file's directory.
///
/// A URI is percent-decoded, then joined to the directory; absolute paths
/// and URIs with a scheme (other than `data:`) are refused. Every file read
/// (the glTF itself included) must be at most [`Limits::max_bytes`] long.
/// Errors name the file. See [`read_gltf_bytes`] for what is read.
///
/// ```no_run
/// use micromap_index_lab::assets::{read_gltf_file, Limits};
/// let asset = read_gltf_file("assets/crytek-sponza/cards.gltf".as_ref(), &Limits::default())?;
/// for primitive in &asset.primitives {
///     let image = &asset.images[primitive.image];
///     println!("mesh {} primitive {}: {} triangles on {} x {}, cutoff {}",
///         primitive.mesh, primitive.primitive, primitive.triangles.len(),
///         image.width, image.height, primitive.alpha_cutoff);
/// }
/// # Ok::<(), micromap_index_lab::assets::AssetError>(())
/// ```
pub fn read_gltf_file(path: &Path, limits: &Limits) -> Result<GltfAsset, AssetError> {
    let bytes = read_file(path, limits.max_bytes)?;
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    let mut resolve = |uri: &str| -> Result<Vec<u8>, AssetError> {
        if uri.starts_with(['/', '\\']) || Path::new(uri).is_absolute() {
            return Err(AssetError::Uri {
                uri: uri.to_string(),
                message: "absolute paths are not supported; use a path relative to the glTF"
                    .to_string(),
            });
        }
        read_file(&base.join(uri), limits.max_bytes)
    };
    read_gltf_bytes(&bytes, &mut resolve, limits).map_err(|e| e.within(path.display().to_string()))
}

/// The whole file, if it is at most `max_bytes` long.
fn read_file(path: &Path, max_bytes: u64) -> Result<Vec<u8>, AssetError> {
    let io = |e: std::io::Error| AssetError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    let file = std::fs::File::open(path).map_err(io)?;
    let length = file.metadata().map_err(io)?.len();
    check_limit(|| format!("file {}", path.display()), length, max_bytes)?;
    let mut bytes = Vec::with_capacity(usize::try_from(length).unwrap_or(0));
    // `take`: a file that grows while being read stays within the limit.
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    check_limit(
        || format!("file {}", path.display()),
        bytes.len() as u64,
        max_bytes,
    )?;
    Ok(bytes)
}

/// Reads a glTF 2.0 asset from bytes: GLB if they start with the magic
/// `glTF`, JSON otherwise. `resolve` is called with each external URI a
/// needed buffer or image names, percent-decoded (`leaf%20a.png` →
/// `leaf a.png`), and returns the bytes; `data:` URIs (base64 or
/// percent-encoded) are decoded here, and URIs with any other scheme are
/// refused without calling it. For fuzzing without a filesystem.
///
/// For every primitive of every mesh (in order; nodes and scenes are not
/// read, so every mesh counts once):
///
/// * mode 4 (`TRIANGLES`, the default) is read; other modes are skipped
///   with a warning;
/// * the material must be `alphaMode: "MASK"` with
///   `pbrMetallicRoughness.baseColorTexture`; primitives with `OPAQUE`
///   (also no material) or `BLEND` materials are skipped and counted in one
///   warning, `MASK` without a texture is skipped with a warning;
/// * `TEXCOORD_<texCoord>`: `VEC2` of `FLOAT`, or of (normalized or not)
///   `UNSIGNED_BYTE`, `UNSIGNED_SHORT`, `BYTE`, `SHORT`
///   (`KHR_mesh_quantization`), through `byteOffset`, the buffer view's
///   `byteStride`, and sparse substitution; an accessor without a buffer
///   view is zeros (plus its sparse values);
/// * `indices`: `SCALAR` `UNSIGNED_BYTE`, `UNSIGNED_SHORT` or
///   `UNSIGNED_INT` (sparse too), each below the UV count; without
///   indices, vertices are taken in order; a count that is not a multiple
///   of 3 drops the last one or two with a warning;
/// * the texture's `source` image (from a `uri` or a `bufferView`) is
///   decoded once by [`decode_alpha_image`]; its sampler is read.
///
/// Buffers are loaded only when a needed buffer view is in them; the GLB
/// `BIN` chunk is buffer 0 when that has no `uri`. A required extension
/// other than `KHR_mesh_quantization`, `KHR_texture_transform` (its
/// transform is not applied: warning), `KHR_materials_*` (except
/// `KHR_materials_pbrSpecularGlossiness`), `KHR_lights_punctual` and
/// `KHR_mesh_gpu_instancing` is an error. Accessor alignment is not checked.
///
/// Limits: each image is decoded within [`Limits::max_pixels`]; the loaded
/// buffers, decoded images and UV, index and triangle arrays together stay
/// within [`Limits::max_bytes`]. Every index, offset and length is checked
/// with overflow-free arithmetic. Never panics.
///
/// ```
/// use micromap_index_lab::assets::{read_gltf_bytes, AssetError, Limits};
/// let gltf = br#"{"asset": {"version": "2.0"}, "meshes": [{"primitives": [{"attributes": {}}]}]}"#;
/// let mut no_files = |uri: &str| Err(AssetError::Uri { uri: uri.into(), message: "no files".into() });
/// let asset = read_gltf_bytes(gltf, &mut no_files, &Limits::default()).unwrap();
/// assert!(asset.primitives.is_empty());
/// assert_eq!(asset.warnings, ["skipped 1 primitive whose material is not alphaMode MASK (1 OPAQUE, 0 BLEND)"]);
/// ```
pub fn read_gltf_bytes(
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
    limits: &Limits,
) -> Result<GltfAsset, AssetError> {
    let mut warnings = Vec::new();
    let (json, bin) = if bytes.starts_with(b"glTF") {
        split_glb(bytes, &mut warnings)?
    } else {
        (bytes, None)
    };
    let json = json.strip_prefix(b"\xef\xbb\xbf").unwrap_or(json);
    let root: Value = serde_json::from_slice(json).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })?;
    let Value::Object(root) = &root else {
        return Err(AssetError::gltf("(top level)", "is not a JSON object"));
    };
    let raw_materials = raw_materials(json)?;
    let mut reader = Reader {
        root: Obj {
            map: root,
            path: String::new(),
        },
        raw_materials,
        bin,
        resolve,
        limits: *limits,
        budget: Budget {
            left: limits.max_bytes,
            limit: limits.max_bytes,
        },
        buffers: HashMap::new(),
        uvs: HashMap::new(),
        images: HashMap::new(),
        asset: GltfAsset {
            warnings,
            ..GltfAsset::default()
        },
    };
    reader.check_header()?;
    reader.read_meshes()?;
    Ok(reader.asset)
}

const GLB_JSON: u32 = 0x4E4F_534A;
const GLB_BIN: u32 = 0x004E_4942;

fn le_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let word = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([word[0], word[1], word[2], word[3]]))
}

/// The JSON chunk and the first `BIN` chunk of a GLB.
fn split_glb<'a>(
    bytes: &'a [u8],
    warnings: &mut Vec<String>,
) -> Result<(&'a [u8], Option<&'a [u8]>), AssetError> {
    let glb = |message: String| AssetError::Glb { message };
    let (Some(version), Some(length)) = (le_u32(bytes, 4), le_u32(bytes, 8)) else {
        return Err(glb(format!(
            "{} bytes, shorter than the 12-byte header",
            bytes.len()
        )));
    };
    if version != 2 {
        return Err(glb(format!("version {version}, expected 2")));
    }
    let length = length as usize;
    if length > bytes.len() {
        return Err(glb(format!(
            "header says {length} bytes, the data has {} (truncated?)",
            bytes.len()
        )));
    }
    if length < bytes.len() {
        warnings.push(format!(
            "GLB: {} bytes after the length of {length} in the header ignored",
            bytes.len() - length
        ));
    }
    let bytes = &bytes[..length.max(12)];
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    let mut chunk = 0usize;
    while at < bytes.len() {
        let (Some(chunk_length), Some(chunk_type)) = (le_u32(bytes, at), le_u32(bytes, at + 4))
        else {
            return Err(glb(format!(
                "{} bytes at offset {at}, too few for a chunk header",
                bytes.len() - at
            )));
        };
        let start = at + 8;
        let end = start
            .checked_add(chunk_length as usize)
            .filter(|&end| end <= bytes.len())
            .ok_or_else(|| {
                glb(format!(
                    "chunk {chunk} at offset {at}: length {chunk_length} runs past the end ({} bytes)",
                    bytes.len()
                ))
            })?;
        if chunk_length % 4 != 0 {
            warnings.push(format!(
                "GLB: chunk {chunk} length {chunk_length} is not a multiple of 4"
            ));
        }
        let data = &bytes[start..end];
        match (chunk, chunk_type) {
            (0, GLB_JSON) => json = Some(data),
            (0, other) => {
                return Err(glb(format!(
                    "the first chunk has type 0x{other:08x}, expected JSON (0x{GLB_JSON:08x})"
                )))
            }
            (_, GLB_JSON) => return Err(glb(format!("chunk {chunk} is a second JSON chunk"))),
            (_, GLB_BIN) if bin.is_none() => bin = Some(data),
            (_, GLB_BIN) => {
                warnings.push(format!("GLB: chunk {chunk}, a second BIN chunk, ignored"));
            }
            // Unknown chunk types are ignored, as the specification says.
            _ => {}
        }
        at = end;
        chunk += 1;
    }
    let json = json.ok_or_else(|| glb("no JSON chunk".to_string()))?;
    // Some writers pad the JSON chunk with NUL instead of spaces.
    let trimmed = json.len() - json.iter().rev().take_while(|&&b| b == 0).count();
    Ok((&json[..trimmed], bin))
}

/// Material fields read from their decimal text (one rounding to binary32).
#[derive(Deserialize)]
struct RawRoot<'a> {
    #[serde(borrow, default)]
    materials: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawMaterial<'a> {
    #[serde(borrow, default, rename = "alphaCutoff")]
    alpha_cutoff: Option<&'a RawValue>,
    #[serde(borrow, default, rename = "pbrMetallicRoughness")]
    pbr: Option<&'a RawValue>,
}

#[derive(Deserialize)]
struct RawPbr<'a> {
    #[serde(borrow, default, rename = "baseColorFactor")]
    base_color_factor: Option<&'a RawValue>,
}

/// The raw text of each material (empty if `materials` is not an array,
/// which the structured reading reports).
fn raw_materials(json: &[u8]) -> Result<Vec<&RawValue>, AssetError> {
    let root: RawRoot<'_> = serde_json::from_slice(json).map_err(|e| AssetError::Json {
        message: e.to_string(),
    })?;
    Ok(root
        .materials
        .and_then(|raw| serde_json::from_str::<Vec<&RawValue>>(raw.get()).ok())
        .unwrap_or_default())
}

/// A JSON object and its path (`meshes[0].primitives[1]`).
#[derive(Clone)]
struct Obj<'a> {
    map: &'a Map<String, Value>,
    path: String,
}

impl<'a> Obj<'a> {
    fn field(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    fn error(&self, key: &str, message: impl Into<String>) -> AssetError {
        AssetError::gltf(self.field(key), message)
    }

    fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    fn opt_u64(&self, key: &str) -> Result<Option<u64>, AssetError> {
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

    fn opt_usize(&self, key: &str) -> Result<Option<usize>, AssetError> {
        match self.opt_u64(key)? {
            None => Ok(None),
            Some(n) => usize::try_from(n)
                .map(Some)
                .map_err(|_| self.error(key, format!("{n} is too large"))),
        }
    }

    fn usize(&self, key: &str) -> Result<usize, AssetError> {
        self.opt_usize(key)?
            .ok_or_else(|| self.error(key, "missing"))
    }

    fn opt_u32(&self, key: &str) -> Result<Option<u32>, AssetError> {
        match self.opt_u64(key)? {
            None => Ok(None),
            Some(n) => u32::try_from(n)
                .map(Some)
                .map_err(|_| self.error(key, format!("{n} is too large"))),
        }
    }

    fn opt_bool(&self, key: &str) -> Result<Option<bool>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(value) => value
                .as_bool()
                .map(Some)
                .ok_or_else(|| self.error(key, format!("{}, expected a boolean", short(value)))),
        }
    }

    fn opt_str(&self, key: &str) -> Result<Option<&'a str>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(value) => value
                .as_str()
                .map(Some)
                .ok_or_else(|| self.error(key, format!("{}, expected a string", short(value)))),
        }
    }

    fn str(&self, key: &str) -> Result<&'a str, AssetError> {
        self.opt_str(key)?.ok_or_else(|| self.error(key, "missing"))
    }

    fn opt_obj(&self, key: &str) -> Result<Option<Obj<'a>>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(Value::Object(map)) => Ok(Some(Obj {
                map,
                path: self.field(key),
            })),
            Some(value) => Err(self.error(key, format!("{}, expected an object", short(value)))),
        }
    }

    fn obj(&self, key: &str) -> Result<Obj<'a>, AssetError> {
        self.opt_obj(key)?.ok_or_else(|| self.error(key, "missing"))
    }

    fn opt_array(&self, key: &str) -> Result<Option<&'a [Value]>, AssetError> {
        match self.map.get(key) {
            None => Ok(None),
            Some(Value::Array(items)) => Ok(Some(items)),
            Some(value) => Err(self.error(key, format!("{}, expected an array", short(value)))),
        }
    }

    /// `self[key][index]`, an object; `what` names the reference for the
    /// error (`meshes[0].primitives[1].material`).
    fn element(&self, key: &str, index: usize, what: &str) -> Result<Obj<'a>, AssetError> {
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
fn short(value: &Value) -> String {
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

/// What may still be held, of [`Limits::max_bytes`].
struct Budget {
    left: u64,
    limit: u64,
}

impl Budget {
    fn take(&mut self, what: impl FnOnce() -> String, bytes: u64) -> Result<(), AssetError> {
        if bytes <= self.left {
            self.left -= bytes;
            Ok(())
        } else {
            Err(AssetError::LimitExceeded {
                what: format!("{} (bytes, with what is already loaded)", what()),
                size: (self.limit - self.left).saturating_add(bytes),
                limit: self.limit,
            })
        }
    }
}

/// `a * b` in bytes, or `u64::MAX` on overflow (then over any budget).
fn bytes_of(count: u64, size: u64) -> u64 {
    count.saturating_mul(size)
}

/// How the reader walks a glTF.
struct Reader<'a, 'r> {
    root: Obj<'a>,
    raw_materials: Vec<&'a RawValue>,
    bin: Option<&'a [u8]>,
    resolve: &'r mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
    limits: Limits,
    budget: Budget,
    /// Loaded buffers by index, each exactly `byteLength` bytes.
    buffers: HashMap<usize, Cow<'a, [u8]>>,
    /// Decoded UV accessors by index.
    uvs: HashMap<usize, Rc<Vec<[f32; 2]>>>,
    /// glTF image index -> index into `asset.images`.
    images: HashMap<usize, usize>,
    asset: GltfAsset,
}

/// An accessor's layout and where its elements are.
struct Layout {
    path: String,
    count: usize,
    component_type: u64,
    normalized: bool,
    element_size: usize,
}

/// Extensions a glTF may require that do not change the mask.
fn supported_required(name: &str) -> bool {
    matches!(
        name,
        "KHR_mesh_quantization"
            | "KHR_texture_transform"
            | "KHR_lights_punctual"
            | "KHR_mesh_gpu_instancing"
    ) || (name.starts_with("KHR_materials_") && name != "KHR_materials_pbrSpecularGlossiness")
}

fn mode_name(mode: u64) -> &'static str {
    match mode {
        0 => "POINTS",
        1 => "LINES",
        2 => "LINE_LOOP",
        3 => "LINE_STRIP",
        5 => "TRIANGLE_STRIP",
        6 => "TRIANGLE_FAN",
        _ => "unknown",
    }
}

fn component_size(component_type: u64) -> Option<usize> {
    match component_type {
        5120 | 5121 => Some(1),
        5122 | 5123 => Some(2),
        5125 | 5126 => Some(4),
        _ => None,
    }
}

fn component_name(component_type: u64) -> &'static str {
    match component_type {
        5120 => "BYTE",
        5121 => "UNSIGNED_BYTE",
        5122 => "SHORT",
        5123 => "UNSIGNED_SHORT",
        5125 => "UNSIGNED_INT",
        5126 => "FLOAT",
        _ => "unknown",
    }
}

impl<'a> Reader<'a, '_> {
    fn warn(&mut self, warning: String) {
        self.asset.warnings.push(warning);
    }

    /// `asset.version` is 2.x, and every required extension is supported.
    fn check_header(&self) -> Result<(), AssetError> {
        let asset = self.root.obj("asset")?;
        let version = asset.str("version")?;
        if version.split('.').next() != Some("2") {
            return Err(asset.error(
                "version",
                format!("{version:?}: only glTF 2.x is supported"),
            ));
        }
        if let Some(min) = asset.opt_str("minVersion")? {
            if min != "2.0" {
                return Err(
                    asset.error("minVersion", format!("{min:?}: only glTF 2.0 is supported"))
                );
            }
        }
        let required = self
            .root
            .opt_array("extensionsRequired")?
            .unwrap_or_default();
        for (i, name) in required.iter().enumerate() {
            let field = format!("extensionsRequired[{i}]");
            let name = name.as_str().ok_or_else(|| {
                AssetError::gltf(&field, format!("{}, expected a string", short(name)))
            })?;
            if !supported_required(name) {
                return Err(AssetError::gltf(
                    field,
                    format!("the asset requires extension {name}, which is not supported"),
                ));
            }
        }
        Ok(())
    }

    fn read_meshes(&mut self) -> Result<(), AssetError> {
        let meshes = self.root.opt_array("meshes")?.unwrap_or_default();
        let (mut opaque, mut blend) = (0usize, 0usize);
        let mut untextured: BTreeMap<usize, usize> = BTreeMap::new();
        let mut colored = Vec::new();
        let mut transformed = BTreeSet::new();
        for m in 0..meshes.len() {
            let mesh = self.root.element("meshes", m, "meshes")?;
            let primitives = mesh
                .opt_array("primitives")?
                .ok_or_else(|| mesh.error("primitives", "missing"))?;
            for p in 0..primitives.len() {
                let primitive = mesh.element("primitives", p, "primitives")?;
                let mode = primitive.opt_u64("mode")?.unwrap_or(4);
                if mode != 4 {
                    self.warn(format!(
                        "{}: mode {mode} ({}) is not TRIANGLES (4), skipped",
                        primitive.path,
                        mode_name(mode)
                    ));
                    continue;
                }
                let Some(material_index) = primitive.opt_usize("material")? else {
                    opaque += 1;
                    continue;
                };
                let material =
                    self.root
                        .element("materials", material_index, &primitive.field("material"))?;
                match material.opt_str("alphaMode")?.unwrap_or("OPAQUE") {
                    "MASK" => {}
                    "OPAQUE" => {
                        opaque += 1;
                        continue;
                    }
                    "BLEND" => {
                        blend += 1;
                        continue;
                    }
                    other => {
                        return Err(material.error(
                            "alphaMode",
                            format!("{other:?} is not OPAQUE, MASK or BLEND"),
                        ))
                    }
                }
                let pbr = material.opt_obj("pbrMetallicRoughness")?;
                let Some(texture_info) = pbr
                    .as_ref()
                    .map(|pbr| pbr.opt_obj("baseColorTexture"))
                    .transpose()?
                    .flatten()
                else {
                    *untextured.entry(material_index).or_default() += 1;
                    continue;
                };
                let texture_index = texture_info.usize("index")?;
                let tex_coord = texture_info.opt_u32("texCoord")?.unwrap_or(0);
                if let Some(extensions) = texture_info.opt_obj("extensions")? {
                    if extensions.has("KHR_texture_transform") {
                        transformed.insert(material_index);
                    }
                }
                let attributes = primitive.obj("attributes")?;
                if attributes.has("COLOR_0") {
                    colored.push(primitive.path.clone());
                }
                let (alpha_cutoff, alpha_factor) =
                    self.material_numbers(material_index, &material)?;
                let uv_key = format!("TEXCOORD_{tex_coord}");
                let uv_accessor = attributes.opt_usize(&uv_key)?.ok_or_else(|| {
                    attributes.error(
                        &uv_key,
                        format!(
                            "missing, but {} = {tex_coord}",
                            texture_info.field("texCoord")
                        ),
                    )
                })?;
                let uvs = self.uvs(uv_accessor, &attributes.field(&uv_key))?;
                let indices = match primitive.opt_usize("indices")? {
                    Some(accessor) => Some(self.indices(accessor, &primitive.field("indices"))?),
                    None => None,
                };
                let triangles = self.triangles(&primitive.path, &uvs, indices.as_deref())?;
                let texture =
                    self.root
                        .element("textures", texture_index, &texture_info.field("index"))?;
                let sampler = match texture.opt_usize("sampler")? {
                    Some(s) => self.sampler(s, &texture.field("sampler"))?,
                    None => GltfSampler::default(),
                };
                let source = texture.opt_usize("source")?.ok_or_else(|| {
                    texture.error(
                        "source",
                        "missing (images only in an extension, such as KHR_texture_basisu, are not supported)",
                    )
                })?;
                let image = self.image(source, &texture.field("source"))?;
                self.asset.primitives.push(MaskPrimitive {
                    mesh: m,
                    primitive: p,
                    material: material_index,
                    alpha_cutoff,
                    alpha_factor,
                    texture: texture_index,
                    image,
                    sampler,
                    tex_coord,
                    triangles,
                });
            }
        }
        if opaque + blend > 0 {
            let total = opaque + blend;
            self.warn(format!(
                "skipped {total} primitive{} whose material is not alphaMode MASK ({opaque} OPAQUE, {blend} BLEND)",
                if total == 1 { "" } else { "s" }
            ));
        }
        for (material, count) in untextured {
            self.warn(format!(
                "materials[{material}] is alphaMode MASK without pbrMetallicRoughness.baseColorTexture: {count} primitive{} skipped",
                if count == 1 { "" } else { "s" }
            ));
        }
        if !colored.is_empty() {
            self.warn(format!(
                "{} primitive{} ha{} COLOR_0, whose alpha is not applied: {}",
                colored.len(),
                if colored.len() == 1 { "" } else { "s" },
                if colored.len() == 1 { "s" } else { "ve" },
                list(&colored)
            ));
        }
        for material in transformed {
            self.warn(format!(
                "materials[{material}].pbrMetallicRoughness.baseColorTexture has KHR_texture_transform, which is not applied to the UVs"
            ));
        }
        Ok(())
    }

    /// `alphaCutoff` and `baseColorFactor[3]`, from their decimal text.
    fn material_numbers(&self, index: usize, material: &Obj<'a>) -> Result<(f32, f32), AssetError> {
        // The structured reading has checked the types; the raw reading gives
        // the text of the same members.
        let raw: Option<RawMaterial<'_>> = self
            .raw_materials
            .get(index)
            .and_then(|raw| serde_json::from_str(raw.get()).ok());
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
        Ok((cutoff, factor))
    }

    fn sampler(&self, index: usize, what: &str) -> Result<GltfSampler, AssetError> {
        let sampler = self.root.element("samplers", index, what)?;
        let code =
            |key: &str, valid: &[u32], default: Option<u32>| -> Result<Option<u32>, AssetError> {
                match sampler.opt_u32(key)? {
                    None => Ok(default),
                    Some(code) if valid.contains(&code) => Ok(Some(code)),
                    Some(code) => Err(sampler.error(
                        key,
                        format!("{code} is not one of the glTF codes {valid:?}"),
                    )),
                }
            };
        let wraps = [REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT];
        Ok(GltfSampler {
            wrap_s: code("wrapS", &wraps, Some(REPEAT))?.unwrap_or(REPEAT),
            wrap_t: code("wrapT", &wraps, Some(REPEAT))?.unwrap_or(REPEAT),
            mag_filter: code("magFilter", &[NEAREST, LINEAR], None)?,
            min_filter: code(
                "minFilter",
                &[NEAREST, LINEAR, 9984, 9985, 9986, 9987],
                None,
            )?,
        })
    }

    /// Loads buffer `index` (once) and checks its length.
    fn load_buffer(&mut self, index: usize, what: &str) -> Result<(), AssetError> {
        if self.buffers.contains_key(&index) {
            return Ok(());
        }
        let buffer = self.root.element("buffers", index, what)?;
        let length = buffer.usize("byteLength")?;
        let data: Cow<'a, [u8]> = match buffer.opt_str("uri")? {
            Some(uri) => {
                self.budget.take(|| buffer.path.clone(), length as u64)?;
                Cow::Owned(
                    self.load_uri(uri).map_err(|e| {
                        e.within(format!("{} (uri {:?})", buffer.path, uri_label(uri)))
                    })?,
                )
            }
            None if index == 0 => Cow::Borrowed(self.bin.ok_or_else(|| {
                buffer.error(
                    "uri",
                    "missing, and there is no GLB BIN chunk to stand for buffer 0",
                )
            })?),
            None => {
                return Err(buffer.error("uri", "missing (only buffer 0 can be the GLB BIN chunk)"))
            }
        };
        if data.len() < length {
            return Err(buffer.error(
                "byteLength",
                format!("{length}, but the data has {} bytes", data.len()),
            ));
        }
        let data = match data {
            Cow::Borrowed(data) => Cow::Borrowed(&data[..length]),
            Cow::Owned(mut data) => {
                data.truncate(length);
                Cow::Owned(data)
            }
        };
        self.buffers.insert(index, data);
        Ok(())
    }

    /// The bytes of a `data:` URI, or of an external one through `resolve`.
    fn load_uri(&mut self, uri: &str) -> Result<Vec<u8>, AssetError> {
        if let Some(data) = uri.strip_prefix("data:") {
            return decode_data_uri(data).map_err(|message| AssetError::Uri {
                uri: uri_label(uri),
                message,
            });
        }
        if has_scheme(uri) {
            return Err(AssetError::Uri {
                uri: uri_label(uri),
                message: "only relative paths and data: URIs are supported".to_string(),
            });
        }
        let path = percent_decode(uri.as_bytes())
            .and_then(|bytes| {
                String::from_utf8(bytes).map_err(|_| "percent-decodes to invalid UTF-8".to_string())
            })
            .map_err(|message| AssetError::Uri {
                uri: uri_label(uri),
                message,
            })?;
        (self.resolve)(&path)
    }

    /// Buffer view `index`: (buffer, start, length, byteStride), with its
    /// buffer loaded and the range checked.
    fn view(
        &mut self,
        index: usize,
        what: &str,
    ) -> Result<(usize, usize, usize, Option<usize>), AssetError> {
        let view = self.root.element("bufferViews", index, what)?;
        let buffer = view.usize("buffer")?;
        let offset = view.opt_usize("byteOffset")?.unwrap_or(0);
        let length = view.usize("byteLength")?;
        let stride = view.opt_usize("byteStride")?;
        if let Some(stride) = stride {
            if !(4..=252).contains(&stride) || stride % 4 != 0 {
                return Err(view.error(
                    "byteStride",
                    format!("{stride}, expected a multiple of 4 in 4..=252"),
                ));
            }
        }
        self.load_buffer(buffer, &view.field("buffer"))?;
        let available = self.buffers.get(&buffer).map_or(0, |data| data.len());
        if !matches!(offset.checked_add(length), Some(end) if end <= available) {
            return Err(view.error(
                "byteLength",
                format!(
                    "bytes {offset}..{offset}+{length} run past the end of buffers[{buffer}] ({available} bytes)"
                ),
            ));
        }
        Ok((buffer, offset, length, stride))
    }

    /// The bytes of buffer view `index` and its `byteStride`.
    fn view_bytes(
        &mut self,
        index: usize,
        what: &str,
    ) -> Result<(&[u8], Option<usize>), AssetError> {
        let (buffer, start, length, stride) = self.view(index, what)?;
        let bytes = self
            .buffers
            .get(&buffer)
            .and_then(|data| data.get(start..start + length))
            .ok_or_else(|| AssetError::gltf(what, "buffer view out of range"))?;
        Ok((bytes, stride))
    }

    /// The layout of accessor `index`, whose type must be `ty`.
    fn layout(
        &self,
        index: usize,
        what: &str,
        ty: &str,
        components: usize,
    ) -> Result<(Obj<'a>, Layout), AssetError> {
        let accessor = self.root.element("accessors", index, what)?;
        let component_type = accessor
            .opt_u64("componentType")?
            .ok_or_else(|| accessor.error("componentType", "missing"))?;
        let size = component_size(component_type).ok_or_else(|| {
            accessor.error(
                "componentType",
                format!("{component_type} is not a glTF component type"),
            )
        })?;
        let actual = accessor.str("type")?;
        if actual != ty {
            return Err(accessor.error("type", format!("{actual:?}, expected {ty:?} for {what}")));
        }
        let count = accessor.usize("count")?;
        let normalized = accessor.opt_bool("normalized")?.unwrap_or(false);
        let layout = Layout {
            path: accessor.path.clone(),
            count,
            component_type,
            normalized,
            element_size: size * components,
        };
        Ok((accessor, layout))
    }

    /// The elements of an accessor, each decoded from its bytes by
    /// `decode`: from its buffer view (zeros without one), then the sparse
    /// substitutions. `T` is budgeted at `size_of::<T>()` bytes.
    fn elements<T: Copy + Default>(
        &mut self,
        accessor: &Obj<'a>,
        layout: &Layout,
        decode: impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>, AssetError> {
        let count = layout.count;
        self.budget.take(
            || format!("{} ({count} elements)", layout.path),
            bytes_of(count as u64, std::mem::size_of::<T>() as u64),
        )?;
        let mut values = if let Some(view_index) = accessor.opt_usize("bufferView")? {
            self.dense(accessor, layout, view_index, &decode)?
        } else {
            if accessor.opt_usize("byteOffset")?.unwrap_or(0) != 0 {
                return Err(accessor.error("byteOffset", "given without a bufferView"));
            }
            vec![T::default(); count]
        };
        if let Some(sparse) = accessor.opt_obj("sparse")? {
            self.sparse(&sparse, layout, &mut values, &decode)?;
        }
        Ok(values)
    }

    /// The elements of an accessor in buffer view `view_index`.
    fn dense<T>(
        &mut self,
        accessor: &Obj<'a>,
        layout: &Layout,
        view_index: usize,
        decode: &impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>, AssetError> {
        let count = layout.count;
        let size = layout.element_size;
        let mut values = Vec::new();
        let offset = accessor.opt_usize("byteOffset")?.unwrap_or(0);
        let (bytes, stride) = self.view_bytes(view_index, &accessor.field("bufferView"))?;
        let stride = stride.unwrap_or(size);
        if stride < size {
            return Err(accessor.error(
                "bufferView",
                format!(
                    "bufferViews[{view_index}].byteStride {stride} is less than the element size {size}"
                ),
            ));
        }
        // The last element ends at offset + stride * (count - 1) + size.
        let end = count.checked_sub(1).map_or(Some(0), |last| {
            stride
                .checked_mul(last)
                .and_then(|n| n.checked_add(size))
                .and_then(|n| n.checked_add(offset))
        });
        match end {
            Some(end) if end <= bytes.len() || count == 0 => {}
            _ => {
                return Err(accessor.error(
                    "count",
                    format!(
                        "{count} elements of {size} bytes, stride {stride}, from byte {offset} run past the end of bufferViews[{view_index}] ({} bytes)",
                        bytes.len()
                    ),
                ))
            }
        }
        values.reserve_exact(count);
        for i in 0..count {
            let start = offset + i * stride;
            values.push(decode(&bytes[start..start + size]));
        }
        Ok(values)
    }

    /// Applies `accessor.sparse` to `values`.
    fn sparse<T>(
        &mut self,
        sparse: &Obj<'a>,
        layout: &Layout,
        values: &mut [T],
        decode: &impl Fn(&[u8]) -> T,
    ) -> Result<(), AssetError> {
        let count = sparse.usize("count")?;
        if count == 0 || count > values.len() {
            return Err(sparse.error(
                "count",
                format!(
                    "{count}, expected 1..={} (the accessor's count)",
                    values.len()
                ),
            ));
        }
        let indices = sparse.obj("indices")?;
        let index_type = indices
            .opt_u64("componentType")?
            .ok_or_else(|| indices.error("componentType", "missing"))?;
        let index_size = match index_type {
            5121 => 1,
            5123 => 2,
            5125 => 4,
            other => {
                return Err(indices.error(
                    "componentType",
                    format!("{other}, expected 5121, 5123 or 5125 (unsigned)"),
                ))
            }
        };
        let index_offset = indices.opt_usize("byteOffset")?.unwrap_or(0);
        let index_view = indices.usize("bufferView")?;
        let (index_bytes, _) = self.view_bytes(index_view, &indices.field("bufferView"))?;
        let index_bytes = count
            .checked_mul(index_size)
            .and_then(|n| n.checked_add(index_offset))
            .and_then(|end| index_bytes.get(index_offset..end))
            .ok_or_else(|| {
                indices.error(
                    "bufferView",
                    format!("{count} indices of {index_size} bytes from byte {index_offset} run past the end of bufferViews[{index_view}]"),
                )
            })?
            .to_vec();
        let value_info = sparse.obj("values")?;
        let value_offset = value_info.opt_usize("byteOffset")?.unwrap_or(0);
        let value_view = value_info.usize("bufferView")?;
        let size = layout.element_size;
        let (value_bytes, _) = self.view_bytes(value_view, &value_info.field("bufferView"))?;
        let value_bytes = count
            .checked_mul(size)
            .and_then(|n| n.checked_add(value_offset))
            .and_then(|end| value_bytes.get(value_offset..end))
            .ok_or_else(|| {
                value_info.error(
                    "bufferView",
                    format!("{count} values of {size} bytes from byte {value_offset} run past the end of bufferViews[{value_view}]"),
                )
            })?;
        for (k, (index, value)) in index_bytes
            .chunks_exact(index_size)
            .zip(value_bytes.chunks_exact(size))
            .enumerate()
        {
            let index = read_unsigned(index) as usize;
            let slot = values.get_mut(index).ok_or_else(|| {
                indices.error(
                    "bufferView",
                    format!(
                        "sparse index {k} is {index}, past the accessor's count {}",
                        layout.count
                    ),
                )
            })?;
            *slot = decode(value);
        }
        Ok(())
    }

    /// The UVs of accessor `index` (decoded once).
    fn uvs(&mut self, index: usize, what: &str) -> Result<Rc<Vec<[f32; 2]>>, AssetError> {
        if let Some(uvs) = self.uvs.get(&index) {
            return Ok(Rc::clone(uvs));
        }
        let (accessor, layout) = self.layout(index, what, "VEC2", 2)?;
        let normalized = layout.normalized;
        let convert: fn(&[u8], bool) -> f32 = match layout.component_type {
            5126 if !normalized => |c, _| f32::from_le_bytes([c[0], c[1], c[2], c[3]]),
            5121 => |c, n| {
                let c = f32::from(c[0]);
                if n { c / 255.0 } else { c }
            },
            5123 => |c, n| {
                let c = f32::from(u16::from_le_bytes([c[0], c[1]]));
                if n { c / 65535.0 } else { c }
            },
            5120 => |c, n| {
                let c = f32::from(c[0] as i8);
                if n { (c / 127.0).max(-1.0) } else { c }
            },
            5122 => |c, n| {
                let c = f32::from(i16::from_le_bytes([c[0], c[1]]));
                if n { (c / 32767.0).max(-1.0) } else { c }
            },
            other => {
                return Err(accessor.error(
                    "componentType",
                    format!(
                        "{other} ({}{}) is not a texture coordinate type (FLOAT, or UNSIGNED_BYTE, UNSIGNED_SHORT, BYTE, SHORT)",
                        if normalized { "normalized " } else { "" },
                        component_name(other)
                    ),
                ))
            }
        };
        let half = layout.element_size / 2;
        let uvs = self.elements(&accessor, &layout, |bytes| {
            [
                convert(&bytes[..half], normalized),
                convert(&bytes[half..], normalized),
            ]
        })?;
        let uvs = Rc::new(uvs);
        self.uvs.insert(index, Rc::clone(&uvs));
        Ok(uvs)
    }

    /// The vertex indices of accessor `index`.
    fn indices(&mut self, index: usize, what: &str) -> Result<Vec<u32>, AssetError> {
        let (accessor, layout) = self.layout(index, what, "SCALAR", 1)?;
        if !matches!(layout.component_type, 5121 | 5123 | 5125) || layout.normalized {
            return Err(accessor.error(
                "componentType",
                format!(
                    "{} ({}{}), expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT for indices",
                    layout.component_type,
                    if layout.normalized { "normalized " } else { "" },
                    component_name(layout.component_type)
                ),
            ));
        }
        self.elements(&accessor, &layout, read_unsigned)
    }

    /// The triangles of a primitive: its UVs through its indices.
    fn triangles(
        &mut self,
        path: &str,
        uvs: &[[f32; 2]],
        indices: Option<&[u32]>,
    ) -> Result<Vec<[[f32; 2]; 3]>, AssetError> {
        let corners = indices.map_or(uvs.len(), <[u32]>::len);
        if corners % 3 != 0 {
            self.warn(format!(
                "{path}: {corners} {}, not a multiple of 3: the last {} ignored",
                if indices.is_some() {
                    "indices"
                } else {
                    "vertices"
                },
                corners % 3
            ));
        }
        let count = corners / 3;
        self.budget.take(
            || format!("{path} ({count} triangles)"),
            bytes_of(count as u64, 24),
        )?;
        let mut triangles = Vec::with_capacity(count);
        for t in 0..count {
            let mut triangle = [[0f32; 2]; 3];
            for (k, corner) in triangle.iter_mut().enumerate() {
                let position = 3 * t + k;
                let vertex = match indices {
                    Some(indices) => indices[position] as usize,
                    None => position,
                };
                *corner = *uvs.get(vertex).ok_or_else(|| {
                    AssetError::gltf(
                        format!("{path}.indices"),
                        format!(
                            "index {position} is {vertex}, past the {} texture coordinates",
                            uvs.len()
                        ),
                    )
                })?;
            }
            triangles.push(triangle);
        }
        Ok(triangles)
    }

    /// Decodes image `index` (once); its position in `asset.images`.
    fn image(&mut self, index: usize, what: &str) -> Result<usize, AssetError> {
        if let Some(&position) = self.images.get(&index) {
            return Ok(position);
        }
        let image = self.root.element("images", index, what)?;
        let uri = image.opt_str("uri")?;
        let view = image.opt_usize("bufferView")?;
        let limits = Limits {
            max_pixels: self.limits.max_pixels,
            max_bytes: self.budget.left,
        };
        let (bytes, label): (Cow<'_, [u8]>, String) = match (uri, view) {
            (Some(uri), None) => {
                let label = format!("{} (uri {:?})", image.path, uri_label(uri));
                let bytes = self.load_uri(uri).map_err(|e| e.within(&label))?;
                (Cow::Owned(bytes), label)
            }
            (None, Some(view)) => {
                let label = format!("{} (bufferViews[{view}])", image.path);
                let (bytes, _) = self.view_bytes(view, &image.field("bufferView"))?;
                (Cow::Borrowed(bytes), label)
            }
            (Some(_), Some(_)) => return Err(image.error("uri", "given together with bufferView")),
            (None, None) => return Err(image.error("uri", "missing, and no bufferView either")),
        };
        let decoded = decode_alpha_image(&bytes, &limits).map_err(|e| e.within(&label));
        drop(bytes);
        let decoded = decoded?;
        let texel_bytes = match &decoded.texels {
            super::AlphaTexels::Unorm8(texels) => texels.len() as u64,
            super::AlphaTexels::Float(texels) => bytes_of(texels.len() as u64, 4),
        };
        self.budget.take(|| label.clone(), texel_bytes)?;
        let info = GltfImageInfo {
            index,
            uri: uri.map(|uri| {
                if uri.starts_with("data:") {
                    uri_label(uri)
                } else {
                    uri.to_string()
                }
            }),
            buffer_view: view,
            mime_type: image.opt_str("mimeType")?.map(str::to_string),
            name: image.opt_str("name")?.map(str::to_string),
        };
        let position = self.asset.images.len();
        self.asset.images.push(decoded);
        self.asset.image_info.push(info);
        self.images.insert(index, position);
        Ok(position)
    }
}

/// A little-endian unsigned integer of 1, 2 or 4 bytes.
fn read_unsigned(bytes: &[u8]) -> u32 {
    match *bytes {
        [a] => u32::from(a),
        [a, b] => u32::from(u16::from_le_bytes([a, b])),
        [a, b, c, d] => u32::from_le_bytes([a, b, c, d]),
        _ => 0,
    }
}

/// The first few paths of a list, for a warning.
fn list(paths: &[String]) -> String {
    let mut text = paths.iter().take(4).cloned().collect::<Vec<_>>().join(", ");
    if paths.len() > 4 {
        let _ = write!(text, ", ... ({} more)", paths.len() - 4);
    }
    text
}

/// A URI for a message: `data:` URIs cut after their header, long ones
/// shortened.
fn uri_label(uri: &str) -> String {
    if uri.starts_with("data:") {
        let header = uri.split(',').next().unwrap_or(uri);
        format!("{},...", header.chars().take(60).collect::<String>())
    } else if uri.chars().count() > 120 {
        format!("{}...", uri.chars().take(120).collect::<String>())
    } else {
        uri.to_string()
    }
}

/// Whether `uri` starts with a scheme (`http:`, `file:`, ...).
fn has_scheme(uri: &str) -> bool {
    let Some(colon) = uri.find(':') else {
        return false;
    };
    let scheme = &uri[..colon];
    scheme.starts_with(|c: char| c.is_ascii_alphabetic())
        && scheme
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// `%XX` escapes decoded to bytes; a `%` not followed by two hex digits is
/// an error.
fn percent_decode(text: &[u8]) -> Result<Vec<u8>, String> {
    let hex = |b: u8| (b as char).to_digit(16);
    let mut out = Vec::with_capacity(text.len());
    let mut i = 0;
    while i < text.len() {
        if text[i] == b'%' {
            let digits = text
                .get(i + 1)
                .copied()
                .and_then(hex)
                .zip(text.get(i + 2).copied().and_then(hex));
            let Some((high, low)) = digits else {
                return Err(format!("'%' at byte {i} is not followed by two hex digits"));
            };
            out.push((high * 16 + low) as u8);
            i += 3;
        } else {
            out.push(text[i]);
            i += 1;
        }
    }
    Ok(out)
}

/// The data of a `data:` URI (after `data:`): `[<media type>][;base64],<data>`.
fn decode_data_uri(rest: &str) -> Result<Vec<u8>, String> {
    let (header, data) = rest
        .split_once(',')
        .ok_or_else(|| "data: URI without ','".to_string())?;
    if header.ends_with(";base64") {
        decode_base64(data.as_bytes())
    } else {
        percent_decode(data.as_bytes())
    }
}

/// Standard base64 (RFC 4648 alphabet `A-Z a-z 0-9 + /`), with or without
/// `=` padding.
fn decode_base64(text: &[u8]) -> Result<Vec<u8>, String> {
    fn value(c: u8) -> Option<u32> {
        match c {
            b'A'..=b'Z' => Some(u32::from(c - b'A')),
            b'a'..=b'z' => Some(u32::from(c - b'a') + 26),
            b'0'..=b'9' => Some(u32::from(c - b'0') + 52),
            b'+' => Some(62),
            b'/' => Some(63),
            _ => None,
        }
    }
    let padding = text.iter().rev().take_while(|&&c| c == b'=').count();
    if padding > 2 || (padding > 0 && text.len() % 4 != 0) {
        return Err("base64: bad '=' padding".to_string());
    }
    let text = &text[..text.len() - padding];
    if text.len() % 4 == 1 {
        return Err(format!(
            "base64: {} characters is not a valid length",
            text.len()
        ));
    }
    let mut out = Vec::with_capacity(text.len() / 4 * 3 + 2);
    for (chunk_index, chunk) in text.chunks(4).enumerate() {
        let mut word = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            let v = value(c).ok_or_else(|| {
                format!(
                    "base64: byte {} ({:?}) is not a base64 character",
                    chunk_index * 4 + k,
                    c as char
                )
            })?;
            word |= v << (18 - 6 * k);
        }
        let bytes = word.to_be_bytes();
        out.extend_from_slice(&bytes[1..chunk.len()]);
    }
    Ok(out)
}

#[cfg(test)]
mod unit {
    use super::{decode_base64, has_scheme, percent_decode};

    #[test]
    fn base64_matches_rfc_4648_vectors() {
        for (encoded, decoded) in [
            ("", ""),
            ("Zg==", "f"),
            ("Zm8=", "fo"),
            ("Zm9v", "foo"),
            ("Zm9vYg==", "foob"),
            ("Zm9vYmE=", "fooba"),
            ("Zm9vYmFy", "foobar"),
            ("Zm9vYg", "foob"),
        ] {
            assert_eq!(
                decode_base64(encoded.as_bytes()).unwrap(),
                decoded.as_bytes()
            );
        }
        assert!(decode_base64(b"Zm9vY").is_err());
        assert!(decode_base64(b"Zm9v====").is_err());
        assert!(decode_base64(b"Zm=v").is_err());
        assert!(decode_base64(b"Zm9v Yg==").is_err());
    }

    #[test]
    fn percent_and_scheme() {
        assert_eq!(percent_decode(b"a%20b%2Fc").unwrap(), b"a b/c");
        assert!(percent_decode(b"a%2").is_err());
        assert!(percent_decode(b"a%zz").is_err());
        assert!(has_scheme("http://x/y.png"));
        assert!(has_scheme("file:y.png"));
        assert!(!has_scheme("textures/y.png"));
        assert!(!has_scheme("a b:c/x.png"));
    }
}
