//! What can be wrong with an input.

use core::fmt;

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
    /// A dyadic point's denominator `2^scale_log2` is above what the
    /// function supports.
    ScaleTooLarge {
        /// The `scale_log2` asked for.
        scale_log2: u32,
        /// The largest supported.
        max: u32,
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
            Error::ScaleTooLarge { scale_log2, max } => write!(
                f,
                "denominator 2^{scale_log2} is too large: this function supports 2^0..=2^{max}"
            ),
        }
    }
}

impl core::error::Error for Error {}
