//! The walk evaluated in `f32` / `f64` arithmetic, as the talk's Python
//! reads. Not exact: see `docs/float.md`.

use super::index;
use crate::{Error, Level};

/// The walk evaluated in binary32 arithmetic, each expression as the talk's
/// Python writes it. **Not** the exact answer near lattice lines (use
/// [`exact_index_f32`](super::exact_index_f32) for that); NaN, infinities and
/// points outside the closed triangle are errors.
///
/// ```
/// use micromap_index::{uv2index, Level, Error, Coordinate};
/// let level = Level::new(4).unwrap();
/// assert_eq!(uv2index::index_in_f32_arithmetic(0.3, 0.3, level), Ok(81));
/// assert_eq!(uv2index::index_in_f32_arithmetic(f32::NAN, 0.0, level), Err(Error::NotANumber(Coordinate::U)));
/// ```
#[inline]
pub fn index_in_f32_arithmetic(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    index(u, v, level)
}

/// The walk evaluated in binary64 arithmetic, each expression as the talk's
/// Python writes it. **Not** the exact answer near lattice lines.
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::index_in_f64_arithmetic(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
#[inline]
pub fn index_in_f64_arithmetic(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    index(u, v, level)
}
