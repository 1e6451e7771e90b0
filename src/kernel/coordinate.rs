//! The first half on the bits (the module comment's "The first half on the
//! bits"): one coordinate's clamp, cell and 31-bit fraction, generic over
//! the word ([`CoordinateWord`]). The kernel runs them on `u32` / `u64`;
//! the lab runs the same code on words of decision diagrams and proves
//! them equal to the definition at every binary32 input and level
//! (`docs/verification.md` 10.12).
//!
//! Every comparison's outcome is a Rust `bool`, so each step is written as
//! the scalar kernel needs it (selects the compiler turns into conditional
//! moves); the shift counts depend on the exponent only, which the lab
//! fixes per case.

use super::{FRACTION_BITS, INF_BITS, ONE_BITS};
use crate::spec::CoordinateWord;

/// The clamped binary32 bits of `x` (as bits): NaN and negatives -> `+0`,
/// `>= 1` (and `+inf`) -> `1.0`. As unsigned integers every NaN and every
/// negative is above `+inf`'s bits, and non-negative floats order like
/// their bits.
#[inline(always)]
pub fn clamp_binary32<W: CoordinateWord>(bits: W) -> W {
    if bits.at_least(W::constant(u64::from(INF_BITS) + 1)) {
        W::constant(0)
    } else if bits.at_least(W::constant(u64::from(ONE_BITS))) {
        W::constant(u64::from(ONE_BITS))
    } else {
        bits
    }
}

/// The significand `m` (24 bits, hidden bit included) and the shift `s`
/// with `x * 2^level = m * 2^-s`, `s = shift_base - max(biased exponent,
/// 1)` (wrapping below 0), for clamped bits.
#[inline(always)]
fn significand_and_shift<W: CoordinateWord>(clamped: W, shift_base: u32) -> (W, u32) {
    let biased = clamped.shift_right(23).low_u32();
    let hidden = if biased == 0 { 0 } else { 1 << 23 };
    let m = clamped.and(W::constant(0x7f_ffff)).or(W::constant(hidden));
    (m, shift_base.wrapping_sub(biased.max(1)))
}

/// `x >> n` in a 32-bit word, or 0 when `n >= 32` (what AVX2's `vpsrlvd`
/// computes).
#[inline(always)]
fn shr_or_zero<W: CoordinateWord>(x: W, n: u32) -> W {
    if n < 32 {
        x.shift_right(n)
    } else {
        W::constant(0)
    }
}

/// `x << n` in a 32-bit word, or 0 when `n >= 32` (what AVX2's `vpsllvd`
/// computes).
#[inline(always)]
fn shl_or_zero<W: CoordinateWord>(x: W, n: u32) -> W {
    if n < 32 {
        x.shift_left(n)
    } else {
        W::constant(0)
    }
}

/// Cell clamped to `last` and `floor(fraction * 2^31)` of one coordinate,
/// in 32-bit words (`W` has 32 bits), every level `0..=32` (`shift_base =
/// 150 - level`, `last = 2^level - 1`).
///
/// `s >= 150 - 32 - 127 = -9`. For `s >= 0` the cell is `m >> s`; for
/// `s < 0` (levels above 23 only) it is `m << -s` (with `WIDE`; without it
/// the levels are `0..=16` and `s >= 7`). Only `x = 1` has a cell beyond
/// `last` (`2^level`, which wraps to 0 at level 32), so `x = 1` takes
/// `last` directly; its fraction then no longer matters, since `iu = last`
/// rules the diagonal out. The fraction `floor(m * 2^(31 - s)) mod 2^31`
/// is `m << (31 - s)` with the bits above 31 dropped when `s <= 31` (0 when
/// `s <= 0`), else `m >> (s - 31)`. Each shift that does not apply has a
/// count `>= 32` as an unsigned number and gives 0.
#[inline(always)]
pub fn binary32_coordinate<W: CoordinateWord, const WIDE: bool>(
    bits: W,
    shift_base: u32,
    last: u32,
) -> (W, W) {
    let clamped = clamp_binary32(bits);
    let (m, s) = significand_and_shift(clamped, shift_base);
    let mut cell = shr_or_zero(m, s);
    if WIDE {
        cell = cell.or(shl_or_zero(m, 0u32.wrapping_sub(s)));
    }
    // `clamped <= 1.0`'s bits: at least them is equal to them.
    let cell = if clamped.at_least(W::constant(u64::from(ONE_BITS))) {
        W::constant(u64::from(last))
    } else {
        cell
    };
    let low = shl_or_zero(m, 31u32.wrapping_sub(s)).and(W::constant(0x7fff_ffff));
    let high = shr_or_zero(m, s.wrapping_sub(31));
    (cell, low.or(high))
}

/// [`binary32_coordinate`] for clamped bits (at most `1.0`'s) at levels
/// `0..=16`, in one 64-bit shift instead of three 32-bit ones (`W` has 64
/// bits), for scalar callers: `floor(x * 2^(level + 31)) = (m << 31) >> s`
/// (`m < 2^24`, and `s >= 150 - 16 - 127 = 7`, so nothing shifts left)
/// holds the cell above its low 31 bits and the fraction in them. Only `x =
/// 1` has a cell beyond `last` (`2^level`, fraction 0), clamped back.
#[inline(always)]
pub fn binary32_unit_coordinate<W: CoordinateWord>(
    clamped: W,
    shift_base: u32,
    last: u32,
) -> (W, W) {
    let (m, s) = significand_and_shift(clamped, shift_base);
    let scaled = if s < 64 {
        m.shift_left(FRACTION_BITS).shift_right(s)
    } else {
        W::constant(0)
    };
    let cell = scaled.shift_right(FRACTION_BITS);
    let last = W::constant(u64::from(last));
    let cell = if cell.at_least(last) { last } else { cell };
    (cell, scaled.and(W::constant(0x7fff_ffff)))
}
