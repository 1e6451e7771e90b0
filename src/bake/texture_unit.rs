//! The texture unit as the baker models it (under
//! [`Model::GpuBinary32`](crate::bake::Model::GpuBinary32)):
//! how a hit's texel coordinate is snapped, how precise the shader's
//! interpolation is, how a linear filter mixes its texels, and what the
//! alpha test compares. Every parameter is one a conforming Vulkan or
//! Direct3D implementation may choose; `docs/bake.md` ("The texture unit")
//! states each one with its source, and the bounds the baker derives.
//!
//! - **Sub-texel snapping** ([`TextureUnit::subtexel_bits`], `k`): the
//!   texel coordinate a filter uses is snapped to a multiple of `2^-k`
//!   texels (Vulkan's `subTexelPrecisionBits`, at least 4, 8 on common
//!   GPUs; Direct3D requires 8). Whether it rounds or truncates is not
//!   public, so the snapped coordinate is any point within `2^-k` of the
//!   computed one: the baker dilates each micro-triangle by that much more.
//! - **Interpolation** ([`Interpolation`]): the shader's texture
//!   coordinate in binary32 (the default) or in 16-bit floats
//!   (`mediump`, `RelaxedPrecision`, `min16float`), whose rounding the
//!   dilation then covers.
//! - **Linear filtering** ([`LinearRule`]): by default by value: the
//!   filtered alpha is the bilinear mix of the 2x2 texels with the
//!   snapped coordinate's weights, within [`TextureUnit::filter_error`] of
//!   the exact mix (the filter's own arithmetic); a micro-triangle is known
//!   when that value passes (fails) the cutoff everywhere on it. The
//!   footprint rule of earlier versions (every texel of the 2x2 footprint
//!   counts as read, whatever its weight) stays available.
//! - **The alpha test** in binary32: an 8- or 16-bit UNORM texel becomes
//!   `c / (2^b - 1)` as binary32 rounded either way (a faithful
//!   conversion, not necessarily the nearest), then `alpha >= cutoff` (or
//!   `>`) against the binary32 cutoff. A texel whose two roundings fall on
//!   both sides of the cutoff is neither surely opaque nor surely
//!   transparent.

use crate::names::named_enum;

/// The precision of the shader's texture-coordinate interpolation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Interpolation {
    /// Binary32 (`highp`, the default).
    #[default]
    F32,
    /// 16-bit floats (`mediump`, `RelaxedPrecision`, `min16float`): every
    /// product and sum of the interpolation rounded to 11 significant bits.
    /// Coordinates of magnitude `2^15` or more are out of its range: such a
    /// triangle is unknown ([`TriangleStatus::OutOfExactRange`](super::TriangleStatus::OutOfExactRange)).
    F16,
}

named_enum!(
    Interpolation,
    "interpolation",
    "f32 or f16",
    [(F32, "f32"), (F16, "f16")]
);

/// How a linear filter's result is judged against the cutoff.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum LinearRule {
    /// By the filtered value (the default): the bilinear mix at every point
    /// the hit can read, within the filter's error.
    #[default]
    Value,
    /// By footprint: a point reads every texel of its 2x2 footprint,
    /// whatever the weights (the rule of earlier versions; looser).
    Footprint,
}

named_enum!(
    LinearRule,
    "linear rule",
    "value or footprint",
    [(Value, "value"), (Footprint, "footprint")]
);

/// The texture unit a bake holds for: its parameters, each one a conforming
/// Vulkan or Direct3D implementation may choose (`docs/bake.md`, "The
/// texture unit", gives each with its source and the bounds derived).
///
/// ```
/// use micromap_index::bake::{Interpolation, LinearRule, TextureUnit};
/// let unit = TextureUnit::default();
/// assert_eq!(unit.subtexel_bits, 8);
/// assert_eq!(unit.interpolation, Interpolation::F32);
/// assert_eq!(unit.linear, LinearRule::Value);
/// assert_eq!(unit.snap_radius(), 1.0 / 256.0);
/// assert_eq!(unit.filter_error, 1.0 / 128.0);
/// assert!(unit.with_subtexel_bits(3).check().is_err());
/// ```
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub struct TextureUnit {
    /// `k`: texel coordinates snap to multiples of `2^-k` texels (4..=16;
    /// default 8, Vulkan's minimum is 4).
    pub subtexel_bits: u32,
    /// The shader's interpolation precision (default binary32).
    pub interpolation: Interpolation,
    /// The largest difference between a linear filter's result and the
    /// exact bilinear mix of its (converted) texels, in alpha units
    /// (default `2^-7`: twice an 8-bit result's unit, since a texture unit
    /// may filter an 8-bit texture to an 8-bit result, as Mesa's lavapipe
    /// does, `docs/render.md`). A finite value in `[0, 1]`.
    pub filter_error: f32,
    /// How a linear filter is judged (default by value).
    pub linear: LinearRule,
}

/// Equal when every parameter is, the filter error bit for bit (so that
/// equality is an equivalence, NaN included).
impl PartialEq for TextureUnit {
    fn eq(&self, other: &Self) -> bool {
        self.subtexel_bits == other.subtexel_bits
            && self.interpolation == other.interpolation
            && self.filter_error.to_bits() == other.filter_error.to_bits()
            && self.linear == other.linear
    }
}

impl Eq for TextureUnit {}

impl Default for TextureUnit {
    fn default() -> Self {
        TextureUnit {
            subtexel_bits: 8,
            interpolation: Interpolation::F32,
            filter_error: 1.0 / 128.0,
            linear: LinearRule::Value,
        }
    }
}

/// A [`TextureUnit`] parameter outside its range.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum TextureUnitError {
    /// `subtexel_bits` outside `4..=16`.
    SubtexelBits(u32),
    /// `filter_error` not a finite number in `[0, 1]`.
    FilterError(f32),
}

impl core::fmt::Display for TextureUnitError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TextureUnitError::SubtexelBits(k) => write!(
                f,
                "sub-texel bits {k}: expected 4..=16 (Vulkan's minimum is 4, Direct3D's 8)"
            ),
            TextureUnitError::FilterError(e) => {
                write!(f, "filter error {e}: expected a number in [0, 1]")
            }
        }
    }
}

impl core::error::Error for TextureUnitError {}

impl TextureUnit {
    /// The same unit with `k` sub-texel bits.
    #[must_use]
    pub fn with_subtexel_bits(mut self, k: u32) -> TextureUnit {
        self.subtexel_bits = k;
        self
    }

    /// The same unit with another interpolation precision.
    #[must_use]
    pub fn with_interpolation(mut self, interpolation: Interpolation) -> TextureUnit {
        self.interpolation = interpolation;
        self
    }

    /// The same unit with another filter error.
    #[must_use]
    pub fn with_filter_error(mut self, error: f32) -> TextureUnit {
        self.filter_error = error;
        self
    }

    /// The same unit with another rule for linear filtering.
    #[must_use]
    pub fn with_linear_rule(mut self, linear: LinearRule) -> TextureUnit {
        self.linear = linear;
        self
    }

    /// The unit, if every parameter is in its range.
    pub fn check(self) -> Result<TextureUnit, TextureUnitError> {
        if !(4..=16).contains(&self.subtexel_bits) {
            return Err(TextureUnitError::SubtexelBits(self.subtexel_bits));
        }
        if !(0.0..=1.0).contains(&self.filter_error) {
            return Err(TextureUnitError::FilterError(self.filter_error));
        }
        Ok(self)
    }

    /// How far a snapped texel coordinate can be from the computed one, in
    /// texels: `2^-k` (rounding moves it at most half of that, truncation
    /// less than all of it; the bound holds for both).
    #[must_use]
    pub fn snap_radius(&self) -> f64 {
        let mut r = 1.0f64;
        for _ in 0..self.subtexel_bits.min(64) {
            r *= 0.5;
        }
        r
    }
}
