//! The safe lanes: the chunked pipeline's portable backend on targets
//! without [`crate::arch`]'s intrinsics, tested on every target.

use super::point::coordinate_float;
use super::word::{interleave_16, interleave_32};
use super::Params;
#[cfg(not(target_arch = "x86_64"))]
use super::{chunked, Narrow, Wide};
use super::{Cells, Halves, Lanes, CHUNK};

/// [`Lanes`] in safe code, points in order: the first half by
/// [`coordinate_float`] (no float-to-integer conversion, which baselines
/// without a vector form of it would do one lane at a time) and the
/// interleave of [`narrow`](super::narrow) and [`wide`](super::wide). The
/// portable backend of targets without [`crate::arch`]'s lanes (x86-64 has
/// SSE2 in its baseline, whose lanes it runs instead); tested on every
/// target.
pub(crate) struct PortableLanes;

impl Lanes for PortableLanes {
    #[inline(always)]
    fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], params: &Params, cells: &mut Cells<u16>) {
        for k in 0..CHUNK {
            let (iu, uf) = coordinate_float(u[k].to_bits(), params);
            let (iv, vf) = coordinate_float(v[k].to_bits(), params);
            // Cells are at most 2^16 - 1 (levels 0..=16, x < 1).
            cells.iu[k] = iu as u16;
            cells.iv[k] = iv as u16;
            cells.diagonal[k] = u16::from(uf + vf >= 1.0);
        }
    }

    #[inline(always)]
    fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
        for ((out, &b0), &b1) in out.iter_mut().zip(&halves.b0).zip(&halves.b1) {
            *out = interleave_16(u32::from(b0), u32::from(b1));
        }
    }

    #[inline(always)]
    fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
        for ((out, &b0), &b1) in out.iter_mut().zip(&halves.b0).zip(&halves.b1) {
            let (low, high) = interleave_32(b0, b1);
            *out = u64::from(low) | (u64::from(high) << 32);
        }
    }
}

/// [`chunked`] through [`PortableLanes`]: the portable backend where no
/// instruction set of [`crate::arch`] applies.
#[cfg(not(target_arch = "x86_64"))]
pub(crate) fn narrow_slice_portable(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) {
    chunked::<Narrow, _>(&PortableLanes, u, v, out, params);
}

/// The wide form through [`PortableLanes`].
#[cfg(not(target_arch = "x86_64"))]
pub(crate) fn wide_slice_portable(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) {
    chunked::<Wide, _>(&PortableLanes, u, v, out, params);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kernel::point::{narrow, wide, BELOW_ONE, CELL_BY_SHIFTS};
    use crate::kernel::{chunked, Narrow, Wide, BINARY32_THRESHOLD, ONE_BITS};

    /// The chunked pipeline with the safe stages (the portable backend of
    /// targets other than x86-64, which CI does not run) against [`narrow`]
    /// point by point: full chunks, a padded tail and a short one, special
    /// values and random bits, every level.
    #[test]
    fn portable_lanes_equal_the_point_kernel() {
        const POINTS: usize = 2 * CHUNK + 40;
        let special = [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            0.0,
            f32::from_bits(1),
            f32::from_bits(0x7f_ffff),
            f32::MIN_POSITIVE,
            BELOW_ONE,
            1.0,
            1.5,
            -0.25,
            0.5,
        ];
        let mut rng = micromap_index_test_support::SplitMix64::new(0x0123_4567_89ab_cdef);
        let (mut u, mut v) = ([0f32; POINTS], [0f32; POINTS]);
        let mut out = [0u32; POINTS];
        for level in 0..=16 {
            let params = Params::new(level, BINARY32_THRESHOLD);
            for (k, (u, v)) in u.iter_mut().zip(v.iter_mut()).enumerate() {
                let x = rng.next_u64();
                *u = special
                    .get(k % 29)
                    .copied()
                    .unwrap_or(f32::from_bits(x as u32));
                *v = f32::from_bits((x >> 32) as u32 % (ONE_BITS + 1));
            }
            for len in [POINTS, 2 * CHUNK + 17, CHUNK + 3, 15, 0] {
                chunked::<Narrow, _>(
                    &PortableLanes,
                    &u[..len],
                    &v[..len],
                    &mut out[..len],
                    &params,
                );
                let mut wide_out = [0u64; POINTS];
                for wide_level in [level, 2 * level, 32 - level] {
                    let params = Params::new(wide_level, BINARY32_THRESHOLD);
                    chunked::<Wide, _>(
                        &PortableLanes,
                        &u[..len],
                        &v[..len],
                        &mut wide_out[..len],
                        &params,
                    );
                    for k in 0..len {
                        let expected = wide(u[k].to_bits(), v[k].to_bits(), &params);
                        assert_eq!(
                            wide_out[k], expected,
                            "wide level {wide_level}, length {len}, point {k}"
                        );
                    }
                }
                for k in 0..len {
                    let expected =
                        narrow::<CELL_BY_SHIFTS>(u[k].to_bits(), v[k].to_bits(), &params);
                    assert_eq!(
                        out[k],
                        expected,
                        "level {level}, length {len}, point {k}: u {:#010x}, v {:#010x}",
                        u[k].to_bits(),
                        v[k].to_bits()
                    );
                }
            }
        }
    }
}
