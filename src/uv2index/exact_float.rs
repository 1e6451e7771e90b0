//! The exact walk's answer for every finite float, with integers only, at
//! the cost of the reference's steps.
//!
//! # Why the reference's steps give the walk's answer
//!
//! `docs/verification.md` proves that at every real point of the closed
//! triangle the walk equals the reference's steps read over the reals
//! (exact `floor`, fractions and `uf + vf >= 1`) with the integer half
//! widened to 64-bit words, at every level `0..=32` at once (section 10:
//! the product of two digit transducers). Those steps are exact integer
//! operations on a float's bits, proved equal to their definition at every
//! binary32 and binary64 input and level (section 10.12):
//!
//! * the cell `floor(x * 2^level)` is the significand shifted by the
//!   exponent;
//! * the fractions are kept floored to 31 (binary32) or 62 (binary64) bits,
//!   and `uf + vf >= 1` is decided on them exactly: a fraction loses bits
//!   only when it is tiny (below `2^-7`, resp. `2^-9`, as it has at most
//!   24, resp. 53, significant bits), and then the other is exact, so the
//!   floored sum is the integer part of the real sum (in units of the last
//!   kept bit) and reaches the integer threshold exactly when the real sum
//!   does.
//!
//! So [`exact_index_f32`] and [`exact_index_f64`] run those steps at every
//! level. (Until the all-levels proof they did only up to level 19, where
//! lattice checks covered them, and walked above.)
//!
//! # The walk, the oracle
//!
//! The walk only compares the point against lattice lines (`u = k/2^level`,
//! `v = k/2^level`, `u + v = k/2^level`), so any point in the same lattice
//! face gives the same index: it does not need every bit of the input. Each
//! coordinate is rounded down to `P - 1` fractional bits and a *sticky* bit,
//! set when anything was cut off, is appended as the `P`-th bit. Per
//! coordinate this preserves the side of every line at multiples of
//! `2^-(P-1)`; for the sum it does so as long as `P >= level + 26` (binary32
//! inputs, 24-bit significands) or `P >= level + 55` (binary64, 53 bits):
//! both coordinates can only carry a sticky bit when both are below
//! `2^(s+1-P)` (`s` the significand width), so their sum stays below the
//! first lattice line. `docs/fixed.md` spells the argument out. With `P = 60`
//! ([`Fixed64`], binary32) and `P = 124` ([`Fixed128`], binary64) every level
//! up to 32 is covered. That walk (`exact_index_f32_ref`,
//! `exact_index_f64_ref`, in `internals` with the
//! `unstable-public-internals` feature) is what the closed form is tested
//! against: a second implementation by other means.

use super::index_unchecked;
use crate::kernel::{self, Params};
use crate::num::fixed::sticky_scaled;
use crate::num::{Fixed128, Fixed64, WalkNumber};
use crate::spec::Cell;
use crate::{Error, Level};

/// The exact walk's index for a finite binary32 point: equal to the walk
/// over the reals (`index_real`, feature `exact`) at the same point, for
/// every level `0..=32`, with integers only. NaN ([`Error::NotANumber`]),
/// infinities ([`Error::Infinite`]) and points outside the closed triangle
/// ([`Error::OutsideTriangle`], decided exactly) are errors.
///
/// Every level uses the reference's steps on the float's bits (proved
/// equal to the walk; the argument is in `src/uv2index/exact_float.rs` and
/// `docs/verification.md`), in 32-bit words up to level 16.
///
/// ```
/// use micromap_index::{uv2index, Error, Level, Outside};
/// let level = Level::new(2).unwrap();
/// assert_eq!(uv2index::exact_index_f32(0.3, 0.3, level), Ok(5));
/// // (1/4, 1/4) lies on a lattice vertex; the walk puts it in triangle 5.
/// assert_eq!(uv2index::exact_index_f32(0.25, 0.25, level), Ok(5));
/// assert_eq!(
///     uv2index::exact_index_f32(1.0, f32::from_bits(1), level),
///     Err(Error::OutsideTriangle { reason: Outside::SumAboveOne })
/// );
/// ```
#[inline]
pub fn exact_index_f32(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    // Widening to binary64 is exact and keeps the order and the sign.
    if !surely_inside(f64::from(u), f64::from(v)) {
        f32::check_point(&u, &v)?;
    }
    if level.get() <= crate::spec::MAX_LEVEL {
        let params = Params::new(level.get(), kernel::EXACT_THRESHOLD);
        // The point is in the triangle: without the sign bit (-0.0 is the
        // only coordinate in it that has one), both are in [0, 1].
        let unit_bits = |x: f32| x.to_bits() & 0x7fff_ffff;
        Ok(u64::from(kernel::narrow_in_unit(
            unit_bits(u),
            unit_bits(v),
            &params,
        )))
    } else {
        let params = Params::new(level.get(), kernel::EXACT_THRESHOLD);
        Ok(kernel::wide(u.to_bits(), v.to_bits(), &params))
    }
}

/// The common case of the triangle test, in one branch: `true` only for a
/// point of the triangle with both coordinates in `[+0, 1]`. Bits of
/// non-negative floats order like the floats (-0.0, NaN and everything
/// negative are above 1.0's bits), and a binary64 sum below 1 means a real
/// sum below 1 (rounding is monotonic and 1 is representable). Everything
/// else, a sum of exactly 1 included, takes the full check.
#[inline]
fn surely_inside(u: f64, v: f64) -> bool {
    let one = 1f64.to_bits();
    #[allow(clippy::needless_bitwise_bool)] // `&`, not `&&`: one branch
    let inside = (u.to_bits() <= one) & (v.to_bits() <= one) & (u + v < 1.0);
    inside
}

/// The exact walk's index for a finite binary64 point: equal to the walk
/// over the reals at the same point, for every level `0..=32`, with
/// integers only (computed like [`exact_index_f32`], in 64-bit words).
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::exact_index_f64(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
#[inline]
pub fn exact_index_f64(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    if !surely_inside(u, v) {
        f64::check_point(&u, &v)?;
    }
    Ok(closed_form_f64(u, v, level))
}

unstable_pub_fn! {
    /// [`exact_index_f32`] by the walk itself on [`Fixed64`] (`level`
    /// steps): the oracle the closed form is checked against.
    fn exact_index_f32_ref(u: f32, v: f32, level: Level) -> Result<u64, Error> {
        let (u, v) = (f64::from(u), f64::from(v));
        f64::check_point(&u, &v)?;
        let p = Fixed64::ONE_LOG2;
        // In [0, 2^60]: fits.
        let to_fixed = |x| Fixed64::from_raw(sticky_scaled(x, p) as i64);
        Ok(index_unchecked(to_fixed(u), to_fixed(v), level))
    }
}

unstable_pub_fn! {
    /// [`exact_index_f64`] by the walk itself on [`Fixed128`]: the oracle.
    fn exact_index_f64_ref(u: f64, v: f64, level: Level) -> Result<u64, Error> {
        f64::check_point(&u, &v)?;
        let p = Fixed128::ONE_LOG2;
        let to_fixed = |x| Fixed128::from_raw(sticky_scaled(x, p));
        Ok(index_unchecked(to_fixed(u), to_fixed(v), level))
    }
}

/// The reference's exact steps, widened, on a binary64 point (clamped like
/// the reference).
#[inline]
fn closed_form_f64(u: f64, v: f64, level: Level) -> u64 {
    let last = ((1u64 << level.get()) - 1) as u32;
    let (iu, uf) = binary64_clamped_coordinate(u.to_bits(), level.get());
    let (iv, vf) = binary64_clamped_coordinate(v.to_bits(), level.get());
    // Both cells are at most `last < 2^32` (proved with the rest of the
    // coordinate): the casts keep them.
    let (iu, iv) = (iu as u32, iv as u32);
    let diagonal = binary64_diagonal(uf, vf);
    if level.get() <= crate::spec::MAX_LEVEL {
        // The same answer (the wide form's extra steps are no-ops below
        // level 17) with one interleave instead of two.
        u64::from(kernel::narrow_from_clamped_cell(iu, iv, diagonal, last))
    } else {
        kernel::wide_from_clamped_cell(iu, iv, diagonal, last)
    }
}

/// Fraction bits kept of a binary64 coordinate's fraction.
const F64_FRACTION_BITS: u32 = 62;
/// `1` in units of the last kept fraction bit.
const F64_ONE: u64 = 1 << F64_FRACTION_BITS;

/// The cell `floor(x * 2^level)` (at most `2^32`) and
/// `floor(fraction * 2^62)` of `x` clamped to `[0, 1]` (NaN and negatives to
/// 0): [`binary64_coordinate`] on the bits.
#[inline]
fn coordinate_f64(x: f64, level: u32) -> (u64, u64) {
    binary64_coordinate(x.to_bits(), level)
}

/// The steps of `coordinate_f64` on the bits of a binary64, generic over
/// the word, every level `0..=32`. `x = m * 2^(e - 1075)` with `m < 2^53`
/// and `e <= 1023` after the clamp, so `x * 2^level = m / 2^s` with `s =
/// 1075 - level - e >= 20`: the cell is `m >> s` and the fraction's 62 bits
/// are `m << (62 - s)` (bits above 62 dropped) for `s <= 62`, else `m >>
/// (s - 62)`; a shift by 64 or more gives 0.
#[inline(always)]
pub fn binary64_coordinate<W: crate::spec::CoordinateWord>(bits: W, level: u32) -> (W, W) {
    let one = W::constant(1f64.to_bits());
    let clamped = if bits.at_least(W::constant(0x7ff0_0000_0000_0001)) {
        W::constant(0) // NaN or negative
    } else if bits.at_least(one) {
        one
    } else {
        bits
    };
    let biased = clamped.shift_right(52).low_u32();
    let hidden = W::constant(if biased == 0 { 0 } else { 1 << 52 });
    let m = clamped.and(W::constant((1 << 52) - 1)).or(hidden);
    let s = 1075 - level - biased.max(1);
    let shifted_right = |count: u32| {
        if count < 64 {
            m.shift_right(count)
        } else {
            W::constant(0)
        }
    };
    let fraction = if s <= F64_FRACTION_BITS {
        m.shift_left(F64_FRACTION_BITS - s)
            .and(W::constant(F64_ONE - 1))
    } else {
        shifted_right(s - F64_FRACTION_BITS)
    };
    (shifted_right(s), fraction)
}

/// [`binary64_coordinate`] with the cell clamped to `last = 2^level - 1`
/// as the reference clamps it (`x >= 1` has cell `2^level`, the one cell
/// past `last`): what `exact_index_f64` runs, proved whole by the lab
/// (`docs/verification.md` 10.12).
#[inline(always)]
pub fn binary64_clamped_coordinate<W: crate::spec::CoordinateWord>(bits: W, level: u32) -> (W, W) {
    let (cell, fraction) = binary64_coordinate(bits, level);
    let last = W::constant((1u64 << level) - 1);
    let cell = if cell.at_least(W::power_of_two(level)) {
        last
    } else {
        cell
    };
    (cell, fraction)
}

/// The diagonal test on two coordinates' 62-bit fractions:
/// `uf + vf >= 2^62`, by the reference's generic dyadic test.
#[inline(always)]
pub fn binary64_diagonal<W: crate::spec::CoordinateWord>(uf: W, vf: W) -> bool {
    crate::spec::fractions_reach_one(uf, vf, W::constant(F64_ONE - 1))
}

unstable_pub_fn! {
    /// The reference's first half over the reals for a binary32 point, from
    /// its bits: equal to `spec::cell_real` (feature `exact`) on the float's
    /// exact value (clamped to `[0, 1]`, NaN to 0), every level `0..=32`.
    /// With [`spec::wide_index_from_cell`](crate::spec::wide_index_from_cell)
    /// it is the closed form of the module docs at any level (for the tests).
    #[must_use]
    fn cell_real_f32(u: f32, v: f32, level: Level) -> Cell {
        cell_real_f64(f64::from(u), f64::from(v), level)
    }
}

unstable_pub_fn! {
    /// [`cell_real_f32`] for a binary64 point.
    #[must_use]
    fn cell_real_f64(u: f64, v: f64, level: Level) -> Cell {
        let (iu, uf) = coordinate_f64(u, level.get());
        let (iv, vf) = coordinate_f64(v, level.get());
        Cell {
            iu,
            iv,
            diagonal: binary64_diagonal(uf, vf),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_form_equals_the_walk_on_lattice_points() {
        // Vertices, edge midpoints and cell centres of levels 0..=5, at
        // levels up to 22 (both sides of the switch to the walk).
        for level in 0..=22 {
            let level = Level::new(level).unwrap();
            for a in 0..=64u32 {
                for b in 0..=(64 - a) {
                    let (u, v) = (a as f32 / 64.0, b as f32 / 64.0);
                    assert_eq!(
                        exact_index_f32(u, v, level),
                        exact_index_f32_ref(u, v, level),
                        "f32 ({u}, {v}) level {level}"
                    );
                    let (u, v) = (f64::from(u), f64::from(v));
                    assert_eq!(
                        exact_index_f64(u, v, level),
                        exact_index_f64_ref(u, v, level),
                        "f64 ({u}, {v}) level {level}"
                    );
                }
            }
        }
    }

    #[test]
    fn f64_coordinates_split_cell_and_fraction() {
        assert_eq!(coordinate_f64(0.75, 1), (1, 1 << 61));
        assert_eq!(coordinate_f64(1.0, 32), (1 << 32, 0));
        assert_eq!(coordinate_f64(f64::NAN, 3), (0, 0));
        assert_eq!(coordinate_f64(-0.5, 3), (0, 0));
        assert_eq!(coordinate_f64(2.0, 3), (8, 0));
        // 2^-70 at level 0: floors to 0 at 62 bits.
        assert_eq!(coordinate_f64(2f64.powi(-70), 0), (0, 0));
        assert_eq!(coordinate_f64(2f64.powi(-62), 0), (0, 1));
    }
}
