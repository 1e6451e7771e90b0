//! The Vulkan reference, `BarycentricsToSpaceFillingCurveIndex`.
//!
//! Ported from the "Reference Code" section of the appendix
//! `appendices/VK_EXT_opacity_micromap.adoc` (identical in
//! `VK_KHR_opacity_micromap.adoc`) of the Khronos Vulkan-Docs repository,
//! read at commit `090f1b190d60ced4a1d198fd3747d071cc271b1c` (Vulkan 1.4.360;
//! the function is unchanged since 2022 but for whitespace). That text is
//! `Copyright 2022-2023 The Khronos Group Inc.`,
//! `SPDX-License-Identifier: CC-BY-4.0`. The C original works on 32-bit
//! `float` and `uint32_t`; this port keeps every step and its order, and is
//! re-licensed here only as the crate's own code (MIT OR Apache-2.0) with this
//! attribution.
//!
//! # Guarantees
//!
//! * [`index_f32`] (also [`crate::index`]) returns, for **every** pair of
//!   `f32` values (NaN, ±0, ±inf, subnormals, values outside `[0, 1]`,
//!   `u + v > 1`) and every [`SpecLevel`] `0..=16`, the bits the reference
//!   returns on a GPU: its float operations are IEEE binary32 with
//!   round-to-nearest-even, `clamp` is `min(max(x, 0), 1)` where `max` and
//!   `min` return the non-NaN operand for every NaN, quiet or signalling (GPU
//!   max/min, SPIR-V `NMax`/`NMin`, IEEE 754-2019 `maximumNumber`), so every
//!   NaN becomes 0, the float-to-integer conversion truncates and all
//!   `uint32_t` arithmetic wraps.
//! * [`reference_bits_f32`] is the same port for any `u32` level: levels
//!   `17..=31` give the 32-bit code's (invalid) indices and levels `>= 32`,
//!   for which C's `1u << level` is undefined, use the shift count modulo 32
//!   as x86, ARM and SPIR-V hardware do. For fuzzers and emulators that must
//!   reproduce a driver's answer to an out-of-range level.
//! * [`index_f32_by_integers`] returns the same bits as [`index_f32`] for every
//!   input, computed from the float bits with integer operations only.
//! * `index_real` (feature `exact`) runs the same steps over the reals ("the
//!   rational reading of the spec"): exact products, floors and fractional
//!   parts, and an exact `uf + vf >= 1`. It differs from [`index_f32`] on a
//!   finite, in-range input only where binary32 rounds `uf + vf` up to
//!   `1.0`, i.e. when the exact sum lies in `[1 - 2^-25, 1)` (see
//!   [`diagonal_decision_f32`] and `docs/float.md`). [`index_dyadic`] is the
//!   same reading for dyadic inputs, with integers only.
//! * The `wide_*` functions run the reference's steps with 64-bit words
//!   ([`wide_index_from_cell`]): valid indices for every level `0..=32`;
//!   equal to the 32-bit functions for levels `0..=16`.
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
//! use micromap_index::{spec, SpecLevel};
//! let one = SpecLevel::new(1).unwrap();
//! // Level 1: left = 0, middle = 1, right = 2, top = 3.
//! assert_eq!(spec::index_f32(0.1, 0.1, one), 0);
//! assert_eq!(spec::index_f32(0.4, 0.4, one), 1);
//! assert_eq!(spec::index_f32(0.9, 0.05, one), 2);
//! assert_eq!(spec::index_f32(0.05, 0.9, one), 3);
//! // NaN clamps to 0, +inf to 1; (1, 1) is pulled back to (0, 1): the top.
//! assert_eq!(spec::index_f32(f32::NAN, f32::INFINITY, one), 3);
//! assert_eq!(spec::index_f32(f32::INFINITY, f32::INFINITY, one), 3);
//! ```

mod by_integers;
mod dyadic;
mod integer_half;
#[cfg(feature = "exact")]
mod real;

pub use by_integers::{index_f32_by_integers, reference_bits_f32_by_integers};
#[cfg(not(feature = "unstable-public-internals"))]
pub(crate) use dyadic::fractions_reach_one;
pub use dyadic::{cell_dyadic, index_dyadic, wide_index_dyadic, MAX_SCALE_LOG2};
#[cfg(feature = "unstable-public-internals")]
pub use dyadic::{dyadic_cell, fractions_reach_one};
#[cfg(not(feature = "unstable-public-internals"))]
pub(crate) use integer_half::CoordinateWord;
pub use integer_half::{index_from_cell, wide_index_from_cell};
#[cfg(feature = "unstable-public-internals")]
pub use integer_half::{
    reference_cell, reference_digits, CoordinateWord, ReferenceWord, NARROW_INTERLEAVE,
    NARROW_PREFIX_XOR, WIDE_INTERLEAVE, WIDE_PREFIX_XOR,
};
#[cfg(all(feature = "exact", feature = "unstable-public-internals"))]
pub use real::cell_real_ref;
#[cfg(feature = "exact")]
pub use real::{cell_real, index_real, wide_index_real};

use crate::kernel;
use crate::{Level, SpecLevel};

/// The highest level for which the 32-bit reference computes valid indices
/// (the same as [`SpecLevel::MAX`]).
pub const MAX_LEVEL: u32 = SpecLevel::MAX;

/// The index the Vulkan reference returns on a GPU for the hit `(u, v)`:
/// defined for every pair of `f32` (see the [module docs](self)).
///
/// The same bits as [`reference_bits_f32`] (the C code's steps literally),
/// computed by the point-by-point form of [`crate::batch`]'s branch-free
/// rewrite (the batch loops run it for short tails): the float clamp, the reference's own exact float steps for the
/// cell and fraction (a `2^23` rounding instead of a float-to-integer
/// conversion), its binary32 `uf + vf >= 1.0f`, and the integer half
/// without branches. In a caller's loop over slices it inlines and the
/// compiler vectorises it (SSE2 on the x86-64 baseline); one call at a time
/// it costs about what the literal port costs (`docs/performance.md`).
/// Checked against the literal port and the C reference on every structured
/// pair, the rounding window and random bits at every level
/// (`crates/lab/tests/batch.rs`, `c_oracle.rs`).
///
/// ```
/// use micromap_index::{spec, SpecLevel};
/// let level = SpecLevel::new(2).unwrap();
/// assert_eq!(spec::index_f32(0.3, 0.3, level), 5);
/// // binary32 rounds uf + vf = 1 - 2^-25 up to 1.0: the flipped triangle.
/// assert_eq!(spec::index_f32(0.125, 0.125 - 2f32.powi(-27), level), 1);
/// ```
#[inline]
#[must_use]
pub fn index_f32(u: f32, v: f32, level: SpecLevel) -> u32 {
    let params = kernel::Params::new(level.get(), kernel::BINARY32_THRESHOLD);
    kernel::narrow::<{ kernel::CELL_BY_FLOAT }>(u.to_bits(), v.to_bits(), &params)
}

/// The reference's bits in binary32 for any `u32` level, exactly as its C
/// code computes them: valid indices for levels `0..=16`, the 32-bit code's
/// wrong ones for `17..=31`, and `level % 32` above (see the
/// [module docs](self)). Prefer [`index_f32`] unless you must reproduce what
/// an implementation returns for a level it should have rejected.
///
/// ```
/// use micromap_index::spec;
/// assert_eq!(spec::reference_bits_f32(0.3, 0.3, 2), 5);
/// // Level 34 shifts like level 2 on x86, ARM and SPIR-V.
/// assert_eq!(spec::reference_bits_f32(0.3, 0.3, 34), 5);
/// ```
#[inline]
#[must_use]
pub fn reference_bits_f32(u: f32, v: f32, level: u32) -> u32 {
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

/// The reference's first half in binary32 (levels above 32 count as 32): clamp, scale
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
#[must_use]
pub fn cell_f32(u: f32, v: f32, level: u32) -> Cell {
    // `(float)(1u << level)`: exact for every power of two up to 2^32.
    let scale = (1u64 << level.min(32)) as f32;
    let (iu, uf) = truncate_scaled(clamp_unit(u) * scale);
    let (iv, vf) = truncate_scaled(clamp_unit(v) * scale);
    Cell {
        iu,
        iv,
        diagonal: diagonal_decision_f32(uf, vf),
    }
}

unstable_pub_fn! {
    /// The reference's `iu = (uint32_t)fu` and `uf = fu - float(iu)` for
    /// `fu` in `[0, 2^32]` (every product [`cell_f32`] forms; the lab checks
    /// both at each of them, `docs/verification.md` 10.12): the cast
    /// truncates like C's, through `i64` (exact on that range), whose
    /// conversions are single x86-64 instructions (`u64`'s need fix-ups
    /// for values this cannot reach).
    #[inline]
    #[must_use]
    fn truncate_scaled(fu: f32) -> (u64, f32) {
        let cell = fu as i64 as u64;
        (cell, fu - cell as i64 as f32)
    }
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
#[must_use]
pub fn diagonal_decision_f32(uf: f32, vf: f32) -> bool {
    uf + vf >= 1.0
}

unstable_pub_fn! {
    /// `x` clamped to `[0, 1]` as `min(max(x, 0), 1)`, every NaN → 0: Rust's
    /// `f32::max` returns the non-NaN operand even for a signalling NaN, like GPU
    /// max/min. (C's `fmaxf` under IEEE 754-2008 `maxNum` returns NaN for a
    /// signalling NaN, so a libm-based C build would map it to 1 instead; the C
    /// oracle in `reference/` clamps with comparisons for that reason.)
    #[allow(clippy::manual_clamp)] // `f32::clamp` keeps NaN; the reference must not
    #[inline]
    #[must_use]
    fn clamp_unit(x: f32) -> f32 {
        x.max(0.0).min(1.0)
    }
}

/// The reference's steps widened to 64 bits ([`wide_index_from_cell`]) in
/// binary32: for every pair of `f32` and every level `0..=32`, the index the
/// reference would compute with wide enough words. Equal to [`index_f32`]
/// for levels `0..=16`.
///
/// ```
/// use micromap_index::{spec, uv2index, Level};
/// assert_eq!(spec::wide_index_f32(0.3, 0.3, Level::new(2).unwrap()), 5);
/// // At level 32 it agrees with the exact walk (away from binary32's
/// // rounding window of `uf + vf`).
/// let top = Level::new(32).unwrap();
/// for (u, v) in [(1.0, 0.0), (0.0, 1.0), (0.1, 0.2), (0.0, 0.0)] {
///     assert_eq!(spec::wide_index_f32(u, v, top), uv2index::exact_index_f32(u, v, top).unwrap());
/// }
/// ```
#[inline]
#[must_use]
pub fn wide_index_f32(u: f32, v: f32, level: Level) -> u64 {
    let cell = cell_f32(u, v, level.get());
    wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, level.get())
}

unstable_pub_fn! {
    /// Whether the reals `uf + vf` (exact) and the binary32 sum disagree about
    /// `>= 1`; `uf`, `vf` are the reference's exact fractional parts: where
    /// [`index_f32`] and the real reading may differ (for the tests).
    #[must_use]
    fn rounding_flips_diagonal(uf: f32, vf: f32) -> bool {
        let exact = f64::from(uf) + f64::from(vf); // exact: both have 24-bit significands
        (exact >= 1.0) != diagonal_decision_f32(uf, vf)
    }
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
