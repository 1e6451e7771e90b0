//! Barycentric coordinates → opacity-micromap micro-triangle index.
//!
//! A ray hit reports barycentrics `(u, v)` (the weights of vertices 1 and 2;
//! `w = 1 - u - v` weighs vertex 0). An opacity micromap of subdivision level
//! `n` splits the triangle into `4^n` micro-triangles stored in the order of a
//! space-filling curve; this crate maps `(u, v, n)` to the position of the
//! micro-triangle on that curve, exactly as the Vulkan specification's
//! reference code `BarycentricsToSpaceFillingCurveIndex` does.
//!
//! # Implementations
//!
//! Sibling modules compute the same mapping in different ways; each states
//! its guarantees in its own docs.
//!
//! | module / function | number type | levels | what "exact" means |
//! |---|---|---|---|
//! | [`spec::index_f32`] | IEEE binary32 | 0..=16 | bit-for-bit the Vulkan reference on a GPU, for every pair of `f32` including NaN, ±inf, subnormals and points outside the triangle (checked against the C reference) |
//! | [`fixed::index_mirror_f32`] | integers | 0..=16 | the same bits as [`spec::index_f32`] for every pair of `f32`, with integer operations only |
//! | [`spec::index_exact`] | exact rationals | 0..=16 | the reference's steps over the reals: exact floor, fractions and `uf + vf >= 1`; differs from binary32 only where `uf + vf` is in `[1 - 2^-25, 1)` |
//! | [`spec::index_wide_exact`], [`spec::index_wide_f32`] | exact / binary32 | 0..=32 | the reference widened to 64-bit words (the original is wrong above 16) |
//! | [`uv2index::index_exact`] | exact rationals | 0..=32 | the paper's walk (Algorithm 4) over the reals; equal to the reference at every real point of levels 0..=16 ([`prove`]) |
//! | [`uv2index::index_f32`], [`uv2index::index_f64`] | binary32 / binary64 | 0..=32 | the paper's walk evaluated left to right in that float type, as the talk's Python reads; *not* the exact answer near lattice lines (see `docs/float.md`) |
//! | [`fixed::index_f32`], [`fixed::index_f64`] | integers | 0..=32 | the walk on fixed-point numbers; equal to [`uv2index::index_exact`] for every finite float |
//! | [`uv2index::index_version1`] | any | 0..=32 | the talk's first walk (rotations, no flip flags): an oracle that shows why the flags exist |
//! | [`inverse::micro_triangle`] | integers | 0..=32 | the inverse: index → the micro-triangle's vertices as exact dyadic numerators, replaying the walk's digits and flags; the walk maps every point inside it back to the index |
//!
//! Exact functions run on machine integers when the inputs allow
//! ([`rational`]) and keep all-[`BigRational`] `*_ref` twins for the tests.
//! Without the default `std` feature the crate is `no_std` and builds the
//! integer core only: [`spec`]'s float and dyadic steps, the generic walk in
//! [`uv2index`], and [`fixed`].
//!
//! [`prove`] checks the walk against the reference on every face of a
//! level's lattice, which decides every real point (`docs/verification.md`).
//!
//! ```
//! use micromap_index::{spec, uv2index, Level};
//!
//! let level = Level::new(3).unwrap();
//! // The micro-triangle holding the centroid-ish point (0.28, 0.4).
//! let by_spec = spec::index_f32_checked(0.28, 0.4, level).unwrap();
//! let by_walk = uv2index::index_f32(0.28, 0.4, level).unwrap();
//! assert_eq!(u64::from(by_spec), by_walk);
//! ```
//!
//! [`BigRational`]: num_rational::BigRational
#![cfg_attr(not(feature = "std"), no_std)]
// `deny`, not `forbid`: `batch::arch` (runtime-dispatched SIMD) is the one
// module allowed `unsafe`, to call `#[target_feature]` functions.
#![deny(unsafe_code)]
#![deny(missing_docs)]

pub mod batch;
#[cfg(feature = "std")]
pub mod eval;
pub mod exact_float;
pub mod fixed;
#[cfg(feature = "fuzzing")]
pub mod fuzzing;
#[cfg(feature = "std")]
pub mod inverse;
#[cfg(feature = "std")]
pub mod lattice;
pub mod micromap;
pub mod microtri;
#[cfg(feature = "std")]
pub mod prove;
#[cfg(feature = "std")]
pub mod rational;
pub mod rng;
pub mod spec;
pub mod uv2index;
#[cfg(feature = "std")]
pub mod value;
#[cfg(feature = "std")]
pub mod vectors;

use core::fmt;

/// A subdivision level: the micromap has `4^level` micro-triangles.
///
/// Every level `0..=32` can be represented (the index of a level-32
/// micro-triangle fills a `u64`); functions with a lower limit, such as the
/// Vulkan reference (16), check it themselves and say so in their error.
///
/// ```
/// use micromap_index::{Level, Error};
/// assert_eq!(Level::new(12).unwrap().get(), 12);
/// assert_eq!(Level::new(33), Err(Error::LevelTooHigh { level: 33, max: 32 }));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Level(u8);

impl Level {
    /// The highest level any function in this crate accepts.
    pub const MAX: u32 = 32;

    /// A level, or [`Error::LevelTooHigh`] above [`Level::MAX`].
    #[inline]
    pub const fn new(level: u32) -> Result<Level, Error> {
        if level > Self::MAX {
            Err(Error::LevelTooHigh {
                level,
                max: Self::MAX,
            })
        } else {
            Ok(Level(level as u8))
        }
    }

    /// The level as a number.
    #[inline]
    pub const fn get(self) -> u32 {
        self.0 as u32
    }

    /// The number of micro-triangles, `4^level`.
    #[inline]
    pub const fn micro_triangle_count(self) -> u128 {
        1u128 << (2 * self.0 as u32)
    }

    /// The level, or [`Error::LevelTooHigh`] if it is above `max`.
    #[inline]
    pub(crate) const fn at_most(self, max: u32) -> Result<Level, Error> {
        if self.get() > max {
            Err(Error::LevelTooHigh {
                level: self.get(),
                max,
            })
        } else {
            Ok(self)
        }
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

/// Which barycentric coordinate an error is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coordinate {
    /// `u`, the weight of vertex 1.
    U,
    /// `v`, the weight of vertex 2.
    V,
}

impl fmt::Display for Coordinate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Coordinate::U => "u",
            Coordinate::V => "v",
        })
    }
}

/// What was wrong with an input.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Error {
    /// The level is above what the function supports.
    LevelTooHigh {
        /// The level asked for.
        level: u32,
        /// The highest level the function supports.
        max: u32,
    },
    /// A coordinate is NaN.
    NotANumber(Coordinate),
    /// A coordinate is +inf or -inf.
    Infinite(Coordinate),
    /// The point is not in the closed triangle `u >= 0, v >= 0, u + v <= 1`
    /// (decided exactly, not after rounding).
    OutsideTriangle {
        /// Which of the three conditions failed first (`u < 0`, `v < 0`,
        /// `u + v > 1`).
        reason: Outside,
    },
    /// The micro-triangle index is not below `4^level`.
    IndexOutOfRange {
        /// The index asked for.
        index: u64,
        /// The level it was asked for at.
        level: u32,
    },
}

/// Which side of the triangle a point is outside of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Outside {
    /// `u < 0`.
    NegativeU,
    /// `v < 0`.
    NegativeV,
    /// `u + v > 1` (so `w < 0`).
    SumAboveOne,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::LevelTooHigh { level, max } => {
                write!(
                    f,
                    "level {level} is too high: this function supports levels 0..={max}"
                )
            }
            Error::NotANumber(c) => write!(f, "{c} is NaN"),
            Error::Infinite(c) => write!(f, "{c} is infinite"),
            Error::OutsideTriangle { reason } => f.write_str(match reason {
                Outside::NegativeU => "point is outside the triangle: u < 0",
                Outside::NegativeV => "point is outside the triangle: v < 0",
                Outside::SumAboveOne => "point is outside the triangle: u + v > 1",
            }),
            Error::IndexOutOfRange { index, level } => {
                write!(f, "index {index} is out of range for level {level}")?;
                // 4^level overflows u128 only for levels no function accepts.
                match 1u128.checked_shl(level.saturating_mul(2)) {
                    Some(count) => write!(f, ": valid indices are 0..={}", count - 1),
                    None => Ok(()),
                }
            }
        }
    }
}

impl core::error::Error for Error {}
