//! The kernel's integer halves equal the reference's, at every level, for
//! every cell: each form's own function (`internals::kernel`, the code the
//! batch loops, `spec::index_f32` and the exact entry points run) and the
//! reference's generic `reference_cell` and `reference_digits` (the code
//! the transducer proof of section 10.3 derives from) run on words of
//! decision diagrams over the cell's bits; equal diagrams are equal
//! functions.
//!
//! The domain is what the kernels accept: cells `iu, iv <= last = 2^level -
//! 1` (the first half clamps them there), both diagonal outcomes, every
//! level of the form. The reference's clamps are then no-ops, so the claim
//! is the kernel's index equal to `spec::index_from_cell` (narrow forms) or
//! `spec::wide_index_from_cell` (wide forms) at every input of the domain.

use super::bdd::{self, Node};
use super::word::{explore, Bits};
use micromap_index::internals::kernel::LaneWord;
use micromap_index::internals::kernel::{narrow_lane, narrow_point, wide_lane, wide_point};
use micromap_index::internals::{
    reference_cell, reference_digits, NARROW_INTERLEAVE, NARROW_PREFIX_XOR, WIDE_INTERLEAVE,
    WIDE_PREFIX_XOR,
};
use micromap_index::spec;
use std::fmt;
use std::ops::RangeInclusive;

/// One copy of the integer half and interleave that the library runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum KernelForm {
    /// `kernel::word::narrow_point`: `spec::index_f32`,
    /// `batch::index_f32_one`, the batch loops' short tails,
    /// `uv2index::exact_index_f32`/`_f64` below level 17.
    PointNarrow,
    /// `kernel::word::wide_point`: `spec::wide_index_f32`, the wide batch
    /// tails, the exact entry points at levels 17..=19.
    PointWide,
    /// `kernel::word::narrow_lane` (16-bit words) and the portable lanes'
    /// interleave: the narrow batch loops (`batch::index_f32`).
    LanesNarrow,
    /// `kernel::word::wide_lane` and the portable lanes' wide interleave:
    /// the wide batch loops (`batch::wide_index_f32`).
    LanesWide,
}

impl KernelForm {
    /// Every form.
    pub const ALL: [KernelForm; 4] = [
        KernelForm::PointNarrow,
        KernelForm::PointWide,
        KernelForm::LanesNarrow,
        KernelForm::LanesWide,
    ];

    /// The form's function, for reports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            KernelForm::PointNarrow => "kernel::word::narrow_point",
            KernelForm::PointWide => "kernel::word::wide_point",
            KernelForm::LanesNarrow => "kernel::word::narrow_lane + interleave_16",
            KernelForm::LanesWide => "kernel::word::wide_lane + interleave_32",
        }
    }

    /// The levels the form serves.
    #[must_use]
    pub fn levels(self) -> RangeInclusive<u32> {
        match self {
            KernelForm::PointNarrow | KernelForm::LanesNarrow => 0..=16,
            KernelForm::PointWide | KernelForm::LanesWide => 0..=32,
        }
    }

    fn is_wide(self) -> bool {
        matches!(self, KernelForm::PointWide | KernelForm::LanesWide)
    }

    /// The form's index on diagram words (cells in 32-bit words, at most
    /// `last`).
    pub(super) fn symbolic(
        self,
        iu: Bits<32>,
        iv: Bits<32>,
        diagonal: bool,
        last: u64,
    ) -> Bits<64> {
        let halves = |(low, high): (Bits<32>, Bits<32>)| {
            Bits(std::array::from_fn(|i| {
                if i < 32 {
                    low.0[i]
                } else {
                    high.0[i - 32]
                }
            }))
        };
        match self {
            KernelForm::PointNarrow => {
                narrow_point(iu, iv, Node::constant(diagonal), Bits::of(last)).resize()
            }
            KernelForm::PointWide => {
                halves(wide_point(iu, iv, Node::constant(diagonal), Bits::of(last)))
            }
            KernelForm::LanesNarrow => {
                let d = Bits::<16>::of(u64::from(diagonal));
                let (b0, b1) = narrow_lane(iu.resize::<16>(), iv.resize(), d, Bits::of(last));
                interleave_16_of_halves(b0, b1).resize()
            }
            KernelForm::LanesWide => {
                let d = Bits::<32>::of(u64::from(diagonal));
                let (b0, b1) = wide_lane(iu, iv, d, Bits::of(last));
                halves(interleave_32_of(b0, b1))
            }
        }
    }

    /// The form's index on machine words: the same functions on `u16` and
    /// `u32`.
    #[must_use]
    pub fn concrete(self, iu: u32, iv: u32, diagonal: bool, level: u32) -> u64 {
        let last = ((1u64 << level) - 1) as u32;
        let halves = |(low, high): (u32, u32)| u64::from(low) | (u64::from(high) << 32);
        match self {
            KernelForm::PointNarrow => u64::from(narrow_point(iu, iv, diagonal, last)),
            KernelForm::PointWide => halves(wide_point(iu, iv, diagonal, last)),
            KernelForm::LanesNarrow => {
                let (b0, b1) = narrow_lane(iu as u16, iv as u16, u16::from(diagonal), last as u16);
                let index =
                    micromap_index::internals::kernel::interleave_16(u32::from(b0), u32::from(b1));
                u64::from(index)
            }
            KernelForm::LanesWide => {
                let (b0, b1) = wide_lane(iu, iv, u32::from(diagonal), last);
                halves(micromap_index::internals::kernel::interleave_32(b0, b1))
            }
        }
    }

    /// The reference's index of a cell on machine words.
    #[must_use]
    pub fn reference(self, iu: u32, iv: u32, diagonal: bool, level: u32) -> u64 {
        if self.is_wide() {
            spec::wide_index_from_cell(u64::from(iu), u64::from(iv), diagonal, level)
        } else {
            u64::from(spec::index_from_cell(iu, iv, diagonal, level))
        }
    }
}

/// The portable lanes' narrow interleave: `interleave_16` of the 16-bit
/// halves widened to 32 bits (`u32::from`).
fn interleave_16_of_halves(b0: Bits<16>, b1: Bits<16>) -> Bits<32> {
    micromap_index::internals::kernel::interleave_16(b0.resize::<32>(), b1.resize())
}

fn interleave_32_of(b0: Bits<32>, b1: Bits<32>) -> (Bits<32>, Bits<32>) {
    micromap_index::internals::kernel::interleave_32(b0, b1)
}

/// A cell where a form and the reference differ, confirmed on machine
/// words.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct KernelCounterexample {
    /// The form.
    pub form: KernelForm,
    /// The level.
    pub level: u32,
    /// The cell.
    pub iu: u32,
    /// The cell.
    pub iv: u32,
    /// The diagonal outcome.
    pub diagonal: bool,
    /// The form's index there (machine words).
    pub kernel: u64,
    /// The reference's index there (machine words).
    pub reference: u64,
}

impl fmt::Display for KernelCounterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} differs from the reference at level {}, cell ({}, {}), diagonal {}: {} vs {}",
            self.form.name(),
            self.level,
            self.iu,
            self.iv,
            self.diagonal,
            self.kernel,
            self.reference
        )
    }
}

/// What the proof of every form covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct KernelProof {
    /// Each form and its levels, every cell and diagonal outcome.
    pub forms: Vec<(KernelForm, RangeInclusive<u32>)>,
    /// Level, form and diagonal combinations proved.
    pub cases: usize,
    /// Paths of the reference's branches explored, over all cases.
    pub reference_paths: usize,
    /// The most diagram nodes one case needed.
    pub peak_nodes: usize,
}

/// Why the proof failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum KernelProofError {
    /// A form differs from the reference at a cell (confirmed on machine
    /// words).
    Differs(KernelCounterexample),
    /// The diagrams say the form differs at a cell where the machine words
    /// agree: the prover is wrong, nothing is proved.
    Unconfirmed(KernelCounterexample),
}

impl fmt::Display for KernelProofError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            KernelProofError::Differs(example) => write!(f, "{example}"),
            KernelProofError::Unconfirmed(example) => write!(
                f,
                "the diagrams disagree with the machine words at {example}: prover error"
            ),
        }
    }
}

/// The variable of bit `i` of `iu` (`v = false`) or `iv`: the two cells'
/// bits interleaved from the top, where the fold's comparison is decided.
fn variable(i: usize, v: bool) -> u32 {
    2 * (31 - i as u32) + u32::from(v)
}

/// Proves every [`KernelForm`] equal to the reference at every level it
/// serves, every cell `iu, iv <= last` and both diagonal outcomes.
///
/// # Errors
/// The first form, level and cell where they differ.
pub fn prove_kernel_integer_halves() -> Result<KernelProof, KernelProofError> {
    prove_forms(&KernelForm::ALL, |form, iu, iv, diagonal, last| {
        form.symbolic(iu, iv, diagonal, last)
    })
}

/// [`prove_kernel_integer_halves`] with the forms' symbolic functions
/// given: how the tests check that a changed kernel is refused. The
/// counterexample's machine-word values come from `concrete`.
///
/// # Errors
/// As [`prove_kernel_integer_halves`].
pub fn prove_forms(
    forms: &[KernelForm],
    symbolic: impl Fn(KernelForm, Bits<32>, Bits<32>, bool, u64) -> Bits<64>,
) -> Result<KernelProof, KernelProofError> {
    prove_forms_with(forms, symbolic, KernelForm::concrete)
}

/// [`prove_forms`] with the machine-word function given too.
///
/// # Errors
/// As [`prove_kernel_integer_halves`].
pub fn prove_forms_with(
    forms: &[KernelForm],
    symbolic: impl Fn(KernelForm, Bits<32>, Bits<32>, bool, u64) -> Bits<64>,
    concrete: impl Fn(KernelForm, u32, u32, bool, u32) -> u64,
) -> Result<KernelProof, KernelProofError> {
    let mut proof = KernelProof {
        forms: Vec::new(),
        cases: 0,
        reference_paths: 0,
        peak_nodes: 0,
    };
    for &form in forms {
        for level in form.levels() {
            for diagonal in [false, true] {
                bdd::reset();
                let n = level as usize;
                let iu = Bits::<32>::input(n, |i| variable(i, false));
                let iv = Bits::<32>::input(n, |i| variable(i, true));
                let last = (1u64 << level) - 1;
                let kernel = symbolic(form, iu, iv, diagonal, last);
                let paths = reference_paths(form, iu, iv, diagonal, level);
                proof.reference_paths += paths.len();
                // The paths are disjoint and cover every input: their
                // results merge into one symbolic index, compared once.
                let mut reference = Bits::<64>::of(0);
                for (path, path_reference) in paths {
                    reference = Bits::select(path, path_reference, reference);
                }
                {
                    let mut differs = Node::FALSE;
                    for (k, r) in kernel.0.iter().zip(reference.0) {
                        differs = differs | (*k ^ r);
                    }
                    if let Some(assignment) = differs.satisfying_assignment() {
                        let iu = iu.value(&assignment) as u32;
                        let iv = iv.value(&assignment) as u32;
                        let example = KernelCounterexample {
                            form,
                            level,
                            iu,
                            iv,
                            diagonal,
                            kernel: concrete(form, iu, iv, diagonal, level),
                            reference: form.reference(iu, iv, diagonal, level),
                        };
                        return Err(if example.kernel == example.reference {
                            KernelProofError::Unconfirmed(example)
                        } else {
                            KernelProofError::Differs(example)
                        });
                    }
                }
                proof.cases += 1;
                proof.peak_nodes = proof.peak_nodes.max(bdd::node_count());
            }
        }
        proof.forms.push((form, form.levels()));
    }
    Ok(proof)
}

/// The reference's index of the symbolic cell, one result per path of its
/// branches: `reference_cell` then `reference_digits` with the narrow
/// (32-bit) or wide (64-bit) constants, as `spec::index_from_cell` and
/// `spec::wide_index_from_cell` call them.
fn reference_paths(
    form: KernelForm,
    iu: Bits<32>,
    iv: Bits<32>,
    diagonal: bool,
    level: u32,
) -> Vec<(Node, Bits<64>)> {
    if form.is_wide() {
        let (iu, iv) = (iu.resize::<64>(), iv.resize::<64>());
        explore(|| {
            let (iu, iv, iw) = reference_cell(iu, iv, diagonal, level);
            reference_digits(iu, iv, iw, level, &WIDE_PREFIX_XOR, &WIDE_INTERLEAVE)
        })
    } else {
        explore(|| {
            let (iu, iv, iw) = reference_cell(iu, iv, diagonal, level);
            reference_digits(iu, iv, iw, level, &NARROW_PREFIX_XOR, &NARROW_INTERLEAVE)
                .resize::<64>()
        })
    }
}
