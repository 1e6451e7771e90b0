//! The reference's steps over the reals (feature `exact`).

use super::{index_from_cell, wide_index_from_cell, Cell};
use crate::num::rational::over_common_denominator;
use crate::{Level, SpecLevel};
use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{One, ToPrimitive, Zero};

/// The reference's steps over the reals, for rational `(u, v)`.
///
/// Each coordinate is clamped to `[0, 1]`, then `iu = floor(u * 2^level)`,
/// `uf = u * 2^level - iu` exactly (likewise for `v`), and the diagonal test
/// is the exact `uf + vf >= 1`.
///
/// ```
/// use micromap_index::{spec, SpecLevel};
/// use num_rational::BigRational;
/// let r = |s: &str| s.parse::<BigRational>().unwrap();
/// let level = SpecLevel::new(2).unwrap();
/// assert_eq!(spec::index_real(&r("3/10"), &r("3/10"), level), 5);
/// // On the diagonal of cell (0, 0) the point goes to the upside-down
/// // micro-triangle (index 1 at level 2).
/// assert_eq!(spec::index_real(&r("1/8"), &r("1/8"), level), 1);
/// ```
#[must_use]
pub fn index_real(u: &BigRational, v: &BigRational, level: SpecLevel) -> u32 {
    let cell = cell_real(u, v, level.level());
    // level <= 16: cells are at most 2^16.
    index_from_cell(cell.iu as u32, cell.iv as u32, cell.diagonal, level.get())
}

/// The reference's steps over the reals, widened to 64-bit words: levels
/// `0..=32`. Equal to [`index_real`] for levels `0..=16`.
///
/// ```
/// use micromap_index::{spec, Level};
/// let r = |s: &str| s.parse().unwrap();
/// assert_eq!(spec::wide_index_real(&r("1/3"), &r("1/3"), Level::new(20).unwrap()), 366_503_875_925);
/// ```
#[must_use]
pub fn wide_index_real(u: &BigRational, v: &BigRational, level: Level) -> u64 {
    let cell = cell_real(u, v, level);
    wide_index_from_cell(cell.iu, cell.iv, cell.diagonal, level.get())
}

/// The reference's first half over the reals: clamp to `[0, 1]`, exact
/// floor and fractions of `x * 2^level`, exact `uf + vf >= 1`.
///
/// Runs on machine integers when both coordinates fit over a common
/// denominator below `2^64`, on [`BigRational`] otherwise (the tests compare
/// the two paths).
///
/// ```
/// use micromap_index::{spec::{cell_real, Cell}, Level};
/// let r = |s: &str| s.parse().unwrap();
/// // (1/3, 2/3) at level 1: cell (0, 1), fractions 2/3 + 1/3 >= 1.
/// assert_eq!(cell_real(&r("1/3"), &r("2/3"), Level::new(1).unwrap()), Cell { iu: 0, iv: 1, diagonal: true });
/// ```
#[must_use]
pub fn cell_real(u: &BigRational, v: &BigRational, level: Level) -> Cell {
    match over_common_denominator(u, v) {
        Some((a, b, d)) => cell_over_denominator(a, b, d, level.get()),
        None => cell_real_ref(u, v, level),
    }
}

/// [`cell_real`] of `a / d`, `b / d` (`d >= 1`, `|a|, |b| <= 2^100`, levels
/// `0..=32`, as `over_common_denominator` gives them) in `u128` words:
/// clamped numerators are at most `d < 2^64`, times `2^32` below `2^96`,
/// so nothing is lost; z3 proves the steps equal to the definition for
/// every such input (`crates/lab/certificates/rationals.py`,
/// `docs/verification.md` 10.12).
fn cell_over_denominator(a: i128, b: i128, d: u64, level: u32) -> Cell {
    let d = u128::from(d);
    let clamp = |x: i128| u128::try_from(x).unwrap_or(0).min(d) << level;
    let (su, sv) = (clamp(a), clamp(b));
    Cell {
        iu: (su / d) as u64,
        iv: (sv / d) as u64,
        diagonal: su % d + sv % d >= d,
    }
}

unstable_pub_fn! {
    /// [`cell_real`] computed entirely on [`BigRational`]: the slow, obviously
    /// exact twin.
    #[must_use]
    fn cell_real_ref(u: &BigRational, v: &BigRational, level: Level) -> Cell {
        let scale = BigRational::from_integer(BigInt::one() << level.get());
        let quantize = |x: &BigRational| {
            let x = clamp_rational(x) * &scale;
            let cell = x.floor();
            let fraction = x - &cell;
            // clamped to [0, 2^32]: always fits.
            let cell = cell.to_integer().to_u64().unwrap_or(u64::MAX);
            (cell, fraction)
        };
        let (iu, uf) = quantize(u);
        let (iv, vf) = quantize(v);
        Cell {
            iu,
            iv,
            diagonal: uf + vf >= BigRational::one(),
        }
    }
}

fn clamp_rational(x: &BigRational) -> BigRational {
    if *x < BigRational::zero() {
        BigRational::zero()
    } else if *x > BigRational::one() {
        BigRational::one()
    } else {
        x.clone()
    }
}
