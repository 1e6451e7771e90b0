//! The exact walk's answer for every finite float, with fixed point.
//!
//! The walk only compares the point against lattice lines (`u = k/2^level`,
//! `v = k/2^level`, `u + v = k/2^level`), so any point in the same lattice
//! face gives the same index: the functions here do not need every bit of
//! the input. Each coordinate is rounded down to `P - 1` fractional bits and
//! a *sticky* bit, set when anything was cut off, is appended as the `P`-th
//! bit. Per coordinate this preserves the side of every line at multiples of
//! `2^-(P-1)`; for the sum it does so as long as `P >= level + 26` (binary32
//! inputs, 24-bit significands) or `P >= level + 55` (binary64, 53 bits):
//! both coordinates can only carry a sticky bit when both are below
//! `2^(s+1-P)` (`s` the significand width), so their sum stays below the
//! first lattice line. `docs/fixed.md` spells the argument out. With `P = 60`
//! ([`Fixed64`], binary32) and `P = 124` ([`Fixed128`], binary64) every level
//! up to 32 is covered.

use super::index_unchecked;
use crate::num::fixed::sticky_scaled;
use crate::num::{Fixed128, Fixed64, WalkNumber};
use crate::{Error, Level};

/// The exact walk's index for a finite binary32 point: equal to the walk
/// over the reals (`index_real`, feature `exact`) at the same point, for
/// every level `0..=32`, with integers only. NaN, infinities and points
/// outside the closed triangle are errors.
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::exact_index_f32(0.3, 0.3, Level::new(2).unwrap()), Ok(5));
/// ```
pub fn exact_index_f32(u: f32, v: f32, level: Level) -> Result<u64, Error> {
    let (u, v) = (f64::from(u), f64::from(v));
    f64::check_point(&u, &v)?;
    let p = Fixed64::ONE_LOG2;
    // In [0, 2^60]: fits.
    let to_fixed = |x| Fixed64::from_raw(sticky_scaled(x, p) as i64);
    Ok(index_unchecked(to_fixed(u), to_fixed(v), level))
}

/// The exact walk's index for a finite binary64 point: equal to the walk
/// over the reals at the same point, for every level `0..=32`, with integers
/// only.
///
/// ```
/// use micromap_index::{uv2index, Level};
/// assert_eq!(uv2index::exact_index_f64(0.28, 0.4, Level::new(1).unwrap()), Ok(1));
/// ```
pub fn exact_index_f64(u: f64, v: f64, level: Level) -> Result<u64, Error> {
    f64::check_point(&u, &v)?;
    let p = Fixed128::ONE_LOG2;
    let to_fixed = |x| Fixed128::from_raw(sticky_scaled(x, p));
    Ok(index_unchecked(to_fixed(u), to_fixed(v), level))
}
