//! The reference in binary32 without floating point: every float
//! operation of the reference is exact except the rounding of `uf + vf`,
//! which becomes an exact comparison with `1 - 2^-25` (`docs/fixed.md`).

use super::index_from_cell;
use crate::num::fixed::sticky_round;
use crate::SpecLevel;

/// Fraction bits (with the sticky bit) the mirror keeps of `uf` and `vf`.
/// `docs/fixed.md`: 27 suffice; 32 leave room.
const MIRROR_FRACTION_BITS: u32 = 32;

/// What the reference's `uf + vf >= 1.0f` becomes on exact fractions:
/// binary32 round-to-nearest-even lifts every real sum in `[1 - 2^-25, 1)`
/// to `1.0`, and no smaller one, so the test is `uf + vf >= 1 - 2^-25`.
const MIRROR_DIAGONAL_THRESHOLD: u128 =
    (1 << MIRROR_FRACTION_BITS) - (1 << (MIRROR_FRACTION_BITS - 25));

/// The reference's first steps on one binary32 coordinate, on its bits:
/// `clamp` (NaN and everything negative -> 0, everything from 1 up,
/// +inf included -> 1), then `x * 2^level` split into the truncated cell and
/// the fraction `fu - float(iu)` (both exact in binary32, so exact here) in
/// sticky fixed point.
fn mirror_cell_and_fraction(x: f32, level: u32) -> (u32, u128) {
    let bits = x.to_bits();
    let (significand, exponent): (u64, i32) = if bits >> 31 == 1 || bits > 0x7f80_0000 {
        (0, 0) // negative (incl. -0, -inf, negative NaN) or positive NaN
    } else if bits >= 0x3f80_0000 {
        (1, 0) // >= 1.0, +inf included
    } else {
        let biased = (bits >> 23) as i32;
        let fraction = u64::from(bits & 0x7f_ffff);
        if biased == 0 {
            (fraction, -149)
        } else {
            (fraction | 0x80_0000, biased - 150)
        }
    };
    // x * 2^level = significand * 2^shift; below 2^31 + 1 for level <= 31.
    let shift = exponent + level as i32;
    if shift >= 0 {
        ((significand << shift) as u32, 0)
    } else {
        let drop = shift.unsigned_abs();
        let (cell, fraction) = if drop >= 64 {
            (0, significand)
        } else {
            (significand >> drop, significand & ((1 << drop) - 1))
        };
        let fraction = sticky_round(fraction, shift, MIRROR_FRACTION_BITS);
        (cell as u32, fraction)
    }
}

/// [`reference_bits_f32`](super::reference_bits_f32) reproduced with
/// integer operations only: for every pair of `f32` (NaN, ±0, ±inf,
/// subnormals, outside the triangle) and every `u32` level, the same bits,
/// including the inputs where binary32 rounding of `uf + vf` makes the
/// reference differ from its real reading. Levels `>= 32` use `level % 32`.
///
/// ```
/// use micromap_index::spec;
/// for (u, v) in [(0.3, 0.3), (f32::NAN, 2.0), (0.125, 0.125 - 2f32.powi(-27))] {
///     assert_eq!(spec::reference_bits_f32_by_integers(u, v, 2), spec::reference_bits_f32(u, v, 2));
/// }
/// ```
#[must_use]
pub fn reference_bits_f32_by_integers(u: f32, v: f32, level: u32) -> u32 {
    let level = level % 32;
    let (iu, uf) = mirror_cell_and_fraction(u, level);
    let (iv, vf) = mirror_cell_and_fraction(v, level);
    let diagonal = uf + vf >= MIRROR_DIAGONAL_THRESHOLD;
    index_from_cell(iu, iv, diagonal, level)
}

/// [`index_f32`](super::index_f32) computed with integer operations only:
/// the same bits as the GPU for every pair of `f32`.
///
/// ```
/// use micromap_index::{spec, SpecLevel};
/// let level = SpecLevel::new(2).unwrap();
/// assert_eq!(spec::index_f32_by_integers(0.3, 0.3, level), 5);
/// assert_eq!(spec::index_f32_by_integers(f32::NAN, 0.9, level), spec::index_f32(f32::NAN, 0.9, level));
/// ```
#[inline]
#[must_use]
pub fn index_f32_by_integers(u: f32, v: f32, level: SpecLevel) -> u32 {
    reference_bits_f32_by_integers(u, v, level.get())
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_fractions_are_exact_or_sticky() {
        assert_eq!(mirror_cell_and_fraction(0.75, 1), (1, 1 << 31));
        assert_eq!(mirror_cell_and_fraction(1.0, 3), (8, 0));
        assert_eq!(mirror_cell_and_fraction(f32::INFINITY, 3), (8, 0));
        assert_eq!(mirror_cell_and_fraction(-f32::NAN, 3), (0, 0));
        assert_eq!(mirror_cell_and_fraction(f32::from_bits(1), 0), (0, 1));
    }
}
