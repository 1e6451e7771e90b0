//! The alpha test as a GPU applies it ([`AlphaTest`]): the binary32
//! cutoff against a texel's converted value (nearest filtering) or against
//! the filtered value, which may differ from the exact bilinear mix by the
//! filter's error and an alpha factor's binary32 products (linear
//! filtering). Contract: every bound here widens toward "may pass" and
//! "may fail", never narrows, so a decision from it holds for every value
//! the texture unit of `docs/bake.md` ("The texture unit") may compare.

use super::float::abs;
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
    /// Linear filtering judged by value ([`judges_by_value`]).
    pub(crate) by_value: bool,
    /// With vertex alpha: the range every interpolated vertex alpha of the
    /// texture's triangles lies in. The texel classes are taken over all
    /// of it (so a class decision holds for any part of any triangle); a
    /// value decision takes the part's own range ([`VertexScale`]).
    pub(crate) vertex: Option<VertexScale>,
}

/// Whether a sampler with `filter` is judged by its filtered value under
/// `unit`: linear filtering under [`LinearRule::Value`].
pub(crate) fn judges_by_value(filter: Filter, unit: &TextureUnit) -> bool {
    filter == Filter::Linear && unit.linear == LinearRule::Value
}

/// The exact vertex alpha (to `f64` rounding) at the corner `(a, b)` of
/// the barycentric grid with `side` (a power of two) steps per side (vertex 0 at the
/// origin, vertex 1 at `(side, 0)`, vertex 2 at `(0, side)`), for vertex
/// alphas `v`: the one formula the bake and the verifier use.
#[inline]
pub(crate) fn alpha_at(v: [f64; 3], side: f64, (a, b): (u64, u64)) -> f64 {
    let (a, b) = (a as f64, b as f64);
    // `side` is a power of two: times its inverse is the exact quotient.
    (v[0] * (side - a - b) + v[1] * a + v[2] * b) * (1.0 / side)
}

/// The largest of a triangle's vertex alphas (the interpolation's error
/// scales with it, [`VertexScale::over`]).
pub(crate) fn largest_alpha(alphas: [f32; 3]) -> f64 {
    f64::from(alphas[0].max(alphas[1]).max(alphas[2]))
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

    /// A "range" narrower than any inside this one, for bounds that hold
    /// for all of them (the tests are monotone in the range: a lower low
    /// may fail more, a higher high may pass more): its low is this
    /// range's high and its high this range's low.
    pub(crate) fn narrowest(self) -> VertexScale {
        VertexScale {
            lo: self.hi,
            hi: self.lo,
        }
    }

    /// The smallest range holding this one and `other`.
    pub(crate) fn union(self, other: VertexScale) -> VertexScale {
        VertexScale {
            lo: self.lo.min(other.lo),
            hi: self.hi.max(other.hi),
        }
    }

    /// A "range" no wider than this one and `other` (the highest low, the
    /// lowest high; possibly low above high): bits taken at it are in the
    /// bits of both.
    pub(crate) fn intersection(self, other: VertexScale) -> VertexScale {
        VertexScale {
            lo: self.lo.max(other.lo),
            hi: self.hi.min(other.hi),
        }
    }

    /// The range over a whole triangle with vertex alphas `alphas`.
    pub(crate) fn of_triangle(alphas: [f32; 3]) -> VertexScale {
        VertexScale::over(alphas.map(f64::from), largest_alpha(alphas))
    }

    /// The range over whole triangles with vertex alphas `triangles`:
    /// holds each one's [`of_triangle`](Self::of_triangle) (`[0, 0]` for
    /// none).
    pub(crate) fn over_all(triangles: &[[f32; 3]]) -> VertexScale {
        triangles
            .iter()
            .map(|&a| VertexScale::of_triangle(a))
            .reduce(VertexScale::union)
            .unwrap_or(VertexScale { lo: 0.0, hi: 0.0 })
    }

    /// The lowest binary32 product of a value of at least `x` and an alpha
    /// in the range (the GPU's product, rounded: [`VERTEX_MARGIN`] relative
    /// and [`TINY`] absolute cover it). NaN stays NaN.
    fn low(self, x: f64) -> f64 {
        let p = if x >= 0.0 { x * self.lo } else { x * self.hi };
        p - abs(p) * VERTEX_MARGIN - TINY
    }

    /// The highest binary32 product of a value of at most `x` and an alpha
    /// in the range (see [`low`](Self::low)).
    fn high(self, x: f64) -> f64 {
        let p = if x >= 0.0 { x * self.hi } else { x * self.lo };
        p + abs(p) * VERTEX_MARGIN + TINY
    }
}

impl AlphaTest {
    /// The test for `cutoff` under `filter` and `unit`, on a texture whose
    /// values are the texels' times `scale` (an alpha factor, at most 1 for
    /// vertex alpha bounds).
    pub(crate) fn new(cutoff: Cutoff, filter: Filter, unit: &TextureUnit, scale: f64) -> AlphaTest {
        AlphaTest {
            cutoff,
            linear_slack: (filter == Filter::Linear)
                .then(|| f64::from(unit.filter_error) * abs(scale)),
            by_value: judges_by_value(filter, unit),
            vertex: None,
        }
    }

    /// The same test for a texture whose triangles' vertex alphas lie in
    /// `vertex` (class decisions hold for the whole range).
    pub(crate) fn with_vertex(mut self, vertex: Option<VertexScale>) -> AlphaTest {
        self.vertex = vertex;
        self
    }

    /// The lowest value the GPU may compare when the values read mix to
    /// at least `v`: `v` itself under nearest filtering; under linear, less
    /// the filter's error and the factor's roundings (relative to the
    /// magnitudes `|v| + e`, not `|v - e|`, which may be near 0).
    pub(crate) fn low(&self, v: f64) -> f64 {
        match self.linear_slack {
            None => v,
            Some(e) => {
                let size = abs(v) + e;
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
                let size = abs(v) + e;
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
        self.bounds(min, max).bits(self, scale)
    }

    /// The part of [`range_bits`](Self::range_bits) that does not depend
    /// on the vertex alpha: the lowest and highest values the GPU may
    /// compare before it.
    pub(crate) fn bounds(&self, min: f64, max: f64) -> CompareBounds {
        CompareBounds {
            low: self.low(min),
            high: self.high(max),
        }
    }
}

/// The lowest and highest value the GPU may compare, before a vertex
/// alpha ([`AlphaTest::bounds`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CompareBounds {
    low: f64,
    high: f64,
}

impl CompareBounds {
    /// The class bits times a vertex alpha in `scale` (none: 1).
    #[inline]
    pub(crate) fn bits(self, test: &AlphaTest, scale: Option<VertexScale>) -> u8 {
        let (low, high) = match scale {
            None => (self.low, self.high),
            Some(s) => (s.low(self.low), s.high(self.high)),
        };
        let may_pass = test.cutoff.is_opaque(high);
        let may_fail = !test.cutoff.is_opaque(low);
        u8::from(may_pass) | (u8::from(may_fail) << 1)
    }
}
