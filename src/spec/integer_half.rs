//! The reference's integer half, written once, generic over the word
//! ([`ReferenceWord`]): `u32` for the Vulkan code, `u64` for its widening,
//! and the lab's symbolic words, which run these very steps to derive the
//! reference's digit transducer (`docs/verification.md`, section 10.3).

/// The operations of a C unsigned word the reference's integer half uses:
/// all arithmetic wraps, as C's does. Implemented by `u32` and `u64` (each
/// method is the one machine operation of its name) and, in the lab, by
/// symbolic words that run [`reference_cell`] and [`reference_digits`] at
/// every level at once.
pub trait ReferenceWord: Copy {
    /// `(word)value` (truncating), for the constants of the code.
    fn constant(value: u64) -> Self;
    /// `(word)1 << level`, the shift wrapping like the hardware's.
    fn power_of_two(level: u32) -> Self;
    /// `self + other`, wrapping.
    #[must_use]
    fn wrapping_add(self, other: Self) -> Self;
    /// `self - other`, wrapping.
    #[must_use]
    fn wrapping_sub(self, other: Self) -> Self;
    /// `self >= other`, unsigned.
    fn at_least(self, other: Self) -> bool;
    /// `~self`.
    #[must_use]
    fn complement(self) -> Self;
    /// `self ^ other`.
    #[must_use]
    fn xor(self, other: Self) -> Self;
    /// `self & other`.
    #[must_use]
    fn and(self, other: Self) -> Self;
    /// `self | other`.
    #[must_use]
    fn or(self, other: Self) -> Self;
    /// `self >> shift` (`shift` below the width).
    #[must_use]
    fn shift_right(self, shift: u32) -> Self;
    /// `self << shift` (`shift` below the width).
    #[must_use]
    fn shift_left(self, shift: u32) -> Self;
}

macro_rules! reference_word {
    ($uint:ty) => {
        impl ReferenceWord for $uint {
            #[inline(always)]
            fn constant(value: u64) -> Self {
                value as $uint
            }
            #[inline(always)]
            fn power_of_two(level: u32) -> Self {
                (1 as $uint).wrapping_shl(level)
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
            fn at_least(self, other: Self) -> bool {
                self >= other
            }
            #[inline(always)]
            fn complement(self) -> Self {
                !self
            }
            #[inline(always)]
            fn xor(self, other: Self) -> Self {
                self ^ other
            }
            #[inline(always)]
            fn and(self, other: Self) -> Self {
                self & other
            }
            #[inline(always)]
            fn or(self, other: Self) -> Self {
                self | other
            }
            #[inline(always)]
            fn shift_right(self, shift: u32) -> Self {
                self >> shift
            }
            #[inline(always)]
            fn shift_left(self, shift: u32) -> Self {
                self << shift
            }
        }
    };
}

reference_word!(u32);
reference_word!(u64);

/// A word the first halves' bit steps run on (`kernel::coordinate`,
/// `uv2index::binary64_coordinate`): the reference's word operations and
/// the low 32 bits as a number (the exponent, which decides the shifts).
/// `u32` and `u64` here; the lab's words of decision diagrams prove the
/// steps (`docs/verification.md` 10.12).
pub trait CoordinateWord: ReferenceWord {
    /// The low 32 bits (for the lab's words: only when they are constants).
    fn low_u32(self) -> u32;
}

impl CoordinateWord for u32 {
    #[inline(always)]
    fn low_u32(self) -> u32 {
        self
    }
}

impl CoordinateWord for u64 {
    #[inline(always)]
    fn low_u32(self) -> u32 {
        self as u32
    }
}

/// The prefix-XOR shifts of the 32-bit code (a 16-bit prefix).
pub const NARROW_PREFIX_XOR: [u32; 4] = [1, 2, 4, 8];
/// The interleave steps `x = (x | (x << shift)) & mask` of the 32-bit code.
pub const NARROW_INTERLEAVE: [(u32, u64); 4] = [
    (8, 0x00ff_00ff),
    (4, 0x0f0f_0f0f),
    (2, 0x3333_3333),
    (1, 0x5555_5555),
];
/// The prefix-XOR shifts of the 64-bit widening (a 32-bit prefix).
pub const WIDE_PREFIX_XOR: [u32; 5] = [1, 2, 4, 8, 16];
/// The interleave steps of the 64-bit widening.
pub const WIDE_INTERLEAVE: [(u32, u64); 5] = [
    (16, 0x0000_ffff_0000_ffff),
    (8, 0x00ff_00ff_00ff_00ff),
    (4, 0x0f0f_0f0f_0f0f_0f0f),
    (2, 0x3333_3333_3333_3333),
    (1, 0x5555_5555_5555_5555),
];

/// The first part of the integer half: from the (unclamped) grid cell
/// `(iu, iv)` and the outcome of the diagonal test, the clamps to the grid,
/// the move of a cell past the hypotenuse, `iw = ~(iu + iv)` and the
/// diagonal's decrement. Returns `(iu, iv, iw)`.
#[inline(always)]
pub fn reference_cell<W: ReferenceWord>(iu: W, iv: W, diagonal: bool, level: u32) -> (W, W, W) {
    let one = W::constant(1);
    let cells = W::power_of_two(level);
    let last = cells.wrapping_sub(one);
    let mut iu = iu;
    let mut iv = iv;
    if iu.at_least(cells) {
        iu = last;
    }
    if iv.at_least(cells) {
        iv = last;
    }
    let iuv = iu.wrapping_add(iv);
    if iuv.at_least(cells) {
        iu = iu.wrapping_sub(iuv.wrapping_sub(cells).wrapping_add(one));
    }
    let mut iw = iu.wrapping_add(iv).complement();
    if diagonal && !iuv.at_least(last) {
        iw = iw.wrapping_sub(one);
    }
    (iu, iv, iw)
}

/// The second part of the integer half: the digits of the cell
/// `(iu, iv, iw)` at `level`, column by column (`b0`, the Top bits `t`,
/// their prefix XOR `f` with the width's shifts, `b1`), interleaved into
/// the index with the width's steps.
#[inline(always)]
pub fn reference_digits<W: ReferenceWord>(
    iu: W,
    iv: W,
    iw: W,
    level: u32,
    prefix_xor: &[u32],
    interleave: &[(u32, u64)],
) -> W {
    let last = W::power_of_two(level).wrapping_sub(W::constant(1));
    let b0 = iu.xor(iw).complement().and(last);
    let t = iu.xor(iv).and(b0);
    let mut f = t;
    for &shift in prefix_xor {
        f = f.xor(f.shift_right(shift));
    }
    let b1 = f.xor(iu).and(b0.complement()).or(t);
    let spread = |x: W| {
        let mut x = x;
        for &(shift, mask) in interleave {
            x = x.or(x.shift_left(shift)).and(W::constant(mask));
        }
        x
    };
    spread(b0).or(spread(b1).shift_left(1))
}

/// The reference's integer half, exactly as the Vulkan code has it: 32-bit
/// words, a 16-bit prefix-XOR and interleave (so only levels `0..=16` give
/// valid indices); shifts by `level >= 32` use `level % 32`.
///
/// Every narrow variant (binary32, exact, dyadic) computes its
/// [`Cell`](super::Cell) its own way and shares this function.
///
/// ```
/// use micromap_index::spec::index_from_cell;
/// // Level 1, cell (0, 0): lower-left half is the left child, upper-right
/// // half is the middle child.
/// assert_eq!(index_from_cell(0, 0, false, 1), 0);
/// assert_eq!(index_from_cell(0, 0, true, 1), 1);
/// ```
#[inline]
#[must_use]
pub fn index_from_cell(iu: u32, iv: u32, diagonal: bool, level: u32) -> u32 {
    let (iu, iv, iw) = reference_cell(iu, iv, diagonal, level);
    reference_digits(iu, iv, iw, level, &NARROW_PREFIX_XOR, &NARROW_INTERLEAVE)
}

/// The integer half widened to 64-bit words: one more prefix-XOR step
/// (32-bit prefix) and a 32-bit interleave, so every level `0..=32` has a
/// valid index (`4^32` indices fill a `u64`; level 33 would need more
/// than 64 index bits). For levels `0..=16` it equals [`index_from_cell`].
///
/// ```
/// use micromap_index::spec::{index_from_cell, wide_index_from_cell};
/// assert_eq!(wide_index_from_cell(5, 9, true, 4), u64::from(index_from_cell(5, 9, true, 4)));
/// ```
#[inline]
#[must_use]
pub fn wide_index_from_cell(iu: u64, iv: u64, diagonal: bool, level: u32) -> u64 {
    let (iu, iv, iw) = reference_cell(iu, iv, diagonal, level);
    reference_digits(iu, iv, iw, level, &WIDE_PREFIX_XOR, &WIDE_INTERLEAVE)
}
