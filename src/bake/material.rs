//! How a material's alpha reaches the cutoff, as a renderer computes it:
//! the sampler, the cutoff and glTF's alpha factor ([`Material`]), the
//! factor applied to every texel in binary32 ([`FactorTexture`]), and the
//! bounds on `texel * factor * vertex alpha` that make vertex alpha sound
//! ([`VertexBoundTexture`], [`vertex_range`]).

use super::baker::Baker;
use super::float::abs;
use super::parallel::Runner;
use super::texture::{faithful_f32, AlphaTexture, Cutoff, Sampler, TextureError};
use super::texture_unit::TextureUnit;
use super::triangle::UvTriangle;
use super::uv_transform::UvTransform;
use alloc::vec::Vec;

/// How a mesh's texture is alpha-tested: the sampler, the cutoff, and a
/// factor on every texel's alpha.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// The sampler the runtime reads the texture with.
    pub sampler: Sampler,
    /// The alpha test.
    pub cutoff: Cutoff,
    /// Multiplies every texel's alpha before the cutoff (glTF's
    /// `pbrMetallicRoughness.baseColorFactor[3]`), as a GPU does: the
    /// texel's alpha as binary32 (`c / 255` rounded once, for 8-bit
    /// texels) times the factor, one binary32 product, compared with the
    /// cutoff; at `1.0` the texel's alpha as it is. Under linear filtering
    /// the filtered alpha lies between its texels' alphas, and the rounded
    /// product is monotone in it, so classifying each texel this way stays
    /// sound.
    pub alpha_factor: f32,
    /// The transform the shader applies to the interpolated texture
    /// coordinate before sampling (glTF's `KHR_texture_transform`; default
    /// [`UvTransform::IDENTITY`]): the mesh's triangles are the
    /// untransformed coordinates ([`Baker::with_uv_transform`]).
    pub uv_transform: UvTransform,
}

impl Default for Material {
    /// The default sampler and cutoff (glTF's `alpha >= 0.5`), factor 1,
    /// no texture transform.
    fn default() -> Self {
        Material {
            sampler: Sampler::default(),
            cutoff: Cutoff::default(),
            alpha_factor: 1.0,
            uv_transform: UvTransform::IDENTITY,
        }
    }
}

impl Material {
    /// The triangle the shader samples for the mesh triangle `uv`: each
    /// vertex through [`uv_transform`](Self::uv_transform)
    /// ([`UvTransform::place`]), for the level choice and the area weights.
    #[must_use]
    pub fn placed(&self, uv: &UvTriangle) -> UvTriangle {
        self.uv_transform.place_triangle(uv)
    }
}

/// A texture whose every alpha is multiplied by `factor` as a GPU does:
/// the texel's alpha rounded to binary32, times `factor`, one binary32
/// product (exact in `f64`).
pub(crate) struct FactorTexture<'a> {
    pub(crate) inner: &'a dyn AlphaTexture,
    pub(crate) factor: f32,
}

impl AlphaTexture for FactorTexture<'_> {
    fn width(&self) -> u32 {
        self.inner.width()
    }
    fn height(&self) -> u32 {
        self.inner.height()
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        // `as f32` rounds once to nearest (for `c / 255` and `c / 65535`,
        // correctly: see `texel_f32`).
        f64::from(texel_f32(self.inner.alpha(x, y)) * self.factor)
    }
    /// The texel's binary32 values times the factor, each one binary32
    /// product (rounded to nearest, which is monotone: the products of the
    /// lowest and the highest value bound every other).
    fn gpu_alpha(&self, x: u32, y: u32) -> (f32, f32) {
        let (lo, hi) = self.inner.gpu_alpha(x, y);
        let (a, b) = (lo * self.factor, hi * self.factor);
        if a.is_nan() || b.is_nan() {
            (f32::NAN, f32::NAN)
        } else {
            (a.min(b), a.max(b))
        }
    }
}

/// A texel's alpha as the binary32 value a GPU reads. The `f64` quotient
/// `c / 255` (or `c / 65535`) rounds to the same binary32 value as the
/// exact quotient: double rounding could differ only if the `f64` value
/// were a binary32 midpoint, whose bits past the 25th are zero, while the
/// binary expansion of `c / (2^k - 1)`, `0 < c < 2^k - 1`, repeats the
/// `k`-bit pattern of `c` forever.
pub(crate) fn texel_f32(alpha: f64) -> f32 {
    alpha as f32
}

/// Relative widening that covers a GPU's binary32 rounding of
/// `texel * factor * vertex` (two products, at most `(1 + 2^-24)^2 - 1`
/// relative), and of the vertex alpha's interpolation (at most about
/// `6 * 2^-24` of the largest vertex alpha, see `docs/bake.md`), with room
/// for the `f64` arithmetic of the bounds.
pub(crate) const VERTEX_MARGIN: f64 = 1.0 / (1u64 << 20) as f64;

/// Absolute widening for products in binary32's subnormal range (each
/// rounding there errs by at most `2^-150`).
pub(crate) const TINY: f64 = 1.0 / (1u64 << 62) as f64 / (1u64 << 62) as f64 / (1u64 << 16) as f64;

/// Vertex alphas are grouped on this grid (bounds rounded outwards), so
/// that a mesh needs few texel classifications.
pub(crate) const VERTEX_GRID: f64 = 1024.0;

/// A texture whose alpha is a bound on `texel * factor * v` as a GPU
/// computes it, for a vertex alpha `v` that is itself a bound of the
/// vertex-alpha range (its low for the lower bound, its high for the
/// upper): the lower bound (`upper: false`), to find what is opaque for
/// sure, or the upper (`upper: true`), to find what is transparent for
/// sure. Texel alphas and factors are never negative, so the product is
/// monotone in `v`.
pub(crate) struct VertexBoundTexture<'a> {
    pub(crate) inner: &'a dyn AlphaTexture,
    pub(crate) factor: f64,
    pub(crate) v: f64,
    pub(crate) upper: bool,
}

impl VertexBoundTexture<'_> {
    /// The bound for a texel of exact alpha `texel`.
    fn bound(&self, texel: f64) -> f64 {
        // NaN stays NaN: it passes no cutoff, on the GPU either.
        let product = f64::from(texel_f32(texel)) * self.factor * self.v;
        if self.upper {
            product + abs(product) * VERTEX_MARGIN + TINY
        } else {
            product - abs(product) * VERTEX_MARGIN - TINY
        }
    }
}

impl AlphaTexture for VertexBoundTexture<'_> {
    fn width(&self) -> u32 {
        self.inner.width()
    }
    fn height(&self) -> u32 {
        self.inner.height()
    }
    fn alpha(&self, x: u32, y: u32) -> f64 {
        self.bound(self.inner.alpha(x, y))
    }

    /// As the default (each texel's [`faithful_f32`] of its bound), with
    /// the answers for the row's distinct texel values remembered: a
    /// texture has few (at most 256 for 8 bits), and a smooth vertex alpha
    /// builds up to 2 [`VERTEX_BOUNDS`] of these textures.
    fn extend_gpu_alpha_row(&self, y: u32, low: &mut Vec<f32>, high: &mut Vec<f32>) {
        // Direct-mapped by the value's bits; every slot starts as texel
        // value 0 with its answer, so a hit is always the right answer.
        let zero = faithful_f32(self.bound(0.0));
        let mut memo = [(0u64, zero); 256];
        for x in 0..self.width() {
            let value = self.inner.alpha(x, y);
            let key = value.to_bits();
            let slot = &mut memo[((key ^ (key >> 23) ^ (key >> 41)) & 255) as usize];
            if slot.0 != key {
                *slot = (key, faithful_f32(self.bound(value)));
            }
            low.push(slot.1 .0);
            high.push(slot.1 .1);
        }
    }
}

/// The baker that classifies the texels of `texture`, read as `material`
/// and `unit` say, by one side's bound of `texel * factor * v` (the lower
/// when `upper` is false) at the vertex alpha `v` (bits, a bound of
/// [`VertexBounds::snap`] or of [`vertex_range`]): the one way the bake
/// and the verifier make it. The caller sets its block budget and model.
pub(crate) fn vertex_bound_baker(
    texture: &dyn AlphaTexture,
    material: &Material,
    unit: TextureUnit,
    (upper, v): (bool, u64),
    runner: &Runner,
) -> Result<Baker, TextureError> {
    let texture = VertexBoundTexture {
        inner: texture,
        factor: f64::from(material.alpha_factor),
        v: f64::from_bits(v),
        upper,
    };
    let test = (
        material.sampler,
        material.cutoff,
        unit,
        f64::from(material.alpha_factor),
    );
    Ok(Baker::new_on(&texture, test, u64::MAX, runner)?.with_uv_transform(material.uv_transform))
}

/// At most this many distinct lower bounds, and as many upper bounds, of
/// the vertex alpha per texture and material: each gets a baker of its own
/// (texel tables the size of the texture), so a smooth vertex alpha, whose
/// every triangle has a range of its own, would otherwise build thousands.
pub(crate) const VERTEX_BOUNDS: usize = 16;

/// The vertex-alpha bounds a set of triangles' ranges ([`vertex_range`])
/// snap to: every distinct low (high) when there are at most
/// [`VERTEX_BOUNDS`] of them, else [`VERTEX_BOUNDS`] of them spread
/// evenly over the sorted distinct values, the lowest low and the highest
/// high included. A range snaps outwards, to the largest bound at or below
/// its low and the smallest at or above its high: a wider range, so the
/// bakes stay sound; only texels near the cutoff become unknown.
#[derive(Clone, Debug, Default)]
pub(crate) struct VertexBounds {
    /// Ascending, as `f64` bits (non-negative, so the bits sort as the
    /// values do).
    lows: Vec<u64>,
    /// Ascending, as bits.
    highs: Vec<u64>,
}

impl VertexBounds {
    /// The bounds for triangles whose ranges ([`vertex_range`]) have these
    /// lows and highs (the caller's lists, sorted and deduplicated in
    /// place: nothing sized by the triangles is allocated here).
    pub(crate) fn new(mut lows: Vec<u64>, mut highs: Vec<u64>) -> VertexBounds {
        let pick = |values: &mut Vec<u64>, upper: bool| {
            values.sort_unstable();
            values.dedup();
            let n = values.len();
            if n > VERTEX_BOUNDS {
                // Lows: the first of each of VERTEX_BOUNDS slices (the
                // lowest included); highs: the last of each (the highest).
                for i in 0..VERTEX_BOUNDS {
                    values[i] = if upper {
                        values[((i + 1) * n).div_ceil(VERTEX_BOUNDS) - 1]
                    } else {
                        values[i * n / VERTEX_BOUNDS]
                    };
                }
                values.truncate(VERTEX_BOUNDS);
            }
            values.shrink_to_fit();
        };
        pick(&mut lows, false);
        pick(&mut highs, true);
        VertexBounds { lows, highs }
    }

    /// The bounds `range` snaps to, as bits: `(low, high)` with `low <=
    /// range.0` and `high >= range.1`. `range` must be one of those given
    /// to [`new`](Self::new).
    pub(crate) fn snap(&self, range: (u64, u64)) -> (u64, u64) {
        let below = self.lows.partition_point(|&l| l <= range.0);
        let above = self.highs.partition_point(|&h| h < range.1);
        (
            self.lows[below.saturating_sub(1)],
            self.highs[above.min(self.highs.len() - 1)],
        )
    }
}

/// The range `[low, high]` a GPU's interpolated vertex alpha can take over
/// a triangle with vertex alphas `v`, widened by the interpolation's
/// rounding and rounded outwards to [`VERTEX_GRID`]; as bits, to group by.
pub(crate) fn vertex_range(v: [f32; 3]) -> (u64, u64) {
    let min = f64::from(v[0].min(v[1]).min(v[2]));
    let max = f64::from(v[0].max(v[1]).max(v[2]));
    // Floor and ceiling without `std`: the values are small (alphas in
    // [0, 1], times the grid), so the casts are exact.
    let scaled_low = (min - max * VERTEX_MARGIN) * VERTEX_GRID;
    let scaled_high = (max + max * VERTEX_MARGIN) * VERTEX_GRID;
    let floor = |x: f64| {
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else {
            t
        }
    };
    let ceil = |x: f64| {
        let t = x as i64 as f64;
        if t < x {
            t + 1.0
        } else {
            t
        }
    };
    let low = floor(scaled_low) / VERTEX_GRID;
    let high = ceil(scaled_high) / VERTEX_GRID;
    (low.max(0.0).to_bits(), high.to_bits())
}
