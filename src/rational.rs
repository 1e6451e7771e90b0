//! Exact rationals on machine integers: a pair of rationals written over one
//! common denominator `d <= 2^64`, so that the walk and the reference's
//! quantization run on `i128` instead of heap-allocated big integers.
//!
//! The walk's coordinates all keep the denominator of the input (each step
//! forms integer combinations of the parent's coordinates, and they always
//! sum to one), so the numerators stay within `[-d, 2d]`: the arithmetic is
//! exact. [`uv2index::index_exact`](crate::uv2index::index_exact) and
//! [`spec::cell_exact`](crate::spec::cell_exact) take this path whenever the
//! input fits and fall back to [`BigRational`] otherwise; both are tested
//! against their pure-BigRational `*_ref` twins.
//!
//! ```
//! use micromap_index::rational::{over_common_denominator, SmallRational};
//! use micromap_index::{uv2index, Level};
//! let r = |s: &str| s.parse().unwrap();
//! let (u, v, d) = over_common_denominator(&r("1/3"), &r("1/4")).unwrap();
//! assert_eq!((u, v, d), (4, 3, 12));
//! let index = uv2index::index(SmallRational::new(u, d), SmallRational::new(v, d), Level::new(5).unwrap());
//! assert_eq!(Ok(index), uv2index::index_exact_ref(&r("1/3"), &r("1/4"), Level::new(5).unwrap()));
//! ```

use crate::uv2index::{check_signs, WalkNumber};
use crate::Error;
use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::ToPrimitive;
use std::cmp::Ordering;

/// `numerator / denominator` with a denominator shared by every value of one
/// walk. Mixing values with different denominators gives meaningless (but
/// panic-free: the arithmetic wraps) results.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SmallRational {
    numerator: i128,
    denominator: u64,
}

impl SmallRational {
    /// `numerator / denominator`; `denominator` must not be 0 (a zero
    /// denominator is treated as 1).
    pub fn new(numerator: i128, denominator: u64) -> Self {
        SmallRational {
            numerator,
            denominator: denominator.max(1),
        }
    }

    /// The numerator over the shared denominator.
    pub fn numerator(self) -> i128 {
        self.numerator
    }

    /// The shared denominator.
    pub fn denominator(self) -> u64 {
        self.denominator
    }

    fn with(self, numerator: i128) -> Self {
        SmallRational { numerator, ..self }
    }
}

impl WalkNumber for SmallRational {
    fn one_minus_sum(u: &Self, v: &Self) -> Self {
        u.with(i128::from(u.denominator).wrapping_sub(u.numerator.wrapping_add(v.numerator)))
    }
    fn twice(&self) -> Self {
        self.with(self.numerator.wrapping_shl(1))
    }
    fn plus(&self, other: &Self) -> Self {
        self.with(self.numerator.wrapping_add(other.numerator))
    }
    fn minus(&self, other: &Self) -> Self {
        self.with(self.numerator.wrapping_sub(other.numerator))
    }
    fn cmp_half(&self) -> Ordering {
        // |numerator| <= 2^127 / 4 for any value a walk on a checked point
        // forms, so doubling cannot overflow there.
        self.numerator
            .wrapping_shl(1)
            .cmp(&i128::from(self.denominator))
    }
    fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
        let sum_minus_one = match u.numerator.checked_add(v.numerator) {
            Some(sum) => sum.cmp(&i128::from(u.denominator)),
            None if u.numerator > 0 => Ordering::Greater,
            None => Ordering::Less,
        };
        check_signs(u.numerator.cmp(&0), v.numerator.cmp(&0), sum_minus_one)
    }
}

/// `(u, v)` as `(a, b, d)` with `u = a/d`, `v = b/d`, `d` the least common
/// denominator, if `d <= 2^64 - 1` and `|a|, |b| <= 2^100` (room for the
/// walk's and the quantization's intermediate products); `None` otherwise.
pub fn over_common_denominator(u: &BigRational, v: &BigRational) -> Option<(i128, i128, u64)> {
    let denominator: BigInt = u.denom().lcm(v.denom());
    let d = denominator.to_u64()?;
    let scale = |r: &BigRational| -> Option<i128> {
        let a = (r.numer() * (&denominator / r.denom())).to_i128()?;
        (a.unsigned_abs() <= 1 << 100).then_some(a)
    };
    Some((scale(u)?, scale(v)?, d))
}
