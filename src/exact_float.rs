//! The exact walk's index for float inputs at the cost of the reference's
//! steps: for every finite point of the closed triangle, the index
//! [`uv2index::index_exact`] returns on the real number the floats denote,
//! computed from the floats' bits with a few integer operations.
//!
//! # Why the reference's steps give the walk's answer
//!
//! `docs/verification.md` proves that at every real point of the closed
//! triangle the walk equals the reference's steps read over the reals
//! (exact `floor`, fractions and `uf + vf >= 1`) with the integer half
//! widened to 64-bit words: for levels `0..=16` (the reference's own) and
//! `17..=19` (spec-wide), by checking one point of every face of the level's
//! lattice. Those steps are exact integer operations on a float's bits:
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
//! For levels `20..=32` the closed form is only sampled (10^9 random faces
//! per level, `docs/verification.md` section 7), not proved; there these
//! functions run the walk itself ([`fixed::index_f32_ref`],
//! [`fixed::index_f64_ref`]), so every level keeps the proved guarantee.
//! [`cell_f32`] and [`cell_f64`] with
//! [`spec::index_from_cell_wide`](crate::spec::index_from_cell_wide) give the
//! closed form at any level for callers who accept that evidence.
//!
//! ```
//! use micromap_index::{exact_float, fixed, Level};
//! let level = Level::new(12).unwrap();
//! // A subnormal v and a point on a lattice line.
//! for (u, v) in [(0.1f32, f32::from_bits(1)), (0.25, 0.5), (0.0, 1.0)] {
//!     assert_eq!(exact_float::index_f32(u, v, level), fixed::index_f32_ref(u, v, level));
//! }
//! ```
//!
//! [`uv2index::index_exact`]: crate::uv2index::index_exact
//! [`fixed::index_f32_ref`]: crate::fixed::index_f32_ref
//! [`fixed::index_f64_ref`]: crate::fixed::index_f64_ref

use crate::batch::kernel::{self, Params};
use crate::spec::Cell;
use crate::uv2index::WalkNumber;
use crate::{Error, Level};

/// The highest level at which the reference's closed form is proved equal
/// to the walk at every real point (exhaustive lattice checks,
/// `docs/verification.md`); above it [`index_f32`] and [`index_f64`] walk.
pub const CLOSED_FORM_PROVED_MAX_LEVEL: u32 = 19;

/// The exact walk's index of the finite binary32 point `(u, v)`, levels
/// `0..=32`: equal to [`uv2index::index_exact`](crate::uv2index::index_exact)
/// on the same real point and to [`fixed::index_f32_ref`](crate::fixed::index_f32_ref).
/// NaN ([`Error::NotANumber`]), infinities ([`Error::Infinite`]) and points
/// outside the closed triangle ([`Error::OutsideTriangle`], decided exactly)
/// are errors.
///
/// Levels up to [`CLOSED_FORM_PROVED_MAX_LEVEL`] use the closed form (see
/// the module docs; in 32-bit words up to level 16), higher ones the walk.
///
/// ```
/// use micromap_index::{exact_float, Error, Level, Outside};
/// let level = Level::new(2).unwrap();
/// assert_eq!(exact_float::index_f32(0.3, 0.3, level), Ok(5));
/// // (1/4, 1/4) lies on a lattice vertex; the walk puts it in triangle 5.
/// assert_eq!(exact_float::index_f32(0.25, 0.25, level), Ok(5));
/// assert_eq!(
///     exact_float::index_f32(1.0, f32::from_bits(1), level),
///     Err(Error::OutsideTriangle { reason: Outside::SumAboveOne })
/// );
/// ```
#[inline]
pub fn index_f32(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    // Bits of non-negative floats order like the floats; -0.0, NaN and
    // everything negative are above 1.0's bits and take the full check.
    let one = 1f32.to_bits();
    let simple = u.to_bits() <= one && v.to_bits() <= one && !sum_above_one(u, v);
    if !simple {
        f32::check_point(&u, &v)?;
    }
    if level.get() <= crate::spec::MAX_LEVEL {
        let params = Params::new(level.get(), kernel::EXACT_THRESHOLD);
        Ok(u64::from(kernel::narrow::<false>(
            u.to_bits(),
            v.to_bits(),
            &params,
        )))
    } else if level.get() <= CLOSED_FORM_PROVED_MAX_LEVEL {
        Ok(closed_form_f32(u, v, level))
    } else {
        crate::fixed::index_f32_ref(u, v, level)
    }
}

/// `u + v > 1` exactly, for `u, v` in `[0, 1]`: the binary64 sum rounds
/// monotonically and 1 is representable, so only a sum that rounds to
/// exactly 1 needs its rounding error (Knuth's two-sum, exact here).
#[inline]
fn sum_above_one(u: f32, v: f32) -> bool {
    let (u, v) = (f64::from(u), f64::from(v));
    let sum = u + v;
    if sum != 1.0 {
        return sum > 1.0;
    }
    let v_part = sum - u;
    let u_part = sum - v_part;
    (u - u_part) + (v - v_part) > 0.0
}

/// [`index_f32`] for binary64 points: equal to
/// [`fixed::index_f64_ref`](crate::fixed::index_f64_ref) and to the exact
/// walk on the same real point.
///
/// ```
/// use micromap_index::{exact_float, Level};
/// assert_eq!(exact_float::index_f64(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
#[inline]
pub fn index_f64(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    f64::check_point(&u, &v)?;
    if level.get() <= CLOSED_FORM_PROVED_MAX_LEVEL {
        Ok(closed_form_f64(u, v, level))
    } else {
        crate::fixed::index_f64_ref(u, v, level)
    }
}

/// The reference's exact steps, widened, on a binary32 point (clamped like
/// the reference), via the batch kernel with the exact diagonal threshold.
#[inline]
fn closed_form_f32(u: f32, v: f32, level: Level) -> u64 {
    let params = Params::new(level.get(), kernel::EXACT_THRESHOLD);
    kernel::wide(u.to_bits(), v.to_bits(), &params)
}

/// [`closed_form_f32`] for binary64.
#[inline]
fn closed_form_f64(u: f64, v: f64, level: Level) -> u64 {
    let last = ((1u64 << level.get()) - 1) as u32;
    let (iu, uf) = coordinate_f64(u, level.get());
    let (iv, vf) = coordinate_f64(v, level.get());
    let clamp = |cell: u64| cell.min(u64::from(last)) as u32;
    kernel::wide_from_clamped_cell(clamp(iu), clamp(iv), uf + vf >= F64_ONE, last)
}

/// Fraction bits kept of a binary64 coordinate's fraction.
const F64_FRACTION_BITS: u32 = 62;
/// `1` in units of the last kept fraction bit.
const F64_ONE: u64 = 1 << F64_FRACTION_BITS;

/// The cell `floor(x * 2^level)` (at most `2^32`) and
/// `floor(fraction * 2^62)` of `x` clamped to `[0, 1]` (NaN and negatives to
/// 0). `x = m * 2^(e - 1075)` with `m < 2^53` and `e <= 1023`, so
/// `x * 2^level = m >> s` with `s = 1075 - level - e >= 20`.
#[inline]
fn coordinate_f64(x: f64, level: u32) -> (u64, u64) {
    let bits = x.to_bits();
    let clamped = if bits > 0x7ff0_0000_0000_0000 {
        0 // NaN or negative
    } else {
        bits.min(1f64.to_bits())
    };
    let biased = (clamped >> 52) as u32;
    let hidden = if biased == 0 { 0 } else { 1 << 52 };
    let m = (clamped & ((1 << 52) - 1)) | hidden;
    let s = 1075 - level - biased.max(1);
    let cell = m.checked_shr(s).unwrap_or(0);
    let fraction = m & 1u64.checked_shl(s).map_or(u64::MAX, |bit| bit - 1);
    let scaled = if s <= F64_FRACTION_BITS {
        fraction << (F64_FRACTION_BITS - s)
    } else {
        fraction.checked_shr(s - F64_FRACTION_BITS).unwrap_or(0)
    };
    (cell, scaled)
}

/// The reference's first half over the reals for a binary32 point, from its
/// bits: equal to [`spec::cell_exact`](crate::spec::cell_exact) on the
/// float's exact value (clamped to `[0, 1]`, NaN to 0), every level
/// `0..=32`. With [`spec::index_from_cell_wide`](crate::spec::index_from_cell_wide)
/// it is the closed form of the module docs at any level.
///
/// ```
/// use micromap_index::{exact_float, spec::Cell, Level};
/// // (3/8, 5/8) at level 2: cell (1, 2), fractions 1/2 + 1/2 >= 1.
/// assert_eq!(
///     exact_float::cell_f32(0.375, 0.625, Level::new(2).unwrap()),
///     Cell { iu: 1, iv: 2, diagonal: true }
/// );
/// ```
#[must_use]
pub fn cell_f32(u: f32, v: f32, level: Level) -> Cell {
    let (iu, uf) = coordinate_f64(f64::from(u), level.get());
    let (iv, vf) = coordinate_f64(f64::from(v), level.get());
    Cell {
        iu,
        iv,
        diagonal: uf + vf >= F64_ONE,
    }
}

/// [`cell_f32`] for a binary64 point.
///
/// ```
/// use micromap_index::{exact_float, spec::Cell, Level};
/// let third = 1.0 / 3.0;
/// assert_eq!(
///     exact_float::cell_f64(third, 2.0 * third, Level::new(1).unwrap()),
///     Cell { iu: 0, iv: 1, diagonal: false } // 2/3 + 1/3 - ulps < 1
/// );
/// ```
#[must_use]
pub fn cell_f64(u: f64, v: f64, level: Level) -> Cell {
    let (iu, uf) = coordinate_f64(u, level.get());
    let (iv, vf) = coordinate_f64(v, level.get());
    Cell {
        iu,
        iv,
        diagonal: uf + vf >= F64_ONE,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
