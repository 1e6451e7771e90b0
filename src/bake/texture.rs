//! Alpha textures, the sampler model and the alpha cutoff.

use crate::names::named_enum;
use alloc::vec::Vec;
use core::fmt;

/// An alpha texture the baker reads: `width x height` texels, row `y = 0`
/// at `v = 0` (the top row of an image, as in Vulkan and glTF).
///
/// Implement it to bake from your own texel storage. [`alpha`](Self::alpha)
/// must be exact: the baker compares it with the cutoff without rounding
/// (see [`Cutoff`]); `f64` holds every `u8`, `u16`, `f16` and `f32` texel
/// value, and the unorm quotients `c / 255` and `c / 65535` compare with any
/// binary32 cutoff as the exact quotients do (their distance from any
/// binary32 value other than 0 and 1 is far above `f64`'s rounding error).
pub trait AlphaTexture {
    /// Texels per row; must be at least 1.
    fn width(&self) -> u32;
    /// Rows; must be at least 1.
    fn height(&self) -> u32;
    /// The alpha of texel `(x, y)`, `x < width`, `y < height`.
    fn alpha(&self, x: u32, y: u32) -> f64;

    /// Whether texel `(x, y)` passes `cutoff`: by default
    /// `cutoff.is_opaque(self.alpha(x, y))`. An implementation may answer
    /// faster (the bake reads every texel once through this), never
    /// differently.
    fn is_opaque(&self, x: u32, y: u32, cutoff: &Cutoff) -> bool {
        cutoff.is_opaque(self.alpha(x, y))
    }

    /// Appends row `y`'s classes to `out`, one byte per texel, `x = 0`
    /// first: 1 where [`is_opaque`](Self::is_opaque) is true, else 0. By
    /// default it asks `is_opaque` texel by texel; an implementation may
    /// answer faster (the bake classifies the whole texture through this,
    /// one call per row), never differently.
    ///
    /// ```
    /// use micromap_index::bake::{AlphaTexture, Cutoff, Unorm8Texture};
    /// let texels = [0u8, 255, 128, 127, 1, 200];
    /// let texture = Unorm8Texture::new(3, 2, &texels).unwrap();
    /// let mut row = Vec::new();
    /// texture.extend_opaque_row(1, &Cutoff::default(), &mut row);
    /// assert_eq!(row, [0, 0, 1]); // 127 and 1 are below 0.5, 200 is not
    /// ```
    fn extend_opaque_row(&self, y: u32, cutoff: &Cutoff, out: &mut Vec<u8>) {
        out.extend((0..self.width()).map(|x| u8::from(self.is_opaque(x, y, cutoff))));
    }
}

/// Why a texture view or a sampler was refused.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum TextureError {
    /// Width or height is zero.
    Empty,
    /// `texels.len()` is not `width * height`, or an
    /// [`AlphaTexture::extend_opaque_row`] gave `got` bytes for a row of
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

    /// Whether the texel passes `cutoff`: by default
    /// `cutoff.is_opaque(self.alpha())`; an implementation may answer
    /// faster, never differently.
    fn is_opaque(self, cutoff: &Cutoff) -> bool {
        cutoff.is_opaque(self.alpha())
    }
}

impl Texel for u8 {
    /// Unorm: `c / 255`.
    fn alpha(self) -> f64 {
        f64::from(self) / 255.0
    }

    /// One integer comparison with the first code that passes, which the
    /// cutoff finds once (`c / 255` rounded grows with `c`), instead of a
    /// division per texel.
    fn is_opaque(self, cutoff: &Cutoff) -> bool {
        u16::from(self) >= cutoff.first_opaque_unorm8
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
    fn is_opaque(&self, x: u32, y: u32, cutoff: &Cutoff) -> bool {
        self.texels[y as usize * self.width as usize + x as usize].is_opaque(cutoff)
    }
    /// One loop over the row's slice, specialised for `T` (no per-texel
    /// indexing or dynamic call: the compiler vectorises it for `u8`).
    fn extend_opaque_row(&self, y: u32, cutoff: &Cutoff, out: &mut Vec<u8>) {
        let width = self.width as usize;
        let row = &self.texels[y as usize * width..][..width];
        out.extend(row.iter().map(|&texel| u8::from(texel.is_opaque(cutoff))));
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
    /// The smallest 8-bit unorm code `c` whose `c / 255` passes (256 if
    /// none): a function of the two fields above.
    first_opaque_unorm8: u16,
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
        let mut cutoff = Cutoff {
            alpha,
            comparison,
            first_opaque_unorm8: 0,
        };
        // Passing is monotone in the code: binary search for the first.
        let (mut low, mut high) = (0u16, 256u16);
        while low < high {
            let mid = (low + high) / 2;
            if cutoff.is_opaque(f64::from(mid) / 255.0) {
                high = mid;
            } else {
                low = mid + 1;
            }
        }
        cutoff.first_opaque_unorm8 = low;
        cutoff
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

    /// The 8-bit shortcut answers like the alpha it stands for: every code
    /// against cutoffs on, just below and just above every `c / 255` (as
    /// binary32), the ends, the infinities and signed zeros, both
    /// comparisons.
    #[test]
    fn unorm8_cutoff_shortcut_equals_the_alpha_test() {
        let mut alphas = vec![
            0.0f32,
            -0.0,
            0.5,
            1.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-30,
            -1e-30,
        ];
        for c in 0..=255u8 {
            let a = (f64::from(c) / 255.0) as f32;
            let bits = a.to_bits();
            alphas.extend([
                a,
                f32::from_bits(bits + 1),
                f32::from_bits(bits.saturating_sub(1)),
            ]);
        }
        for alpha in alphas {
            for comparison in [Comparison::AtLeast, Comparison::Above] {
                let cutoff = Cutoff::new(alpha, comparison).unwrap();
                for c in 0..=255u8 {
                    assert_eq!(
                        Texel::is_opaque(c, &cutoff),
                        cutoff.is_opaque(c.alpha()),
                        "code {c}, cutoff {alpha:e} ({:#010x}) {comparison:?}",
                        alpha.to_bits()
                    );
                }
            }
        }
        assert_eq!(
            Cutoff::default(),
            Cutoff::new(0.5, Comparison::AtLeast).unwrap()
        );
    }

    /// The slice textures' row loop gives, byte for byte, what the
    /// trait's per-texel default gives (every row of textures of each
    /// texel type, odd widths, codes on both sides of the cutoffs).
    #[test]
    fn slice_rows_equal_the_per_texel_default() {
        /// Only the required methods: `extend_opaque_row` is the default.
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
            for alpha in [0.0f32, 0.25, 0.5, 0.75, 1.0] {
                for comparison in [Comparison::AtLeast, Comparison::Above] {
                    let cutoff = Cutoff::new(alpha, comparison).unwrap();
                    for y in 0..height {
                        let (mut a, mut b) = (vec![9u8], vec![9u8]);
                        fast.extend_opaque_row(y, &cutoff, &mut a);
                        slow.extend_opaque_row(y, &cutoff, &mut b);
                        assert_eq!(
                            a, b,
                            "row {y} of {width} wide, cutoff {alpha} {comparison:?}"
                        );
                        assert_eq!(a.len(), width as usize + 1);
                    }
                }
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
