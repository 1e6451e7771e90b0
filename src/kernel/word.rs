//! The kernel's integer half and interleave, written once, generic over the
//! lane word ([`LaneWord`]): `u16` and `u32` in the point kernel and the
//! chunked pipeline, and the lab's bit-level symbolic words, which run
//! these very functions to prove them equal to the reference's integer
//! half at every level (`docs/verification.md`, section 10.12).
//!
//! Two shapes of the same steps, each used where it compiles best:
//!
//! * [`point_integer_half`]: one point at a time; the fold as a compare and
//!   a select (the narrow form's compare signed, one instruction in SSE2
//!   and AVX2, which lack unsigned ones).
//! * [`lane_integer_half`]: the chunked pipeline's loops; the fold as a
//!   `min` and the decrement as a saturating add, which vectorise.

use core::ops::{BitAnd, BitOr, BitXor, Not, Shl, Shr};

/// The operations of an unsigned lane word the kernel's integer half and
/// interleave use. Arithmetic wraps unless its name says otherwise.
/// Implemented by `u16` and `u32` (each method one machine operation) and,
/// in the lab, by words of binary decision diagrams.
pub trait LaneWord:
    Copy
    + BitAnd<Output = Self>
    + BitOr<Output = Self>
    + BitXor<Output = Self>
    + Not<Output = Self>
    + Shl<u32, Output = Self>
    + Shr<u32, Output = Self>
{
    /// A comparison's outcome: `bool` for machine words.
    type Bool: Copy + BitAnd<Output = Self::Bool>;
    /// `value` truncated to the word.
    fn constant(value: u64) -> Self;
    /// 1 for true, 0 for false.
    fn from_bool(value: Self::Bool) -> Self;
    /// `self + other`, wrapping.
    #[must_use]
    fn wrapping_add(self, other: Self) -> Self;
    /// `self - other`, wrapping.
    #[must_use]
    fn wrapping_sub(self, other: Self) -> Self;
    /// `self + other`, saturating at the word's maximum.
    #[must_use]
    fn saturating_add(self, other: Self) -> Self;
    /// The smaller of the two, unsigned.
    #[must_use]
    fn min(self, other: Self) -> Self;
    /// `self < other`, unsigned.
    fn less_than(self, other: Self) -> Self::Bool;
    /// `self < other` with both read as two's complement signed words.
    fn less_than_signed(self, other: Self) -> Self::Bool;
    /// `if condition { if_true } else { if_false }`.
    fn select(condition: Self::Bool, if_true: Self, if_false: Self) -> Self;
}

macro_rules! lane_word {
    ($uint:ty, $int:ty) => {
        impl LaneWord for $uint {
            type Bool = bool;
            #[inline(always)]
            fn constant(value: u64) -> Self {
                value as $uint
            }
            #[inline(always)]
            fn from_bool(value: bool) -> Self {
                <$uint>::from(value)
            }
            #[inline(always)]
            fn wrapping_add(self, other: Self) -> Self {
                <$uint>::wrapping_add(self, other)
            }
            #[inline(always)]
            fn wrapping_sub(self, other: Self) -> Self {
                <$uint>::wrapping_sub(self, other)
            }
            #[inline(always)]
            fn saturating_add(self, other: Self) -> Self {
                <$uint>::saturating_add(self, other)
            }
            #[inline(always)]
            fn min(self, other: Self) -> Self {
                Ord::min(self, other)
            }
            #[inline(always)]
            fn less_than(self, other: Self) -> bool {
                self < other
            }
            #[inline(always)]
            #[allow(clippy::cast_possible_wrap)]
            fn less_than_signed(self, other: Self) -> bool {
                (self as $int) < (other as $int)
            }
            #[inline(always)]
            fn select(condition: bool, if_true: Self, if_false: Self) -> Self {
                if condition {
                    if_true
                } else {
                    if_false
                }
            }
        }
    };
}

lane_word!(u16, i16);
lane_word!(u32, i32);

/// The prefix-XOR shifts of levels `0..=16` (every value below `2^16`).
pub const NARROW_PREFIX_XOR: [u32; 4] = [1, 2, 4, 8];
/// The prefix-XOR shifts of levels `0..=32`.
pub const WIDE_PREFIX_XOR: [u32; 5] = [1, 2, 4, 8, 16];

/// The reference's integer half from cells already clamped to `last`
/// (`iu, iv <= last = 2^level - 1`), one point: returns `(b0, b1)` before
/// the interleave. `WIDE` (levels `0..=32`) compares unsigned and adds the
/// fifth prefix-XOR step; the narrow form (levels `0..=16`, every value
/// below `2^16`) compares signed, the same there.
///
/// The reference folds a cell past the hypotenuse back
/// (`iu = min(iu, last - iv)`), subtracts one from `iw = ~(iu + iv)` on the
/// diagonal when `iu + iv < last` (so `~iw = iu + iv + d`), then
/// `b0 = ~(iu ^ iw) & last`.
#[inline(always)]
fn point_integer_half<W: LaneWord, const WIDE: bool>(
    iu: W,
    iv: W,
    diagonal: W::Bool,
    last: W,
) -> (W, W) {
    let room = last.wrapping_sub(iv);
    let below_room = if WIDE {
        iu.less_than(room)
    } else {
        iu.less_than_signed(room)
    };
    let d = W::from_bool(diagonal & below_room);
    let iu = W::select(below_room, iu, room);
    let b0 = (iu ^ iu.wrapping_add(iv).wrapping_add(d)) & last;
    let t = (iu ^ iv) & b0;
    let prefix_xor: &[u32] = if WIDE {
        &WIDE_PREFIX_XOR
    } else {
        &NARROW_PREFIX_XOR
    };
    let mut f = t;
    for &shift in prefix_xor {
        f = f ^ (f >> shift);
    }
    let b1 = ((f ^ iu) & !b0) | t;
    (b0, b1)
}

/// The integer half of one lane of the chunked pipeline, from cells `iu, iv
/// <= last` and the diagonal outcome `d` (0 or 1), with the word's
/// prefix-XOR shifts:
///
/// * the fold is `iu = min(iu, last - iv)`;
/// * `~iw` is `s = min(iu + iv + d, last)` after the fold: when the sum is
///   below `last` the reference subtracts `d` from `iw`; when it is `last`
///   (on the hypotenuse, folded or not) it does not, and the `min` takes
///   `last` back (at level 0 too, where `last` is 0). The addition of `d`
///   saturates, so `last + 1` does not wrap at level 16 in 16-bit words or
///   at level 32 in 32-bit ones;
/// * `b0 = iu ^ s` (both at most `last`, so the reference's `& last` changes
///   nothing), then `t`, the prefix XOR and `b1` as the reference has them.
#[inline(always)]
fn lane_integer_half<W: LaneWord>(iu: W, iv: W, d: W, last: W, prefix_xor: &[u32]) -> (W, W) {
    let room = last.wrapping_sub(iv);
    let iu = iu.min(room);
    let s = iu.wrapping_add(iv).saturating_add(d).min(last);
    let b0 = iu ^ s;
    let t = (iu ^ iv) & b0;
    let mut f = t;
    for &shift in prefix_xor {
        f = f ^ (f >> shift);
    }
    (b0, ((f ^ iu) & !b0) | t)
}

/// `b0` to the even bits and `b1` to the odd bits, for 16-bit halves in
/// 32-bit words: the outer perfect shuffle of `b1:b0` (Hacker's Delight,
/// 7-2).
#[inline(always)]
pub fn interleave_16<W: LaneWord>(b0: W, b1: W) -> W {
    let mut x = b0 | (b1 << 16);
    for (shift, mask) in [
        (8, 0x0000_ff00),
        (4, 0x00f0_00f0),
        (2, 0x0c0c_0c0c),
        (1, 0x2222_2222),
    ] {
        let t = (x ^ (x >> shift)) & W::constant(mask);
        x = x ^ t ^ (t << shift);
    }
    x
}

/// `b0` to the even bits and `b1` to the odd bits, for 32-bit halves: two
/// 16-bit interleaves, returned as the index's low and high 32 bits.
#[inline(always)]
pub fn interleave_32<W: LaneWord>(b0: W, b1: W) -> (W, W) {
    let low_half = W::constant(0xffff);
    let low = interleave_16(b0 & low_half, b1 & low_half);
    let high = interleave_16(b0 >> 16, b1 >> 16);
    (low, high)
}

/// The point kernel's integer half and interleave of levels `0..=16` from
/// cells already clamped to `last` (`iu, iv <= last`): the index.
#[inline(always)]
pub fn narrow_point<W: LaneWord>(iu: W, iv: W, diagonal: W::Bool, last: W) -> W {
    let (b0, b1) = point_integer_half::<W, false>(iu, iv, diagonal, last);
    interleave_16(b0, b1)
}

/// The point kernel's integer half and interleave of levels `0..=32` from
/// cells already clamped to `last`: the index's low and high 32 bits.
#[inline(always)]
pub fn wide_point<W: LaneWord>(iu: W, iv: W, diagonal: W::Bool, last: W) -> (W, W) {
    let (b0, b1) = point_integer_half::<W, true>(iu, iv, diagonal, last);
    interleave_32(b0, b1)
}

/// One lane of the chunked pipeline's narrow integer half (levels
/// `0..=16`, 16-bit words): `(b0, b1)`.
#[inline(always)]
pub fn narrow_lane<W: LaneWord>(iu: W, iv: W, d: W, last: W) -> (W, W) {
    lane_integer_half(iu, iv, d, last, &NARROW_PREFIX_XOR)
}

/// One lane of the chunked pipeline's wide integer half (levels `0..=32`,
/// 32-bit words): `(b0, b1)`.
#[inline(always)]
pub fn wide_lane<W: LaneWord>(iu: W, iv: W, d: W, last: W) -> (W, W) {
    lane_integer_half(iu, iv, d, last, &WIDE_PREFIX_XOR)
}
