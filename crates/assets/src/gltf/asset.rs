//! What the reader returns: [`GltfAsset`], its [`MaskPrimitive`]s and
//! [`GltfImageInfo`]s.

use crate::{AlphaImage, AssetError};
use micromap_index::bake::mesh::Material;
use micromap_index::bake::{Cutoff, Sampler, UvTransform};

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
    /// text to binary32, with glTF's comparison
    /// ([`Comparison::AtLeast`](micromap_index::bake::Comparison::AtLeast)):
    /// a texel is opaque where `alpha * alpha_factor >= cutoff`. Never
    /// negative.
    pub cutoff: Cutoff,
    /// `pbrMetallicRoughness.baseColorFactor[3]` (default 1), rounded once
    /// from its decimal text; it multiplies the texture's alpha.
    pub alpha_factor: f32,
    /// The texture: index into the glTF's `textures`.
    pub texture: usize,
    /// The decoded image: index into [`GltfAsset::images`] (not into the
    /// glTF's `images`; [`GltfAsset::image_info`] maps back).
    pub image: usize,
    /// The texture's sampler (`samplers[i]`, or glTF's defaults), as the
    /// runtime samples: `magFilter` `NEAREST` is
    /// [`Filter::Nearest`](micromap_index::bake::Filter::Nearest), `LINEAR`
    /// or unspecified `Linear`; `wrapS` and `wrapT` (default `REPEAT`) are
    /// the address modes along `u` and `v` of the same names; border alpha 0
    /// (glTF has no clamp-to-border). The reader checks that every code is
    /// one glTF defines (`minFilter` too, which magnification-free baking
    /// does not use).
    pub sampler: Sampler,
    /// `baseColorTexture.texCoord` (or the `texCoord` of its
    /// `KHR_texture_transform`, which overrides it): the triangles are
    /// `TEXCOORD_<tex_coord>`.
    pub tex_coord: u32,
    /// The UVs of each triangle, in order, with the indices applied (or
    /// vertices `3i, 3i + 1, 3i + 2` without indices), as stored: the
    /// texture's `KHR_texture_transform` is [`uv_transform`](Self::uv_transform),
    /// which the shader applies to the interpolated coordinate. Integer UVs
    /// (`KHR_mesh_quantization`) are converted as glTF says: normalized
    /// `c / 255`, `c / 65535`, `max(c / 127, -1)`, `max(c / 32767, -1)`,
    /// each one binary32 division; others as the integer's value.
    pub triangles: Vec<[[f32; 2]; 3]>,
    /// The base-colour texture's `KHR_texture_transform` (offset,
    /// rotation and scale, each rounded once from its JSON text to
    /// binary32), or [`UvTransform::IDENTITY`] without one. The baker
    /// models the shader's binary32 transform of the interpolated
    /// coordinate ([`Material::uv_transform`]);
    /// [`placed_triangles`](Self::placed_triangles) gives the transformed
    /// triangles for drawing.
    pub uv_transform: UvTransform,
    /// The `COLOR_0` alpha of each triangle's vertices (as
    /// [`triangles`](Self::triangles), one entry per triangle), which
    /// multiplies the texture's alpha; `None` without `COLOR_0` or with a
    /// `VEC3` one (alpha 1). `FLOAT` values as stored (each in `[0, 1]`),
    /// normalized `c / 255` and `c / 65535`, each one binary32 division.
    pub vertex_alpha: Option<Vec<[f32; 3]>>,
    /// The `POSITION` of each triangle's vertices (as
    /// [`triangles`](Self::triangles), one entry per triangle), in the
    /// mesh's own space (node transforms are not applied), for renderers;
    /// `None` without `POSITION`. `VEC3` of `FLOAT`, every value finite.
    pub positions: Option<Vec<[[f32; 3]; 3]>>,
    /// Where a renderer draws the mesh: the world transforms (row-major
    /// 3x4, binary32, rounded once from binary64 products) of the default
    /// scene's nodes that instance [`mesh`](Self::mesh), depth first from
    /// the scene's roots: `matrix`, or `translation * rotation * scale`,
    /// composed from the roots down. A node with `EXT_mesh_gpu_instancing`
    /// (or its `KHR_` spelling) contributes one transform per instance, in
    /// accessor order, `node_world * T * R * S` with the instance's
    /// `TRANSLATION`, `ROTATION` (normalised) and `SCALE` (each identity
    /// when absent), and not its own world transform; the extension on a
    /// node without a mesh is ignored (the extension defines nothing for
    /// it). Empty when no node of the scene instances the mesh;
    /// [`IDENTITY_TRANSFORM`](super::IDENTITY_TRANSFORM) once when the
    /// asset has no `nodes`, or when its node tree or an instancing
    /// extension in it is malformed (a warning says why: among others,
    /// attributes of different counts, an extension without attributes,
    /// whose instance count is then undefined, a type the extension does
    /// not allow), or when the transforms exceed the byte budget.
    pub instances: Vec<[f32; 12]>,
}

impl MaskPrimitive {
    /// Its material as [`bake::mesh`](micromap_index::bake::mesh) takes it:
    /// sampler, cutoff and alpha factor (the vertex alpha is
    /// [`vertex_alpha`](Self::vertex_alpha), for
    /// [`Mesh::vertex_alpha`](micromap_index::bake::mesh::Mesh::vertex_alpha)).
    ///
    /// ```
    /// use micromap_index_assets::{read_gltf_file, Limits};
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/crytek-sponza/cards.gltf");
    /// let asset = read_gltf_file(path.as_ref(), &Limits::default()).unwrap();
    /// let material = asset.primitives[1].material();
    /// assert_eq!(material.cutoff.alpha(), 0.3);
    /// assert_eq!(material.alpha_factor, 1.0);
    /// ```
    #[must_use]
    pub fn material(&self) -> Material {
        Material {
            sampler: self.sampler,
            cutoff: self.cutoff,
            alpha_factor: self.alpha_factor,
            uv_transform: self.uv_transform,
        }
    }

    /// [`triangles`](Self::triangles) through
    /// [`uv_transform`](Self::uv_transform), each vertex rounded once to
    /// binary32 ([`UvTransform::place`]): the triangles in texture space,
    /// for previews and renderers that transform per vertex.
    #[must_use]
    pub fn placed_triangles(&self) -> Vec<[[f32; 2]; 3]> {
        self.triangles
            .iter()
            .map(|t| self.uv_transform.place_triangle(t))
            .collect()
    }
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
    /// Where its alpha came from: its alpha channel, or
    /// [`AlphaSource::One`](crate::AlphaSource::One) for an image without
    /// one (glTF: alpha 1; never its grey value).
    pub alpha: crate::AlphaSource,
}

/// What [`read_gltf_file`](crate::read_gltf_file) and [`read_gltf_bytes`](crate::read_gltf_bytes) read from a glTF.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct GltfAsset {
    /// Every alpha-tested triangle primitive, in the order of `meshes` and
    /// their `primitives`.
    pub primitives: Vec<MaskPrimitive>,
    /// The images the primitives use, each decoded once
    /// ([`decode_image_alpha`](crate::decode_image_alpha) with
    /// [`MissingAlpha::One`](crate::MissingAlpha::One): an image without an
    /// alpha channel is opaque, as glTF says), in order of first use.
    pub images: Vec<AlphaImage>,
    /// For each of [`GltfAsset::images`], where it came from.
    pub image_info: Vec<GltfImageInfo>,
    /// What was skipped or is not applied, one line each: primitives that
    /// are not triangles, materials that are not `MASK` (counted), `MASK`
    /// materials without a base colour texture, base-colour images without
    /// an alpha channel (read as alpha 1), `COLOR_0` alpha (multiplied in),
    /// `KHR_texture_transform` (modelled in the shader), oddities of the GLB
    /// container.
    pub warnings: Vec<String>,
    /// The `MASK` primitives that cannot be baked soundly, in order, each
    /// with its reason; they are not among [`GltfAsset::primitives`]. A
    /// malformed asset is an error instead; these are well-formed
    /// primitives the model does not cover (a `KHR_texture_transform`
    /// rotation above [`MAX_ROTATION`](micromap_index::bake::MAX_ROTATION)
    /// radians). A caller bakes the rest, or refuses the asset (`--strict`).
    pub refused: Vec<RefusedPrimitive>,
}

/// A primitive [`GltfAsset::refused`] lists.
#[derive(Clone, Debug, PartialEq)]
pub struct RefusedPrimitive {
    /// Its mesh.
    pub mesh: usize,
    /// Its index among the mesh's primitives.
    pub primitive: usize,
    /// The field at fault and why, one line (as an error would say it).
    pub reason: AssetError,
}

impl RefusedPrimitive {
    /// What a caller that cannot leave primitives out says of `refused`:
    /// the first, how many there are, and why the first is refused
    /// (`meshes[M].primitives[P] cannot be baked soundly (N primitive(s)
    /// so): REASON`); `None` when there are none.
    #[must_use]
    pub fn refusal(refused: &[RefusedPrimitive]) -> Option<String> {
        refused.first().map(|r| {
            format!(
                "meshes[{}].primitives[{}] cannot be baked soundly ({} primitive(s) so): {}",
                r.mesh,
                r.primitive,
                refused.len(),
                r.reason
            )
        })
    }
}
