//! The float first half's clamp (`clamp_flushed`: `spec::index_f32`, the
//! batch loops' short tails, the narrow lanes) departs from the
//! reference's clamp to `[0, 1]` in two places; this proves that neither
//! changes the index, at every binary32 pair and level `0..=16`.
//!
//! [`super::float`] proves the clamp's shape (every input up to `2^-126`,
//! NaN and negatives included, becomes `2^-126`; every input from `1 -
//! 2^-24` up becomes `1 - 2^-24`; the rest is kept) and that the kept
//! inputs get the definition's cell and exact fraction. Per coordinate
//! there are three cases, and the index is equal in each combination:
//!
//! * **Stopped** (`x >= 1`): the definition's cell is `last = 2^level - 1`
//!   (the reference clamps the cell `2^level` there), fraction 0. The float
//!   form's `1 - 2^-24` times `2^level` truncates to `last` too (checked
//!   here at every level, on the crate's own `BELOW_ONE` and
//!   `truncate_float`), with another fraction. The fraction only reaches
//!   the index through the diagonal outcome, and **with either cell at
//!   `last` the index does not depend on the diagonal outcome**: checked
//!   here on decision diagrams for the narrow integer halves the float
//!   form feeds (`narrow_point`, and `narrow_lane` + `interleave_16`),
//!   every other cell `<= last`, every level `0..=16`.
//! * **Flushed** (`x <= 2^-126`, NaN, negatives): both cells are 0. The
//!   float form's fraction is `2^(level - 126)` (checked here: at most
//!   `2^-110`), the definition's is 0 (NaN, negatives, zeros) or `x 2^level`
//!   (subnormals), also at most `2^-110`. A fraction that small never makes
//!   the diagonal true, whatever the other coordinate's fraction (a
//!   binary32 below 1): binary32's `uf + vf` stays below `1.0` in either
//!   order, and the real sum below `1 - 2^-25` (lemma 7 of
//!   `crates/lab/certificates/lemmas.py`, z3). So both sides' diagonal is
//!   false, unless the other coordinate is stopped, which the first case
//!   covers.
//! * **Kept**: the same cell and fraction on both sides ([`super::float`]).

use super::bdd::{self, Node};
use super::kernel::KernelForm;
use super::word::Bits;
use micromap_index::internals::kernel::{truncate_float, BELOW_ONE};
use std::fmt;
use std::ops::RangeInclusive;

/// The levels of the float first half.
pub const FLOAT_LEVELS: RangeInclusive<u32> = 0..=16;

/// The largest fraction a flushed coordinate may carry: `2^-110`, what
/// lemma 7 of `lemmas.py` allows.
pub const TINY_FRACTION: f32 = 1.0 / (1u128 << 110) as f32;

/// Where the clamp's argument fails.
#[derive(Clone, Debug, PartialEq)]
pub enum ClampCounterexample {
    /// The stop value's cell at this level is not `last`.
    StopCell {
        /// The level.
        level: u32,
        /// The cell the float form gives `BELOW_ONE * 2^level`.
        cell: u32,
    },
    /// The flush value's cell or fraction at this level.
    Flush {
        /// The level.
        level: u32,
        /// The cell the float form gives `2^-126 * 2^level`.
        cell: u32,
        /// Its fraction.
        fraction: f32,
    },
    /// With a cell at `last`, the index depends on the diagonal outcome.
    DiagonalRead {
        /// The integer half.
        form: KernelForm,
        /// The level.
        level: u32,
        /// `iu` (`last` when the `u` side is at `last`).
        iu: u32,
        /// `iv`.
        iv: u32,
    },
}

impl fmt::Display for ClampCounterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClampCounterexample::StopCell { level, cell } => write!(
                f,
                "the float clamp's stop (1 - 2^-24) has cell {cell} at level {level}, not \
                 2^level - 1"
            ),
            ClampCounterexample::Flush {
                level,
                cell,
                fraction,
            } => write!(
                f,
                "the float clamp's flush value (2^-126) has cell {cell} and fraction {fraction:e} \
                 at level {level}: cell 0 and a fraction at most 2^-110 expected"
            ),
            ClampCounterexample::DiagonalRead {
                form,
                level,
                iu,
                iv,
            } => write!(
                f,
                "{} reads the diagonal outcome at level {level}, cell ({iu}, {iv}), which has a \
                 coordinate at 2^level - 1",
                form.name()
            ),
        }
    }
}

/// What was checked.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ClampProof {
    /// The levels.
    pub levels: RangeInclusive<u32>,
    /// The integer halves shown not to read the diagonal at a `last` cell.
    pub forms: Vec<KernelForm>,
}

/// The integer halves after the float first half.
pub const FLOAT_FORMS: [KernelForm; 2] = [KernelForm::PointNarrow, KernelForm::LanesNarrow];

/// Checks the crate's clamp (module comment).
///
/// # Errors
/// The first level or cell where the argument fails.
pub fn prove_float_clamp() -> Result<ClampProof, ClampCounterexample> {
    prove_clamp_with(
        BELOW_ONE,
        truncate_float,
        &FLOAT_FORMS,
        KernelForm::symbolic,
    )
}

/// [`prove_float_clamp`] with the stop value, the truncation and the
/// integer halves given: how the tests check that changes are refused.
///
/// # Errors
/// As [`prove_float_clamp`].
pub fn prove_clamp_with(
    below_one: f32,
    truncate: impl Fn(f32) -> (u32, f32),
    forms: &[KernelForm],
    symbolic: impl Fn(KernelForm, Bits<32>, Bits<32>, bool, u64) -> Bits<64>,
) -> Result<ClampProof, ClampCounterexample> {
    for level in FLOAT_LEVELS {
        // The kernel's scale (`Params::new`), and its products: exact
        // (lemma 6), as the kernel forms them.
        let scale = (1u64 << level) as f32;
        let last = ((1u64 << level) - 1) as u32;
        let (cell, _) = truncate(below_one * scale);
        if cell != last {
            return Err(ClampCounterexample::StopCell { level, cell });
        }
        let (cell, fraction) = truncate(f32::MIN_POSITIVE * scale);
        if cell != 0 || !(0.0..=TINY_FRACTION).contains(&fraction) {
            return Err(ClampCounterexample::Flush {
                level,
                cell,
                fraction,
            });
        }
    }
    for &form in forms {
        for level in FLOAT_LEVELS {
            for u_side in [true, false] {
                bdd::reset();
                let last = (1u64 << level) - 1;
                let other = Bits::<32>::input(level as usize, |i| 31 - i as u32);
                let (iu, iv) = if u_side {
                    (Bits::of(last), other)
                } else {
                    (other, Bits::of(last))
                };
                let on = symbolic(form, iu, iv, true, last);
                let off = symbolic(form, iu, iv, false, last);
                let mut differs = Node::FALSE;
                for (a, b) in on.0.iter().zip(off.0) {
                    differs = differs | (*a ^ b);
                }
                if let Some(assignment) = differs.satisfying_assignment() {
                    return Err(ClampCounterexample::DiagonalRead {
                        form,
                        level,
                        iu: iu.value(&assignment) as u32,
                        iv: iv.value(&assignment) as u32,
                    });
                }
            }
        }
    }
    Ok(ClampProof {
        levels: FLOAT_LEVELS,
        forms: forms.to_vec(),
    })
}
