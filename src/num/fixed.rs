//! Fixed-point numbers for the walk: integers only, no allocation, no
//! `std`.
//!
//! [`Fixed64`] holds `x * 2^60` in an `i64`, [`Fixed128`] holds `x * 2^124`
//! in an `i128`. The walk's steps on them are exact: the children's
//! barycentrics are integer combinations (`2u`, `u - v - w`, ...) of the
//! parent's, and the scale never changes because every child's coordinates
//! again sum to one. For a point of the closed triangle every value the walk
//! forms, stored or intermediate, lies in `[0, 1]` (z3 proves it by
//! induction over the modelled step, `crates/lab/certificates/product.py`,
//! `docs/verification.md` 10.12): raw values stay in `[0, 2^ONE_LOG2]`, no
//! operation wraps, and each step is the exact step over the reals. (On
//! points outside the triangle, which only
//! [`index_unchecked`](crate::uv2index::index_unchecked) accepts, the
//! arithmetic wraps instead of panicking.)

use super::{check_signs, WalkNumber};
use crate::Error;
use core::cmp::Ordering;

macro_rules! fixed_point_type {
    ($(#[$doc:meta])* $name:ident, $int:ty, $one_log2:expr) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        pub struct $name($int);

        // `1` (raw `2^ONE_LOG2`), the largest value a walk of a point of
        // the triangle forms, is a positive integer of the type.
        const _: () = assert!($one_log2 < <$int>::BITS - 1);

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
    /// use micromap_index::num::Fixed64;
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
    /// use micromap_index::num::Fixed128;
    /// assert_eq!(Fixed128::ONE.raw(), 1 << 124);
    /// ```
    Fixed128,
    i128,
    124
);

/// A finite, non-negative float split into `significand * 2^exponent`.
pub(crate) struct Decoded {
    pub(crate) significand: u64,
    pub(crate) exponent: i32,
}

pub(crate) fn decode_f64(x: f64) -> Decoded {
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
pub(crate) fn sticky_scaled(x: f64, p: u32) -> i128 {
    let Decoded {
        significand,
        exponent,
    } = decode_f64(x);
    // x <= 1 so the result is at most 2^p: fits.
    sticky_round(significand, exponent, p) as i128
}

/// `significand * 2^exponent` (at most 1) as `2 * floor(value * 2^(p-1)) +
/// sticky`, the sticky bit set when the floor dropped anything.
pub(crate) fn sticky_round(significand: u64, exponent: i32, p: u32) -> u128 {
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
