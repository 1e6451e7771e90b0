//! The reference transducer: the column table (learnt from the code,
//! verified symbolically by [`verify_columns`]) and the top-down borrow of
//! the decremented coordinate (the module docs, "The reference").

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
    /// Runs the reference's digit steps ([`internals::reference_digits`],
    /// 64-bit words, the code [`spec::wide_index_from_cell`] runs after its
    /// cell) on every cell `(iu, iv, iw)` of levels 1..=3 (any three words
    /// below `2^level`) and reads off, for every digit position, the digit
    /// against the parity of the Top digits above it and the column's bits.
    /// Fails unless every key is seen and always with one digit.
    /// [`verify_columns`] then checks the table symbolically at every level.
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
        for level in 1..=3u32 {
            let cells = 1u64 << level;
            for iu in 0..cells {
                for iv in 0..cells {
                    for iw in 0..cells {
                        let index = internals::reference_digits(
                            iu,
                            iv,
                            iw,
                            level,
                            &internals::WIDE_PREFIX_XOR,
                            &internals::WIDE_INTERLEAVE,
                        );
                        let mut parity = false;
                        for position in (0..level).rev() {
                            let digit = ((index >> (2 * position)) & 3) as u8;
                            let bit = |x: u64| ((x >> position) & 1) as usize;
                            let key = bit(iu) | bit(iv) << 1 | bit(iw) << 2;
                            let slot = &mut digits[usize::from(parity)][key];
                            if slot.is_some_and(|known| known != digit) {
                                return Err(format!(
                                    "reference digit is not a function of (parity, column): \
                                     cell ({iu}, {iv}, {iw}) level {level} position {position}"
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
    /// [`derive_cell_rule`]).
    pub decremented: Option<usize>,
    /// `u == 0` (known from the first column and its rest).
    pub u_zero: bool,
    /// `w == 0`.
    pub w_zero: bool,
}

/// The reference's cell bits in one column: the point's bits with those
/// of the decremented coordinate flipped wherever its rest is zero (the
/// borrow of "minus one" runs up through the trailing zeros).
pub(super) fn effective_bits(state: &ReferenceState, column: Column) -> [bool; 3] {
    std::array::from_fn(|c| column.bits[c] ^ (state.decremented == Some(c) && column.rest.zero[c]))
}
