//! The GPU model ([`Model::GpuBinary32`]): how far the texel a GPU reads for
//! a binary32 hit can be from the exact model's footprint, as a margin per
//! axis (a power of two in texels) by which the baker dilates every
//! micro-triangle. The derivation is in `docs/bake.md` ("The GPU model");
//! the names below follow it.

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

/// `2^k` as `f64`, for `-1022 <= k <= 1023`.
fn exp2(k: i32) -> f64 {
    f64::from_bits(((1023 + k) as u64) << 52)
}

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

/// The GPU model's margin on one axis, in texels, as the exponent `e` of
/// a power of two `2^e` at least the bound of `docs/bake.md`:
///
/// `m = S·D·2^(-25-n) + S·A·(2^-20 + 2^-21) + 2^-21`
///
/// for the axis's three (finite) coordinates `c` of a triangle baked at
/// level `n` over `S = size` texels, with `A = max |c_k|` and
/// `D = max(|c1 - c0|, |c2 - c0|)`: the index function's rounding window
/// mapped through the triangle's edges, the shader's texture-coordinate
/// formulas, and the sampler's scaling (and linear filtering's half-texel
/// offset). Computed in `f64` and enlarged by `2^-30` relative, far more
/// than the few `f64` roundings can lose.
pub(crate) fn margin_exponent(c: [f32; 3], size: u32, level: u32) -> i32 {
    // |x| and max by hand: neither is in `core` at the minimum Rust.
    let abs = |x: f64| f64::from_bits(x.to_bits() & !(1 << 63));
    let max = |x: f64, y: f64| if x >= y { x } else { y };
    let a = c.iter().map(|&x| abs(f64::from(x))).fold(0.0, max);
    let d = max(
        abs(f64::from(c[1]) - f64::from(c[0])),
        abs(f64::from(c[2]) - f64::from(c[0])),
    );
    let s = f64::from(size);
    let m = s * d * exp2(-25 - level as i32) + s * a * (exp2(-20) + exp2(-21)) + exp2(-21);
    ceil_log2(m * (1.0 + exp2(-30)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn margins_are_the_stated_powers_of_two() {
        // No extent: only the half-texel offset's 2^-21 remains, and the
        // f64 allowance rounds it up to the next power of two.
        assert_eq!(margin_exponent([0.0; 3], 512, 8), -20);
        // The unit square over 512 texels at level 8:
        // 512 (2^-33 + 1.5 2^-20) + 2^-21 = 2^-24 + 1.5 2^-11 + 2^-21,
        // just above 2^-10.5: 2^-10.
        assert_eq!(margin_exponent([0.0, 1.0, 0.0], 512, 8), -10);
        // Far outside [0, 1] the margin grows with the coordinates.
        assert_eq!(margin_exponent([1000.0, 1001.0, 1000.0], 512, 8), 0);
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
