//! The reference's steps over the reals for dyadic points, with integers
//! only: what the face-by-face proof feeds the reference.

use super::integer_half::ReferenceWord;
use super::{index_from_cell, wide_index_from_cell, Cell};
use crate::{Error, Level, SpecLevel};

/// The largest `scale_log2` the dyadic functions accept: the clamped
/// numerators stay at most `2^62`, so the fraction sums fit a `u64`.
pub const MAX_SCALE_LOG2: u32 = 62;

/// The reference's first half over the reals for the dyadic point
/// `(u_scaled, v_scaled) / 2^scale_log2` (non-negative numerators;
/// coordinates above 1 clamp to 1), with integers only. Equal to
/// `cell_real` (feature `exact`) on that point. Levels `0..=32`;
/// [`Error::ScaleTooLarge`] when `scale_log2 > 62`.
///
/// ```
/// use micromap_index::{spec::{cell_dyadic, Cell}, Error, Level};
/// // (3/8, 5/8) at level 2: cell (1, 2), fractions 1/2 + 1/2 >= 1.
/// let level = Level::new(2).unwrap();
/// assert_eq!(cell_dyadic(3, 5, 3, level), Ok(Cell { iu: 1, iv: 2, diagonal: true }));
/// assert_eq!(
///     cell_dyadic(1 << 62, 0, 63, Level::new(1).unwrap()),
///     Err(Error::ScaleTooLarge { scale_log2: 63, max: 62 })
/// );
/// ```
#[inline]
pub fn cell_dyadic(
    u_scaled: u64,
    v_scaled: u64,
    scale_log2: u32,
    level: Level,
) -> Result<Cell, Error> {
    if scale_log2 > MAX_SCALE_LOG2 {
        return Err(Error::ScaleTooLarge {
            scale_log2,
            max: MAX_SCALE_LOG2,
        });
    }
    let (iu, iv, diagonal) = dyadic_cell(u_scaled, v_scaled, scale_log2, level.get());
    Ok(Cell { iu, iv, diagonal })
}

/// [`cell_dyadic`]'s steps for `scale_log2 <= 62` and `level <= 32`,
/// generic over the word: `(iu, iv, diagonal)`. The lab runs them on words
/// of decision diagrams and proves them equal to the definition (the
/// floor and fraction of `2^level` times the clamped coordinate, fractions
/// summing to at least 1) at every input (`docs/verification.md` 10.12).
#[inline(always)]
pub fn dyadic_cell<W: ReferenceWord>(u: W, v: W, scale_log2: u32, level: u32) -> (W, W, bool) {
    let one = W::power_of_two(scale_log2);
    let clamp = |x: W| if x.at_least(one) { one } else { x };
    let (u, v) = (clamp(u), clamp(v));
    if scale_log2 >= level {
        let shift = scale_log2 - level;
        let mask = W::power_of_two(shift).wrapping_sub(W::constant(1));
        let diagonal = fractions_reach_one(u.and(mask), v.and(mask), mask);
        (u.shift_right(shift), v.shift_right(shift), diagonal)
    } else {
        // Coarser than the lattice: every such point is a lattice vertex.
        let shift = level - scale_log2;
        (u.shift_left(shift), v.shift_left(shift), false)
    }
}

/// The diagonal test `uf + vf >= 1` on the fractions below the level,
/// `uf = u & mask`, `vf = v & mask` with `mask = 2^shift - 1` (units of
/// `2^-shift`): `uf + vf > mask`. Generic so that the lab runs it on
/// symbolic fractions (`docs/verification.md`, section 10.3).
#[inline(always)]
pub fn fractions_reach_one<W: ReferenceWord>(uf: W, vf: W, mask: W) -> bool {
    !mask.at_least(uf.wrapping_add(vf))
}

/// The reference's steps over the reals for the dyadic point
/// `(u_scaled, v_scaled) / 2^scale_log2` (see [`cell_dyadic`]): the same
/// result as `index_real` (feature `exact`) on that point, with integers
/// only.
///
/// ```
/// use micromap_index::{spec, SpecLevel};
/// // (1/8, 1/8) with 8 = 2^3: on the diagonal, the flipped triangle.
/// assert_eq!(spec::index_dyadic(1, 1, 3, SpecLevel::new(2).unwrap()), Ok(1));
/// ```
#[inline]
pub fn index_dyadic(
    u_scaled: u64,
    v_scaled: u64,
    scale_log2: u32,
    level: SpecLevel,
) -> Result<u32, Error> {
    let cell = cell_dyadic(u_scaled, v_scaled, scale_log2, level.level())?;
    // level <= 16: cells are at most 2^16.
    Ok(index_from_cell(
        cell.iu as u32,
        cell.iv as u32,
        cell.diagonal,
        level.get(),
    ))
}

/// [`index_dyadic`] widened to 64-bit words: levels `0..=32`.
///
/// ```
/// use micromap_index::{spec, Level};
/// assert_eq!(spec::wide_index_dyadic(1, 1, 3, Level::new(2).unwrap()), Ok(1));
/// ```
#[inline]
pub fn wide_index_dyadic(
    u_scaled: u64,
    v_scaled: u64,
    scale_log2: u32,
    level: Level,
) -> Result<u64, Error> {
    let cell = cell_dyadic(u_scaled, v_scaled, scale_log2, level)?;
    Ok(wide_index_from_cell(
        cell.iu,
        cell.iv,
        cell.diagonal,
        level.get(),
    ))
}
