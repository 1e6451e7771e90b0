//! Readers for the real assets an opacity-micromap baker starts from: alpha
//! textures (PNG, JPEG), triangle lists in UV space (`TRIS.json`) and glTF
//! 2.0 scenes (`.gltf` with external or `data:` buffers, or `.glb`),
//! returning the types of [`micromap_index::bake`]: textures it views
//! without conversion ([`AlphaImage::texture`]),
//! [`Sampler`](micromap_index::bake::Sampler)s and [`Cutoff`]s.
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

mod gltf;
mod image;
mod tris_json;

#[cfg(test)]
mod cards;
#[cfg(test)]
mod tests;

pub use self::gltf::{
    read_gltf_bytes, read_gltf_file, read_gltf_micromaps, relative_uri_prefix,
    write_gltf_micromaps, write_gltf_micromaps_file, GltfAsset, GltfContainer, GltfFiles,
    GltfImageInfo, GltfMicromap, GltfMicromapPrimitive, GltfMicromapWrite, GltfMicromaps,
    MaskPrimitive, EXTENSION, IDENTITY_TRANSFORM, MAX_GLTF_LEVEL,
};
pub use self::image::{
    decode_alpha_image, decode_image_alpha, AlphaSource, ImageFormat, MissingAlpha,
};
pub use self::tris_json::read_triangles_json;

use micromap_index::bake::{
    AlphaTexture, Cutoff, F32Texture, TextureError, Unorm16Texture, Unorm8Texture,
};
use std::fmt;

/// The texels of an [`AlphaImage`]: one value per pixel, row-major, row 0 the
/// image's top row, in the texel types of [`micromap_index::bake`]
/// ([`Texel`](micromap_index::bake::Texel)), so that a
/// [`SliceTexture`](micromap_index::bake::SliceTexture) views them as they
/// are ([`AlphaImage::texture`]).
#[derive(Clone, Debug, PartialEq)]
pub enum AlphaTexels {
    /// 8-bit samples; `0` is transparent, `255` opaque (alpha `c / 255`).
    Unorm8(Vec<u8>),
    /// 16-bit samples, exactly as stored (alpha `c / 65535`).
    Unorm16(Vec<u16>),
    /// Alpha values as they are. The decoders here never produce them; for
    /// images built by the caller (from a float format, say).
    Float(Vec<f32>),
}

impl AlphaTexels {
    /// The number of texels.
    #[must_use]
    pub fn len(&self) -> usize {
        match self {
            AlphaTexels::Unorm8(texels) => texels.len(),
            AlphaTexels::Unorm16(texels) => texels.len(),
            AlphaTexels::Float(texels) => texels.len(),
        }
    }

    /// Whether there are no texels.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Texel `i` as a binary32 value (`Unorm8` as `c / 255` and `Unorm16`
    /// as `c / 65535`, each rounded once to binary32; the baker reads the
    /// exact quotients instead); `None` past the end.
    #[must_use]
    pub fn get(&self, i: usize) -> Option<f32> {
        match self {
            AlphaTexels::Unorm8(texels) => texels.get(i).map(|&t| f32::from(t) / 255.0),
            AlphaTexels::Unorm16(texels) => texels.get(i).map(|&t| f32::from(t) / 65535.0),
            AlphaTexels::Float(texels) => texels.get(i).copied(),
        }
    }

    /// Bytes the texels hold (1, 2 or 4 per texel).
    #[must_use]
    pub fn byte_len(&self) -> u64 {
        match self {
            AlphaTexels::Unorm8(texels) => texels.len() as u64,
            AlphaTexels::Unorm16(texels) => (texels.len() as u64).saturating_mul(2),
            AlphaTexels::Float(texels) => (texels.len() as u64).saturating_mul(4),
        }
    }
}

/// One channel of a decoded image: the alpha channel if it has one,
/// otherwise its grey value (see [`decode_alpha_image`]).
#[derive(Clone, Debug, PartialEq)]
pub struct AlphaImage {
    /// Width in pixels (at least 1).
    pub width: u32,
    /// Height in pixels (at least 1).
    pub height: u32,
    /// `width * height` texels, row-major, row 0 the image's top row.
    pub texels: AlphaTexels,
}

impl AlphaImage {
    /// The image as a texture the baker reads, over the texels as they are
    /// (no copy, no conversion). Fails only if `texels` does not hold
    /// `width * height` values (the readers never return such an image) or
    /// the image has `2^32` texels or more.
    ///
    /// ```
    /// use micromap_index::bake::{AlphaTexture, Baker, Cutoff, Sampler};
    /// use micromap_index_assets::{AlphaImage, AlphaTexels};
    /// let image = AlphaImage { width: 2, height: 1, texels: AlphaTexels::Unorm16(vec![0, 65535]) };
    /// let texture = image.texture().unwrap();
    /// assert_eq!((texture.alpha(0, 0), texture.alpha(1, 0)), (0.0, 1.0));
    /// let baker = Baker::new(&texture, Sampler::default(), Cutoff::default()).unwrap();
    /// assert_eq!(baker.size(), (2, 1));
    /// ```
    pub fn texture(&self) -> Result<ImageTexture<'_>, TextureError> {
        Ok(match &self.texels {
            AlphaTexels::Unorm8(t) => {
                ImageTexture::Unorm8(Unorm8Texture::new(self.width, self.height, t)?)
            }
            AlphaTexels::Unorm16(t) => {
                ImageTexture::Unorm16(Unorm16Texture::new(self.width, self.height, t)?)
            }
            AlphaTexels::Float(t) => {
                ImageTexture::Float(F32Texture::new(self.width, self.height, t)?)
            }
        })
    }

    /// The texel in column `x`, row `y` (row 0 at the top) as a binary32
    /// value (see [`AlphaTexels::get`]); `None` outside the image.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> Option<f32> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = u64::from(y) * u64::from(self.width) + u64::from(x);
        self.texels.get(usize::try_from(i).ok()?)
    }
}

/// An [`AlphaImage`] viewed as the baker's texture ([`AlphaImage::texture`]):
/// the library's [`SliceTexture`](micromap_index::bake::SliceTexture) over
/// the image's own texels, whichever their type.
#[derive(Clone, Copy, Debug)]
pub enum ImageTexture<'a> {
    /// 8-bit texels.
    Unorm8(Unorm8Texture<'a>),
    /// 16-bit texels.
    Unorm16(Unorm16Texture<'a>),
    /// `f32` texels.
    Float(F32Texture<'a>),
}

impl AlphaTexture for ImageTexture<'_> {
    fn width(&self) -> u32 {
        match self {
            ImageTexture::Unorm8(t) => t.width(),
            ImageTexture::Unorm16(t) => t.width(),
            ImageTexture::Float(t) => t.width(),
        }
    }
    fn height(&self) -> u32 {
        match self {
            ImageTexture::Unorm8(t) => t.height(),
            ImageTexture::Unorm16(t) => t.height(),
            ImageTexture::Float(t) => t.height(),
        }
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        match self {
            ImageTexture::Unorm8(t) => t.alpha(x, y),
            ImageTexture::Unorm16(t) => t.alpha(x, y),
            ImageTexture::Float(t) => t.alpha(x, y),
        }
    }
    fn is_opaque(&self, x: u32, y: u32, cutoff: &Cutoff) -> bool {
        match self {
            ImageTexture::Unorm8(t) => t.is_opaque(x, y, cutoff),
            ImageTexture::Unorm16(t) => t.is_opaque(x, y, cutoff),
            ImageTexture::Float(t) => t.is_opaque(x, y, cutoff),
        }
    }
    // The slice textures' row loop: without it the bake's texel
    // classification asks `is_opaque` (through this match) per texel.
    fn extend_opaque_row(&self, y: u32, cutoff: &Cutoff, out: &mut Vec<u8>) {
        match self {
            ImageTexture::Unorm8(t) => t.extend_opaque_row(y, cutoff, out),
            ImageTexture::Unorm16(t) => t.extend_opaque_row(y, cutoff, out),
            ImageTexture::Float(t) => t.extend_opaque_row(y, cutoff, out),
        }
    }
}

/// Bounds on what a reader may decode or hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Most pixels (`width * height`) of one image, checked from its header
    /// before any pixel is allocated.
    pub max_pixels: u64,
    /// Most bytes a reader holds: for an image its decoding buffers and
    /// texels; for a glTF everything it loads and builds together (buffers,
    /// decoded images, UV and triangle arrays), and every file it reads.
    pub max_bytes: u64,
}

impl Default for Limits {
    /// `2^26` pixels (an 8192 x 8192 image) and 1 GiB.
    fn default() -> Self {
        Limits {
            max_pixels: 1 << 26,
            max_bytes: 1 << 30,
        }
    }
}

/// Why an asset could not be read. `Display` writes one line naming the
/// file, the part of it or the field at fault.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum AssetError {
    /// A file could not be read (`path` as given, `message` the system's).
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// The image bytes start with neither the PNG nor the JPEG signature.
    UnknownImageFormat {
        /// Up to the first 8 bytes.
        start: Vec<u8>,
    },
    /// The image decoder rejected the image (truncated, corrupt, ...).
    Image {
        /// PNG or JPEG.
        format: ImageFormat,
        /// The decoder's message.
        message: String,
    },
    /// The image decoded, but its pixel format is not supported (CMYK JPEG).
    UnsupportedImage {
        /// PNG or JPEG.
        format: ImageFormat,
        /// What is not supported.
        message: String,
    },
    /// A size is over a [`Limits`] bound.
    LimitExceeded {
        /// What was measured ("image of 9000 x 9000 pixels", ...).
        what: String,
        /// Its size, in the unit of the limit (pixels or bytes).
        size: u64,
        /// The bound it broke.
        limit: u64,
    },
    /// The bytes are not JSON text of the expected top-level shape (with
    /// `serde_json`'s line and column).
    Json {
        /// `serde_json`'s message.
        message: String,
    },
    /// A `TRIS.json` triangle is malformed.
    Triangles {
        /// The index of the triangle in `"triangles"`, if the fault is in one.
        triangle: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// The GLB container is malformed (header, chunk lengths).
    Glb {
        /// What is wrong.
        message: String,
    },
    /// A glTF field is missing, of the wrong type, out of range, or
    /// inconsistent with the data it describes.
    Gltf {
        /// The field as a JSON path, e.g. `accessors[3].count`.
        field: String,
        /// What is wrong.
        message: String,
    },
    /// A URI could not be decoded or resolved.
    Uri {
        /// The URI as written in the glTF (shortened if long).
        uri: String,
        /// What is wrong.
        message: String,
    },
    /// An error inside a named file or part of an asset.
    In {
        /// The file or part, e.g. `cards.gltf` or `images[1] ("chain.png")`.
        context: String,
        /// The error inside it.
        source: Box<AssetError>,
    },
}

impl AssetError {
    /// This error inside `context` (a file name or a part of an asset).
    #[must_use]
    pub fn within(self, context: impl Into<String>) -> AssetError {
        AssetError::In {
            context: context.into(),
            source: Box::new(self),
        }
    }

    /// The innermost error, below every [`AssetError::In`].
    #[must_use]
    pub fn root(&self) -> &AssetError {
        match self {
            AssetError::In { source, .. } => source.root(),
            other => other,
        }
    }

    pub(crate) fn gltf(field: impl Into<String>, message: impl Into<String>) -> AssetError {
        AssetError::Gltf {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for AssetError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AssetError::Io { path, message } => {
                write!(f, "cannot read {}: {}", line(path), line(message))
            }
            AssetError::UnknownImageFormat { start } => {
                write!(f, "not a PNG or JPEG image (starts with")?;
                if start.is_empty() {
                    write!(f, " nothing: empty")?;
                }
                for byte in start {
                    write!(f, " {byte:02x}")?;
                }
                write!(f, ")")
            }
            AssetError::Image { format, message } => {
                write!(f, "{format} image: {}", line(message))
            }
            AssetError::UnsupportedImage { format, message } => {
                write!(f, "{format} image not supported: {}", line(message))
            }
            AssetError::LimitExceeded { what, size, limit } => {
                write!(f, "{}: {size} is over the limit of {limit}", line(what))
            }
            AssetError::Json { message } => write!(f, "invalid JSON: {}", line(message)),
            AssetError::Triangles {
                triangle: Some(i),
                message,
            } => write!(f, "triangle {i}: {}", line(message)),
            AssetError::Triangles {
                triangle: None,
                message,
            } => write!(f, "triangles: {}", line(message)),
            AssetError::Glb { message } => write!(f, "GLB container: {}", line(message)),
            AssetError::Gltf { field, message } => {
                write!(f, "{}: {}", line(field), line(message))
            }
            AssetError::Uri { uri, message } => write!(f, "URI {uri:?}: {}", line(message)),
            AssetError::In { context, source } => write!(f, "{}: {source}", line(context)),
        }
    }
}

/// `text` with control characters (line breaks included) escaped, so that
/// every message stays on one line.
fn line(text: &str) -> std::borrow::Cow<'_, str> {
    if text.chars().any(char::is_control) {
        text.chars()
            .map(|c| {
                if c.is_control() {
                    c.escape_default().to_string()
                } else {
                    c.to_string()
                }
            })
            .collect::<String>()
            .into()
    } else {
        text.into()
    }
}

impl std::error::Error for AssetError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            AssetError::In { source, .. } => Some(source.as_ref()),
            _ => None,
        }
    }
}

/// `Err(LimitExceeded)` unless `size <= limit`.
fn check_limit(what: impl FnOnce() -> String, size: u64, limit: u64) -> Result<(), AssetError> {
    if size <= limit {
        Ok(())
    } else {
        Err(AssetError::LimitExceeded {
            what: what(),
            size,
            limit,
        })
    }
}

/// Reads a JSON number's text as binary32 with one rounding (Rust's
/// correctly rounded `f32` parser). `None` unless `text` is a JSON number:
/// an optional `-`, digits, an optional fraction and exponent. Values past
/// the binary32 range give `±inf`, tiny ones `±0` or a subnormal.
fn json_number_f32(text: &str) -> Option<f32> {
    let text = text.trim_matches(|c: char| c == ' ' || c == '\t' || c == '\n' || c == '\r');
    let digits = text.strip_prefix('-').unwrap_or(text);
    // A JSON number starts with a digit after its sign; this also rules out
    // what Rust's parser accepts beyond JSON ("inf", "NaN", "+1", ".5").
    if !digits.starts_with(|c: char| c.is_ascii_digit())
        || !digits
            .bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'e' | b'E' | b'+' | b'-'))
    {
        return None;
    }
    text.parse::<f32>().ok()
}
