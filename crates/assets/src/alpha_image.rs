//! The decoded alpha channel of an image ([`AlphaImage`], its texels
//! [`AlphaTexels`]) and its view as the baker's texture ([`ImageTexture`]).

use micromap_index::bake::{AlphaTexture, F32Texture, TextureError, Unorm16Texture, Unorm8Texture};

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
/// otherwise its grey value (see [`decode_alpha_image`](crate::decode_alpha_image)).
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
    fn gpu_alpha(&self, x: u32, y: u32) -> (f32, f32) {
        match self {
            ImageTexture::Unorm8(t) => t.gpu_alpha(x, y),
            ImageTexture::Unorm16(t) => t.gpu_alpha(x, y),
            ImageTexture::Float(t) => t.gpu_alpha(x, y),
        }
    }
    // The slice textures' row loop: without it the bake's texel
    // classification asks `gpu_alpha` (through this match) per texel.
    fn extend_gpu_alpha_row(&self, y: u32, low: &mut Vec<f32>, high: &mut Vec<f32>) {
        match self {
            ImageTexture::Unorm8(t) => t.extend_gpu_alpha_row(y, low, high),
            ImageTexture::Unorm16(t) => t.extend_gpu_alpha_row(y, low, high),
            ImageTexture::Float(t) => t.extend_gpu_alpha_row(y, low, high),
        }
    }
}
