//! The alpha test as a GPU applies it ([`AlphaTest`]): the binary32
//! cutoff against a texel's converted value (nearest filtering) or against
//! the filtered value, which may differ from the exact bilinear mix by the
//! filter's error and an alpha factor's binary32 products (linear
//! filtering). Contract: every bound here widens toward "may pass" and
//! "may fail", never narrows, so a decision from it holds for every value
//! the texture unit of `docs/bake.md` ("The texture unit") may compare.

use super::material::{TINY, VERTEX_MARGIN};
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
    /// With vertex alpha: the range every interpolated vertex alpha of the
    /// texture's triangles lies in. The texel classes are taken over all
    /// of it (so a class decision holds for any part of any triangle); a
    /// value decision takes the part's own range ([`VertexScale`]).
    pub(crate) vertex: Option<VertexScale>,
}

/// The range `[lo, hi]` (both `>= 0`) a GPU's binary32 interpolation of
/// the vertex alpha can give over some part of a triangle, its rounding
/// included (`docs/bake.md`, "Vertex alpha"): what the filtered, factored
/// value is multiplied by before the test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VertexScale {
    pub(crate) lo: f64,
    pub(crate) hi: f64,
}

impl VertexScale {
    /// The range over a part whose corners' exact vertex alphas are
    /// `corners`, of a triangle whose largest vertex alpha is `largest`:
    /// the corners' extremes (the alpha is affine over the part), widened
    /// by `largest` times [`VERTEX_MARGIN`] (the interpolation's binary32
    /// rounding, and this `f64` arithmetic's), never below 0.
    pub(crate) fn over(corners: [f64; 3], largest: f64) -> VertexScale {
        let min = corners[0].min(corners[1]).min(corners[2]);
        let max = corners[0].max(corners[1]).max(corners[2]);
        let slack = largest * VERTEX_MARGIN;
        VertexScale {
            lo: (min - slack).max(0.0),
            hi: max + slack,
        }
    }

    /// The range over whole triangles with vertex alphas `triangles`:
    /// holds each one's [`over`](Self::over).
    pub(crate) fn over_all(triangles: &[[f32; 3]]) -> VertexScale {
        let mut all = VertexScale {
            lo: f64::MAX,
            hi: 0.0,
        };
        for &a in triangles {
            let largest = f64::from(a[0].max(a[1]).max(a[2]));
            let v = VertexScale::over(a.map(f64::from), largest);
            all.lo = all.lo.min(v.lo);
            all.hi = all.hi.max(v.hi);
        }
        all.lo = all.lo.min(all.hi);
        all
    }

    /// The lowest binary32 product of a value of at least `x` and an alpha
    /// in the range (the GPU's product, rounded: [`VERTEX_MARGIN`] relative
    /// and [`TINY`] absolute cover it). NaN stays NaN.
    fn low(self, x: f64) -> f64 {
        let p = if x >= 0.0 { x * self.lo } else { x * self.hi };
        let abs = f64::from_bits(p.to_bits() & !(1 << 63));
        p - abs * VERTEX_MARGIN - TINY
    }

    /// The highest binary32 product of a value of at most `x` and an alpha
    /// in the range (see [`low`](Self::low)).
    fn high(self, x: f64) -> f64 {
        let p = if x >= 0.0 { x * self.hi } else { x * self.lo };
        let abs = f64::from_bits(p.to_bits() & !(1 << 63));
        p + abs * VERTEX_MARGIN + TINY
    }
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
            vertex: None,
        }
    }

    /// The same test for a texture whose triangles' vertex alphas lie in
    /// `vertex` (class decisions hold for the whole range).
    pub(crate) fn with_vertex(mut self, vertex: Option<VertexScale>) -> AlphaTest {
        self.vertex = vertex;
        self
    }

    /// [`low`](Self::low), then times the lowest alpha of `scale`.
    fn low_scaled(&self, v: f64, scale: Option<VertexScale>) -> f64 {
        let v = self.low(v);
        scale.map_or(v, |s| s.low(v))
    }

    /// [`high`](Self::high), then times the highest alpha of `scale`.
    fn high_scaled(&self, v: f64, scale: Option<VertexScale>) -> f64 {
        let v = self.high(v);
        scale.map_or(v, |s| s.high(v))
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
    /// With vertex alpha, over the whole of [`vertex`](Self::vertex).
    pub(crate) fn class_bits(&self, lo: f32, hi: f32) -> u8 {
        self.range_bits(f64::from(lo), f64::from(hi), self.vertex)
    }

    /// What values mixed to at least `min` and at most `max` everywhere on
    /// a region, times a vertex alpha in `scale` (none: 1), make of it:
    /// `(may pass, may fail)` as class bits.
    pub(crate) fn range_bits(&self, min: f64, max: f64, scale: Option<VertexScale>) -> u8 {
        let may_pass = self.cutoff.is_opaque(self.high_scaled(max, scale));
        let may_fail = !self.cutoff.is_opaque(self.low_scaled(min, scale));
        u8::from(may_pass) | (u8::from(may_fail) << 1)
    }
}
