//! The kernel's binary32 first half on the bits equals the definition:
//! `internals::kernel::binary32_coordinate::<_, true>` (the wide form:
//! `spec::wide_index_f32`, the wide batch tails and cells,
//! `uv2index::exact_index_f32` at levels 17..=19) at every binary32 input
//! and level `0..=32`, and `clamp_binary32` followed by
//! `binary32_unit_coordinate` (the scalar narrow form: `spec::index_f32`,
//! `batch::index_f32_one`, `exact_index_f32` at levels 0..=16) at every
//! input and level `0..=16`. They run on words of decision diagrams, 32-bit
//! for the clamp and the wide form, 64-bit for the unit form, as the kernel
//! runs them on `u32` and `u64`.
//!
//! The inputs are split into cases in which the exponent is a constant:
//! `x` negative (sign set, every other bit free), exponent 255 (infinity
//! and NaN, the significand free) and one case per exponent `e in 0..=254`
//! (sign clear, the 23 significand bits free). The definition, for the
//! clamped `c` (NaN and negatives 0, `x >= 1` gives 1) written `c = m 2^-s
//! / 2^level` with an integer `m < 2^24` (`s = 150 - level - max(e, 1)`):
//!
//! * `x >= 1` (and `+inf`) gives the cell `2^level - 1` (the reference's
//!   clamp of the cell) and fraction 0; NaN and negatives cell 0, fraction
//!   0;
//! * otherwise, for `s >= 0`, the cell `i` satisfies `i 2^s <= m < (i + 1)
//!   2^s`; the fraction `F` satisfies `F 2^s <= r 2^31 < (F + 1) 2^s`, `r =
//!   m - i 2^s` (it is `floor(frac(2^level c) 2^31)`); and `F` is exact (`r
//!   2^31` a multiple of `2^s`) or the fraction is below `2^-7` (`r 2^7 <
//!   2^s`); for `s < 0` (levels above 23) the cell is `m 2^-s` and the
//!   fraction 0.
//!
//! The diagonal is then the kernel's `F_u + F_v >= T` on 32-bit words (no
//! overflow: both are below `2^31`), with `T = 2^31` (exact) or `2^31 -
//! 2^6` (binary32): with the last property, an integer threshold is reached
//! by `F_u + F_v` exactly when the real `(frac_u + frac_v) 2^31` reaches
//! it (`src/kernel/mod.rs`, "Diagonal"); that binary32's `uf + vf >= 1.0f`
//! is the real sum reaching `1 - 2^-25` is the rounding argument there, not
//! checked here.

use super::bdd::{self, Node};
use super::first_half::{floor_claims, FractionFormat};
use super::word::{explore_pair, Bits};
use micromap_index::internals::kernel::LaneWord;
use micromap_index::internals::kernel::{
    binary32_coordinate, binary32_unit_coordinate, clamp_binary32,
};
use std::fmt;

/// A binary32 input and level where a form's steps and the definition
/// differ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binary32Counterexample {
    /// The form (`wide` or `unit`).
    pub form: &'static str,
    /// The coordinate's bits.
    pub bits: u32,
    /// The level.
    pub level: u32,
    /// Which claim failed.
    pub claim: &'static str,
}

impl fmt::Display for Binary32Counterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the kernel's {} binary32 first half: {} fails at {:#010x} ({}), level {}",
            self.form,
            self.claim,
            self.bits,
            f32::from_bits(self.bits),
            self.level
        )
    }
}

/// What the proof covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binary32Proof {
    /// `(form, input class, level)` cases proved.
    pub cases: usize,
    /// The most diagram nodes one case needed.
    pub peak_nodes: usize,
}

/// A form of the first half: bits to (cell, fraction) at a level, on
/// diagram words (each result widened to 64 bits).
pub type Binary32Form<'a> = dyn Fn(Bits<32>, u32) -> (Bits<64>, Bits<64>) + 'a;

/// The wide form as the kernel runs it.
fn wide(bits: Bits<32>, level: u32) -> (Bits<64>, Bits<64>) {
    let (cell, fraction) = binary32_coordinate::<_, true>(bits, 150 - level, last(level));
    (cell.resize(), fraction.resize())
}

/// The clamp, then the unit form, as the scalar narrow kernel runs them.
fn unit(bits: Bits<32>, level: u32) -> (Bits<64>, Bits<64>) {
    let clamped: Bits<64> = clamp_binary32(bits).resize();
    binary32_unit_coordinate(clamped, 150 - level, last(level))
}

fn last(level: u32) -> u32 {
    ((1u64 << level) - 1) as u32
}

/// Proves both forms (module comment).
///
/// # Errors
/// The first input where a form and the definition differ.
pub fn prove_binary32_first_half() -> Result<Binary32Proof, Binary32Counterexample> {
    prove_binary32_forms(&[("wide", 32, &wide), ("unit", 16, &unit)])
}

/// [`prove_binary32_first_half`] for the forms given, each with its name
/// and highest level: how the tests check that changed steps are refused.
///
/// # Errors
/// As [`prove_binary32_first_half`].
pub fn prove_binary32_forms(
    forms: &[(&'static str, u32, &Binary32Form<'_>)],
) -> Result<Binary32Proof, Binary32Counterexample> {
    let mut proof = Binary32Proof {
        cases: 0,
        peak_nodes: 0,
    };
    bdd::reset();
    for &(name, max_level, form) in forms {
        for level in 0..=max_level {
            let classes = [InputClass::Negative]
                .into_iter()
                .chain((0..=255).map(InputClass::Exponent));
            for class in classes {
                let bits = class.input();
                let (cell, fraction) = explore_pair(|| form(bits, level));
                for (claim, holds) in class.definition(bits, &cell, &fraction, level) {
                    if let Some(assignment) = (!holds).satisfying_assignment() {
                        return Err(Binary32Counterexample {
                            form: name,
                            bits: bits.value(&assignment) as u32,
                            level,
                            claim,
                        });
                    }
                }
                proof.cases += 1;
                proof.peak_nodes = proof.peak_nodes.max(bdd::node_count());
            }
        }
    }
    Ok(proof)
}

/// A set of binary32 bit patterns proved as one case.
#[derive(Clone, Copy, Debug)]
enum InputClass {
    /// Sign set, everything else free.
    Negative,
    /// Sign clear, this biased exponent (`0..=255`), significand free.
    Exponent(u32),
}

/// The variable of input bit `i` (from the top of the 32).
fn variable(i: usize) -> u32 {
    31 - i as u32
}

impl InputClass {
    fn input(self) -> Bits<32> {
        match self {
            InputClass::Negative => {
                let mut bits = Bits::<32>::input(31, variable);
                bits.0[31] = Node::TRUE;
                bits
            }
            InputClass::Exponent(e) => {
                let mut bits = Bits::<32>::input(23, variable);
                for i in 0..8 {
                    bits.0[23 + i] = Node::constant((e >> i) & 1 == 1);
                }
                bits
            }
        }
    }

    /// The definition's claims on `(cell, fraction)` for the inputs `bits`
    /// of this class, each a diagram that must be true.
    fn definition(
        self,
        bits: Bits<32>,
        cell: &Bits<64>,
        fraction: &Bits<64>,
        level: u32,
    ) -> Vec<(&'static str, Node)> {
        let zero = Bits::<64>::of(0);
        let last_cell = Bits::<64>::of(u64::from(last(level)));
        match self {
            InputClass::Negative => vec![(
                "a negative clamps to cell 0, fraction 0",
                cell.equals(&zero) & fraction.equals(&zero),
            )],
            InputClass::Exponent(255) => {
                let nan = bits.0[..23].iter().fold(Node::FALSE, |any, &x| any | x);
                vec![(
                    "NaN clamps to cell 0 and +inf to the last cell, fraction 0",
                    fraction.equals(&zero) & cell.equals(&Bits::select(nan, zero, last_cell)),
                )]
            }
            InputClass::Exponent(e) if e >= 127 => vec![(
                "x >= 1 clamps to the last cell, fraction 0",
                cell.equals(&last_cell) & fraction.equals(&zero),
            )],
            InputClass::Exponent(e) => {
                let hidden = if e == 0 { 0 } else { 1u64 << 23 };
                let m: Bits<192> = (bits & Bits::of(0x7f_ffff) | Bits::of(hidden)).resize();
                let s = 150 - i64::from(level) - i64::from(e.max(1));
                if s < 0 {
                    return vec![(
                        "an integer 2^level x is the cell, fraction 0",
                        cell.resize().equals(&(m << (-s) as u32)) & fraction.equals(&zero),
                    )];
                }
                floor_claims(&m, cell, fraction, s as u32, &BINARY32_FRACTION)
            }
        }
    }
}

/// Binary32's 31-bit fraction: exact, or below `2^-7`.
const BINARY32_FRACTION: FractionFormat = FractionFormat {
    bits: 31,
    tiny_log2: 7,
    fraction_claim: "fraction = floor(frac(2^level x) 2^31)",
    tiny_claim: "the fraction is exact or below 2^-7",
};
