//! A proof for **every** level at once: the walk ([`Walk::step`], version 2)
//! equals the reference's steps (the integer half read with unbounded
//! words, i.e. [`spec::wide_index_from_cell`] for levels `0..=32` and
//! [`spec::index_from_cell`] for `0..=16`, after the exact first half) at
//! every real point of the closed triangle, for every subdivision level `n`.
//!
//! [`crate::prove`] checks one level at a time by enumerating faces. Here
//! both algorithms become finite-state transducers that read the binary
//! digits of the point, most significant first, and emit one index digit
//! per digit column; their product has finitely many reachable states, and
//! exploring it covers every level and every point in one finite search.
//! `docs/verification.md` (section 10) gives the argument step by step.
//!
//! # The input
//!
//! A dyadic point `u = X / 2^m`, `v = Y / 2^m` of the closed triangle, with
//! `Z = 2^m - X - Y >= 0` (so `w = Z / 2^m`), is written as `m + 1`
//! [`Column`]s `k = 0..=m`: the bits of `X`, `Y`, `Z` at position `m - k`
//! (column 0 is the integer part), each annotated with what the rest of
//! the number below it is: which of the three remainders
//! `R_c(k) = frac(2^k c)` are zero, and their sum `D(k)` (an integer, since
//! `2^k (u + v + w)` is one; at most 2). The annotations are a function of
//! the point; read top down they are a guess that the [`Rest`] automaton
//! checks column by column (`2 D(k-1) = bits + D(k)`) and at the end
//! (`D(m) = 0`, all remainders zero). So every accepted annotated word is
//! exactly one point and every point has exactly one accepted word.
//!
//! Every face of the level-`n` lattice contains a dyadic point with `m =
//! n + 2` (its representative, [`crate::lattice`]) and both algorithms are
//! constant on faces, so words of every length cover every real point.
//!
//! # The walk: the real step on symbolic numbers
//!
//! Before step `d + 1` each of the walk's local `u`, `v`, `w` is an affine
//! function of the remainders `R_u(d)`, `R_v(d)` with small integer
//! coefficients (a [`Form`]). [`Symbolic`] implements [`WalkNumber`] on
//! forms: `twice`, `plus`, `minus` are exact on the coefficients, and
//! `cmp_half` decides `form <=> 1/2` from the next column's bits and the
//! zero flags (a form in one remainder `s R + k`, `s = +-1`, compared with a
//! half integer: `2 R(d) = bit + R(d+1)` and `R(d+1)` is 0 or in `(0, 1)`).
//! The transition of the walk transducer *is* [`Walk::step`] (or
//! the talk's version 1, `internals::step_version1`) run on these numbers, followed by the change
//! of variables `R(d) = (bit + R(d+1)) / 2`. Nothing of the step is
//! restated.
//!
//! # The reference: derived from its code
//!
//! The reference's integer half turns its cell `(iu, iv, iw)` into digits
//! column by column from the top, carrying the parity of the Top digits
//! above (its prefix XOR). The table `(parity, u bit, v bit, w bit) ->
//! digit` is *learnt* from the code's `internals::reference_digits`
//! ([`ReferenceColumns::learn`]) and *verified* by running the same code on
//! words of GF(2) polynomials at every level `0..=32` (64-bit) and `0..=16`
//! (32-bit) ([`verify_columns`]). How the cell relates to the point's
//! digits (the point's integer parts at level `n` with at most one of them
//! decremented by one) is *derived* by running the code's
//! `internals::reference_cell` and dyadic diagonal test on symbolic affine
//! forms for every case and level ([`derive_cell_rule`]). Read from the
//! top, "minus one" flips exactly the bits below which the number's rest is
//! zero, so the transducer guesses the decremented coordinate at the start
//! and the guess is checked where the level ends. [`prove_all_levels`] then
//! [`certify`]s the search: every face of levels 0..=8 runs along explored
//! transitions and the product is the committed listing.
//! [`AllLevelsReport::certificate`] exports the proved product for an
//! independent checker (`crates/lab/certificates/product.py`, z3).
//!
//! ```
//! use micromap_index_lab::prove::WalkVersion;
//! use micromap_index_lab::prove_all_levels::{prove_all_levels, Verdict};
//!
//! let report = prove_all_levels(WalkVersion::Version2).unwrap();
//! assert!(matches!(report.verdict, Verdict::Proved));
//!
//! // The talk's version 1 is refuted, with a concrete face.
//! let report = prove_all_levels(WalkVersion::Version1).unwrap();
//! let Verdict::Counterexample(example) = report.verdict else { panic!() };
//! assert_ne!(example.walk_index, example.reference_index);
//! ```

use crate::lattice::{Face, FaceKind};
use crate::prove::WalkVersion;
use core::cmp::Ordering;
use micromap_index::uv2index::{self, Walk, WalkNumber};
use micromap_index::{internals, spec, Error, Level, Outside};
use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet, VecDeque};
use std::fmt;

mod certificate;
mod certify;
mod product;
mod reference_code;
mod report;
mod search;
mod symbolic;
#[cfg(test)]
mod tests;
mod transducer;

pub use certificate::*;
pub use certify::*;
pub use product::*;
pub use reference_code::*;
pub use report::*;
pub use search::*;
pub use symbolic::*;
pub use transducer::*;

/// Index of `u` in the coordinate triples of this module.
pub const U: usize = 0;
/// Index of `v`.
pub const V: usize = 1;
/// Index of `w = 1 - u - v`.
pub const W: usize = 2;

/// The checker's state after column `k`: which remainders `R_c(k)` are zero
/// and their sum `D(k)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Rest {
    /// `D(k) = R_u(k) + R_v(k) + R_w(k)`, an integer in `0..=2`.
    pub sum: u8,
    /// `R_c(k) == 0` for `c` = `u`, `v`, `w`.
    pub zero: [bool; 3],
}

impl Rest {
    /// All 24 candidate values (`sum` in `0..=2`, any zero flags).
    fn all() -> impl Iterator<Item = Rest> {
        (0..=2u8).flat_map(|sum| {
            (0..8u8).map(move |z| Rest {
                sum,
                zero: [z & 1 != 0, z & 2 != 0, z & 4 != 0],
            })
        })
    }

    /// The accepting state: nothing left.
    const DONE: Rest = Rest {
        sum: 0,
        zero: [true; 3],
    };

    /// Whether `self` (after column `k - 1`) may be followed by the column
    /// with these bits and the rest `next` (after column `k`):
    /// `R(k-1) = (bit + R(k)) / 2` summed and tested for zero.
    ///
    /// ```
    /// use micromap_index_lab::prove_all_levels::Rest;
    /// // u = v = 1/4, w = 1/2: after the integer column the remainders are
    /// // (1/4, 1/4, 1/2), none zero, sum 1; after the next column (bits
    /// // 0, 0, 1) they are (1/2, 1/2, 0).
    /// let before = Rest { sum: 1, zero: [false; 3] };
    /// let after = Rest { sum: 1, zero: [false, false, true] };
    /// assert!(before.admits([false, false, true], after));
    /// assert!(!before.admits([true, false, false], after));
    /// ```
    #[must_use]
    pub fn admits(self, bits: [bool; 3], next: Rest) -> bool {
        let ones = bits.iter().filter(|&&b| b).count() as u8;
        2 * self.sum == ones + next.sum
            && (0..3).all(|c| self.zero[c] == (!bits[c] && next.zero[c]))
    }
}

/// One input column as the transducers see it: the bits of `X`, `Y`, `Z`
/// at this position and the checker's state after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Column {
    /// Bits of `X`, `Y`, `Z`.
    pub bits: [bool; 3],
    /// The remainders below this column.
    pub rest: Rest,
}

/// Eight bit triples in a fixed order.
fn bit_triples() -> impl Iterator<Item = [bool; 3]> {
    (0..8u8).map(|b| [b & 1 != 0, b & 2 != 0, b & 4 != 0])
}
