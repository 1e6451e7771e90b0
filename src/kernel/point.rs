//! The point kernel: the reference for one pair of bit patterns, one lane
//! at a time, and the scalar steps the chunked pipeline's safe stages
//! share.

use super::coordinate::{binary32_coordinate, binary32_unit_coordinate, clamp_binary32};
use super::word::{narrow_point, wide_point};
use super::Params;

/// Cell clamped to `last` and `floor(fraction * 2^31)` of one coordinate,
/// in 32-bit words, every level `0..=32`: [`binary32_coordinate`] on `u32`.
#[inline(always)]
pub(super) fn coordinate<const WIDE: bool>(bits: u32, params: &Params) -> (u32, u32) {
    binary32_coordinate::<u32, WIDE>(bits, params.shift_base, params.last)
}

/// [`coordinate`] for bits already in `[0, 1]` (`bits <= ONE_BITS`: no
/// clamp) at levels `0..=16`, in one 64-bit shift:
/// [`binary32_unit_coordinate`] on `u64`.
#[inline(always)]
pub(crate) fn unit_coordinate(bits: u32, params: &Params) -> (u32, u32) {
    let (cell, fraction) =
        binary32_unit_coordinate(u64::from(bits), params.shift_base, params.last);
    // Both below 2^31: the cell is at most `last`, the fraction masked.
    (cell as u32, fraction as u32)
}

/// The reference's clamp to `[0, 1]` on floats, with two changes that
/// leave its index alone (the lab proves it: `docs/verification.md`
/// 10.12, `crates/lab/src/entry_points/clamp.rs`):
///
/// * Everything below the smallest normal, `2^-126`, becomes `2^-126`:
///   subnormals, zeros, negatives and NaN (which compares false), in one
///   `max` whose NaN operand is the first (x86's `maxps` then returns the
///   second). This keeps the float steps after it off the slow paths CPUs
///   take on subnormals. Every such value has cell 0 and a fraction below
///   `2^-110` at level 16 (the reference's is 0 or a subnormal's
///   `2^level` multiple, below `2^-110` too), and a fraction that small
///   cannot move `uf + vf` across `1 - 2^-25`: the other fraction is at
///   most `1 - 2^-24`, so the real sum stays below `1 - 2^-25` and the
///   binary32 sum below 1 either way.
/// * Everything from 1 up (`+inf` too) becomes `1 - 2^-24`, the float below
///   1, whose cell is `last` at every level `0..=16`: the cell the
///   reference clamps `x = 1` to, so no cell needs clamping afterwards. Its
///   fraction differs from `x = 1`'s 0 but is never read: a cell of `last`
///   makes `iu + iv < last` false, which rules the diagonal step out.
#[inline(always)]
#[must_use]
pub fn clamp_flushed(bits: u32) -> f32 {
    let x = f32::from_bits(bits);
    let x = if x > f32::MIN_POSITIVE {
        x
    } else {
        f32::MIN_POSITIVE
    };
    if x < BELOW_ONE {
        x
    } else {
        BELOW_ONE
    }
}

/// `1 - 2^-24`, the float below 1: where [`clamp_flushed`] stops.
pub const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// `2^23`: adding it to a float in `[0, 2^23)` leaves an integer in the low
/// bits of the sum's significand.
const MAGIC: f32 = 8_388_608.0;

/// Cell (at most `last`) and the exact binary32 fraction, by the
/// reference's own float operations (every one exact): `fu = x * 2^level`,
/// `iu = trunc(fu)`, `uf = fu - iu` ([`truncate_float`]). Levels `0..=16`
/// (`fu <= 2^16`).
#[inline(always)]
pub(super) fn coordinate_float(bits: u32, params: &Params) -> (u32, f32) {
    truncate_float(clamp_flushed(bits) * params.scale)
}

/// `(trunc(fu), fu - trunc(fu))` for `fu` in `[0, 2^23)`, both exact.
///
/// The truncation avoids a float-to-integer conversion, which baselines
/// without a vector form of it (SSE2) do one lane at a time: adding `2^23`
/// rounds `fu < 2^23` to an integer `r` in the low bits of the sum (exact),
/// and `r - 1` is taken when `r > fu`. The lab checks it at every binary32
/// `fu` the kernel passes (`[2^-126, 2^16)`, `docs/verification.md` 10.12).
#[inline(always)]
#[must_use]
pub fn truncate_float(fu: f32) -> (u32, f32) {
    let sum = fu + MAGIC;
    let rounded = sum - MAGIC;
    let above = rounded > fu;
    let truncated = rounded - if above { 1.0 } else { 0.0 };
    let cell = (sum.to_bits() & 0x7f_ffff) - u32::from(above);
    (cell, fu - truncated)
}

/// How [`narrow`] takes the cell and fraction: the bits clamped, then
/// [`unit_coordinate`]'s one 64-bit shift (scalar callers).
pub(crate) const CELL_BY_SHIFTS: u8 = 0;
/// [`coordinate_float`]'s float steps (SSE2 has no per-lane shifts).
pub(crate) const CELL_BY_FLOAT: u8 = 1;

/// The reference in binary32 for one pair of bit patterns, levels `0..=16`:
/// the same bits as `spec::index_f32`, the cell and fraction taken as `CELL`
/// says.
#[inline(always)]
pub(crate) fn narrow<const CELL: u8>(u_bits: u32, v_bits: u32, params: &Params) -> u32 {
    if CELL == CELL_BY_FLOAT {
        narrow_by_floats(u_bits, v_bits, params, coordinate_float)
    } else {
        narrow_in_unit(clamp_binary32(u_bits), clamp_binary32(v_bits), params)
    }
}

/// [`narrow`] from a float first half: `coordinate` gives each cell (at
/// most `last`) and exact binary32 fraction, and the diagonal test is the
/// reference's own `uf + vf >= 1.0f`.
#[inline(always)]
fn narrow_by_floats(
    u_bits: u32,
    v_bits: u32,
    params: &Params,
    coordinate: impl Fn(u32, &Params) -> (u32, f32),
) -> u32 {
    let (iu, uf) = coordinate(u_bits, params);
    let (iv, vf) = coordinate(v_bits, params);
    narrow_from_clamped_cell(iu, iv, uf + vf >= 1.0, params.last)
}

/// [`narrow`] for bits already in `[0, 1]` (callers check `bits <=
/// ONE_BITS`), scalar: [`unit_coordinate`]'s one shift per coordinate.
#[inline(always)]
pub(crate) fn narrow_in_unit(u_bits: u32, v_bits: u32, params: &Params) -> u32 {
    let (iu, uf) = unit_coordinate(u_bits, params);
    let (iv, vf) = unit_coordinate(v_bits, params);
    narrow_from_clamped_cell(iu, iv, uf + vf >= params.threshold, params.last)
}

/// The integer half and interleave of levels `0..=16` from cells already
/// clamped to `last` (`iu, iv <= last`): [`wide_from_clamped_cell`]'s
/// value there.
#[inline(always)]
pub(crate) fn narrow_from_clamped_cell(iu: u32, iv: u32, diagonal: bool, last: u32) -> u32 {
    narrow_point::<u32>(iu, iv, diagonal, last)
}

/// The reference widened to 64 bits for one pair of bit patterns, levels
/// `0..=32`: the same bits as `spec::wide_index_f32` (binary32 threshold) or
/// the exact reading of the reference (exact threshold).
#[inline(always)]
pub(crate) fn wide(u_bits: u32, v_bits: u32, params: &Params) -> u64 {
    let (iu, iv, diagonal) = wide_cell(u_bits, v_bits, params);
    wide_from_clamped_cell(iu, iv, diagonal, params.last)
}

/// The first half of [`wide`], levels `0..=32`: both cells clamped to
/// `last` and the diagonal test `Fu + Fv >= threshold` on the 31-bit
/// floored fractions (proved equal to the definition at every binary32
/// input, `docs/verification.md` 10.12).
#[inline(always)]
pub(crate) fn wide_cell(u_bits: u32, v_bits: u32, params: &Params) -> (u32, u32, bool) {
    let (iu, uf) = coordinate::<true>(u_bits, params);
    let (iv, vf) = coordinate::<true>(v_bits, params);
    (iu, iv, uf + vf >= params.threshold)
}

/// The wide integer half and interleave (two 16-bit interleaves in 32-bit
/// words, then one widening) from cells already clamped to
/// `last` (`iu, iv <= last`): `spec::wide_index_from_cell` on such cells.
#[inline(always)]
pub(crate) fn wide_from_clamped_cell(iu: u32, iv: u32, diagonal: bool, last: u32) -> u64 {
    let (low, high) = wide_point::<u32>(iu, iv, diagonal, last);
    u64::from(low) | (u64::from(high) << 32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::ONE_BITS;
    use crate::kernel::{BINARY32_THRESHOLD, EXACT_THRESHOLD};

    #[test]
    fn interleave_puts_b0_on_even_bits() {
        use crate::kernel::word::interleave_16;
        assert_eq!(interleave_16(0xffff_u32, 0), 0x5555_5555);
        assert_eq!(interleave_16(0_u32, 0xffff), 0xaaaa_aaaa);
        assert_eq!(interleave_16(0b10_u32, 0b01), 0b0110);
    }

    #[test]
    fn unit_coordinate_is_coordinate_in_the_unit_interval() {
        // No allocation: the lib's tests also run without `alloc`.
        let check = |b: u32| {
            if b > ONE_BITS {
                return;
            }
            for level in 0..=16 {
                let p = Params::new(level, EXACT_THRESHOLD);
                assert_eq!(
                    unit_coordinate(b, &p),
                    coordinate::<false>(b, &p),
                    "level {level}, bits {b:#010x}"
                );
            }
        };
        for b in [0, 1, 0x7f_ffff, 0x80_0000, ONE_BITS - 1, ONE_BITS] {
            check(b);
        }
        for e in 0..=127u32 {
            for b in [e << 23, (e << 23) | 0x7f_ffff, (e << 23) | 0x40_0001] {
                check(b);
            }
        }
        let mut rng = micromap_index_test_support::SplitMix64::new(0x9e37_79b9_7f4a_7c15);
        for _ in 0..20_000 {
            let x = rng.next_u64();
            check((x as u32) % (ONE_BITS + 1));
        }
    }

    #[test]
    fn coordinates_split_cell_and_fraction() {
        let p = Params::new(1, BINARY32_THRESHOLD);
        assert_eq!(coordinate::<false>(0.75f32.to_bits(), &p), (1, 1 << 30));
        assert_eq!(coordinate::<false>(1.0f32.to_bits(), &p), (1, 0));
        assert_eq!(coordinate::<false>(f32::NAN.to_bits(), &p), (0, 0));
        assert_eq!(coordinate::<false>((-0.5f32).to_bits(), &p), (0, 0));
        assert_eq!(coordinate::<false>(f32::INFINITY.to_bits(), &p), (1, 0));
        // 2^-149 * 2: far below 2^-31, floors to 0.
        assert_eq!(coordinate::<false>(1, &p), (0, 0));
        let p = Params::new(32, BINARY32_THRESHOLD);
        assert_eq!(coordinate::<true>(1.0f32.to_bits(), &p), (u32::MAX, 0));
        assert_eq!(coordinate::<true>(0.5f32.to_bits(), &p), (1 << 31, 0));
        // 2^-40 * 2^32 = 2^-8: fraction 2^-8 * 2^31.
        assert_eq!(
            coordinate::<true>(2f32.powi(-40).to_bits(), &p),
            (0, 1 << 23)
        );
        assert_eq!(coordinate::<true>(1, &p), (0, 0));
    }
}
