//! The [`Reader`] every glTF reading walks with ([`with_reader`]): the JSON
//! root, the raw material texts, the `BIN` chunk, the `resolve` of external
//! URIs, the byte budget ([`Budget`]), what is loaded so far and the
//! [`GltfAsset`] being built; and the header check (version, required
//! extensions). The readers of each part (`accessor`, `image`, `material`,
//! `sampler`, `transform`, `uri`, `micromap_ext`, the mesh walk in `mod`)
//! are `impl Reader` blocks in their own files.

use super::asset::GltfAsset;
use super::glb::split_glb;
use super::json::{short, Obj};
use super::material::raw_materials;
use crate::{AssetError, Limits};
use serde_json::value::RawValue;
use serde_json::Value;
use std::borrow::Cow;
use std::collections::HashMap;
use std::rc::Rc;

/// The extension's name, as the Khronos registry has it (ratified).
pub(super) const INSTANCING: &str = "EXT_mesh_gpu_instancing";

/// The same extension under the name this reader has always accepted in
/// `extensionsRequired` (no registry extension has it): read as
/// [`INSTANCING`] (by `super::instancing`).
pub(super) const INSTANCING_KHR: &str = "KHR_mesh_gpu_instancing";

/// `f` on a [`Reader`] of the glTF `bytes` whose header is checked.
pub(super) fn with_reader<T>(
    bytes: &[u8],
    resolve: &mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
    limits: &Limits,
    f: impl FnOnce(&mut Reader<'_, '_>) -> Result<T, AssetError>,
) -> Result<T, AssetError> {
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
    f(&mut reader)
}

/// What may still be held, of [`Limits::max_bytes`].
pub(super) struct Budget {
    pub(super) left: u64,
    pub(super) limit: u64,
}

impl Budget {
    pub(super) fn take(
        &mut self,
        what: impl FnOnce() -> String,
        bytes: u64,
    ) -> Result<(), AssetError> {
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
pub(super) fn bytes_of(count: u64, size: u64) -> u64 {
    count.saturating_mul(size)
}

/// How the reader walks a glTF.
pub(super) struct Reader<'a, 'r> {
    pub(super) root: Obj<'a>,
    pub(super) raw_materials: Vec<&'a RawValue>,
    pub(super) bin: Option<&'a [u8]>,
    pub(super) resolve: &'r mut dyn FnMut(&str) -> Result<Vec<u8>, AssetError>,
    pub(super) limits: Limits,
    pub(super) budget: Budget,
    /// Loaded buffers by index, each exactly `byteLength` bytes.
    pub(super) buffers: HashMap<usize, Cow<'a, [u8]>>,
    /// Decoded UV accessors by index.
    pub(super) uvs: HashMap<usize, Rc<Vec<[f32; 2]>>>,
    /// glTF image index -> index into `asset.images`.
    pub(super) images: HashMap<usize, usize>,
    pub(super) asset: GltfAsset,
}

/// Extensions a glTF may require that the reader models
/// (`KHR_mesh_quantization`, `KHR_texture_transform`,
/// `EXT_mesh_gpu_instancing`, also under the `KHR_` spelling it has always
/// accepted) or that do not change the mask.
fn supported_required(name: &str) -> bool {
    matches!(
        name,
        "KHR_mesh_quantization"
            | "KHR_texture_transform"
            | "KHR_lights_punctual"
            | INSTANCING
            | INSTANCING_KHR
            | "EXT_mesh_opacity_micromap"
    ) || (name.starts_with("KHR_materials_") && name != "KHR_materials_pbrSpecularGlossiness")
}

impl Reader<'_, '_> {
    pub(super) fn warn(&mut self, warning: String) {
        self.asset.warnings.push(warning);
    }

    /// `asset.version` is 2.x, and every required extension is supported.
    pub(super) fn check_header(&self) -> Result<(), AssetError> {
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
}
