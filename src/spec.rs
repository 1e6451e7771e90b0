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
//!   with round-to-nearest-even, `clamp` is `min(max(x, 0), 1)` where `max`
//!   and `min` return the non-NaN operand for every NaN, quiet or signalling
//!   (GPU max/min, SPIR-V `NMax`/`NMin`, IEEE 754-2019 `maximumNumber`), so
//!   every NaN becomes 0, the float-to-integer conversion
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
#[cfg(feature = "std")]
use num_bigint::BigInt;
#[cfg(feature = "std")]
use num_rational::BigRational;
#[cfg(feature = "std")]
use num_traits::{One, ToPrimitive, Zero};

/// The highest level for which the reference computes valid indices.
pub const MAX_LEVEL: u32 = 16;

/// The reference in binary32, total: defined for every input (see the
/// module docs for levels above 16).
#[inline]
pub fn index_f32(u: f32, v: f32, level: u32) -> u32 {
    let level = level % 32; // C's `1u << level` as x86 / SPIR-V hardware shifts
    let cell = cell_f32(u, v, level);
    // level < 32: the cells are below 2^31 + 1 and fit u32 exactly.
    index_from_cell(cell.iu as u32, cell.iv as u32, cell.diagonal, level)
}

/// The reference's quantization: the grid cell of the clamped point at
/// `level` and the outcome of the diagonal test, before any integer step.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cell {
    /// `trunc(u * 2^level)` of the clamped `u` (not yet clamped to the grid).
    pub iu: u64,
    /// `trunc(v * 2^level)` of the clamped `v`.
    pub iv: u64,
    /// The outcome of `uf + vf >= 1` (in the arithmetic of the variant).
    pub diagonal: bool,
}

/// The reference's first half in binary32, for `level <= 32`: clamp, scale
/// by `2^level` (exact), truncate, take the exact fractions and decide
/// `uf + vf >= 1.0f` after binary32 rounding.
///
/// ```
/// use micromap_index::spec::{cell_f32, Cell};
/// assert_eq!(cell_f32(0.25, 0.5, 1), Cell { iu: 0, iv: 1, diagonal: false });
/// assert_eq!(cell_f32(0.375, 0.125, 2), Cell { iu: 1, iv: 0, diagonal: true });
/// assert_eq!(cell_f32(f32::NAN, 2.0, 3), Cell { iu: 0, iv: 8, diagonal: false });
/// ```
#[inline]
pub fn cell_f32(u: f32, v: f32, level: u32) -> Cell {
    let u = clamp_unit(u);
    let v = clamp_unit(v);
    // `(float)(1u << level)`: exact for every power of two up to 2^32.
    let scale = (1u64 << level.min(32)) as f32;
    let fu = u * scale;
    let fv = v * scale;
    // `fu`, `fv` are in [0, 2^32]: the cast truncates like C's. Through
    // `i64` (exact on that range), whose conversions are single x86-64
    // instructions; `u64`'s need fix-ups for values this cannot reach.
    let iu = fu as i64 as u64;
    let iv = fv as i64 as u64;
    let uf = fu - iu as i64 as f32;
    let vf = fv - iv as i64 as f32;
    Cell {
        iu,
        iv,
        diagonal: diagonal_decision_f32(uf, vf),
    }
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
#[inline]
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
#[inline]
pub fn diagonal_decision_f32(uf: f32, vf: f32) -> bool {
    uf + vf >= 1.0
}

/// `x` clamped to `[0, 1]` as `min(max(x, 0), 1)`, every NaN → 0: Rust's
/// `f32::max` returns the non-NaN operand even for a signalling NaN, like GPU
/// max/min. (C's `fmaxf` under IEEE 754-2008 `maxNum` returns NaN for a
/// signalling NaN, so a libm-based C build would map it to 1 instead; the C
/// oracle in `reference/` clamps with comparisons for that reason.)
#[allow(clippy::manual_clamp)] // `f32::clamp` keeps NaN; the reference must not
#[inline]
fn clamp_unit(x: f32) -> f32 {
    x.max(0.0).min(1.0)
}

/// Generates the integer half of the reference for one word width: from the
/// (unclamped) grid cell `(iu, iv)` = `(trunc(u * 2^level), trunc(v * 2^level))`
/// and the outcome of the diagonal test `uf + vf >= 1`, the curve index. All
/// arithmetic wraps like C's unsigned types; the prefix-XOR shifts and the
/// interleave steps are the width's parameters.
macro_rules! integer_half {
    (
        $(#[$doc:meta])*
        $name:ident, $uint:ty, prefix_xor: [$($prefix:expr),*],
        interleave: [$(($shift:expr, $mask:expr)),*]
    ) => {
        $(#[$doc])*
        #[inline]
        pub fn $name(iu: $uint, iv: $uint, diagonal: bool, level: u32) -> $uint {
            let cells = (1 as $uint).wrapping_shl(level);
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
            $(f ^= f >> $prefix;)*
            let b1 = ((f ^ iu) & !b0) | t;
            let spread = |x: $uint| {
                let mut x = x;
                $(x = (x | (x << $shift)) & $mask;)*
                x
            };
            spread(b0) | (spread(b1) << 1)
        }
    };
}

integer_half!(
    /// The reference's integer half, exactly as the Vulkan code has it: 32-bit
    /// words, a 16-bit prefix-XOR and interleave (so only levels `0..=16` give
    /// valid indices); shifts by `level >= 32` use `level % 32`.
    ///
    /// Every narrow variant (binary32, exact, dyadic) computes its [`Cell`] its
    /// own way and shares this function.
    ///
    /// ```
    /// use micromap_index::spec::index_from_cell;
    /// // Level 1, cell (0, 0): lower-left half is the left child, upper-right
    /// // half is the middle child.
    /// assert_eq!(index_from_cell(0, 0, false, 1), 0);
    /// assert_eq!(index_from_cell(0, 0, true, 1), 1);
    /// ```
    index_from_cell,
    u32,
    prefix_xor: [1, 2, 4, 8],
    interleave: [(8, 0x00ff_00ff), (4, 0x0f0f_0f0f), (2, 0x3333_3333), (1, 0x5555_5555)]
);

integer_half!(
    /// The integer half widened to 64-bit words: one more prefix-XOR step
    /// (32-bit prefix) and a 32-bit interleave, so every level `0..=32` has a
    /// valid index (`4^32` indices fill a `u64`; level 33 would need more
    /// than 64 index bits). For levels `0..=16` it equals [`index_from_cell`].
    ///
    /// ```
    /// use micromap_index::spec::{index_from_cell, index_from_cell_wide};
    /// assert_eq!(index_from_cell_wide(5, 9, true, 4), u64::from(index_from_cell(5, 9, true, 4)));
    /// ```
    index_from_cell_wide,
    u64,
    prefix_xor: [1, 2, 4, 8, 16],
    interleave: [
        (16, 0x0000_ffff_0000_ffff),
        (8, 0x00ff_00ff_00ff_00ff),
        (4, 0x0f0f_0f0f_0f0f_0f0f),
        (2, 0x3333_3333_3333_3333),
        (1, 0x5555_5555_5555_5555)
    ]
);

#[cfg(feature = "std")]
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
    let cell = cell_exact(u, v, level);
    // level <= 16: cells are at most 2^16.
    Ok(index_from_cell(
        cell.iu as u32,
        cell.iv as u32,
        cell.diagonal,
        level.get(),
    ))
}

#[cfg(feature = "std")]
/// The reference's first half over the reals: clamp to `[0, 1]`, exact
/// floor and fractions of `x * 2^level`, exact `uf + vf >= 1`.
///
/// Runs on machine integers when both coordinates fit over a common
/// denominator below `2^64` (see [`crate::rational`]), on [`BigRational`]
/// otherwise; [`cell_exact_ref`] is the all-BigRational twin.
///
/// ```
/// use micromap_index::{spec::{cell_exact, Cell}, Level};
/// let r = |s: &str| s.parse().unwrap();
/// // (1/3, 2/3) at level 1: cell (0, 1), fractions 2/3 + 1/3 >= 1.
/// assert_eq!(cell_exact(&r("1/3"), &r("2/3"), Level::new(1).unwrap()), Cell { iu: 0, iv: 1, diagonal: true });
/// ```
pub fn cell_exact(u: &BigRational, v: &BigRational, level: Level) -> Cell {
    let Some((u, v, denominator)) = crate::rational::over_common_denominator(u, v) else {
        return cell_exact_ref(u, v, level);
    };
    let d = u128::from(denominator);
    // Clamped numerators are at most d <= 2^64; times 2^32 fits u128.
    let clamp = |a: i128| u128::try_from(a).unwrap_or(0).min(d) << level.get();
    let (su, sv) = (clamp(u), clamp(v));
    Cell {
        iu: (su / d) as u64,
        iv: (sv / d) as u64,
        diagonal: su % d + sv % d >= d,
    }
}

#[cfg(feature = "std")]
/// [`cell_exact`] computed entirely on [`BigRational`].
pub fn cell_exact_ref(u: &BigRational, v: &BigRational, level: Level) -> Cell {
    let scale = BigRational::from_integer(BigInt::one() << level.get());
    let quantize = |x: &BigRational| {
        let x = clamp_rational(x) * &scale;
        let cell = x.floor();
        let fraction = x - &cell;
        // clamped to [0, 2^32]: always fits.
        let cell = cell.to_integer().to_u64().unwrap_or(u64::MAX);
        (cell, fraction)
    };
    let (iu, uf) = quantize(u);
    let (iv, vf) = quantize(v);
    Cell {
        iu,
        iv,
        diagonal: uf + vf >= BigRational::one(),
    }
}

#[cfg(feature = "std")]
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
#[inline]
pub fn index_exact_dyadic(
    u_scaled: u64,
    v_scaled: u64,
    scale_log2: u32,
    level: Level,
) -> Result<u32, Error> {
    let level = level.at_most(MAX_LEVEL)?;
    let cell = cell_dyadic(u_scaled, v_scaled, scale_log2, level);
    Ok(index_from_cell(
        cell.iu as u32,
        cell.iv as u32,
        cell.diagonal,
        level.get(),
    ))
}

/// [`cell_exact`] for the dyadic point `(u_scaled, v_scaled) / 2^scale_log2`
/// with integers only (`scale_log2 <= 62`; coordinates above 1 clamp to 1).
///
/// ```
/// use micromap_index::{spec::{cell_dyadic, Cell}, Level};
/// // (3/8, 5/8) at level 2: cell (1, 2), fractions 1/2 + 1/2 >= 1.
/// assert_eq!(cell_dyadic(3, 5, 3, Level::new(2).unwrap()), Cell { iu: 1, iv: 2, diagonal: true });
/// ```
#[inline]
pub fn cell_dyadic(u_scaled: u64, v_scaled: u64, scale_log2: u32, level: Level) -> Cell {
    let scale_log2 = scale_log2.min(62);
    let one = 1u64 << scale_log2;
    let u = u_scaled.min(one);
    let v = v_scaled.min(one);
    if scale_log2 >= level.get() {
        let shift = scale_log2 - level.get();
        let mask = (1u64 << shift) - 1;
        Cell {
            iu: u >> shift,
            iv: v >> shift,
            diagonal: (u & mask) + (v & mask) > mask,
        }
    } else {
        // Coarser than the lattice: every such point is a lattice vertex.
        let shift = level.get() - scale_log2;
        Cell {
            iu: u << shift,
            iv: v << shift,
            diagonal: false,
        }
    }
}

/// The reference's steps widened to 64 bits ([`index_from_cell_wide`]) in
/// binary32: for every pair of `f32` and every level `0..=32`, the index the
/// reference would compute with wide enough words. Equal to [`index_f32`]
/// for levels `0..=16`.
///
/// ```
/// use micromap_index::{fixed, spec, Level};
/// assert_eq!(spec::index_wide_f32(0.3, 0.3, Level::new(2).unwrap()), 5);
/// // At level 32 it agrees with the exact walk (away from binary32's
/// // rounding window of `uf + vf`).
/// let top = Level::new(32).unwrap();
/// for (u, v) in [(1.0, 0.0), (0.0, 1.0), (0.1, 0.2), (0.0, 0.0)] {
///     assert_eq!(spec::index_wide_f32(u, v, top), fixed::index_f32(u, v, top).unwrap());
/// }
/// ```
#[inline]
pub fn index_wide_f32(u: f32, v: f32, level: Level) -> u64 {
    let cell = cell_f32(u, v, level.get());
    index_from_cell_wide(cell.iu, cell.iv, cell.diagonal, level.get())
}

#[cfg(feature = "std")]
/// The reference's steps over the reals, widened to 64 bits: levels `0..=32`.
/// Equal to [`index_exact`] for levels `0..=16`.
pub fn index_wide_exact(u: &BigRational, v: &BigRational, level: Level) -> u64 {
    let cell = cell_exact(u, v, level);
    index_from_cell_wide(cell.iu, cell.iv, cell.diagonal, level.get())
}

/// [`index_wide_exact`] for dyadic points, with integers only (see
/// [`cell_dyadic`]).
#[inline]
pub fn index_wide_dyadic(u_scaled: u64, v_scaled: u64, scale_log2: u32, level: Level) -> u64 {
    let cell = cell_dyadic(u_scaled, v_scaled, scale_log2, level);
    index_from_cell_wide(cell.iu, cell.iv, cell.diagonal, level.get())
}

/// Whether the reals `uf + vf` (exact) and the binary32 sum disagree about
/// `>= 1`; `uf`, `vf` are the reference's exact fractional parts. Used to
/// state precisely where [`index_f32`] and [`index_exact`] may differ.
#[inline]
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
