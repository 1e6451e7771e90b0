//! The branch-free reference: the Vulkan reference's steps rewritten
//! without branches on the bits of the floats, in safe code, in two shapes:
//!
//! * **Point by point** (`point.rs`: [`narrow`], [`wide`]): one lane at a
//!   time, written so that a loop over slices vectorises;
//!   `spec::index_f32`, `batch::index_f32_one`, the exact entry points of
//!   `uv2index` and the batch loops' short tails run it.
//! * **In chunks** (`pipeline.rs`: [`chunked`], the batch loops, in two
//!   forms: [`Narrow`] for levels `0..=16`, [`Wide`] for `0..=32`):
//!   [`CHUNK`] points go through three stages, each its own loop. The
//!   narrow first half (float) and both interleaves come from a [`Lanes`]:
//!   the safe `PortableLanes` (`portable.rs`, the portable backend of
//!   targets other than x86-64), or [`crate::arch`]'s SSE2, AVX2 and
//!   AVX-512 ones with intrinsics. The wide first half
//!   ([`wide_cells`](pipeline::wide_cells)) and the integer half
//!   ([`integer_half_u16`](pipeline::integer_half_u16),
//!   [`integer_half_u32`](pipeline::integer_half_u32): `kernel::word`'s
//!   lane functions) are safe code for
//!   every backend; the narrow one runs in 16-bit words, since every value
//!   is below `2^16` at its levels, so a vector holds twice as many points
//!   as in 32-bit words.
//!
//! A leaf of the crate: `spec`, `uv2index`, `batch` and `arch` call it, and
//! it calls none of them (`arch` instantiates [`chunked`] with its lanes
//! inside its `#[target_feature]` loops).
//!
//! Everything here is `#[inline(always)]` so that each caller gets its own
//! copy under its own target features.
//!
//! # The first half in floats
//!
//! [`narrow`] takes the cell and fraction as `CELL` says. The vector
//! backends use the reference's own binary32 steps (a truncating
//! conversion in [`crate::arch`],
//! [`coordinate_float`](point::coordinate_float)'s `2^23` rounding trick in
//! safe code), after a float clamp that flushes subnormals and stops below
//! 1 ([`clamp_flushed`](point::clamp_flushed) says why neither changes the
//! index), and decide `uf + vf >= 1.0f` as the reference does: fewer
//! operations than the shifts below, which serve the wide form (levels
//! above 16) and `batch::index_f32_one`.
//!
//! # The first half on the bits
//!
//! The Vulkan reference clamps `x` to `[0, 1]`, multiplies by `2^level`,
//! truncates to the cell and keeps the fraction; every one of those binary32
//! operations is exact. Only `uf + vf >= 1.0f` rounds: binary32
//! round-to-nearest-even lifts every real sum in `[1 - 2^-25, 1)` to `1.0`
//! and no smaller one, so the test is `uf + vf >= 1 - 2^-25` over the reals
//! (`docs/fixed.md`).
//!
//! * **Clamp.** As an unsigned integer, every NaN and every negative value
//!   (sign bit set) is above the bits of `+inf`, `0x7f80_0000`: they become
//!   `+0`. Everything else is `min(bits, bits of 1.0)` (bits of non-negative
//!   floats order like the floats; `+inf` becomes 1).
//! * **Cell and fraction.** The clamped `x` is `m * 2^(e - 150)` with `m`
//!   the 24-bit significand (hidden bit included) and `e = max(biased
//!   exponent, 1)`. With `P` fraction bits, `floor(x * 2^(level + P)) =
//!   floor(m * 2^(P - s))`, `s = 150 - level - e`: the cell is its integer
//!   part and the fraction its low `P` bits, floored.
//! * **Diagonal.** With `P = 31` the fractions are `Fu = floor(uf * 2^31)`,
//!   `Fv` likewise, and the test is `Fu + Fv >= T` with `T = 2^31 - 2^6`
//!   (`(1 - 2^-25) * 2^31`; the `exact` variants use `T = 2^31`, the real
//!   `uf + vf >= 1`). Flooring keeps it exact: a fraction loses bits only if
//!   its lowest bit is below `2^-31`, and then, having at most 24 significant
//!   bits, it is below `2^-7`. If both lose bits the sum is below `2^-6`, far
//!   from `T`. If one does, the other is exact, so `Fu + Fv` is the integer
//!   part of the real `(uf + vf) * 2^31`, and an integer threshold `T` is
//!   reached by a real number exactly when it is reached by its integer part.
//!
//! # The integer half
//!
//! From the cell `(iu, iv)` clamped to `last = 2^level - 1` and the diagonal
//! outcome, the reference folds a cell past the hypotenuse back
//! (`iu -= iu + iv - last`, i.e. `iu = min(iu, last - iv)`), subtracts one
//! from `iw = ~(iu + iv)` on the diagonal when `iu + iv < last` (so
//! `~iw = iu + iv + d` with `d` that outcome), and then
//! `b0 = ~(iu ^ iw) & last = (iu ^ (iu + iv + d)) & last`. Nothing exceeds
//! `last`, so 32-bit words hold every level `0..=32`. The prefix XOR and the
//! bit interleave are the reference's; the interleave of `b0` and `b1` is one
//! perfect shuffle of the word holding both (Hacker's Delight, 7-2).

pub(crate) mod coordinate;
pub(crate) mod pipeline;
pub(crate) mod point;
#[cfg(any(test, not(target_arch = "x86_64")))]
mod portable;
pub(crate) mod word;

pub(crate) use pipeline::{chunked, Cells, Halves, Lanes, Narrow, Wide, CHUNK};
#[cfg(target_arch = "x86_64")]
pub(crate) use point::BELOW_ONE;
pub(crate) use point::{
    narrow, narrow_from_clamped_cell, narrow_in_unit, wide, wide_cell, wide_from_clamped_cell,
    CELL_BY_FLOAT, CELL_BY_SHIFTS,
};
#[cfg(not(target_arch = "x86_64"))]
pub(crate) use portable::{narrow_slice_portable, wide_slice_portable};

/// Bits of `1.0f32`.
const ONE_BITS: u32 = 0x3f80_0000;
/// Bits of `+inf`: everything above (as an unsigned integer) is NaN or negative.
const INF_BITS: u32 = 0x7f80_0000;
/// Fraction bits kept of `uf` and `vf`.
pub(crate) const FRACTION_BITS: u32 = 31;
/// `uf + vf >= 1.0f` in binary32: the real sum at least `1 - 2^-25`.
pub(crate) const BINARY32_THRESHOLD: u32 = (1 << FRACTION_BITS) - (1 << (FRACTION_BITS - 25));
/// `uf + vf >= 1` over the reals.
pub(crate) const EXACT_THRESHOLD: u32 = 1 << FRACTION_BITS;

/// What the per-element kernels need of the level, computed once per call.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Params {
    /// `2^level - 1` (for level 32 all ones).
    pub last: u32,
    /// `150 - level`: `s = shift_base - e`.
    pub shift_base: u32,
    /// `2^level` as a float (levels `0..=16` only).
    pub scale: f32,
    /// The diagonal threshold on `Fu + Fv`.
    pub threshold: u32,
}

impl Params {
    /// The parameters of `level` (`0..=32`, clamped there) and a threshold.
    #[inline(always)]
    pub const fn new(level: u32, threshold: u32) -> Params {
        let level = if level > 32 { 32 } else { level };
        Params {
            last: ((1u64 << level) - 1) as u32,
            shift_base: 150 - level,
            scale: (1u64 << level) as f32,
            threshold,
        }
    }
}
