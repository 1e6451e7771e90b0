//! Fixed-point instantiations of the [`uv2index`] walk:
//! integers only, no allocation, no `std`: with `default-features = false`
//! the crate is `no_std` and this module, the generic walk and the
//! reference's float and dyadic steps are all that is built.
//!
//! [`Fixed64`] holds `x * 2^60` in an `i64`, [`Fixed128`] holds `x * 2^124`
//! in an `i128`. The walk's steps on them are exact: the children's
//! barycentrics are integer combinations (`2u`, `u - v - w`, ...) of the
//! parent's, and the scale never changes because every child's coordinates
//! again sum to one. For a point of the closed triangle every coordinate the
//! walk stores stays in `[0, 1]` and every intermediate in `[-1, 2]`, far from
//! overflow. (On points outside the triangle, which only the unchecked
//! [`uv2index::index`] accepts, the arithmetic wraps instead of panicking.)
//!
//! # Exact answers for every finite float
//!
//! [`index_f32`] and [`index_f64`] return, for every finite float point of
//! the closed triangle and every level `0..=32`, the index the walk computes
//! over the reals ([`uv2index::index_exact`]). They do not need every bit of
//! the input: the walk only compares the point against lattice lines
//! (`u = k/2^level`, `v = k/2^level`, `u + v = k/2^level`), so any point in the
//! same lattice face gives the same index. Each coordinate is rounded down to
//! `P - 1` fractional bits and a *sticky* bit, set when anything was cut off,
//! is appended as the `P`-th bit. Per coordinate this preserves the side of
//! every line at multiples of `2^-(P-1)`; for the sum it does so as long as
//! `P >= level + 26` (binary32 inputs, 24-bit significands) or
//! `P >= level + 55` (binary64, 53 bits): both coordinates can only carry a
//! sticky bit when both are below `2^(s+1-P)` (`s` the significand width), so
//! their sum stays below the first lattice line. `docs/fixed.md` spells the
//! argument out. With `P = 60` ([`Fixed64`], binary32) and `P = 124`
//! ([`Fixed128`], binary64) every level up to 32 is covered. That walk is
//! [`index_f32_ref`] / [`index_f64_ref`]; [`index_f32`] and [`index_f64`]
//! return the same answers faster through
//! [`exact_float`](crate::exact_float) (the reference's exact steps on the
//! float bits, where those are proved equal to the walk).
//!
//! # Mirroring the GPU
//!
//! [`index_mirror_f32`] is a different contract: not the exact answer but,
//! bit for bit, what the Vulkan reference returns in binary32
//! ([`spec::index_f32`](crate::spec::index_f32)) for every pair of `f32`,
//! computed from the float bits with integer operations only. Each float
//! operation of the reference is exact except the rounding of `uf + vf`,
//! which becomes an exact comparison with `1 - 2^-25` (`docs/fixed.md`).
//!
//! ```
//! use micromap_index::{fixed, uv2index, Level};
//! let level = Level::new(24).unwrap();
//! let (u, v) = (0.1f32, f32::from_bits(1)); // a subnormal v
//! let exact = uv2index::index_exact(
//!     &num_rational::BigRational::from_float(u).unwrap(),
//!     &num_rational::BigRational::from_float(v).unwrap(),
//!     level,
//! );
//! assert_eq!(fixed::index_f32(u, v, level), exact);
//! ```
//!
//! [`uv2index::index`]: crate::uv2index::index
//! [`uv2index::index_exact`]: crate::uv2index::index_exact

use crate::uv2index::{self, check_finite, check_signs, WalkNumber};
use crate::{Error, Level};
use core::cmp::Ordering;

macro_rules! fixed_point_type {
    ($(#[$doc:meta])* $name:ident, $int:ty, $one_log2:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name($int);

        impl $name {
            /// The value `1` is `2^ONE_LOG2` in the raw representation.
            pub const ONE_LOG2: u32 = $one_log2;
            /// The value `1`.
            pub const ONE: $name = $name(1 << $one_log2);

            /// `numerator / 2^scale_log2`, or `None` if that needs more than
            /// `ONE_LOG2` fractional bits or does not fit.
            pub fn from_scaled(numerator: $int, scale_log2: u32) -> Option<Self> {
                let shift = Self::ONE_LOG2.checked_sub(scale_log2)?;
                let raw = numerator.checked_mul((1 as $int).checked_shl(shift)?)?;
                Some($name(raw))
            }

            /// The raw integer: the value times `2^ONE_LOG2`.
            pub const fn raw(self) -> $int {
                self.0
            }

            /// The value whose raw integer is `raw`.
            pub const fn from_raw(raw: $int) -> Self {
                $name(raw)
            }
        }

        impl WalkNumber for $name {
            fn one_minus_sum(u: &Self, v: &Self) -> Self {
                Self::ONE.minus(&u.plus(v))
            }
            fn twice(&self) -> Self {
                $name(self.0.wrapping_shl(1))
            }
            fn plus(&self, other: &Self) -> Self {
                $name(self.0.wrapping_add(other.0))
            }
            fn minus(&self, other: &Self) -> Self {
                $name(self.0.wrapping_sub(other.0))
            }
            fn cmp_half(&self) -> Ordering {
                self.0.cmp(&(1 << ($one_log2 - 1)))
            }
            fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
                let sum_minus_one = match u.0.checked_add(v.0) {
                    Some(sum) => sum.cmp(&Self::ONE.0),
                    None if u.0 > 0 => Ordering::Greater,
                    None => Ordering::Less,
                };
                check_signs(u.0.cmp(&0), v.0.cmp(&0), sum_minus_one)
            }
        }
    };
}

fixed_point_type!(
    /// A real number `x` stored as the `i64` `x * 2^60`.
    ///
    /// ```
    /// use micromap_index::fixed::Fixed64;
    /// let quarter = Fixed64::from_scaled(1, 2).unwrap();
    /// assert_eq!(quarter.raw(), 1 << 58);
    /// ```
    Fixed64,
    i64,
    60
);

fixed_point_type!(
    /// A real number `x` stored as the `i128` `x * 2^124`.
    ///
    /// ```
    /// use micromap_index::fixed::Fixed128;
    /// assert_eq!(Fixed128::ONE.raw(), 1 << 124);
    /// ```
    Fixed128,
    i128,
    124
);

/// A finite, non-negative float split into `significand * 2^exponent`.
struct Decoded {
    significand: u64,
    exponent: i32,
}

fn decode_f64(x: f64) -> Decoded {
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1 << 52) - 1);
    if biased == 0 {
        Decoded {
            significand: fraction,
            exponent: -1074,
        }
    } else {
        Decoded {
            significand: fraction | (1 << 52),
            exponent: biased - 1075,
        }
    }
}

/// `x` (finite, in `[0, 1]`) as `2 * floor(x * 2^(p-1)) + sticky`, where
/// sticky is 1 when the floor dropped a non-zero part: the representation
/// the module docs argue preserves every lattice decision.
fn sticky_scaled(x: f64, p: u32) -> i128 {
    let Decoded {
        significand,
        exponent,
    } = decode_f64(x);
    // x <= 1 so the result is at most 2^p: fits.
    sticky_round(significand, exponent, p) as i128
}

/// `significand * 2^exponent` (at most 1) as `2 * floor(value * 2^(p-1)) +
/// sticky`, the sticky bit set when the floor dropped anything.
fn sticky_round(significand: u64, exponent: i32, p: u32) -> u128 {
    let shift = exponent + (p as i32 - 1);
    let (kept, sticky) = if shift >= 0 {
        (u128::from(significand) << shift, false)
    } else {
        let drop = shift.unsigned_abs();
        if drop >= 64 {
            (0, significand != 0)
        } else {
            (
                u128::from(significand >> drop),
                significand & ((1u64 << drop) - 1) != 0,
            )
        }
    };
    2 * kept + u128::from(sticky)
}

fn check_float_point(u: f64, v: f64) -> Result<(), Error> {
    check_finite(u.is_nan(), u.is_infinite(), v.is_nan(), v.is_infinite())?;
    f64::check_point(&u, &v)
}

/// The exact walk's index for a finite binary32 point:
/// equal to [`uv2index::index_exact`] of the
/// same real point for every level `0..=32`. NaN, infinities and points
/// outside the closed triangle are errors.
///
/// Computed by [`exact_float::index_f32`](crate::exact_float::index_f32):
/// the reference's exact steps on the float's bits where they are proved
/// equal to the walk, the walk ([`index_f32_ref`]) elsewhere.
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_f32(0.3, 0.3, Level::new(2).unwrap()), Ok(5));
/// ```
#[inline]
pub fn index_f32(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    crate::exact_float::index_f32(u, v, level)
}

/// [`index_f32`] by the walk itself on [`Fixed64`] (`level` steps): the
/// oracle the closed form is checked against.
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_f32_ref(0.3, 0.3, Level::new(2).unwrap()), Ok(5));
/// ```
pub fn index_f32_ref(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    let (u, v) = (f64::from(u), f64::from(v));
    check_float_point(u, v)?;
    let p = Fixed64::ONE_LOG2;
    // In [0, 2^60]: fits.
    let to_fixed = |x| Fixed64::from_raw(sticky_scaled(x, p) as i64);
    Ok(uv2index::index(to_fixed(u), to_fixed(v), level))
}

/// The exact walk's index for a finite binary64 point:
/// equal to [`uv2index::index_exact`] of the
/// same real point for every level `0..=32`. Computed like [`index_f32`]
/// ([`exact_float::index_f64`](crate::exact_float::index_f64)).
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_f64(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
#[inline]
pub fn index_f64(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    crate::exact_float::index_f64(u, v, level)
}

/// [`index_f64`] by the walk itself on [`Fixed128`]: the oracle.
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_f64_ref(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
pub fn index_f64_ref(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    check_float_point(u, v)?;
    let p = Fixed128::ONE_LOG2;
    let to_fixed = |x| Fixed128::from_raw(sticky_scaled(x, p));
    Ok(uv2index::index(to_fixed(u), to_fixed(v), level))
}

/// Fraction bits (with the sticky bit) the mirror keeps of `uf` and `vf`.
/// `docs/fixed.md`: 27 suffice; 32 leave room.
const MIRROR_FRACTION_BITS: u32 = 32;

/// What the reference's `uf + vf >= 1.0f` becomes on exact fractions:
/// binary32 round-to-nearest-even lifts every real sum in `[1 - 2^-25, 1)`
/// to `1.0`, and no smaller one, so the test is `uf + vf >= 1 - 2^-25`.
const MIRROR_DIAGONAL_THRESHOLD: u128 =
    (1 << MIRROR_FRACTION_BITS) - (1 << (MIRROR_FRACTION_BITS - 25));

/// The reference's first steps on one binary32 coordinate, on its bits:
/// `clamp` (NaN and everything negative -> 0, everything from 1 up,
/// +inf included -> 1), then `x * 2^level` split into the truncated cell and
/// the fraction `fu - float(iu)` (both exact in binary32, so exact here) in
/// sticky fixed point.
fn mirror_cell_and_fraction(x: f32, level: u32) -> (u32, u128) {
    let bits = x.to_bits();
    let (significand, exponent): (u64, i32) = if bits >> 31 == 1 || bits > 0x7f80_0000 {
        (0, 0) // negative (incl. -0, -inf, negative NaN) or positive NaN
    } else if bits >= 0x3f80_0000 {
        (1, 0) // >= 1.0, +inf included
    } else {
        let biased = (bits >> 23) as i32;
        let fraction = u64::from(bits & 0x7f_ffff);
        if biased == 0 {
            (fraction, -149)
        } else {
            (fraction | 0x80_0000, biased - 150)
        }
    };
    // x * 2^level = significand * 2^shift; below 2^31 + 1 for level <= 31.
    let shift = exponent + level as i32;
    if shift >= 0 {
        ((significand << shift) as u32, 0)
    } else {
        let drop = shift.unsigned_abs();
        let (cell, fraction) = if drop >= 64 {
            (0, significand)
        } else {
            (significand >> drop, significand & ((1 << drop) - 1))
        };
        let fraction = sticky_round(fraction, shift, MIRROR_FRACTION_BITS);
        (cell as u32, fraction)
    }
}

/// The Vulkan reference in binary32, reproduced with integer operations
/// only: for every pair of `f32` (NaN, ±0, ±inf, subnormals, outside the
/// triangle) and every level, the same bits as
/// [`spec::index_f32`](crate::spec::index_f32) — including the inputs where
/// binary32 rounding of `uf + vf` makes the reference differ from its exact
/// reading. Levels `>= 32` use `level % 32`, like the reference port.
///
/// ```
/// use micromap_index::{fixed, spec};
/// for (u, v) in [(0.3, 0.3), (f32::NAN, 2.0), (0.125, 0.125 - 2f32.powi(-27))] {
///     assert_eq!(fixed::index_mirror_f32(u, v, 2), spec::index_f32(u, v, 2));
/// }
/// ```
#[inline]
pub fn index_mirror_f32(u: f32, v: f32, level: u32) -> u32 {
    let level = level % 32;
    let (iu, uf) = mirror_cell_and_fraction(u, level);
    let (iv, vf) = mirror_cell_and_fraction(v, level);
    let diagonal = uf + vf >= MIRROR_DIAGONAL_THRESHOLD;
    crate::spec::index_from_cell(iu, iv, diagonal, level)
}

/// [`index_mirror_f32`] for levels `0..=16` ([`Error::LevelTooHigh`] above,
/// as [`spec::index_f32_checked`](crate::spec::index_f32_checked)).
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_mirror_f32_checked(0.3, 0.3, Level::new(2).unwrap()), Ok(5));
/// assert!(fixed::index_mirror_f32_checked(0.3, 0.3, Level::new(17).unwrap()).is_err());
/// ```
#[inline]
pub fn index_mirror_f32_checked(u: f32, v: f32, level: Level) -> Result<u32, Error> {
    let level = level.at_most(crate::spec::MAX_LEVEL)?;
    Ok(index_mirror_f32(u, v, level.get()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_fractions_are_exact_or_sticky() {
        assert_eq!(mirror_cell_and_fraction(0.75, 1), (1, 1 << 31));
        assert_eq!(mirror_cell_and_fraction(1.0, 3), (8, 0));
        assert_eq!(mirror_cell_and_fraction(f32::INFINITY, 3), (8, 0));
        assert_eq!(mirror_cell_and_fraction(-f32::NAN, 3), (0, 0));
        assert_eq!(mirror_cell_and_fraction(f32::from_bits(1), 0), (0, 1));
    }

    #[test]
    fn sticky_marks_dropped_bits() {
        assert_eq!(sticky_scaled(0.5, 4), 8);
        assert_eq!(sticky_scaled(1.0, 4), 16);
        assert_eq!(sticky_scaled(0.5 + 2f64.powi(-20), 4), 9);
        assert_eq!(sticky_scaled(f64::from_bits(1), 60), 1);
        assert_eq!(sticky_scaled(0.0, 60), 0);
    }
}
