//! The reference transducer: the learnt column table and the restated
//! decrement rule (the module docs, "The reference").

#[allow(clippy::wildcard_imports)]
use super::*;

/// The reference's digit per column, learnt from the real integer half:
/// `digits[parity][u + 2 v + 4 w]`, `parity` the parity of the Top digits
/// (3) above the column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReferenceColumns {
    /// The digit for each (parity of Top digits above, column bits).
    pub digits: [[u8; 8]; 2],
}

impl ReferenceColumns {
    /// Runs [`spec::wide_index_from_cell`] on every cell `(iu, iv)` with
    /// `iu + iv < 2^level` and both diagonal bits, levels 1..=5, and reads
    /// off, for every digit position, the digit against the parity of the
    /// Top digits above it and the column's bits of `(iu, iv, iw)`, where
    /// `iw = 2^level - 1 - iu - iv - [diagonal and iu + iv < 2^level - 1]`
    /// (the code's `~(iu + iv)` and decrement, restated for cells inside
    /// the grid, where no clamp applies). Fails unless every key is seen
    /// and always with one digit.
    ///
    /// ```
    /// use micromap_index_lab::prove_all_levels::ReferenceColumns;
    /// let columns = ReferenceColumns::learn().unwrap();
    /// // Column (u, v, w) bits 0, 0, 1 is Left: digit 0, or 2 below an odd
    /// // number of Top digits; 0, 1, 0 is Top (3) and flips the parity.
    /// assert_eq!(columns.digit(false, [false, false, true]), (0, false));
    /// assert_eq!(columns.digit(true, [false, false, true]), (2, true));
    /// assert_eq!(columns.digit(false, [false, true, false]), (3, true));
    /// ```
    pub fn learn() -> Result<ReferenceColumns, String> {
        let mut digits: [[Option<u8>; 8]; 2] = [[None; 8]; 2];
        for level in 1..=5u32 {
            let cells = 1u64 << level;
            for iu in 0..cells {
                for iv in 0..cells - iu {
                    for diagonal in [false, true] {
                        let decrement = u64::from(diagonal && iu + iv < cells - 1);
                        let iw = cells - 1 - iu - iv - decrement;
                        let index = spec::wide_index_from_cell(iu, iv, diagonal, level);
                        let mut parity = false;
                        for position in (0..level).rev() {
                            let digit = ((index >> (2 * position)) & 3) as u8;
                            let bit = |x: u64| ((x >> position) & 1) as usize;
                            let key = bit(iu) | bit(iv) << 1 | bit(iw) << 2;
                            let slot = &mut digits[usize::from(parity)][key];
                            if slot.is_some_and(|known| known != digit) {
                                return Err(format!(
                                    "reference digit is not a function of (parity, column): \
                                     cell ({iu}, {iv}, {diagonal}) level {level} position {position}"
                                ));
                            }
                            *slot = Some(digit);
                            parity ^= digit == 3;
                        }
                    }
                }
            }
        }
        let mut table = [[0; 8]; 2];
        for parity in 0..2 {
            for key in 0..8 {
                table[parity][key] = digits[parity][key].ok_or_else(|| {
                    format!("column (parity {parity}, bits {key:03b}) never seen")
                })?;
            }
        }
        Ok(ReferenceColumns { digits: table })
    }

    /// The digit for the column and the new parity.
    #[must_use]
    pub fn digit(&self, parity: bool, bits: [bool; 3]) -> (u8, bool) {
        let key = usize::from(bits[U]) | usize::from(bits[V]) << 1 | usize::from(bits[W]) << 2;
        let digit = self.digits[usize::from(parity)][key];
        (digit, parity ^ (digit == 3))
    }
}

/// The reference transducer's state.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ReferenceState {
    /// Parity of the Top digits emitted so far (the prefix XOR).
    pub parity: bool,
    /// The guessed coordinate the reference's cell decrements (see
    /// [`decremented_coordinate`]).
    pub decremented: Option<usize>,
    /// `u == 0` (known from the first column and its rest).
    pub u_zero: bool,
    /// `w == 0`.
    pub w_zero: bool,
}

/// Which of the point's integer parts `(U, V, W) = floor(2^n (u, v, w))`
/// the reference's cell `(iu, iv, iw)` has one less of, from the rest
/// below level `n` and whether `u` or `w` is zero (restated by hand from
/// [`spec::wide_index_from_cell`]'s clamps, hypotenuse move and diagonal
/// test; `docs/verification.md` section 10.3 has the case analysis):
///
/// * `w`'s rest is zero and `w > 0` (vertices, and points on a line
///   `u + v = k/2^n` below the hypotenuse): `iw = W - 1`;
/// * `w = 0` and the point is a lattice vertex: `iu = U - 1` (the
///   hypotenuse move, and the clamp of `u = 1`), or `iv = V - 1` when
///   `u = 0` (the clamp of `v = 1`);
/// * otherwise the cell is `(U, V, W)`.
///
/// ```
/// use micromap_index_lab::prove_all_levels::{decremented_coordinate, U, V, W};
/// // A vertex below the hypotenuse: iw = W - 1.
/// assert_eq!(decremented_coordinate([true; 3], false, false), Some(W));
/// // The vertex u = 1 (w = 0): iu clamped to U - 1; v = 1 (u = 0 too): iv.
/// assert_eq!(decremented_coordinate([true; 3], false, true), Some(U));
/// assert_eq!(decremented_coordinate([true; 3], true, true), Some(V));
/// // Inside an upright micro-triangle: the cell is (U, V, W).
/// assert_eq!(decremented_coordinate([false; 3], false, false), None);
/// ```
#[must_use]
pub fn decremented_coordinate(rest_zero: [bool; 3], u_zero: bool, w_zero: bool) -> Option<usize> {
    if !w_zero && rest_zero[W] {
        Some(W)
    } else if w_zero && rest_zero[U] && rest_zero[V] {
        Some(if u_zero { V } else { U })
    } else {
        None
    }
}

/// The rule [`Machine`] uses for [`decremented_coordinate`].
pub type DecrementRule = fn([bool; 3], bool, bool) -> Option<usize>;

/// The reference's cell bits in one column: the point's bits with those
/// of the decremented coordinate flipped wherever its rest is zero (the
/// borrow of "minus one" runs up through the trailing zeros).
pub(super) fn effective_bits(state: &ReferenceState, column: Column) -> [bool; 3] {
    std::array::from_fn(|c| column.bits[c] ^ (state.decremented == Some(c) && column.rest.zero[c]))
}
