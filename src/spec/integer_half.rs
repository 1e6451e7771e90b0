//! The reference's integer half, written once for two word widths.

/// Generates the integer half of the reference for one word width: from the
/// (unclamped) grid cell `(iu, iv)` = `(trunc(u * 2^level), trunc(v * 2^level))`
/// and the outcome of the diagonal test `uf + vf >= 1`, the curve index. All
/// arithmetic wraps like C's unsigned types; the prefix-XOR shifts and the
/// interleave steps are the width's parameters.
macro_rules! integer_half {
    (
        $(#[$doc:meta])*
        $name:ident, $uint:ty, prefix_xor: [$($prefix:expr),*],
        interleave: [$(($shift:expr, $mask:expr)),*]
    ) => {
        $(#[$doc])*
        #[inline]
        #[must_use]
        pub fn $name(iu: $uint, iv: $uint, diagonal: bool, level: u32) -> $uint {
            let cells = (1 as $uint).wrapping_shl(level);
            let last = cells.wrapping_sub(1);
            let mut iu = iu;
            let mut iv = iv;
            if iu >= cells {
                iu = last;
            }
            if iv >= cells {
                iv = last;
            }
            let iuv = iu.wrapping_add(iv);
            if iuv >= cells {
                iu = iu.wrapping_sub(iuv.wrapping_sub(cells).wrapping_add(1));
            }
            let mut iw = !iu.wrapping_add(iv);
            if diagonal && iuv < last {
                iw = iw.wrapping_sub(1);
            }
            let b0 = !(iu ^ iw) & last;
            let t = (iu ^ iv) & b0;
            let mut f = t;
            $(f ^= f >> $prefix;)*
            let b1 = ((f ^ iu) & !b0) | t;
            let spread = |x: $uint| {
                let mut x = x;
                $(x = (x | (x << $shift)) & $mask;)*
                x
            };
            spread(b0) | (spread(b1) << 1)
        }
    };
}

integer_half!(
    /// The reference's integer half, exactly as the Vulkan code has it: 32-bit
    /// words, a 16-bit prefix-XOR and interleave (so only levels `0..=16` give
    /// valid indices); shifts by `level >= 32` use `level % 32`.
    ///
    /// Every narrow variant (binary32, exact, dyadic) computes its [`Cell`](super::Cell) its
    /// own way and shares this function.
    ///
    /// ```
    /// use micromap_index::spec::index_from_cell;
    /// // Level 1, cell (0, 0): lower-left half is the left child, upper-right
    /// // half is the middle child.
    /// assert_eq!(index_from_cell(0, 0, false, 1), 0);
    /// assert_eq!(index_from_cell(0, 0, true, 1), 1);
    /// ```
    index_from_cell,
    u32,
    prefix_xor: [1, 2, 4, 8],
    interleave: [(8, 0x00ff_00ff), (4, 0x0f0f_0f0f), (2, 0x3333_3333), (1, 0x5555_5555)]
);

integer_half!(
    /// The integer half widened to 64-bit words: one more prefix-XOR step
    /// (32-bit prefix) and a 32-bit interleave, so every level `0..=32` has a
    /// valid index (`4^32` indices fill a `u64`; level 33 would need more
    /// than 64 index bits). For levels `0..=16` it equals [`index_from_cell`].
    ///
    /// ```
    /// use micromap_index::spec::{index_from_cell, wide_index_from_cell};
    /// assert_eq!(wide_index_from_cell(5, 9, true, 4), u64::from(index_from_cell(5, 9, true, 4)));
    /// ```
    wide_index_from_cell,
    u64,
    prefix_xor: [1, 2, 4, 8, 16],
    interleave: [
        (16, 0x0000_ffff_0000_ffff),
        (8, 0x00ff_00ff_00ff_00ff),
        (4, 0x0f0f_0f0f_0f0f_0f0f),
        (2, 0x3333_3333_3333_3333),
        (1, 0x5555_5555_5555_5555)
    ]
);
