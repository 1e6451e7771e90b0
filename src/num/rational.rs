//! Exact rationals for the walk (feature `exact`).
//!
//! [`BigRational`] is the obviously exact type. It is slow because every
//! operation normalises by a gcd. The walk never needs that: each step forms
//! integer combinations of the parent's coordinates, and the coordinates
//! always sum to one, so they all keep the input's common denominator.
//! [`Shared`] therefore walks on numerators over one shared denominator:
//! on `i128` ([`SmallRational`]) when the input fits, on big integers
//! ([`BigShared`]) otherwise. Each step costs a few additions and shifts of
//! the numerators, whatever their size, so the cost of a big input grows
//! linearly with its digits instead of with repeated gcds.

#![cfg_attr(not(feature = "unstable-public-internals"), allow(dead_code))]

use super::{check_signs, WalkNumber};
use crate::Error;
use alloc::rc::Rc;
use core::cmp::Ordering;
use num_bigint::BigInt;
use num_integer::Integer;
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};

/// What a numerator type needs for [`Shared`]: exact (or, for `i128` on
/// inputs that fit, provably non-overflowing) ring operations and a way to
/// compare with the shared denominator.
pub trait Numerator: Clone {
    /// How the shared denominator is held (cheap to clone).
    type Denominator: Clone;
    /// `self + other`.
    #[must_use]
    fn add(&self, other: &Self) -> Self;
    /// `self - other`.
    #[must_use]
    fn sub(&self, other: &Self) -> Self;
    /// `2 * self`.
    #[must_use]
    fn double(&self) -> Self;
    /// The denominator as a numerator (the value one).
    fn one(denominator: &Self::Denominator) -> Self;
    /// `self` compared with zero.
    fn sign(&self) -> Ordering;
    /// `a + b` compared with the denominator, without overflow.
    fn sum_cmp_one(a: &Self, b: &Self, denominator: &Self::Denominator) -> Ordering;
    /// `2 * self` compared with the denominator, without overflow.
    fn double_cmp_one(&self, denominator: &Self::Denominator) -> Ordering;
}

impl Numerator for i128 {
    type Denominator = u64;
    fn add(&self, other: &Self) -> Self {
        self.wrapping_add(*other)
    }
    fn sub(&self, other: &Self) -> Self {
        self.wrapping_sub(*other)
    }
    fn double(&self) -> Self {
        self.wrapping_shl(1)
    }
    fn one(denominator: &u64) -> Self {
        i128::from(*denominator)
    }
    fn sign(&self) -> Ordering {
        self.cmp(&0)
    }
    fn sum_cmp_one(a: &Self, b: &Self, denominator: &u64) -> Ordering {
        match a.checked_add(*b) {
            Some(sum) => sum.cmp(&i128::from(*denominator)),
            None if *a > 0 => Ordering::Greater,
            None => Ordering::Less,
        }
    }
    fn double_cmp_one(&self, denominator: &u64) -> Ordering {
        // |numerator| <= 2^127 / 4 for any value a walk on a checked point
        // forms, so doubling cannot overflow there.
        self.wrapping_shl(1).cmp(&i128::from(*denominator))
    }
}

impl Numerator for BigInt {
    type Denominator = Rc<BigInt>;
    fn add(&self, other: &Self) -> Self {
        self + other
    }
    fn sub(&self, other: &Self) -> Self {
        self - other
    }
    fn double(&self) -> Self {
        self << 1u32
    }
    fn one(denominator: &Rc<BigInt>) -> Self {
        BigInt::clone(denominator)
    }
    fn sign(&self) -> Ordering {
        self.cmp(&BigInt::zero())
    }
    fn sum_cmp_one(a: &Self, b: &Self, denominator: &Rc<BigInt>) -> Ordering {
        (a + b).cmp(denominator)
    }
    fn double_cmp_one(&self, denominator: &Rc<BigInt>) -> Ordering {
        (self << 1u32).cmp(denominator)
    }
}

/// `numerator / denominator` with a denominator shared by every value of one
/// walk. Mixing values with different denominators gives meaningless (but
/// panic-free) results.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Shared<N: Numerator> {
    numerator: N,
    denominator: N::Denominator,
}

/// [`Shared`] on `i128` numerators over a `u64` denominator.
pub type SmallRational = Shared<i128>;

/// [`Shared`] on big-integer numerators over one big denominator.
pub type BigShared = Shared<BigInt>;

impl<N: Numerator> Shared<N> {
    /// The numerator over the shared denominator.
    #[must_use]
    pub fn numerator(&self) -> &N {
        &self.numerator
    }

    /// The shared denominator.
    #[must_use]
    pub fn denominator(&self) -> &N::Denominator {
        &self.denominator
    }

    fn with(&self, numerator: N) -> Self {
        Shared {
            numerator,
            denominator: self.denominator.clone(),
        }
    }
}

impl SmallRational {
    /// `numerator / denominator`; a zero denominator is taken as 1.
    #[must_use]
    pub fn new(numerator: i128, denominator: u64) -> Self {
        Shared {
            numerator,
            denominator: denominator.max(1),
        }
    }
}

impl BigShared {
    /// `(u, v)` over their least common denominator (for a zero
    /// denominator, impossible in a [`BigRational`], nothing is built).
    #[must_use]
    pub fn pair(u: &BigRational, v: &BigRational) -> (BigShared, BigShared) {
        let denominator = Rc::new(u.denom().lcm(v.denom()));
        let scale = |r: &BigRational| Shared {
            numerator: r.numer() * (&*denominator / r.denom()),
            denominator: Rc::clone(&denominator),
        };
        (scale(u), scale(v))
    }
}

impl<N: Numerator> WalkNumber for Shared<N> {
    fn one_minus_sum(u: &Self, v: &Self) -> Self {
        u.with(N::one(&u.denominator).sub(&u.numerator.add(&v.numerator)))
    }
    fn twice(&self) -> Self {
        self.with(self.numerator.double())
    }
    fn plus(&self, other: &Self) -> Self {
        self.with(self.numerator.add(&other.numerator))
    }
    fn minus(&self, other: &Self) -> Self {
        self.with(self.numerator.sub(&other.numerator))
    }
    fn cmp_half(&self) -> Ordering {
        self.numerator.double_cmp_one(&self.denominator)
    }
    fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
        let sum_minus_one = N::sum_cmp_one(&u.numerator, &v.numerator, &u.denominator);
        check_signs(u.numerator.sign(), v.numerator.sign(), sum_minus_one)
    }
}

/// `(u, v)` as `(a, b, d)` with `u = a/d`, `v = b/d`, `d` the least common
/// denominator, if `d <= 2^64 - 1` and `|a|, |b| <= 2^100` (room for the
/// walk's and the quantization's intermediate products); `None` otherwise.
#[must_use]
pub fn over_common_denominator(u: &BigRational, v: &BigRational) -> Option<(i128, i128, u64)> {
    let denominator: BigInt = u.denom().lcm(v.denom());
    let d = denominator.to_u64()?;
    let scale = |r: &BigRational| -> Option<i128> {
        let a = (r.numer() * (&denominator / r.denom())).to_i128()?;
        (a.unsigned_abs() <= 1 << 100).then_some(a)
    };
    Some((scale(u)?, scale(v)?, d))
}

impl WalkNumber for BigRational {
    fn one_minus_sum(u: &Self, v: &Self) -> Self {
        BigRational::one() - (u + v)
    }
    fn twice(&self) -> Self {
        self + self
    }
    fn plus(&self, other: &Self) -> Self {
        self + other
    }
    fn minus(&self, other: &Self) -> Self {
        self - other
    }
    fn cmp_half(&self) -> Ordering {
        // Compare 2x with 1 to avoid building 1/2.
        let doubled = self + self;
        doubled.cmp(&BigRational::one())
    }
    fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
        let zero = BigRational::zero();
        let sum_minus_one = (u + v) - BigRational::one();
        check_signs(u.cmp(&zero), v.cmp(&zero), sum_minus_one.cmp(&zero))
    }
}
