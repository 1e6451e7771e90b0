//! The kernel's float first half (`coordinate_float`: `spec::index_f32`,
//! the batch loops' short tails and the portable lanes) is, at every
//! binary32 input, the exact cell and fraction of its clamped input, by
//! exhaustion over its two steps:
//!
//! * `clamp_flushed`, every one of the `2^32` bit patterns: NaN, negatives
//!   and everything up to the smallest normal `2^-126` give `2^-126`;
//!   everything from `1 - 2^-24` up gives `1 - 2^-24`; every other input is
//!   kept.
//! * `truncate_float`, every binary32 `fu` in `[2^-126, 2^16)` (the
//!   products `c 2^level` of a clamped `c` at levels `0..=16`): the cell is
//!   `floor(fu)` and the fraction exactly `fu - floor(fu)` (compared in
//!   binary64, where both are exact).
//!
//! Between them the kernel multiplies by `2^level`, which is exact for a
//! normal `c < 1` and `level <= 16` (the product stays normal and below
//! `2^16`): lemma 6 of `crates/lab/certificates/lemmas.py` (z3). So the
//! float form's cell and fraction are the definition's for `c`; its
//! diagonal `uf + vf >= 1.0f` is the real sum reaching `1 - 2^-25` (lemma
//! 4), which the bit form's `Fu + Fv >= 2^31 - 2^6` decides the same way
//! (lemma 5 with the bit form's proved exact-or-tiny fraction). That the
//! clamp's two changes (flushing below `2^-126`, stopping at `1 - 2^-24`)
//! leave the index alone is [`super::clamp`]'s proof.

use micromap_index::internals::kernel::{clamp_flushed, truncate_float, BELOW_ONE};
use std::fmt;
use std::ops::Range;

/// An input where a step of the float first half departs from its claim.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FloatCounterexample {
    /// The step (`clamp_flushed` or `truncate_float`).
    pub step: &'static str,
    /// The input's bits.
    pub bits: u32,
}

impl fmt::Display for FloatCounterexample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "the kernel's float first half: {} departs from its claim at {:#010x} ({})",
            self.step,
            self.bits,
            f32::from_bits(self.bits)
        )
    }
}

/// What the exhaustion covered.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FloatProof {
    /// Inputs checked, both steps together.
    pub inputs: u64,
}

/// Checks both steps at every input (module comment), on every core.
///
/// # Errors
/// The smallest input where a step departs from its claim.
pub fn prove_float_first_half() -> Result<FloatProof, FloatCounterexample> {
    prove_float_steps(clamp_flushed, truncate_float)
}

/// [`prove_float_first_half`] with the steps given: how the tests check
/// that changed steps are refused.
///
/// # Errors
/// As [`prove_float_first_half`].
pub fn prove_float_steps(
    clamp: impl Fn(u32) -> f32 + Sync,
    truncate: impl Fn(f32) -> (u32, f32) + Sync,
) -> Result<FloatProof, FloatCounterexample> {
    let clamp_holds = |bits: u32| {
        let x = f32::from_bits(bits);
        let expected = if x.is_nan() || x <= f32::MIN_POSITIVE {
            f32::MIN_POSITIVE
        } else if x >= BELOW_ONE {
            BELOW_ONE
        } else {
            x
        };
        clamp(bits).to_bits() == expected.to_bits()
    };
    let truncate_holds = |bits: u32| {
        let fu = f32::from_bits(bits);
        let (cell, fraction) = truncate(fu);
        let floor = f64::from(fu).floor();
        f64::from(cell) == floor && f64::from(fraction) == f64::from(fu) - floor
    };
    let products = u64::from(f32::MIN_POSITIVE.to_bits())..u64::from(65_536f32.to_bits());
    let inputs = (1 << 32) + (products.end - products.start);
    if let Some(bits) = first_failure(products, &truncate_holds) {
        return Err(FloatCounterexample {
            step: "truncate_float",
            bits,
        });
    }
    if let Some(bits) = first_failure(0..u64::from(u32::MAX) + 1, &clamp_holds) {
        return Err(FloatCounterexample {
            step: "clamp_flushed",
            bits,
        });
    }
    Ok(FloatProof { inputs })
}

/// The smallest input of `range` (bit patterns, below `2^32`) where
/// `holds` is false, split across the available cores.
pub(super) fn first_failure(
    range: Range<u64>,
    holds: &(impl Fn(u32) -> bool + Sync),
) -> Option<u32> {
    let threads = std::thread::available_parallelism().map_or(1, usize::from) as u64;
    let share = (range.end - range.start).div_ceil(threads);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let start = range.start + t * share;
                let end = (start + share).min(range.end);
                scope.spawn(move || {
                    (start..end)
                        .map(|bits| bits as u32)
                        .find(|&bits| !holds(bits))
                })
            })
            .collect();
        workers
            .into_iter()
            .filter_map(|worker| worker.join().expect("a checking thread panicked"))
            .min()
    })
}
