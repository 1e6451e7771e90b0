//! The alpha test as a GPU applies it ([`AlphaTest`]): the binary32
//! cutoff against a texel's converted value (nearest filtering) or against
//! the filtered value, which may differ from the exact bilinear mix by the
//! filter's error and an alpha factor's binary32 products (linear
//! filtering). Contract: every bound here widens toward "may pass" and
//! "may fail", never narrows, so a decision from it holds for every value
//! the texture unit of `docs/bake.md` ("The texture unit") may compare.

use super::texture::{Cutoff, Filter};
use super::texture_unit::{LinearRule, TextureUnit};

/// Relative widening for the factor's binary32 products under linear
/// filtering: the texels' values carry the factor already (each product
/// rounded, `2^-24` relative, which the mix carries), the GPU multiplies
/// the filtered value (one more rounding): `2^-22` of the magnitudes
/// involved covers both, with room for `f64`'s own.
const PRODUCT_ROUNDING: f64 = 1.0 / (1u64 << 22) as f64;

/// Absolute widening for products in binary32's subnormal range.
const SUBNORMAL: f64 = 1.0 / (1u64 << 62) as f64 / (1u64 << 62) as f64 / (1u64 << 24) as f64;

/// The alpha test as a GPU applies it to what the texture unit returns:
/// the binary32 cutoff compared with a texel's value (nearest filtering)
/// or with the filtered value, which lies within the filter's error of
/// the bilinear mix of its texels' values, then multiplied by a factor in
/// binary32 (linear filtering). The one place the baker and the verifier
/// turn values into decisions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct AlphaTest {
    pub(crate) cutoff: Cutoff,
    /// Linear filtering: the filter's error in the texture's alpha units
    /// ([`TextureUnit::filter_error`] times the factor the texture's
    /// values carry); `None` for nearest filtering.
    linear_slack: Option<f64>,
    /// Linear filtering judged by value ([`LinearRule::Value`]).
    pub(crate) by_value: bool,
}

impl AlphaTest {
    /// The test for `cutoff` under `filter` and `unit`, on a texture whose
    /// values are the texels' times `scale` (an alpha factor, at most 1 for
    /// vertex alpha bounds).
    pub(crate) fn new(cutoff: Cutoff, filter: Filter, unit: &TextureUnit, scale: f64) -> AlphaTest {
        let linear = filter == Filter::Linear;
        let abs = |x: f64| f64::from_bits(x.to_bits() & !(1 << 63));
        AlphaTest {
            cutoff,
            linear_slack: linear.then(|| f64::from(unit.filter_error) * abs(scale)),
            by_value: linear && unit.linear == LinearRule::Value,
        }
    }

    /// The lowest value the GPU may compare when the values read mix to
    /// at least `v`: `v` itself under nearest filtering; under linear, less
    /// the filter's error and the factor's roundings (relative to the
    /// magnitudes `|v| + e`, not `|v - e|`, which may be near 0).
    pub(crate) fn low(&self, v: f64) -> f64 {
        match self.linear_slack {
            None => v,
            Some(e) => {
                let size = f64::from_bits(v.to_bits() & !(1 << 63)) + e;
                (v - e) - size * PRODUCT_ROUNDING - SUBNORMAL
            }
        }
    }

    /// The highest value the GPU may compare when the values read mix to at
    /// most `v` (see [`low`](Self::low)).
    pub(crate) fn high(&self, v: f64) -> f64 {
        match self.linear_slack {
            None => v,
            Some(e) => {
                let size = f64::from_bits(v.to_bits() & !(1 << 63)) + e;
                (v + e) + size * PRODUCT_ROUNDING + SUBNORMAL
            }
        }
    }

    /// A texel's class bits from the binary32 values it may convert to:
    /// bit 0, it may pass (a GPU value from it can be opaque); bit 1, it
    /// may fail. A texel whose range straddles the cutoff has both.
    pub(crate) fn class_bits(&self, lo: f32, hi: f32) -> u8 {
        let may_pass = self.cutoff.is_opaque(self.high(f64::from(hi)));
        let may_fail = !self.cutoff.is_opaque(self.low(f64::from(lo)));
        u8::from(may_pass) | (u8::from(may_fail) << 1)
    }

    /// What values mixed to at least `min` and at most `max` everywhere on
    /// a region make of it: `(may pass, may fail)` as class bits.
    pub(crate) fn range_bits(&self, min: f64, max: f64) -> u8 {
        let may_pass = self.cutoff.is_opaque(self.high(max));
        let may_fail = !self.cutoff.is_opaque(self.low(min));
        u8::from(may_pass) | (u8::from(may_fail) << 1)
    }
}
