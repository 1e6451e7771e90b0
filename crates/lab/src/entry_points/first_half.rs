//! The definition of an exact first half in fixed point, shared by the
//! binary32 and binary64 proofs: for a clamped coordinate `c = m 2^-s /
//! 2^level` below 1 (an integer `m`, `s >= 0`), the cell `i` is
//! `floor(2^level c)`, the fraction `F` is `floor(frac(2^level c) 2^P)` with
//! `P` fraction bits, and `F` is exact or the fraction is below `2^-t`
//! (what makes the integer diagonal test exact: `src/kernel/mod.rs`,
//! "Diagonal").

use super::bdd::Node;
use super::word::Bits;
use micromap_index::internals::kernel::LaneWord;

/// A fixed-point format of the fraction and the claims' names.
pub(super) struct FractionFormat {
    /// `P`: the fraction's bits.
    pub bits: u32,
    /// `t`: an inexact fraction is below `2^-t`.
    pub tiny_log2: u32,
    /// The fraction claim's name.
    pub fraction_claim: &'static str,
    /// The exact-or-tiny claim's name.
    pub tiny_claim: &'static str,
}

/// The claims on `(cell, fraction)` for the significand `m` (every input
/// of a case) at shift `s`, each a diagram that must be true. The callers
/// keep every value below `2^192` (`m 2^P < 2^115` and `2^s <= 2^149`;
/// larger shifts give cell 0, fraction 0, which they claim themselves).
pub(super) fn floor_claims(
    m: &Bits<192>,
    cell: &Bits<64>,
    fraction: &Bits<64>,
    s: u32,
    format: &FractionFormat,
) -> Vec<(&'static str, Node)> {
    let i: Bits<192> = cell.resize();
    let f: Bits<192> = fraction.resize();
    let one = Bits::<192>::of(1);
    let low = i << s;
    let r = m.wrapping_sub(low);
    let scaled = r << format.bits;
    let unit = one << s;
    vec![
        (
            "cell = floor(2^level x)",
            !m.less_than(low)
                & m.less_than(i.wrapping_add(one) << s)
                & i.less_than(Bits::of(1 << 34)),
        ),
        (
            format.fraction_claim,
            !scaled.less_than(f << s)
                & scaled.less_than(f.wrapping_add(one) << s)
                & f.less_than(one << format.bits),
        ),
        (
            format.tiny_claim,
            (scaled & unit.wrapping_sub(one)).equals(&Bits::of(0))
                | (r << format.tiny_log2).less_than(unit),
        ),
    ]
}
