//! The Vulkan reference, `BarycentricsToSpaceFillingCurveIndex`.
//!
//! Ported from the "Reference Code" section of the Vulkan specification's
//! appendix `VK_EXT_opacity_micromap.adoc` (identical in
//! `VK_KHR_opacity_micromap.adoc`, Khronos Vulkan-Docs, unchanged since 2022
//! but for whitespace). The C original works on 32-bit `float` and
//! `uint32_t`; this port keeps every step and its order.
//!
//! # Guarantees
//!
//! * [`index_f32`] returns, for **every** pair of `f32` values (NaN, ±0, ±inf,
//!   subnormals, values outside `[0, 1]`, `u + v > 1`) and every level, the
//!   bits the reference returns when its float operations are IEEE binary32
//!   with round-to-nearest-even, `clamp` is `min(max(x, 0), 1)` with IEEE
//!   maxNum/minNum (so NaN becomes 0), the float-to-integer conversion
//!   truncates and all `uint32_t` arithmetic wraps. Levels `>= 32`, for which
//!   C's `1u << level` is undefined, use the shift count modulo 32 as x86,
//!   ARM and SPIR-V hardware do. The reference only computes *valid* indices
//!   for levels `0..=16`: its prefix-XOR and bit interleave handle 16 bits.
//! * [`index_f32_checked`] is the same function with the level limited to
//!   `0..=16` ([`Error::LevelTooHigh`] above).
//! * [`index_exact`] runs the same steps over the reals ("the rational reading
//!   of the spec"): exact products, floors and fractional parts, and an exact
//!   `uf + vf >= 1`. It differs from [`index_f32`] on a finite, in-range
//!   input only where binary32 rounds `uf + vf` up to `1.0`, i.e. when the
//!   exact sum lies in `[1 - 2^-25, 1)` (see [`diagonal_decision_f32`] and
//!   `docs/float.md`).
//!
//! # Points outside the triangle
//!
//! Each coordinate is first clamped to `[0, 1]` on its own (NaN → 0,
//! -inf → 0, +inf → 1). The grid cell `(iu, iv)` is then clamped to
//! `0..2^level` per axis, and a cell past the hypotenuse (`iu + iv >= 2^level`)
//! is moved along `u` to the last cell of its row, `iu = 2^level - 1 - iv`,
//! keeping `v`. The fraction test `uf + vf >= 1` is then ignored (the cell is
//! on the hypotenuse, where `iuv < 2^level - 1` is false), so such a point
//! lands in the *upright* micro-triangle at the end of row `iv`. Points with
//! `u + v > 1` but inside the last cell's diagonal half are therefore mapped
//! as if projected along `u` onto the hypotenuse.
//!
//! ```
//! use micromap_index::{spec, Level};
//! // Level 1: left = 0, middle = 1, right = 2, top = 3.
//! assert_eq!(spec::index_f32(0.1, 0.1, 1), 0);
//! assert_eq!(spec::index_f32(0.4, 0.4, 1), 1);
//! assert_eq!(spec::index_f32(0.9, 0.05, 1), 2);
//! assert_eq!(spec::index_f32(0.05, 0.9, 1), 3);
//! // NaN clamps to 0, +inf to 1; (1, 1) is pulled back to (0, 1): the top.
//! assert_eq!(spec::index_f32(f32::NAN, f32::INFINITY, 1), 3);
//! assert_eq!(spec::index_f32(f32::INFINITY, f32::INFINITY, 1), 3);
//! assert!(spec::index_f32_checked(0.5, 0.5, Level::new(17).unwrap()).is_err());
//! ```

use crate::{Error, Level};
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};

/// The highest level for which the reference computes valid indices.
pub const MAX_LEVEL: u32 = 16;

/// The reference in binary32, total: defined for every input (see the
/// module docs for levels above 16).
pub fn index_f32(u: f32, v: f32, level: u32) -> u32 {
    let u = clamp_unit(u);
    let v = clamp_unit(v);
    let cells = 1u32.wrapping_shl(level);
    // `(float)(1u << level)`: exact for every power of two up to 2^31.
    let scale = cells as f32;
    let fu = u * scale;
    let fv = v * scale;
    // `fu`, `fv` are in [0, 2^31]: the cast truncates like C's (uint32_t).
    let iu = fu as u32;
    let iv = fv as u32;
    let uf = fu - iu as f32;
    let vf = fv - iv as f32;
    index_from_cell(iu, iv, diagonal_decision_f32(uf, vf), level)
}

/// The reference in binary32 for levels `0..=16`.
///
/// ```
/// use micromap_index::{spec, Level, Error};
/// assert_eq!(spec::index_f32_checked(0.3, 0.3, Level::new(2).unwrap()), Ok(5));
/// assert_eq!(
///     spec::index_f32_checked(0.3, 0.3, Level::new(20).unwrap()),
///     Err(Error::LevelTooHigh { level: 20, max: 16 })
/// );
/// ```
pub fn index_f32_checked(u: f32, v: f32, level: Level) -> Result<u32, Error> {
    let level = level.at_most(MAX_LEVEL)?;
    Ok(index_f32(u, v, level.get()))
}

/// The reference's `uf + vf >= 1.0f` in binary32: the sum is rounded to
/// nearest-even before the compare, so it holds exactly when the real sum is
/// at least `1 - 2^-25` (the midpoint between `1 - 2^-24` and `1`, which ties
/// to the even `1.0`).
///
/// ```
/// use micromap_index::spec::diagonal_decision_f32;
/// let below = 0.5 - f32::EPSILON / 4.0; // 0.5 - 2^-25, exactly representable
/// // The real sum is 1 - 2^-25 < 1, but binary32 rounds it (ties-to-even) to 1.0.
/// assert!(diagonal_decision_f32(0.5, below));
/// // One ulp further down, the sum rounds to 1 - 2^-24.
/// assert!(!diagonal_decision_f32(0.5, f32::from_bits(below.to_bits() - 1)));
/// ```
pub fn diagonal_decision_f32(uf: f32, vf: f32) -> bool {
    uf + vf >= 1.0
}

/// `x` clamped to `[0, 1]` as `min(max(x, 0), 1)` with IEEE maxNum/minNum:
/// NaN → 0 (Rust's `f32::max` returns the non-NaN operand).
fn clamp_unit(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

/// The integer half of the reference: from the (unclamped) grid cell
/// `(iu, iv)` = `(trunc(u * 2^level), trunc(v * 2^level))` and the outcome of
/// the diagonal test `uf + vf >= 1`, the curve index. All arithmetic wraps
/// like C's `uint32_t`; shifts by `level >= 32` use `level % 32`.
///
/// Every variant of the spec (binary32, exact, dyadic) computes its cell and
/// diagonal decision its own way and shares this function.
///
/// ```
/// use micromap_index::spec::index_from_cell;
/// // Level 1, cell (0, 0): lower-left half is the left child, upper-right
/// // half is the middle child.
/// assert_eq!(index_from_cell(0, 0, false, 1), 0);
/// assert_eq!(index_from_cell(0, 0, true, 1), 1);
/// ```
pub fn index_from_cell(iu: u32, iv: u32, diagonal: bool, level: u32) -> u32 {
    let cells = 1u32.wrapping_shl(level);
    let last = cells.wrapping_sub(1);
    let mut iu = iu;
    let mut iv = iv;
    if iu >= cells {
        iu = last;
    }
    if iv >= cells {
        iv = last;
    }
    let iuv = iu.wrapping_add(iv);
    if iuv >= cells {
        iu = iu.wrapping_sub(iuv.wrapping_sub(cells).wrapping_add(1));
    }
    let mut iw = !iu.wrapping_add(iv);
    if diagonal && iuv < last {
        iw = iw.wrapping_sub(1);
    }
    let b0 = !(iu ^ iw) & last;
    let t = (iu ^ iv) & b0;
    let mut f = t;
    f ^= f >> 1;
    f ^= f >> 2;
    f ^= f >> 4;
    f ^= f >> 8;
    let b1 = ((f ^ iu) & !b0) | t;
    interleave_16(b0) | (interleave_16(b1) << 1)
}

/// Spreads the low 16 bits of `x` to the even bit positions (the reference's
/// interleave; higher bits are partly lost, as in the reference).
fn interleave_16(x: u32) -> u32 {
    let mut x = x;
    x = (x | (x << 8)) & 0x00ff_00ff;
    x = (x | (x << 4)) & 0x0f0f_0f0f;
    x = (x | (x << 2)) & 0x3333_3333;
    x = (x | (x << 1)) & 0x5555_5555;
    x
}

/// The reference's steps over the reals, for rational `(u, v)`.
///
/// Each coordinate is clamped to `[0, 1]`, then `iu = floor(u * 2^level)`,
/// `uf = u * 2^level - iu` exactly (likewise for `v`), and the diagonal test
/// is the exact `uf + vf >= 1`. Levels `0..=16`.
///
/// ```
/// use micromap_index::{spec, Level};
/// use num_rational::BigRational;
/// let r = |s: &str| s.parse::<BigRational>().unwrap();
/// let level = Level::new(2).unwrap();
/// assert_eq!(spec::index_exact(&r("3/10"), &r("3/10"), level), Ok(5));
/// // On the diagonal of cell (0, 0) the point goes to the upside-down
/// // micro-triangle (index 1 at level 2).
/// assert_eq!(spec::index_exact(&r("1/8"), &r("1/8"), level), Ok(1));
/// ```
pub fn index_exact(u: &BigRational, v: &BigRational, level: Level) -> Result<u32, Error> {
    let level = level.at_most(MAX_LEVEL)?;
    let scale = BigRational::from_integer((1u32 << level.get()).into());
    let quantize = |x: &BigRational| {
        let x = clamp_rational(x) * &scale;
        let cell = x.floor();
        let fraction = x - &cell;
        // clamped to [0, 2^16]: always fits.
        let cell = cell.to_integer().to_u32().unwrap_or(u32::MAX);
        (cell, fraction)
    };
    let (iu, uf) = quantize(u);
    let (iv, vf) = quantize(v);
    let diagonal = uf + vf >= BigRational::one();
    Ok(index_from_cell(iu, iv, diagonal, level.get()))
}

fn clamp_rational(x: &BigRational) -> BigRational {
    if *x < BigRational::zero() {
        BigRational::zero()
    } else if *x > BigRational::one() {
        BigRational::one()
    } else {
        x.clone()
    }
}

/// The reference's steps over the reals for dyadic points `u = u_scaled /
/// 2^scale_log2`, `v = v_scaled / 2^scale_log2` with non-negative
/// numerators: the same result as [`index_exact`] on those rationals,
/// computed with integers only (this is what the lattice checks use).
///
/// Requires `scale_log2 <= 62` and `level <= 16`; coordinates above 1 are
/// clamped like the reference does.
///
/// ```
/// use micromap_index::{spec, Level};
/// let level = Level::new(2).unwrap();
/// // (1/8, 1/8) with 8 = 2^3.
/// assert_eq!(spec::index_exact_dyadic(1, 1, 3, level), Ok(1));
/// ```
pub fn index_exact_dyadic(
    u_scaled: u64,
    v_scaled: u64,
    scale_log2: u32,
    level: Level,
) -> Result<u32, Error> {
    let level = level.at_most(MAX_LEVEL)?;
    let one = 1u64 << scale_log2.min(62);
    let u = u_scaled.min(one);
    let v = v_scaled.min(one);
    let (iu, uf, iv, vf, one_fraction) = if scale_log2 >= level.get() {
        let shift = scale_log2 - level.get();
        let mask = (1u64 << shift) - 1;
        (u >> shift, u & mask, v >> shift, v & mask, 1u64 << shift)
    } else {
        // Coarser than the lattice: every point is on a lattice vertex.
        let shift = level.get() - scale_log2;
        (u << shift, 0, v << shift, 0, 1)
    };
    let diagonal = uf + vf >= one_fraction;
    Ok(index_from_cell(iu as u32, iv as u32, diagonal, level.get()))
}

/// Whether the reals `uf + vf` (exact) and the binary32 sum disagree about
/// `>= 1`; `uf`, `vf` are the reference's exact fractional parts. Used to
/// state precisely where [`index_f32`] and [`index_exact`] may differ.
pub fn rounding_flips_diagonal(uf: f32, vf: f32) -> bool {
    let exact = f64::from(uf) + f64::from(vf); // exact: both have 24-bit significands
    (exact >= 1.0) != diagonal_decision_f32(uf, vf)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounding_window_is_one_minus_two_to_minus_25() {
        let just_below = 1.0 - 2f64.powi(-25);
        // 0.5 + (0.5 - 2^-25): exact sum is 1 - 2^-25, rounds to even 1.0.
        let vf = (0.5 - 2f64.powi(-25)) as f32;
        assert_eq!(f64::from(vf) + 0.5, just_below);
        assert!(diagonal_decision_f32(0.5, vf));
        assert!(rounding_flips_diagonal(0.5, vf));
        // one ulp lower (spacing 2^-26 below 0.5) stays below 1.
        let lower = f32::from_bits(vf.to_bits() - 1);
        assert!(!diagonal_decision_f32(0.5, lower));
    }
}
