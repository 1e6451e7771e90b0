//! Fixed-point instantiations of the [`uv2index`](crate::uv2index) walk:
//! integers only, no allocation.
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
//! ([`Fixed128`], binary64) every level up to 32 is covered.
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
use std::cmp::Ordering;

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
    let shift = exponent + (p as i32 - 1);
    let (kept, sticky) = if shift >= 0 {
        // x <= 1 so significand * 2^shift <= 2^(p-1): no overflow.
        (i128::from(significand) << shift, false)
    } else {
        let drop = shift.unsigned_abs();
        if drop >= 64 {
            (0, significand != 0)
        } else {
            (
                i128::from(significand >> drop),
                significand & ((1u64 << drop) - 1) != 0,
            )
        }
    };
    2 * kept + i128::from(sticky)
}

fn check_float_point(u: f64, v: f64) -> Result<(), Error> {
    check_finite(u.is_nan(), u.is_infinite(), v.is_nan(), v.is_infinite())?;
    f64::check_point(&u, &v)
}

/// The exact walk's index for a finite binary32 point, on [`Fixed64`]:
/// equal to [`uv2index::index_exact`](crate::uv2index::index_exact) of the
/// same real point for every level `0..=32`. NaN, infinities and points
/// outside the closed triangle are errors.
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_f32(0.3, 0.3, Level::new(2).unwrap()), Ok(5));
/// ```
pub fn index_f32(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    let (u, v) = (f64::from(u), f64::from(v));
    check_float_point(u, v)?;
    let p = Fixed64::ONE_LOG2;
    // In [0, 2^60]: fits.
    let to_fixed = |x| Fixed64::from_raw(sticky_scaled(x, p) as i64);
    Ok(uv2index::index(to_fixed(u), to_fixed(v), level))
}

/// The exact walk's index for a finite binary64 point, on [`Fixed128`]:
/// equal to [`uv2index::index_exact`](crate::uv2index::index_exact) of the
/// same real point for every level `0..=32`.
///
/// ```
/// use micromap_index::{fixed, Level};
/// assert_eq!(fixed::index_f64(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
pub fn index_f64(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    check_float_point(u, v)?;
    let p = Fixed128::ONE_LOG2;
    let to_fixed = |x| Fixed128::from_raw(sticky_scaled(x, p));
    Ok(uv2index::index(to_fixed(u), to_fixed(v), level))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sticky_marks_dropped_bits() {
        assert_eq!(sticky_scaled(0.5, 4), 8);
        assert_eq!(sticky_scaled(1.0, 4), 16);
        assert_eq!(sticky_scaled(0.5 + 2f64.powi(-20), 4), 9);
        assert_eq!(sticky_scaled(f64::from_bits(1), 60), 1);
        assert_eq!(sticky_scaled(0.0, 60), 0);
    }
}
