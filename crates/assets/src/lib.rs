//! Readers for the real assets an opacity-micromap baker starts from: alpha
//! textures (PNG, JPEG), triangle lists in UV space (`TRIS.json`) and glTF
//! 2.0 scenes (`.gltf` with external or `data:` buffers, or `.glb`),
//! returning the types of [`micromap_index::bake`]: textures it views
//! without conversion ([`AlphaImage::texture`]),
//! [`Sampler`](micromap_index::bake::Sampler)s and [`Cutoff`](micromap_index::bake::Cutoff)s.
//!
//! Every reader takes untrusted bytes: it never panics, and it bounds every
//! allocation by [`Limits`] or by the length of its input (the fuzz targets
//! `alpha_image`, `triangles_json` and `gltf_asset` check this, see
//! `docs/fuzzing.md`). Errors are typed ([`AssetError`]) and print as one
//! line naming the file or field at fault.
//!
//! * [`decode_alpha_image`]: the alpha (or grey) channel of a PNG or JPEG;
//!   [`decode_image_alpha`] with glTF's rule for an image without alpha
//!   (alpha 1, [`MissingAlpha::One`]).
//! * [`read_triangles_json`]: `{"triangles": [[[u0, v0], [u1, v1], [u2, v2]], ...]}`,
//!   each number rounded once from its decimal text to binary32.
//! * [`read_gltf_file`] and [`read_gltf_bytes`]: every triangle primitive of
//!   a glTF whose material is `alphaMode: "MASK"` with a base colour
//!   texture, with its UVs, alpha cutoff, sampler and decoded image.
//!
//!
//! ## Coordinates
//!
//! Images are row-major with row 0 the **top** row of the picture, as PNG
//! and JPEG store them. glTF puts UV `(0, 0)` at the top-left corner of the
//! image too (`u` to the right, `v` down), so texel `(x, y)` covers
//! `u` in `[x / width, (x + 1) / width]` and `v` in `[y / height, (y + 1) / height]`
//! with no flip. UVs are returned as stored: outside `[0, 1]` the
//! sampler's address modes ([`MaskPrimitive::sampler`]) apply.
//!
//! ```
//! use micromap_index_assets::{read_triangles_json, AssetError};
//! let triangles = read_triangles_json(br#"{"triangles": [[[0, 0], [1, 0], [0, 0.1]]]}"#)?;
//! assert_eq!(triangles, vec![[[0.0, 0.0], [1.0, 0.0], [0.0, 0.1]]]);
//! # Ok::<(), AssetError>(())
//! ```

#![forbid(unsafe_code)]

mod alpha_image;
mod error;
mod gltf;
mod image;
mod image_format;
mod json_number;
mod limits;
mod tris_json;

#[cfg(test)]
mod cards;
#[cfg(test)]
mod tests;

pub use self::gltf::{
    read_gltf_bytes, read_gltf_file, read_gltf_micromaps, read_gltf_micromaps_file,
    write_gltf_micromaps, write_gltf_micromaps_file, GltfAsset, GltfContainer, GltfFiles,
    GltfImageInfo, GltfMicromap, GltfMicromapPrimitive, GltfMicromapWrite, GltfMicromaps,
    MaskPrimitive, RefusedPrimitive, EXTENSION, IDENTITY_TRANSFORM, MAX_GLTF_LEVEL,
};
pub use self::image::{decode_alpha_image, decode_image_alpha, AlphaSource, MissingAlpha};
pub use self::tris_json::read_triangles_json;

pub use self::alpha_image::{AlphaImage, AlphaTexels, ImageTexture};
pub use self::error::AssetError;
pub use self::image_format::ImageFormat;
pub use self::limits::{Limits, UriScope};
