//! The paper's `uv2index` walk (Waldemarson & Doggett, "Succinct Opacity
//! Micromaps", Algorithm 4; the talk's "Lookup Function – 2"), written once
//! and generic over the number type.
//!
//! Each step splits the current triangle at its edge midpoints into the
//! Left, Middle, Right and Top children, picks the child holding the point,
//! appends its digit to the index and re-expresses `(u, v, w)` in the child's
//! barycentrics. Two flags carry the orientation: `top_flip` swaps the digits
//! of Left and Right (the Top child's curve runs the other way) and
//! `mid_flip` sends ties on `v = 1/2` to the Middle child (inside an
//! upside-down child the reference's tie-breaks point the other way). See
//! `docs/algorithm.md`.
//!
//! # Guarantees
//!
//! * Over exact numbers ([`index_exact`], or the integer instantiations in
//!   [`crate::fixed`]) the walk equals the Vulkan reference's steps over the
//!   reals ([`crate::spec::index_exact`]) at every point of the closed
//!   triangle, for levels `0..=16` (checked face by face, see
//!   `tests/lattice.rs`), and defines the mapping for levels up to 32.
//! * Over `f32` / `f64` ([`index_f32`], [`index_f64`]) each expression is
//!   evaluated left to right exactly as the talk's Python writes it
//!   (`w - u - v` is `(w - u) - v`, `w = 1 - (u + v)`), so the results are
//!   reproducible by anyone reading the paper. Rounding makes them differ
//!   from the exact walk near lattice lines; `docs/float.md` measures where.
//! * The checked functions reject NaN, infinities and points outside the
//!   closed triangle (decided exactly, before any rounding) with a typed
//!   [`Error`]. [`index`] and [`index_version1`] check nothing and never
//!   panic.
//!
//! ```
//! use micromap_index::{uv2index, Level};
//! use num_rational::BigRational;
//! let r = |s: &str| s.parse::<BigRational>().unwrap();
//! let level = Level::new(2).unwrap();
//! assert_eq!(uv2index::index_exact(&r("3/10"), &r("3/10"), level), Ok(5));
//! assert_eq!(uv2index::index_f32(0.3, 0.3, level), Ok(5));
//! assert!(uv2index::index_f64(0.75, 0.5, level).is_err()); // u + v > 1
//! ```

use crate::{Coordinate, Error, Level, Outside};
use core::cmp::Ordering;
#[cfg(feature = "std")]
use num_rational::BigRational;
#[cfg(feature = "std")]
use num_traits::{One, Zero};

/// The arithmetic one walk step needs. Implement it for a number type and
/// the whole walk (and everything built on it) works on that type.
pub trait WalkNumber: Clone {
    /// `1 - (u + v)`, the third barycentric, computed as written.
    fn one_minus_sum(u: &Self, v: &Self) -> Self;
    /// `2 * self`.
    fn twice(&self) -> Self;
    /// `self + other`.
    fn plus(&self, other: &Self) -> Self;
    /// `self - other`.
    fn minus(&self, other: &Self) -> Self;
    /// `self` compared with `1/2`. Unordered values (NaN) compare as `Less`.
    fn cmp_half(&self) -> Ordering;
    /// `Ok` if `(u, v)` is a point of the closed triangle, else what is wrong.
    fn check_point(u: &Self, v: &Self) -> Result<(), Error>;
}

/// The digits of the four children when the current triangle is not
/// flipped; a `top_flip` swaps Left and Right.
pub mod digit {
    /// Left child: the corner at vertex 0 (`w > 1/2`).
    pub const LEFT: u8 = 0;
    /// Middle child: the upside-down centre triangle.
    pub const MIDDLE: u8 = 1;
    /// Right child: the corner at vertex 1 (`u >= 1/2`).
    pub const RIGHT: u8 = 2;
    /// Top child: the corner at vertex 2 (`v >= 1/2`).
    pub const TOP: u8 = 3;
}

/// The state of the walk between steps: the point's barycentrics in the
/// current micro-triangle and the two orientation flags.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Walk<T> {
    /// Weight of the current triangle's vertex 1.
    pub u: T,
    /// Weight of the current triangle's vertex 2.
    pub v: T,
    /// Weight of the current triangle's vertex 0.
    pub w: T,
    /// Ties on `v = 1/2` go to the Middle child (toggled by each Middle step).
    pub mid_flip: bool,
    /// Left and Right digits are swapped (toggled by each Top step).
    pub top_flip: bool,
}

impl<T: WalkNumber> Walk<T> {
    /// The walk at the root triangle, with `w = 1 - (u + v)`.
    pub fn new(u: T, v: T) -> Self {
        let w = T::one_minus_sum(&u, &v);
        Walk {
            u,
            v,
            w,
            mid_flip: false,
            top_flip: false,
        }
    }

    /// One subdivision step (paper Algorithm 4, talk version 2): returns the
    /// child's digit `0..=3` and moves the state into that child.
    ///
    /// ```
    /// use micromap_index::uv2index::{Walk, digit};
    /// let mut walk = Walk::new(0.25f64, 0.25);
    /// assert_eq!(walk.step(), digit::MIDDLE);
    /// assert!(walk.mid_flip);
    /// assert_eq!((walk.u, walk.v, walk.w), (0.0, 0.5, 0.5));
    /// ```
    pub fn step(&mut self) -> u8 {
        let (left, right) = if self.top_flip {
            (digit::RIGHT, digit::LEFT)
        } else {
            (digit::LEFT, digit::RIGHT)
        };
        let tie_to_middle = self.mid_flip && self.v.cmp_half() == Ordering::Equal;
        if self.w.cmp_half() == Ordering::Greater {
            let w = self.w.minus(&self.u).minus(&self.v);
            self.u = self.u.twice();
            self.v = self.v.twice();
            self.w = w;
            left
        } else if self.v.cmp_half() != Ordering::Less && !tie_to_middle {
            let v = self.v.minus(&self.u).minus(&self.w);
            self.u = self.u.twice();
            self.v = v;
            self.w = self.w.twice();
            self.top_flip = !self.top_flip;
            digit::TOP
        } else if self.u.cmp_half() != Ordering::Less && !tie_to_middle {
            let u = self.u.minus(&self.v).minus(&self.w);
            self.u = u;
            self.v = self.v.twice();
            self.w = self.w.twice();
            right
        } else {
            self.enter_middle();
            self.mid_flip = !self.mid_flip;
            digit::MIDDLE
        }
    }

    /// One step of the talk's first version ("Lookup Function – 1"): fixed
    /// digits, and the Top child re-oriented by rotating the coordinates
    /// instead of a flag. Flags are left untouched.
    ///
    /// It agrees with [`Walk::step`] inside every micro-triangle but not on
    /// some edges and vertices; it is kept as an oracle that shows why the
    /// flags exist (`tests/lattice.rs` counts the faces where they differ).
    pub fn step_version1(&mut self) -> u8 {
        if self.w.cmp_half() == Ordering::Greater {
            let w = self.w.minus(&self.u).minus(&self.v);
            self.u = self.u.twice();
            self.v = self.v.twice();
            self.w = w;
            digit::LEFT
        } else if self.v.cmp_half() != Ordering::Less {
            let v = self.v.minus(&self.u).minus(&self.w);
            let u = self.w.twice();
            self.w = self.u.twice();
            self.u = u;
            self.v = v;
            digit::TOP
        } else if self.u.cmp_half() != Ordering::Less {
            let u = self.u.minus(&self.v).minus(&self.w);
            self.u = u;
            self.v = self.v.twice();
            self.w = self.w.twice();
            digit::RIGHT
        } else {
            self.enter_middle();
            digit::MIDDLE
        }
    }

    /// `(u, v, w) <- (u + v - w, w + u - v, v + w - u)`, shared by both
    /// versions.
    fn enter_middle(&mut self) {
        let u = self.u.plus(&self.v).minus(&self.w);
        let v = self.w.plus(&self.u).minus(&self.v);
        let w = self.v.plus(&self.w).minus(&self.u);
        self.u = u;
        self.v = v;
        self.w = w;
    }
}

/// The walk's index for `(u, v)` at `level`, unchecked: no validation of the
/// point, never panics. For points outside the closed triangle the result
/// is whatever the walk computes (use [`index_checked`] to reject them).
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::index(0.3f32, 0.3, Level::new(2).unwrap()), 5);
/// ```
pub fn index<T: WalkNumber>(u: T, v: T, level: Level) -> u64 {
    let mut walk = Walk::new(u, v);
    (0..level.get()).fold(0u64, |index, _| (index << 2) | u64::from(walk.step()))
}

/// The talk's version 1 walk (see [`Walk::step_version1`]), unchecked.
///
/// ```
/// use micromap_index::{uv2index, Level};
/// let level = Level::new(2).unwrap();
/// // Inside micro-triangles both versions agree ...
/// assert_eq!(uv2index::index_version1(0.3f64, 0.3, level), 5);
/// // ... on some lattice vertices and edges they do not: at the vertex
/// // (1/4, 1/4) the reference (and version 2) say 5, version 1 says 7.
/// assert_eq!(uv2index::index(0.25f64, 0.25, level), 5);
/// assert_eq!(uv2index::index_version1(0.25f64, 0.25, level), 7);
/// ```
pub fn index_version1<T: WalkNumber>(u: T, v: T, level: Level) -> u64 {
    let mut walk = Walk::new(u, v);
    (0..level.get()).fold(0u64, |index, _| {
        (index << 2) | u64::from(walk.step_version1())
    })
}

/// The walk's index after checking that `(u, v)` is a finite point of the
/// closed triangle.
pub fn index_checked<T: WalkNumber>(u: T, v: T, level: Level) -> Result<u64, Error> {
    T::check_point(&u, &v)?;
    Ok(index(u, v, level))
}

#[cfg(feature = "std")]
/// The walk over exact rationals: the paper's algorithm over the reals.
///
/// Runs on machine integers ([`SmallRational`](crate::rational::SmallRational))
/// when both coordinates fit over a common denominator below `2^64`, on
/// [`BigRational`] otherwise; the result is the same ([`index_exact_ref`]
/// is the all-BigRational twin the tests compare with).
///
/// ```
/// use micromap_index::{uv2index, Level, Error, Outside};
/// use num_rational::BigRational;
/// let r = |s: &str| s.parse::<BigRational>().unwrap();
/// let level = Level::new(32).unwrap();
/// assert_eq!(uv2index::index_exact(&r("0"), &r("0"), level), Ok(0));
/// assert_eq!(
///     uv2index::index_exact(&r("2/3"), &r("1/2"), level),
///     Err(Error::OutsideTriangle { reason: Outside::SumAboveOne })
/// );
/// ```
pub fn index_exact(u: &BigRational, v: &BigRational, level: Level) -> Result<u64, Error> {
    match crate::rational::over_common_denominator(u, v) {
        Some((u, v, denominator)) => {
            use crate::rational::SmallRational;
            index_checked(
                SmallRational::new(u, denominator),
                SmallRational::new(v, denominator),
                level,
            )
        }
        None => index_exact_ref(u, v, level),
    }
}

#[cfg(feature = "std")]
/// [`index_exact`] computed entirely on [`BigRational`]: the slow, obviously
/// exact twin.
///
/// ```
/// use micromap_index::{uv2index, Level};
/// let r = |s: &str| s.parse().unwrap();
/// let level = Level::new(9).unwrap();
/// assert_eq!(
///     uv2index::index_exact_ref(&r("1/3"), &r("1/7"), level),
///     uv2index::index_exact(&r("1/3"), &r("1/7"), level)
/// );
/// ```
pub fn index_exact_ref(u: &BigRational, v: &BigRational, level: Level) -> Result<u64, Error> {
    index_checked(u.clone(), v.clone(), level)
}

/// The walk in binary32, expressions evaluated as the talk's Python writes
/// them.
///
/// ```
/// use micromap_index::{uv2index, Level, Error, Coordinate};
/// let level = Level::new(4).unwrap();
/// assert_eq!(uv2index::index_f32(f32::NAN, 0.0, level), Err(Error::NotANumber(Coordinate::U)));
/// ```
#[inline]
pub fn index_f32(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    index_checked(u, v, level)
}

/// The walk in binary64, expressions evaluated as the talk's Python writes
/// them.
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::index_f64(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
#[inline]
pub fn index_f64(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    index_checked(u, v, level)
}

/// `Ok` unless `u` or `v` is NaN or infinite; shared by the float checks.
pub(crate) fn check_finite(
    u_nan: bool,
    u_inf: bool,
    v_nan: bool,
    v_inf: bool,
) -> Result<(), Error> {
    match (u_nan, u_inf, v_nan, v_inf) {
        (true, _, _, _) => Err(Error::NotANumber(Coordinate::U)),
        (_, true, _, _) => Err(Error::Infinite(Coordinate::U)),
        (_, _, true, _) => Err(Error::NotANumber(Coordinate::V)),
        (_, _, _, true) => Err(Error::Infinite(Coordinate::V)),
        _ => Ok(()),
    }
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

macro_rules! impl_walk_number_for_float {
    ($float:ty, $exact_sum_above_one:expr) => {
        impl WalkNumber for $float {
            fn one_minus_sum(u: &Self, v: &Self) -> Self {
                1.0 - (u + v)
            }
            fn twice(&self) -> Self {
                2.0 * self
            }
            fn plus(&self, other: &Self) -> Self {
                self + other
            }
            fn minus(&self, other: &Self) -> Self {
                self - other
            }
            fn cmp_half(&self) -> Ordering {
                self.partial_cmp(&0.5).unwrap_or(Ordering::Less)
            }
            fn check_point(u: &Self, v: &Self) -> Result<(), Error> {
                check_finite(u.is_nan(), u.is_infinite(), v.is_nan(), v.is_infinite())?;
                let sum_above_one: fn($float, $float) -> bool = $exact_sum_above_one;
                let above = if sum_above_one(*u, *v) {
                    Ordering::Greater
                } else {
                    Ordering::Equal
                };
                check_signs(u.sign(), v.sign(), above)
            }
        }
    };
}

/// Sign of a finite float against zero (`-0.0` counts as zero).
trait SignOfFinite {
    fn sign(&self) -> Ordering;
}

impl SignOfFinite for f32 {
    fn sign(&self) -> Ordering {
        self.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }
}

impl SignOfFinite for f64 {
    fn sign(&self) -> Ordering {
        self.partial_cmp(&0.0).unwrap_or(Ordering::Equal)
    }
}

// f32 -> f64 is exact, and the two-sum decides the f64 sum exactly.
impl_walk_number_for_float!(f32, |u, v| sum_above_one_f64(f64::from(u), f64::from(v)));
impl_walk_number_for_float!(f64, sum_above_one_f64);

/// `u + v > 1` decided exactly for finite `u`, `v`: the rounded sum plus its
/// exact rounding error (Knuth's two-sum, exact in round-to-nearest when the
/// sum does not overflow, which it cannot once the sum is compared to 1:
/// an overflowing sum is `inf > 1` either way).
fn sum_above_one_f64(u: f64, v: f64) -> bool {
    let sum = u + v;
    let v_part = sum - u;
    let u_part = sum - v_part;
    let error = (u - u_part) + (v - v_part);
    sum > 1.0 || (sum == 1.0 && error > 0.0)
}

#[cfg(feature = "std")]
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_sum_test_catches_rounding() {
        // 0.5 + (0.5 + 2^-53) rounds to 1.0 in f64 but is above 1.
        let v = 0.5 + 2f64.powi(-53);
        assert!(sum_above_one_f64(0.5, v));
        assert!(!sum_above_one_f64(0.5, 0.5));
        let tiny = 2f64.powi(-80);
        assert!(sum_above_one_f64(1.0, tiny));
        assert!(!sum_above_one_f64(1.0 - 2f64.powi(-53), tiny));
        assert_eq!(
            f64::check_point(&1.0, &tiny),
            Err(Error::OutsideTriangle {
                reason: Outside::SumAboveOne
            })
        );
        assert_eq!(f32::check_point(&-0.0, &1.0), Ok(()));
        assert_eq!(
            f32::check_point(&1.0, &f32::from_bits(1)),
            Err(Error::OutsideTriangle {
                reason: Outside::SumAboveOne
            })
        );
    }
}
