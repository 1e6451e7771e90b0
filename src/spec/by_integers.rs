//! The reference in binary32 without floating point: every float
//! operation of the reference is exact except the rounding of `uf + vf`,
//! which becomes an exact comparison with `1 - 2^-25` (`docs/fixed.md`).
//! The first half is the kernel's on the bits (`kernel::wide_cell`,
//! proved equal to the definition at every binary32 input and level,
//! `docs/verification.md` 10.12), the integer half the reference's own
//! 32-bit code.

use super::index_from_cell;
use crate::kernel::{self, Params};
use crate::SpecLevel;

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
    let params = Params::new(level, kernel::BINARY32_THRESHOLD);
    // The cells come clamped to `2^level - 1`, which the reference's own
    // clamp in `index_from_cell` leaves alone; the fraction of `x >= 1` is 0
    // as the reference's (`fu = 2^level` exactly).
    let (iu, iv, diagonal) = kernel::wide_cell(u.to_bits(), v.to_bits(), &params);
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
    fn the_mirror_gives_the_literal_ports_bits_on_the_clamps() {
        let values = [
            0.75,
            1.0,
            f32::INFINITY,
            -f32::NAN,
            f32::NAN,
            -0.0,
            f32::from_bits(1),
            1.0 - f32::EPSILON / 2.0,
            0.5 - f32::EPSILON / 4.0,
        ];
        for level in 0..=33 {
            for u in values {
                for v in values {
                    assert_eq!(
                        reference_bits_f32_by_integers(u, v, level),
                        super::super::reference_bits_f32(u, v, level),
                        "{u} {v} level {level}"
                    );
                }
            }
        }
    }
}
