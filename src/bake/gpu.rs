//! The GPU model ([`Model::GpuBinary32`]): how far the texel coordinate a
//! GPU filters with for a binary32 hit can be from the exact point, as a
//! margin per axis (four significant bits, in texels) by which the baker
//! dilates every micro-triangle. The derivation is in `docs/bake.md` ("The GPU model");
//! the names below follow it.

use super::float::{abs, exp2};
use super::texture_unit::{Interpolation, TextureUnit};
use super::uv_transform::AxisErrors;
use crate::names::named_enum;

/// Which points a known state must hold for.
///
/// ```
/// use micromap_index::bake::Model;
/// assert_eq!(Model::default(), Model::GpuBinary32);
/// assert_eq!(Model::Exact.name(), "exact");
/// assert_eq!("gpu-binary32".parse(), Ok(Model::GpuBinary32));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Model {
    /// What a GPU computes (the default): every binary32 hit `(b1, b2)` in
    /// the closed triangle that [`spec::index_f32`](crate::spec::index_f32)
    /// assigns to the micro-triangle (its rounding window included), the
    /// texture coordinate any of the renderers' binary32 formulas gives
    /// for it (with or without fused multiply-add), and the sampler's
    /// binary32 `u · size` (and `- 1/2` for linear) within `2^-22`
    /// relative error. The baker dilates each micro-triangle in texel space
    /// by a proven bound on the difference from the exact point (see
    /// `docs/bake.md`), and decides the dilated region exactly.
    #[default]
    GpuBinary32,
    /// The exact real point `(1 - b1 - b2) uv0 + b1 uv1 + b2 uv2` of every
    /// point of the closed micro-triangle: the model of earlier versions,
    /// tighter, but a binary32 hit on a texel-aligned edge can contradict it.
    Exact,
}

impl Model {
    /// Both models, the default first.
    pub const ALL: [Model; 2] = [Model::GpuBinary32, Model::Exact];
}

named_enum!(
    Model,
    "model",
    "gpu-binary32 or exact",
    [(GpuBinary32, "gpu-binary32"), (Exact, "exact")]
);

/// The least `e` with `x <= 2^e`, for a positive normal `x`.
fn ceil_log2(x: f64) -> i32 {
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i32 - 1023;
    if bits & ((1 << 52) - 1) == 0 {
        exponent
    } else {
        exponent + 1
    }
}

/// A margin of `units * 2^exponent` texels, `units` in `1..=8`: four
/// significant bits, so that it exceeds the bound it covers by less than
/// a quarter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TexelMargin {
    pub(crate) exponent: i32,
    pub(crate) units: u32,
}

/// The GPU model's margin on one axis, in texels, at least the bound of
/// `docs/bake.md` ("The GPU model", "The texture unit"):
///
/// `m = S·D·2^(-25-n) + r·S·A·(2^-20 + 2^-21) + 2^-21 + 2^-k` (+ `S·2^-22`
/// for 16-bit interpolation)
///
/// for the axis's three (finite) coordinates `c` of a triangle baked at
/// level `n` over `S = size` texels, with `A = max |c_k|` and
/// `D = max(|c1 - c0|, |c2 - c0|)`: the index function's rounding window
/// mapped through the triangle's edges, the shader's texture-coordinate
/// formulas (`r = 1` in binary32; in 16-bit floats, whose unit roundoff is
/// `2^13` times binary32's, `r = 2^13 (1 + 2^-6)`, the last factor for the
/// second-order terms, and `S·2^-22` for their subnormal spacing), the
/// sampler's scaling (and linear filtering's half-texel offset), and the
/// sub-texel snapping `2^-k` of `unit`. Computed in `f64` and enlarged by
/// `2^-30` relative, far more than the few `f64` roundings can lose.
/// `None` when 16-bit interpolation cannot hold the coordinates
/// (`A >= 2^15`).
pub(crate) fn margin(
    c: [f32; 3],
    size: u32,
    level: u32,
    unit: &TextureUnit,
) -> Option<TexelMargin> {
    let (a, d) = extent(c);
    let s = f64::from(size);
    let (r, floor) = precision(unit, a)?;
    let floor = s * floor;
    let m = s * d * exp2(-25 - level as i32)
        + r * s * a * (exp2(-20) + exp2(-21))
        + exp2(-21)
        + floor
        + unit.snap_radius();
    Some(four_bits(m))
}

/// The GPU model's margin on one axis of a triangle whose texture
/// coordinates the shader transforms ([`UvTransform`](super::UvTransform)): `c` the axis's
/// placed coordinates, `e` the transform's error terms. In texture units,
/// with `w = D 2^(-25-n)` (the index window through the placed edges),
/// `i = r 2^-20 interpolated + f (row_sum + 1)` (the source
/// interpolation's error through the linear part and the transform's own
/// absolute rounding; `f` 16-bit floats' `2^-22` spacing, else 0), `t = r tau + rho (1 + 2^-20)` and `E = w + i + t`:
///
/// `m = S E + r 2^-21 (S (A + E) + 1) + 2^-k`
///
/// (`docs/bake.md`, "Texture transforms"). `None` when 16-bit
/// interpolation cannot hold the source or the placed coordinates.
pub(crate) fn margin_transformed(
    c: [f32; 3],
    e: &AxisErrors,
    size: u32,
    level: u32,
    unit: &TextureUnit,
) -> Option<TexelMargin> {
    let (a, d) = extent(c);
    let s = f64::from(size);
    let (r, floor) = precision(unit, if a >= e.source_max { a } else { e.source_max })?;
    let window = d * exp2(-25 - level as i32);
    // 16-bit floats' absolute spacing: the interpolation's through the
    // linear part, and the transform's own operations (at most five, half
    // a spacing each) once more.
    let interpolation = r * exp2(-20) * e.interpolated + floor * (e.row_sum + 1.0);
    let transform = r * e.tau + e.rho * (1.0 + exp2(-20));
    let error = window + interpolation + transform;
    let m = s * error + r * exp2(-21) * (s * (a + error) + 1.0) + unit.snap_radius();
    if !m.is_finite() {
        return None;
    }
    Some(four_bits(m))
}

/// `A = max |c_k|` and `D = max(|c1 - c0|, |c2 - c0|)` of one axis.
fn extent(c: [f32; 3]) -> (f64, f64) {
    // |x| and max by hand: neither is in `core` at the minimum Rust.
    let max = |x: f64, y: f64| if x >= y { x } else { y };
    let a = c.iter().map(|&x| abs(f64::from(x))).fold(0.0, max);
    let d = max(
        abs(f64::from(c[1]) - f64::from(c[0])),
        abs(f64::from(c[2]) - f64::from(c[0])),
    );
    (a, d)
}

/// The interpolation's error factor `r` and absolute floor (in texture
/// units) of `unit`: `(1, 0)` in binary32; in 16-bit floats `2^13 (1 +
/// 2^-6)` and `2^-22`, or `None` when the coordinates' magnitude `a`
/// reaches `2^15`.
fn precision(unit: &TextureUnit, a: f64) -> Option<(f64, f64)> {
    match unit.interpolation {
        Interpolation::F32 => Some((1.0, 0.0)),
        Interpolation::F16 => (a < exp2(15)).then(|| (exp2(13) * (1.0 + exp2(-6)), exp2(-22))),
    }
}

/// `m` (positive, finite) enlarged by `2^-30` relative and rounded up to
/// four significant bits.
fn four_bits(m: f64) -> TexelMargin {
    let m = m * (1.0 + exp2(-30));
    let exponent = ceil_log2(m);
    // m / 2^(e - 3) is in (4, 8]: its ceiling, 5..=8 units of 2^(e - 3).
    let scaled = m / exp2(exponent - 3);
    let mut units = scaled as u32;
    if f64::from(units) < scaled {
        units += 1;
    }
    TexelMargin {
        exponent: exponent - 3,
        units: units.clamp(1, 8),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn margins_cover_the_stated_bounds_with_four_bits() {
        let unit = TextureUnit::default();
        let m = |c, size, level, unit: &TextureUnit| {
            let t = margin(c, size, level, unit).unwrap();
            f64::from(t.units) * exp2(t.exponent)
        };
        // No extent: the half-texel offset's 2^-21 and the snapping 2^-8,
        // to four bits: 5/8 of 2^-7 (2^-8 + 2^-21 is just above 2^-8).
        assert_eq!(m([0.0; 3], 512, 8, &unit), 5.0 * exp2(-10));
        // The unit square over 512 texels at level 8:
        // 512 (2^-33 + 1.5 2^-20) + 2^-21 + 2^-8, about 2^-8 + 2^-10.4.
        let square = m([0.0, 1.0, 0.0], 512, 8, &unit);
        assert!(
            square >= exp2(-8) + 512.0 * 1.5 * exp2(-20)
                && square <= 1.25 * (exp2(-8) + 2.0 * exp2(-10))
        );
        // Far outside [0, 1] the margin grows with the coordinates.
        assert!(m([1000.0, 1001.0, 1000.0], 512, 8, &unit) >= 512.0 * 1001.0 * 3.0 * exp2(-21));
        // Four snapping bits: 2^-4 dominates.
        let coarse = TextureUnit {
            subtexel_bits: 4,
            ..unit
        };
        assert_eq!(m([0.0; 3], 512, 8, &coarse), 5.0 * exp2(-6));
        // 16-bit interpolation: 2^13 times the coordinates' term, and no
        // coordinate of 2^15 or more.
        let half = TextureUnit {
            interpolation: Interpolation::F16,
            ..unit
        };
        assert!(m([0.0, 1.0, 0.0], 512, 8, &half) > 512.0 * 1.5 * exp2(-7));
        assert!(margin([40000.0, 0.0, 0.0], 512, 8, &half).is_none());
        assert_eq!(ceil_log2(1.0), 0);
        assert_eq!(ceil_log2(1.5), 1);
        assert_eq!(ceil_log2(0.75), 0);
        assert_eq!(exp2(-3), 0.125);
        for m in Model::ALL {
            assert_eq!(m.name().parse(), Ok(m));
        }
        assert!("gpu".parse::<Model>().is_err());
    }
}
