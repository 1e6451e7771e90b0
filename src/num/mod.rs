//! Number types for the walk: the [`WalkNumber`] trait and its
//! implementations for `f32` and `f64`, fixed point
//! ([`Fixed64`], [`Fixed128`]) and, with the `exact` feature, rationals.
//!
//! The walk ([`crate::uv2index::Walk::step`]) is written once against this
//! trait; every implementation of the index that walks (float, exact,
//! fixed point, the prover's tables) instantiates it with one of these types.

use crate::{Coordinate, Error, Outside};
use core::cmp::Ordering;

pub mod fixed;
mod float;
#[cfg(all(feature = "exact", feature = "unstable-public-internals"))]
pub mod rational;
#[cfg(all(feature = "exact", not(feature = "unstable-public-internals")))]
pub(crate) mod rational;
// Its one user, the baker, needs `alloc`.
#[cfg(feature = "alloc")]
pub(crate) mod wide;

pub use fixed::{Fixed128, Fixed64};

/// The arithmetic one walk step needs. Implement it for a number type and
/// the whole walk (and everything built on it) works on that type.
pub trait WalkNumber: Clone {
    /// `1 - (u + v)`, the third barycentric, computed as written.
    fn one_minus_sum(u: &Self, v: &Self) -> Self;
    /// `2 * self`.
    #[must_use]
    fn twice(&self) -> Self;
    /// `self + other`.
    #[must_use]
    fn plus(&self, other: &Self) -> Self;
    /// `self - other`.
    #[must_use]
    fn minus(&self, other: &Self) -> Self;
    /// `self` compared with `1/2`. Unordered values (NaN) compare as `Less`.
    fn cmp_half(&self) -> Ordering;
    /// `Ok` if `(u, v)` is a point of the closed triangle, else what is wrong.
    fn check_point(u: &Self, v: &Self) -> Result<(), Error>;
}

/// `Ok` unless `u` or `v` is NaN or infinite; shared by the float checks
/// (every `f32` converts to `f64` exactly).
pub(crate) fn check_finite(u: f64, v: f64) -> Result<(), Error> {
    let class = |x: f64, c| {
        if x.is_nan() {
            Err(Error::NotANumber(c))
        } else if x.is_infinite() {
            Err(Error::Infinite(c))
        } else {
            Ok(())
        }
    };
    class(u, Coordinate::U)?;
    class(v, Coordinate::V)
}

/// The triangle test from the signs of `u`, `v` and of `u + v - 1`.
pub(crate) fn check_signs(u: Ordering, v: Ordering, sum_minus_one: Ordering) -> Result<(), Error> {
    let reason = if u == Ordering::Less {
        Outside::NegativeU
    } else if v == Ordering::Less {
        Outside::NegativeV
    } else if sum_minus_one == Ordering::Greater {
        Outside::SumAboveOne
    } else {
        return Ok(());
    };
    Err(Error::OutsideTriangle { reason })
}
