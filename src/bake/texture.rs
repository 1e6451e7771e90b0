//! Alpha textures, the sampler model and the alpha cutoff.

use crate::names::named_enum;
use alloc::vec::Vec;
use core::fmt;

/// An alpha texture the baker reads: `width x height` texels, row `y = 0`
/// at `v = 0` (the top row of an image, as in Vulkan and glTF).
///
/// Implement it to bake from your own texel storage. [`alpha`](Self::alpha)
/// is the texel's exact value (`f64` holds every `u8`, `u16`, `f16` and
/// `f32` texel value, and the unorm quotients `c / 255` and `c / 65535`
/// closely enough: see [`faithful_f32`]); [`gpu_alpha`](Self::gpu_alpha) is
/// what a GPU's texture unit may read for it, as binary32.
pub trait AlphaTexture {
    /// Texels per row; must be at least 1.
    fn width(&self) -> u32;
    /// Rows; must be at least 1.
    fn height(&self) -> u32;
    /// The alpha of texel `(x, y)`, `x < width`, `y < height`.
    fn alpha(&self, x: u32, y: u32) -> f64;

    /// The lowest and highest binary32 value a texture unit may convert
    /// texel `(x, y)` to: by default the two binary32 neighbours of
    /// [`alpha`](Self::alpha) ([`faithful_f32`]: a conversion rounded either
    /// way; one value when it is exact). An implementation may answer
    /// faster, never with a narrower range.
    fn gpu_alpha(&self, x: u32, y: u32) -> (f32, f32) {
        faithful_f32(self.alpha(x, y))
    }

    /// Appends row `y`'s [`gpu_alpha`](Self::gpu_alpha) ranges, `x = 0`
    /// first, the lows to `low` and the highs to `high`. By default it asks
    /// `gpu_alpha` texel by texel; an implementation may answer faster (the
    /// bake reads the whole texture through this, one call per row), never
    /// differently.
    ///
    /// ```
    /// use micromap_index::bake::{AlphaTexture, Unorm8Texture};
    /// let texels = [0u8, 255, 51];
    /// let texture = Unorm8Texture::new(3, 1, &texels).unwrap();
    /// let (mut low, mut high) = (Vec::new(), Vec::new());
    /// texture.extend_gpu_alpha_row(0, &mut low, &mut high);
    /// assert_eq!((low[0], high[0], low[1], high[1]), (0.0, 0.0, 1.0, 1.0));
    /// // 51 / 255 = 0.2 is no binary32 value: either neighbour may be read.
    /// assert!(low[2] < high[2] && f64::from(low[2]) < 0.2 && f64::from(high[2]) > 0.2);
    /// assert_eq!(high[2], 0.2f32);
    /// ```
    fn extend_gpu_alpha_row(&self, y: u32, low: &mut Vec<f32>, high: &mut Vec<f32>) {
        for x in 0..self.width() {
            let (lo, hi) = self.gpu_alpha(x, y);
            low.push(lo);
            high.push(hi);
        }
    }
}

/// The binary32 values a faithful conversion of `value` can give: `value`
/// itself twice when it is a binary32 value, else the binary32 values just
/// below and above it (rounding either way). A NaN gives NaN twice; values
/// past binary32's range give the largest finite value and infinity.
///
/// ```
/// use micromap_index::bake::faithful_f32;
/// assert_eq!(faithful_f32(0.5), (0.5, 0.5));
/// let (lo, hi) = faithful_f32(0.2);
/// assert_eq!(hi, 0.2f32); // f32(0.2) lies above 0.2
/// assert_eq!(lo, f32::from_bits(0.2f32.to_bits() - 1));
/// ```
#[must_use]
pub fn faithful_f32(value: f64) -> (f32, f32) {
    let nearest = value as f32;
    let back = f64::from(nearest);
    if back == value || value.is_nan() {
        (nearest, nearest)
    } else if back > value {
        (next_toward_zero_or_down(nearest), nearest)
    } else {
        (nearest, next_up(nearest))
    }
}

/// The binary32 value just above `x` (finite `x`).
fn next_up(x: f32) -> f32 {
    if x.is_infinite() && x > 0.0 {
        return x;
    }
    let bits = x.to_bits();
    if x == 0.0 {
        f32::from_bits(1)
    } else if bits >> 31 == 0 {
        f32::from_bits(bits + 1)
    } else {
        f32::from_bits(bits - 1)
    }
}

/// The binary32 value just below `x`.
fn next_toward_zero_or_down(x: f32) -> f32 {
    -next_up(-x)
}

/// Why a texture view or a sampler was refused.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum TextureError {
    /// Width or height is zero.
    Empty,
    /// `texels.len()` is not `width * height`, or an
    /// [`AlphaTexture::extend_gpu_alpha_row`] gave `got` values for a row of
    /// `expected` texels.
    WrongLength {
        /// `width * height`.
        expected: u64,
        /// The slice's length.
        got: usize,
    },
    /// `width * height` is `2^32` or more: the classifier counts texels in
    /// `u32`.
    TooLarge {
        /// Texels per row.
        width: u32,
        /// Rows.
        height: u32,
    },
    /// The cutoff or the border alpha is NaN.
    NanThreshold,
    /// A texture-unit parameter is outside its range.
    TextureUnit(super::texture_unit::TextureUnitError),
    /// The baker's tables (`w h` class bytes and `2 (w + 1) (h + 1)` bytes
    /// of prefix sums) could not be allocated: over the caller's limit
    /// ([`Baker::new_within`](super::Baker::new_within)), past the address
    /// space, or refused by the allocator. Never an abort.
    AllocationFailed {
        /// The bytes the tables need (saturated at `u64::MAX`).
        bytes: u64,
        /// The limit they were held to (`u64::MAX`: none but the
        /// allocator's).
        limit: u64,
    },
}

impl fmt::Display for TextureError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TextureError::Empty => f.write_str("the texture has no texels"),
            TextureError::WrongLength { expected, got } => {
                write!(f, "expected {expected} texels, got {got}")
            }
            TextureError::TooLarge { width, height } => {
                write!(f, "a {width}x{height} texture has 2^32 texels or more")
            }
            TextureError::NanThreshold => f.write_str("the cutoff or the border alpha is NaN"),
            TextureError::TextureUnit(e) => e.fmt(f),
            TextureError::AllocationFailed { bytes, limit } => {
                if *limit == u64::MAX {
                    write!(f, "cannot allocate the baker's {bytes}-byte texel tables")
                } else {
                    write!(
                        f,
                        "the baker's texel tables need {bytes} bytes, over the limit of {limit} bytes"
                    )
                }
            }
        }
    }
}

impl core::error::Error for TextureError {}

fn check_dimensions(width: u32, height: u32, len: usize) -> Result<(), TextureError> {
    if width == 0 || height == 0 {
        return Err(TextureError::Empty);
    }
    let expected = u64::from(width) * u64::from(height);
    if expected >= 1 << 32 {
        return Err(TextureError::TooLarge { width, height });
    }
    if len as u64 != expected {
        return Err(TextureError::WrongLength { expected, got: len });
    }
    Ok(())
}

/// A texel type a [`SliceTexture`] can hold, with its alpha as the sampler
/// reads it.
pub trait Texel: Copy {
    /// The texel's alpha, exactly (see [`AlphaTexture`]).
    fn alpha(self) -> f64;

    /// The binary32 values a texture unit may convert it to (see
    /// [`AlphaTexture::gpu_alpha`]); by default [`faithful_f32`] of the
    /// alpha. An implementation may answer faster, never with a narrower
    /// range.
    fn gpu_alpha(self) -> (f32, f32) {
        faithful_f32(self.alpha())
    }
}

/// The faithful binary32 conversions of every `c / 255` (see
/// [`faithful_f32`]), as bits, computed once.
static UNORM8_GPU: [[u32; 2]; 256] = unorm8_table();

/// [`UNORM8_GPU`] by integer arithmetic (a `const fn`: no floating point
/// at compile time at the minimum Rust). For `0 < c < 255`, `c / 255` is
/// in `[2^e, 2^(e+1))` with `e = floor(log2(c / 255))`; its 24 significant
/// bits are `floor(c 2^(23 - e) / 255)`, and never exact (the binary
/// expansion of `c / 255` repeats `c`'s byte), so the value above has the
/// next significand. `faithful_f32` gives the same (a test checks all 256).
const fn unorm8_table() -> [[u32; 2]; 256] {
    let mut table = [[0u32; 2]; 256];
    table[255] = [0x3f80_0000, 0x3f80_0000];
    let mut c = 1u64;
    while c < 255 {
        // k = -e: the least with c 2^k >= 255 (then c 2^k < 510).
        let mut k = 1u64;
        while c << k < 255 {
            k += 1;
        }
        let significand = (c << (23 + k)) / 255;
        let bits = ((127 - k as u32) << 23) | (significand as u32 & 0x7f_ffff);
        table[c as usize] = [bits, bits + 1];
        c += 1;
    }
    table
}

impl Texel for u8 {
    /// Unorm: `c / 255`.
    fn alpha(self) -> f64 {
        f64::from(self) / 255.0
    }

    /// From a table of all 256 codes.
    fn gpu_alpha(self) -> (f32, f32) {
        let [lo, hi] = UNORM8_GPU[usize::from(self)];
        (f32::from_bits(lo), f32::from_bits(hi))
    }
}

impl Texel for u16 {
    /// Unorm: `c / 65535`.
    fn alpha(self) -> f64 {
        f64::from(self) / 65535.0
    }
}

impl Texel for f32 {
    /// As is. A NaN texel passes no cutoff (every comparison with NaN is
    /// false), so it is transparent.
    fn alpha(self) -> f64 {
        f64::from(self)
    }

    /// Exact: the texel is binary32 already.
    fn gpu_alpha(self) -> (f32, f32) {
        (self, self)
    }
}

/// Alpha texels in a slice, row-major, of any [`Texel`] type.
///
/// ```
/// use micromap_index::bake::{AlphaTexture, F32Texture, Unorm8Texture};
/// let texels = [0u8, 255, 128, 64];
/// let texture = Unorm8Texture::new(2, 2, &texels).unwrap();
/// assert_eq!(texture.alpha(1, 0), 1.0);
/// assert!(Unorm8Texture::new(3, 2, &texels).is_err());
/// let floats = [0.25f32, 1.0];
/// assert_eq!(F32Texture::new(2, 1, &floats).unwrap().alpha(0, 0), 0.25);
/// ```
#[derive(Clone, Copy, Debug)]
pub struct SliceTexture<'a, T> {
    width: u32,
    height: u32,
    texels: &'a [T],
}

/// 8-bit unorm alpha texels (`alpha = c / 255`).
pub type Unorm8Texture<'a> = SliceTexture<'a, u8>;
/// 16-bit unorm alpha texels (`alpha = c / 65535`).
pub type Unorm16Texture<'a> = SliceTexture<'a, u16>;
/// `f32` alpha texels.
pub type F32Texture<'a> = SliceTexture<'a, f32>;

impl<'a, T: Texel> SliceTexture<'a, T> {
    /// A view of `texels` as `width x height`, row-major.
    pub fn new(width: u32, height: u32, texels: &'a [T]) -> Result<Self, TextureError> {
        check_dimensions(width, height, texels.len())?;
        Ok(SliceTexture {
            width,
            height,
            texels,
        })
    }
}

impl<T: Texel> AlphaTexture for SliceTexture<'_, T> {
    fn width(&self) -> u32 {
        self.width
    }
    fn height(&self) -> u32 {
        self.height
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        self.texels[y as usize * self.width as usize + x as usize].alpha()
    }
    fn gpu_alpha(&self, x: u32, y: u32) -> (f32, f32) {
        self.texels[y as usize * self.width as usize + x as usize].gpu_alpha()
    }
    /// One loop over the row's slice, specialised for `T` (no per-texel
    /// indexing or dynamic call).
    fn extend_gpu_alpha_row(&self, y: u32, low: &mut Vec<f32>, high: &mut Vec<f32>) {
        let width = self.width as usize;
        let row = &self.texels[y as usize * width..][..width];
        for &texel in row {
            let (lo, hi) = texel.gpu_alpha();
            low.push(lo);
            high.push(hi);
        }
    }
}

/// Texture filtering, as Vulkan's `VkFilter`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Filter {
    /// The texel containing the sample point: `floor(u * width)`.
    #[default]
    Nearest,
    /// A weighted mix of the 2x2 texels around `u * width - 1/2`.
    Linear,
}

/// What a texel coordinate outside `0..size` reads, per axis, as Vulkan's
/// `VkSamplerAddressMode` (the "wrapping operation" on integer texel
/// coordinates, applied after `floor`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AddressMode {
    /// `i mod size`.
    #[default]
    Repeat,
    /// `(size - 1) - mirror((i mod 2 size) - size)`, `mirror(n) = n` for
    /// `n >= 0`, else `-(1 + n)`.
    MirroredRepeat,
    /// `clamp(i, 0, size - 1)`.
    ClampToEdge,
    /// The border alpha ([`Sampler::border_alpha`]) outside `0..size`.
    ClampToBorder,
    /// `clamp(mirror(i), 0, size - 1)`.
    MirrorClampToEdge,
}

named_enum!(
    Filter,
    "filter",
    "nearest or linear",
    [(Nearest, "nearest"), (Linear, "linear")]
);

named_enum!(
    AddressMode,
    "address mode",
    "repeat, mirrored-repeat, clamp-to-edge, clamp-to-border or mirror-clamp-to-edge",
    [
        (Repeat, "repeat"),
        (MirroredRepeat, "mirrored-repeat"),
        (ClampToEdge, "clamp-to-edge"),
        (ClampToBorder, "clamp-to-border"),
        (MirrorClampToEdge, "mirror-clamp-to-edge"),
    ]
);

named_enum!(
    Comparison,
    "comparison",
    "at-least or above",
    [(AtLeast, "at-least"), (Above, "above")]
);

impl AddressMode {
    /// Every mode.
    pub const ALL: [AddressMode; 5] = [
        AddressMode::Repeat,
        AddressMode::MirroredRepeat,
        AddressMode::ClampToEdge,
        AddressMode::ClampToBorder,
        AddressMode::MirrorClampToEdge,
    ];

    /// The texel `i` reads in `0..size`, or `None` for the border. Total:
    /// every `i64` and every `size >= 1`.
    ///
    /// ```
    /// use micromap_index::bake::AddressMode;
    /// assert_eq!(AddressMode::Repeat.wrap(-1, 4), Some(3));
    /// assert_eq!(AddressMode::MirroredRepeat.wrap(4, 4), Some(3));
    /// assert_eq!(AddressMode::MirroredRepeat.wrap(-1, 4), Some(0));
    /// assert_eq!(AddressMode::ClampToEdge.wrap(9, 4), Some(3));
    /// assert_eq!(AddressMode::ClampToBorder.wrap(4, 4), None);
    /// assert_eq!(AddressMode::MirrorClampToEdge.wrap(-3, 4), Some(2));
    /// assert_eq!(AddressMode::MirrorClampToEdge.wrap(-9, 4), Some(3));
    /// ```
    #[must_use]
    pub fn wrap(self, i: i64, size: u32) -> Option<u32> {
        self.wrap_wide(i128::from(i), size)
    }

    /// [`wrap`](Self::wrap) for any `i128` coordinate: the one place the
    /// baker's wrapping formulas are written.
    pub(crate) fn wrap_wide(self, i: i128, size: u32) -> Option<u32> {
        let n = i128::from(size.max(1));
        let mirror = |k: i128| if k >= 0 { k } else { -(1 + k) };
        let t = match self {
            AddressMode::Repeat => i.rem_euclid(n),
            AddressMode::MirroredRepeat => (n - 1) - mirror(i.rem_euclid(2 * n) - n),
            AddressMode::ClampToEdge => i.clamp(0, n - 1),
            AddressMode::ClampToBorder => {
                if (0..n).contains(&i) {
                    i
                } else {
                    return None;
                }
            }
            AddressMode::MirrorClampToEdge => mirror(i).clamp(0, n - 1),
        };
        Some(t as u32)
    }
}

/// The sampler the runtime uses with the texture: filter, address mode per
/// axis, border alpha. [`Default`] is nearest with repeat on both axes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sampler {
    /// Nearest or linear.
    pub filter: Filter,
    /// Address mode along `u` (texel columns).
    pub address_u: AddressMode,
    /// Address mode along `v` (texel rows).
    pub address_v: AddressMode,
    /// The alpha [`AddressMode::ClampToBorder`] reads (Vulkan's border
    /// colours have alpha 0 or 1; any value is allowed here).
    pub border_alpha: f32,
}

/// Which side of the cutoff is opaque.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Comparison {
    /// Opaque when `alpha >= cutoff`: glTF's `alphaMode: MASK`.
    #[default]
    AtLeast,
    /// Opaque when `alpha > cutoff`: the OMM SDK's convention.
    Above,
}

/// The alpha test: a texel is opaque when its alpha passes.
///
/// ```
/// use micromap_index::bake::{Comparison, Cutoff};
/// let gltf = Cutoff::new(0.5, Comparison::AtLeast).unwrap();
/// assert!(gltf.is_opaque(0.5));
/// let sdk = Cutoff::new(0.5, Comparison::Above).unwrap();
/// assert!(!sdk.is_opaque(0.5));
/// assert!(!gltf.is_opaque(f64::NAN));
/// assert!(Cutoff::new(f32::NAN, Comparison::AtLeast).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cutoff {
    alpha: f32,
    comparison: Comparison,
}

impl Default for Cutoff {
    /// glTF's default: opaque when `alpha >= 0.5`.
    fn default() -> Self {
        Cutoff::with(0.5, Comparison::AtLeast)
    }
}

impl Cutoff {
    /// A cutoff at `alpha` (any non-NaN value; `-inf` and `+inf` make every
    /// texel opaque or transparent).
    pub fn new(alpha: f32, comparison: Comparison) -> Result<Cutoff, TextureError> {
        if alpha.is_nan() {
            return Err(TextureError::NanThreshold);
        }
        Ok(Cutoff::with(alpha, comparison))
    }

    /// The cutoff for a non-NaN `alpha`.
    fn with(alpha: f32, comparison: Comparison) -> Cutoff {
        Cutoff { alpha, comparison }
    }

    /// The cutoff value.
    #[must_use]
    pub fn alpha(&self) -> f32 {
        self.alpha
    }

    /// The comparison.
    #[must_use]
    pub fn comparison(&self) -> Comparison {
        self.comparison
    }

    /// Does `alpha` pass (is the texel opaque)? Exact: one comparison of
    /// `alpha` with the binary32 cutoff; NaN never passes.
    #[must_use]
    pub fn is_opaque(&self, alpha: f64) -> bool {
        match self.comparison {
            Comparison::AtLeast => alpha >= f64::from(self.alpha),
            Comparison::Above => alpha > f64::from(self.alpha),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    /// The 8-bit table holds what [`faithful_f32`] gives for every code,
    /// and every pair brackets `c / 255` (the two neighbours when it is
    /// not a binary32 value, which it is only for 0 and 255).
    #[test]
    fn unorm8_table_is_the_faithful_conversion() {
        for c in 0..=255u8 {
            let exact = f64::from(c) / 255.0;
            let (lo, hi) = Texel::gpu_alpha(c);
            assert_eq!((lo, hi), faithful_f32(exact), "code {c}");
            assert!(f64::from(lo) <= exact && exact <= f64::from(hi), "code {c}");
            if c == 0 || c == 255 {
                assert_eq!(lo, hi);
            } else {
                assert_eq!(hi.to_bits(), lo.to_bits() + 1, "code {c}");
            }
        }
        for v in [0.0, -0.0, 1e-40, -0.3, 1e39, f64::INFINITY] {
            let (lo, hi) = faithful_f32(v);
            assert!(f64::from(lo) <= v && v <= f64::from(hi), "{v}");
        }
        assert!(faithful_f32(f64::NAN).0.is_nan());
    }

    /// The slice textures' row loop gives, bit for bit, what the
    /// trait's per-texel default gives (every row of textures of each
    /// texel type, odd widths, codes on both sides of the cutoffs).
    #[test]
    fn slice_rows_equal_the_per_texel_default() {
        /// Only the required methods: `extend_gpu_alpha_row` is the default.
        struct PerTexel<'a, T>(SliceTexture<'a, T>);
        impl<T: Texel> AlphaTexture for PerTexel<'_, T> {
            fn width(&self) -> u32 {
                self.0.width()
            }
            fn height(&self) -> u32 {
                self.0.height()
            }
            fn alpha(&self, x: u32, y: u32) -> f64 {
                self.0.alpha(x, y)
            }
        }
        fn check<T: Texel + core::fmt::Debug>(width: u32, texels: &[T]) {
            let height = texels.len() as u32 / width;
            let fast = SliceTexture::new(width, height, texels).unwrap();
            let slow = PerTexel(fast);
            for y in 0..height {
                let (mut a, mut b) = ((vec![9.0f32], vec![9.0f32]), (vec![9.0f32], vec![9.0f32]));
                fast.extend_gpu_alpha_row(y, &mut a.0, &mut a.1);
                slow.extend_gpu_alpha_row(y, &mut b.0, &mut b.1);
                let bits = |v: &[f32]| {
                    v.iter()
                        .map(|x| x.to_bits())
                        .collect::<alloc::vec::Vec<_>>()
                };
                assert_eq!(bits(&a.0), bits(&b.0), "row {y} of {width} wide");
                assert_eq!(bits(&a.1), bits(&b.1), "row {y} of {width} wide");
                assert_eq!(a.0.len(), width as usize + 1);
            }
        }
        let codes: alloc::vec::Vec<u8> = (0..=255u8).chain(0..=255).take(37 * 13).collect();
        check(37, &codes);
        let wide: alloc::vec::Vec<u16> = (0..7 * 11).map(|c| (c * 853) as u16).collect();
        check(7, &wide);
        let floats: alloc::vec::Vec<f32> = (0..5 * 9)
            .map(|c| c as f32 / 40.0 - 0.05)
            .chain([f32::NAN, -0.0])
            .collect();
        check(47, &floats);
    }
}
