//! [`read_gltf_file`] and [`read_gltf_bytes`]: the alpha-tested triangles of
//! a glTF 2.0 asset, with their UVs, cutoffs, samplers and images.
//!
//! This file holds the entry points and the walk over meshes; `asset` the
//! public types they return, `reader` the [`Reader`] every part is read
//! with; `glb` splits the container, `json` walks the JSON, `uri`,
//! `accessor`, `material`, `sampler` and `image` read what their names say;
//! `micromap_ext` reads `EXT_mesh_opacity_micromap` (`extension`: its name
//! and highest level);
//! `files` reads the asset and the files it names from disk; `write` writes
//! an asset back with micromaps, `write_dir` does it for a
//! file on disk and an output directory.

use self::files::{read_file, resolve_beside};
use self::material::material_numbers;
use self::reader::{bytes_of, with_reader, Reader};
use crate::{AssetError, Limits};
use micromap_index::bake::UvTransform;
use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::Path;

mod accessor;
mod asset;
mod embed;
mod extension;
mod files;
mod glb;
mod image;
mod instancing;
mod json;
mod material;
mod micromap_ext;
mod nodes;
mod position;
mod raw;
mod reader;
mod sampler;
mod transform;
mod uri;
mod write;
mod write_dir;

pub use self::asset::{GltfAsset, GltfImageInfo, MaskPrimitive, RefusedPrimitive};
pub use self::extension::{EXTENSION, MAX_GLTF_LEVEL};
pub use self::micromap_ext::{
    read_gltf_micromaps, read_gltf_micromaps_file, GltfMicromap, GltfMicromapPrimitive,
    GltfMicromaps,
};
pub use self::nodes::IDENTITY_TRANSFORM;
pub use self::write::{write_gltf_micromaps, GltfContainer, GltfFiles, GltfMicromapWrite};
pub use self::write_dir::write_gltf_micromaps_file;

#[cfg(test)]
pub(crate) use self::sampler::{
    GltfSampler, CLAMP_TO_EDGE, LINEAR, MIRRORED_REPEAT, NEAREST, REPEAT,
};

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
/// use micromap_index_assets::{read_gltf_file, Limits};
/// let asset = read_gltf_file("assets/crytek-sponza/cards.gltf".as_ref(), &Limits::default())?;
/// for primitive in &asset.primitives {
///     let image = &asset.images[primitive.image];
///     println!("mesh {} primitive {}: {} triangles on {} x {}, cutoff {}",
///         primitive.mesh, primitive.primitive, primitive.triangles.len(),
///         image.width, image.height, primitive.cutoff.alpha());
/// }
/// # Ok::<(), micromap_index_assets::AssetError>(())
/// ```
pub fn read_gltf_file(path: &Path, limits: &Limits) -> Result<GltfAsset, AssetError> {
    let bytes = read_file(path, limits.max_bytes)?;
    let base = path.parent().unwrap_or_else(|| Path::new(""));
    let mut resolve = resolve_beside(base, limits);
    read_gltf_bytes(&bytes, &mut resolve, limits).map_err(|e| e.within(path.display().to_string()))
}

/// Reads a glTF 2.0 asset from bytes: GLB if they start with the magic
/// `glTF`, JSON otherwise. `resolve` is called with each external URI a
/// needed buffer or image names, percent-decoded (`leaf%20a.png` →
/// `leaf a.png`), and returns the bytes; `data:` URIs (base64 or
/// percent-encoded) are decoded here, and URIs with any other scheme are
/// refused without calling it. For fuzzing without a filesystem.
///
/// For every primitive of every mesh (in order; every mesh counts once:
/// the default scene's nodes only place it, [`MaskPrimitive::instances`]):
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
///   decoded once by [`decode_image_alpha`](crate::decode_image_alpha): its
///   alpha channel, or alpha 1 everywhere if it has none (glTF 2.0: without
///   a fourth component the alpha coverage is 1; a note in `warnings` says
///   so); its sampler is read.
///
/// Buffers are loaded only when a needed buffer view is in them; the GLB
/// `BIN` chunk is buffer 0 when that has no `uri`.
///
/// `COLOR_0` (`VEC4`: `FLOAT` in `[0, 1]`, normalized `UNSIGNED_BYTE` or
/// `UNSIGNED_SHORT`) gives [`MaskPrimitive::vertex_alpha`]; a `VEC3` one
/// has alpha 1. `KHR_texture_transform` on the base-colour texture
/// (`offset`, `rotation`, `scale`, and `texCoord`, which overrides the
/// texture info's) is [`MaskPrimitive::uv_transform`], each number rounded
/// once from its text to binary32: the triangles stay as stored, and the
/// baker models the shader's transform of the interpolated UV
/// (`translation * rotation * scale`) with its binary32 error. A rotation
/// above [`MAX_ROTATION`](micromap_index::bake::MAX_ROTATION) radians
/// refuses the primitive ([`GltfAsset::refused`]).
///
/// A required extension
/// other than `KHR_mesh_quantization`, `KHR_texture_transform`, `KHR_materials_*` (except
/// `KHR_materials_pbrSpecularGlossiness`), `KHR_lights_punctual`,
/// `EXT_mesh_gpu_instancing` (also spelt `KHR_mesh_gpu_instancing`, which
/// this reader has always accepted; it is read as the same extension) and
/// `EXT_mesh_opacity_micromap` is an error. Accessor alignment is not checked.
///
/// Limits: each image is decoded within [`Limits::max_pixels`]; the loaded
/// buffers, decoded images, UV, index and triangle arrays and instance
/// transforms together stay within [`Limits::max_bytes`] (instance
/// transforms over it are a warning, as a malformed node tree). Every index, offset and length is checked
/// with overflow-free arithmetic. Never panics.
///
/// ```
/// use micromap_index_assets::{read_gltf_bytes, AssetError, Limits};
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
    with_reader(bytes, resolve, limits, |reader| {
        reader.read_meshes()?;
        Ok(std::mem::take(&mut reader.asset))
    })
}

/// The library's [`UvTransform`] of `transform`, or why it cannot be one
/// (the primitive is then refused, `GltfAsset::refused`): a rotation above
/// [`MAX_ROTATION`](micromap_index::bake::MAX_ROTATION) radians.
fn uv_transform(
    transform: &transform::Transform,
    texture_path: &str,
) -> Result<UvTransform, AssetError> {
    UvTransform::new(transform.offset, transform.rotation, transform.scale).map_err(|e| {
        AssetError::gltf(
            format!("{texture_path}.extensions.KHR_texture_transform"),
            format!("{e}, refused"),
        )
    })
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

impl Reader<'_, '_> {
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
                // KHR_materials_variants: only the default material is
                // read; say so rather than bake one look silently.
                if let Some(variants) = primitive
                    .opt_obj("extensions")?
                    .map(|e| e.opt_obj("KHR_materials_variants"))
                    .transpose()?
                    .flatten()
                {
                    let mappings = variants.opt_array("mappings")?.map_or(0, <[_]>::len);
                    self.warn(format!(
                        "{}: KHR_materials_variants maps {mappings} variant material(s); only the \
                         primitive's default material ({}) is read, so a variant's look needs a \
                         bake of its own",
                        primitive.path,
                        primitive
                            .opt_usize("material")?
                            .map_or("none".to_string(), |m| format!("materials[{m}]"))
                    ));
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
                let transform = self.texture_transform(material_index, &texture_info)?;
                // The extension's texCoord overrides the texture info's.
                let tex_coord = match transform.and_then(|t| t.tex_coord) {
                    Some(n) => n,
                    None => texture_info.opt_u32("texCoord")?.unwrap_or(0),
                };
                let attributes = primitive.obj("attributes")?;
                let (cutoff, alpha_factor) =
                    material_numbers(self.raw_materials.get(material_index).copied(), &material)?;
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
                let uv_transform = match transform {
                    None => UvTransform::IDENTITY,
                    Some(transform) => match uv_transform(&transform, &texture_info.path) {
                        Ok(t) => {
                            transformed.insert(material_index);
                            t
                        }
                        Err(reason) => {
                            // Well-formed, but not modelled: this primitive
                            // is refused, the rest of the asset is read.
                            self.asset.refused.push(RefusedPrimitive {
                                mesh: m,
                                primitive: p,
                                reason,
                            });
                            continue;
                        }
                    },
                };
                let vertex_alpha = match attributes.opt_usize("COLOR_0")? {
                    None => None,
                    Some(accessor) => {
                        match self.vertex_alphas(accessor, &attributes.field("COLOR_0"))? {
                            None => None,
                            Some(alphas) => {
                                colored.push(primitive.path.clone());
                                Some(self.triangle_alphas(
                                    &primitive.path,
                                    &alphas,
                                    indices.as_deref(),
                                    triangles.len(),
                                )?)
                            }
                        }
                    }
                };
                let positions = match attributes.opt_usize("POSITION")? {
                    None => None,
                    Some(accessor) => Some(self.triangle_positions(
                        &primitive.path,
                        accessor,
                        indices.as_deref(),
                        triangles.len(),
                    )?),
                };
                let texture =
                    self.root
                        .element("textures", texture_index, &texture_info.field("index"))?;
                let sampler = match texture.opt_usize("sampler")? {
                    Some(s) => self.sampler(s, &texture.field("sampler"))?,
                    None => sampler::GltfSampler::default(),
                }
                .to_sampler();
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
                    cutoff,
                    alpha_factor,
                    texture: texture_index,
                    image,
                    sampler,
                    tex_coord,
                    triangles,
                    uv_transform,
                    vertex_alpha,
                    positions,
                    instances: vec![IDENTITY_TRANSFORM],
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
                "{} primitive{} ha{} COLOR_0 alpha, multiplied in with bounds per triangle (texels near the cutoff may bake unknown): {}",
                colored.len(),
                if colored.len() == 1 { "" } else { "s" },
                if colored.len() == 1 { "s" } else { "ve" },
                list(&colored)
            ));
        }
        for material in transformed {
            self.warn(format!(
                "materials[{material}].pbrMetallicRoughness.baseColorTexture has KHR_texture_transform: modelled as the shader applies it to the interpolated UV (binary32)"
            ));
        }
        self.place_primitives(meshes.len());
        Ok(())
    }

    /// Each primitive's [`MaskPrimitive::instances`] from the node tree and
    /// its `EXT_mesh_gpu_instancing` (bakes do not need them: a malformed
    /// tree or extension, or transforms over the byte budget, is a
    /// warning).
    fn place_primitives(&mut self, meshes: usize) {
        let root = self.root.clone();
        let placed = nodes::mesh_instances(&root, meshes, &mut |node| self.gpu_instances(node))
            .and_then(|instances| {
                let Some(instances) = instances else {
                    return Ok(None);
                };
                // Each primitive holds a copy of its mesh's transforms.
                let bytes = self
                    .asset
                    .primitives
                    .iter()
                    .map(|p| bytes_of(instances[p.mesh].len() as u64, 48))
                    .fold(0, u64::saturating_add);
                self.budget
                    .take(|| "the primitives' instance transforms".to_string(), bytes)
                    .map_err(|e| e.to_string())?;
                Ok(Some(instances))
            });
        match placed {
            Ok(None) => {}
            Ok(Some(instances)) => {
                for p in &mut self.asset.primitives {
                    p.instances.clone_from(&instances[p.mesh]);
                }
            }
            Err(why) => self.warn(format!(
                "node transforms not applied ({why}): renderers draw each mesh once, in its own space"
            )),
        }
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
