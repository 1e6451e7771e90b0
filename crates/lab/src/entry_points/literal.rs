//! The reference's literal port in binary32 (`spec::cell_f32`, the first
//! half of `spec::reference_bits_f32` and `spec::wide_index_f32`) is, at
//! every binary32 input and level `0..=32`, the definition's cell and exact
//! fraction, by exhaustion over its two steps:
//!
//! * `clamp_unit` (`min(max(x, 0), 1)`), every one of the `2^32` bit
//!   patterns: NaN, negatives and zeros give 0 (`+0.0`, or `-0.0`: Rust
//!   leaves the sign of `max(-0.0, 0.0)` open), everything from 1 up gives
//!   1, every other input is kept.
//! * `truncate_scaled` (`iu = (uint32_t)fu`, `uf = fu - float(iu)`), every
//!   binary32 `fu` in `[+0, 2^32]` and `-0.0`: the cell is `floor(fu)` and
//!   the fraction exactly `fu - floor(fu)` (compared in binary64, where
//!   both are exact).
//!
//! Between them the port multiplies by `2^level` in binary32, which for a
//! clamped `c` in `[0, 1]` (subnormals and 1 included) and level `0..=32`
//! is exact and stays in `[0, 2^32]`: lemma 8 of
//! `crates/lab/certificates/lemmas.py` (z3). So the port's cell is
//! `floor(2^level c)` (at most `2^level`; the integer half clamps it, as
//! the reference does) and its fraction the exact one, and its
//! `uf + vf >= 1.0f` is the real sum reaching `1 - 2^-25` (lemma 4; a
//! `-0.0` fraction never reaches the diagonal either, lemma 7): the
//! definition the float and bit forms of 10.12 are proved against. Its
//! integer half is the generic reference itself (`spec::index_from_cell`,
//! `spec::wide_index_from_cell`).

use super::float::first_failure;
use micromap_index::internals::{clamp_unit, truncate_scaled};
use std::fmt;

/// An input where a step of the literal port departs from its claim.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LiteralCounterexample {
    /// The step (`clamp_unit` or `truncate_scaled`).
    pub step: &'static str,
    /// The input's bits.
    pub bits: u32,
}

impl fmt::Display for LiteralCounterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the literal port (spec::cell_f32): {} departs from its claim at {:#010x} ({})",
            self.step,
            self.bits,
            f32::from_bits(self.bits)
        )
    }
}

/// What the exhaustion covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LiteralProof {
    /// Inputs checked, both steps together.
    pub inputs: u64,
}

/// Bits of `2^32`, the largest product the port forms.
const TWO_TO_32_BITS: u32 = 0x4f80_0000;
/// Bits of `-0.0`.
const NEGATIVE_ZERO_BITS: u32 = 0x8000_0000;

/// Checks both steps at every input (module comment), on every core.
///
/// # Errors
/// The smallest input where a step departs from its claim.
pub fn prove_literal_first_half() -> Result<LiteralProof, LiteralCounterexample> {
    prove_literal_steps(clamp_unit, truncate_scaled)
}

/// [`prove_literal_first_half`] with the steps given: how the tests check
/// that changed steps are refused.
///
/// # Errors
/// As [`prove_literal_first_half`].
pub fn prove_literal_steps(
    clamp: impl Fn(f32) -> f32 + Sync,
    truncate: impl Fn(f32) -> (u64, f32) + Sync,
) -> Result<LiteralProof, LiteralCounterexample> {
    let clamp_holds = |bits: u32| {
        let x = f32::from_bits(bits);
        let clamped = clamp(x);
        if x.is_nan() || x <= 0.0 {
            // Either zero: `-0.0 == 0.0`.
            clamped == 0.0
        } else if x >= 1.0 {
            clamped.to_bits() == 1f32.to_bits()
        } else {
            clamped.to_bits() == bits
        }
    };
    let truncate_holds = |bits: u32| {
        let fu = f32::from_bits(bits);
        let (cell, fraction) = truncate(fu);
        let floor = f64::from(fu).floor();
        cell as f64 == floor && f64::from(fraction) == f64::from(fu) - floor
    };
    let products = 0..u64::from(TWO_TO_32_BITS) + 1;
    let inputs = (1 << 32) + (products.end - products.start) + 1;
    if let Some(bits) = first_failure(products, &truncate_holds)
        .or_else(|| (!truncate_holds(NEGATIVE_ZERO_BITS)).then_some(NEGATIVE_ZERO_BITS))
    {
        return Err(LiteralCounterexample {
            step: "truncate_scaled",
            bits,
        });
    }
    if let Some(bits) = first_failure(0..u64::from(u32::MAX) + 1, &clamp_holds) {
        return Err(LiteralCounterexample {
            step: "clamp_unit",
            bits,
        });
    }
    Ok(LiteralProof { inputs })
}
