//! The inverse in constant time: the reference's integer half inverted.
//!
//! Deinterleaving the index gives `b0` (even bits) and `b1` (odd bits). The
//! reference computes `b0 = iu ^ (iu + iv + d)` (`d` = 1 for the upside-down
//! triangle of the cell), `t = (iu ^ iv) & b0`, the suffix XOR `f` of `t`,
//! and `b1 = ((f ^ iu) & !b0) | t`. So `t = b0 & b1`, and where `b0` is
//! clear `iu = b1 ^ f`. Writing the sum bit by bit with carries `c`
//! (`c_0 = d`), `iu ^ (iu + iv + d) = iv ^ c`, so `iv = b0 ^ c`; a carry
//! passes unchanged where `b0` is clear and becomes `iu_k = !(t_k ^ c_k)`
//! where it is set. Hence `c_k = d ^ (parity of (b0 & !t) below k)`, a
//! prefix XOR, and since the sum stays below `2^level` (no carry out), `d`
//! is the parity of all of `b0 & !t`. Everything is a fixed number of word
//! operations, whatever the level.
//!
//! At levels `0..=19` the walk and the reference agree at every point
//! (`docs/verification.md`), so inverting one inverts the other; the tests
//! (`tests/micro_triangles.rs`) compare every index of levels `0..=10` with
//! the digit replay (`micro_triangle_ref`), random indices of every level
//! up to 32, and the first and last index of every level.

use crate::Level;

/// The lattice cell `(iu, iv)` (numerators over `2^level` of the lower-left
/// corner of its square) of the micro-triangle `index < 4^level`, and
/// whether it is upright (the upside-down one is the upper-right half of its
/// cell).
#[inline]
pub(super) fn cell_and_orientation(level: Level, index: u64) -> ((u64, u64), bool) {
    let last = ((1u64 << level.get()) - 1) as u32;
    let (b0, b1) = deinterleave(index);
    let t = b0 & b1;
    let mut f = t;
    f ^= f >> 1;
    f ^= f >> 2;
    f ^= f >> 4;
    f ^= f >> 8;
    f ^= f >> 16;
    // Inclusive prefix XOR from the bottom: bit k is the parity of
    // `b0 & !t` at bits 0..=k, bit 31 the parity of all of it, which is `d`.
    let mut p = b0 & !t;
    p ^= p << 1;
    p ^= p << 2;
    p ^= p << 4;
    p ^= p << 8;
    p ^= p << 16;
    let d = p >> 31;
    let carries = (0u32.wrapping_sub(d)) ^ (p << 1);
    let iv = (b0 ^ carries) & last;
    let iu = (((b1 ^ f) & !b0) | ((t ^ !carries) & b0)) & last;
    ((u64::from(iu), u64::from(iv)), d == 0)
}

/// The even bits of `x` (packed, low to high) and the odd bits: the inverse
/// perfect shuffle (Hacker's Delight, 7-2).
#[inline]
fn deinterleave(x: u64) -> (u32, u32) {
    let mut x = x;
    let mut t;
    t = (x ^ (x >> 1)) & 0x2222_2222_2222_2222;
    x ^= t ^ (t << 1);
    t = (x ^ (x >> 2)) & 0x0c0c_0c0c_0c0c_0c0c;
    x ^= t ^ (t << 2);
    t = (x ^ (x >> 4)) & 0x00f0_00f0_00f0_00f0;
    x ^= t ^ (t << 4);
    t = (x ^ (x >> 8)) & 0x0000_ff00_0000_ff00;
    x ^= t ^ (t << 8);
    t = (x ^ (x >> 16)) & 0x0000_0000_ffff_0000;
    x ^= t ^ (t << 16);
    (x as u32, (x >> 32) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deinterleave_splits_even_and_odd_bits() {
        assert_eq!(deinterleave(0x5555_5555_5555_5555), (u32::MAX, 0));
        assert_eq!(deinterleave(0xaaaa_aaaa_aaaa_aaaa), (0, u32::MAX));
        assert_eq!(deinterleave(0b0110), (0b10, 0b01));
        assert_eq!(deinterleave(1 << 63), (0, 1 << 31));
    }
}
