//! `uv2index::exact_index_f64`'s first half (levels `0..=32`, its closed
//! form) equals the reference's exact first half: its steps
//! (`internals::binary64_clamped_coordinate`, one coordinate with its cell
//! clamped as the reference clamps it, and `internals::binary64_diagonal`)
//! run on words of decision diagrams and are compared with the definition.
//!
//! **One coordinate**, every binary64 `x` and level `0..=32`. The inputs
//! are split into cases in which the exponent is a constant: `x` negative
//! (sign set, every other bit free), `x >= 2` or not a number (sign clear,
//! top exponent bit set, every other bit free) and one case per exponent
//! `e in 0..=1023` (sign clear, the 52 significand bits free). The
//! definition, for the clamped `c` (NaN and negatives 0, `x >= 1` gives 1)
//! written `c = m 2^-s / 2^level` with an integer `m < 2^53` (`s = 1075 -
//! level - max(e, 1)`):
//!
//! * the cell `i` satisfies `i 2^s <= m < (i + 1) 2^s` (for `c < 1`; `c = 1`
//!   has the reference's clamped cell `last = 2^level - 1` and fraction 0,
//!   so every cell is below `2^32` and `closed_form_f64`'s casts to `u32`
//!   keep it);
//! * the fraction `F` satisfies `F 2^s <= r 2^62 < (F + 1) 2^s`, `r = m - i
//!   2^s` (it is `floor(frac(2^level c) 2^62)`);
//! * and `F` is exact (`r 2^62` a multiple of `2^s`) or the fraction is
//!   below `2^-9` (`r 2^9 < 2^s`).
//!
//! **The diagonal**: `binary64_diagonal(F_u, F_v)` is `F_u + F_v >= 2^62`
//! for every pair of 62-bit fractions. With the last property of each
//! coordinate that is the exact test `frac_u + frac_v >= 1`: if both
//! fractions are exact the sums agree; if one is not, it is below `2^-9` and
//! the other is exact, so `F_u + F_v` is the integer part of the real sum
//! times `2^62`, which reaches the integer `2^62` exactly when the real sum
//! reaches 1; if neither is, both sums stay below 1.

use super::bdd::{self, Node};
use super::first_half::{floor_claims, FractionFormat};
use super::word::{explore, explore_pair, Bits};
use micromap_index::internals::kernel::LaneWord;
use micromap_index::internals::{binary64_clamped_coordinate, binary64_diagonal};
use std::fmt;

/// A binary64 input and level where the steps and the definition differ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binary64Counterexample {
    /// The coordinate's bits (for the diagonal: the two fractions).
    pub inputs: (u64, u64),
    /// The level (0 for the diagonal).
    pub level: u32,
    /// Which claim failed.
    pub claim: &'static str,
}

impl fmt::Display for Binary64Counterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} fails at {:#018x}, {:#018x}, level {}",
            self.claim, self.inputs.0, self.inputs.1, self.level
        )
    }
}

/// What the proof covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Binary64Proof {
    /// `(input class, level)` cases of the coordinate proved.
    pub cases: usize,
    /// The most diagram nodes one case needed.
    pub peak_nodes: usize,
}

/// The variable of significand bit `i` (from the top).
fn variable(i: usize) -> u32 {
    63 - i as u32
}

/// Store size beyond which a case starts with a fresh store.
const RESET_ABOVE_NODES: usize = 2_000_000;

/// Proves `binary64_clamped_coordinate` (every input, levels `0..=32`) and
/// `binary64_diagonal` (every pair of 62-bit fractions) equal to the
/// definition (module comment).
///
/// # Errors
/// The first input where they differ.
pub fn prove_binary64_first_half() -> Result<Binary64Proof, Binary64Counterexample> {
    prove_binary64_steps(binary64_clamped_coordinate, binary64_diagonal)
}

/// [`prove_binary64_first_half`] with the steps given: how the tests check
/// that changed steps are refused.
///
/// # Errors
/// As [`prove_binary64_first_half`].
pub fn prove_binary64_steps(
    coordinate: impl Fn(Bits<64>, u32) -> (Bits<64>, Bits<64>),
    diagonal: impl Fn(Bits<64>, Bits<64>) -> bool,
) -> Result<Binary64Proof, Binary64Counterexample> {
    let mut proof = Binary64Proof {
        cases: 0,
        peak_nodes: 0,
    };
    bdd::reset();
    prove_diagonal(&diagonal)?;
    for level in 0..=32 {
        // (sign, top exponent bit) free classes, then one case per
        // exponent 0..=1023.
        let classes = [InputClass::Negative, InputClass::TwoOrMore]
            .into_iter()
            .chain((0..=1023).map(InputClass::Exponent));
        for class in classes {
            bdd::reset_above(RESET_ABOVE_NODES);
            let bits = class.input();
            let (cell, fraction) = explore_pair(|| coordinate(bits, level));
            for (claim, holds) in class.definition(bits, &cell, &fraction, level) {
                if let Some(assignment) = (!holds).satisfying_assignment() {
                    return Err(Binary64Counterexample {
                        inputs: (bits.value(&assignment), 0),
                        level,
                        claim,
                    });
                }
            }
            proof.cases += 1;
            proof.peak_nodes = proof.peak_nodes.max(bdd::node_count());
        }
    }
    Ok(proof)
}

/// `diagonal(F_u, F_v) <=> F_u + F_v >= 2^62` for all 62-bit fractions.
fn prove_diagonal(
    diagonal: &impl Fn(Bits<64>, Bits<64>) -> bool,
) -> Result<(), Binary64Counterexample> {
    let uf = Bits::<64>::input(62, |i| 2 * (61 - i as u32));
    let vf = Bits::<64>::input(62, |i| 2 * (61 - i as u32) + 1);
    let paths = explore(|| diagonal(uf, vf));
    let mut computed = Node::FALSE;
    for (path, outcome) in paths {
        computed = path.select(Node::constant(outcome), computed);
    }
    let sum = uf.wrapping_add(vf);
    let reaches = !sum.less_than(Bits::of(1 << 62));
    if let Some(assignment) = (computed ^ reaches).satisfying_assignment() {
        return Err(Binary64Counterexample {
            inputs: (uf.value(&assignment), vf.value(&assignment)),
            level: 0,
            claim: "binary64_diagonal(F_u, F_v) == (F_u + F_v >= 2^62)",
        });
    }
    Ok(())
}

/// A set of binary64 bit patterns proved as one case.
#[derive(Clone, Copy, Debug)]
enum InputClass {
    /// Sign set, everything else free.
    Negative,
    /// Sign clear, top exponent bit set (`x >= 2`, infinity, NaN).
    TwoOrMore,
    /// Sign clear, this biased exponent (`0..=1023`), significand free.
    Exponent(u64),
}

impl InputClass {
    fn input(self) -> Bits<64> {
        match self {
            InputClass::Negative => {
                let mut bits = Bits::<64>::input(63, variable);
                bits.0[63] = Node::TRUE;
                bits
            }
            InputClass::TwoOrMore => {
                let mut bits = Bits::<64>::input(62, variable);
                bits.0[62] = Node::TRUE;
                bits
            }
            InputClass::Exponent(e) => {
                let mut bits = Bits::<64>::input(52, variable);
                for i in 0..11 {
                    bits.0[52 + i] = Node::constant((e >> i) & 1 == 1);
                }
                bits
            }
        }
    }

    /// The definition's claims on `(cell, fraction)` for the inputs `bits`
    /// of this class, each a diagram that must be true.
    fn definition(
        self,
        bits: Bits<64>,
        cell: &Bits<64>,
        fraction: &Bits<64>,
        level: u32,
    ) -> Vec<(&'static str, Node)> {
        let zero = Bits::<64>::of(0);
        match self {
            InputClass::Negative => vec![(
                "a negative clamps to cell 0, fraction 0",
                cell.equals(&zero) & fraction.equals(&zero),
            )],
            InputClass::TwoOrMore => {
                // NaN: exponent all ones and a significand not zero.
                let exponent_ones = bits.0[52..63].iter().fold(Node::TRUE, |all, &x| all & x);
                let significand = bits.0[..52].iter().fold(Node::FALSE, |any, &x| any | x);
                let nan = exponent_ones & significand;
                let one_cell = Bits::<64>::of((1 << level) - 1);
                vec![(
                    "NaN clamps to 0 and x >= 2 to 1 (cell 2^level - 1)",
                    fraction.equals(&zero) & cell.equals(&Bits::select(nan, zero, one_cell)),
                )]
            }
            InputClass::Exponent(e) if e >= 1023 => vec![(
                "x >= 1 clamps to 1 (cell 2^level - 1)",
                cell.equals(&Bits::of((1 << level) - 1)) & fraction.equals(&zero),
            )],
            InputClass::Exponent(e) => {
                let s = 1075 - level - (e as u32).max(1);
                if s >= 115 {
                    // m 2^62 < 2^115 <= 2^s: both floors are 0 (and the
                    // fraction is below 2^-62).
                    return vec![(
                        "a fraction below 2^-62 gives cell 0, fraction 0",
                        cell.equals(&zero) & fraction.equals(&zero),
                    )];
                }
                let hidden = if e == 0 { 0 } else { 1u64 << 52 };
                let m: Bits<192> = (bits & Bits::of((1 << 52) - 1) | Bits::of(hidden)).resize();
                floor_claims(&m, cell, fraction, s, &BINARY64_FRACTION)
            }
        }
    }
}

/// Binary64's 62-bit fraction: exact, or below `2^-9`.
const BINARY64_FRACTION: FractionFormat = FractionFormat {
    bits: 62,
    tiny_log2: 9,
    fraction_claim: "fraction = floor(frac(2^level x) 2^62)",
    tiny_claim: "the fraction is exact or below 2^-9",
};
