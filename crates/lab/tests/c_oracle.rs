//! `spec::reference_bits_f32` and `spec::reference_bits_f32_by_integers` (integers only), and at
//! levels `0..=16` the kernel-based `spec::index_f32` and `batch::index_f32_one`, against
//! the Vulkan reference compiled from C
//! (`reference/c/spec_reference.c`, via the `micromap-index-c-reference`
//! dev-dependency): bit-exact on structured edge cases, on pairs straddling
//! the binary32 rounding window of the diagonal test, and on pseudo-random
//! pairs, at every level `0..=31` (and a few above, taken modulo 32).
//!
//! Every input is deterministic. Each test prints how many inputs it compared
//! (to stderr, uncaptured, so the count shows in CI logs).

use micromap_index::internals::rounding_flips_diagonal;
use micromap_index::spec::{reference_bits_f32, reference_bits_f32_by_integers};
use micromap_index::{batch, spec, SpecLevel};
use micromap_index_c_reference::spec_index;
use micromap_index_test_support::{edge_values, step_ulps, window_partner, SplitMix64};
use std::io::Write;

/// The levels every pair is checked at.
const LEVELS: std::ops::RangeInclusive<u32> = 0..=31;

/// Levels past 31: both sides shift by `level % 32`.
const HIGH_LEVELS: [u32; 6] = [32, 33, 47, 63, 1000, u32::MAX];

/// Mismatches printed in full before the test gives up listing them.
const MAX_REPORTED: usize = 20;

/// The reference's quantisation of one coordinate, for choosing inputs (the
/// comparison never uses it): the clamped `x * 2^level`, its truncation and
/// its fraction, for `level <= 31`.
fn quantize(x: f32, level: u32) -> (u32, f32) {
    // max/min rather than f32::clamp, which keeps NaN: the reference maps it to 0.
    #[allow(clippy::manual_clamp)]
    let scaled = x.max(0.0).min(1.0) * (1u32 << level) as f32;
    let cell = scaled as u32;
    (cell, scaled - cell as f32)
}

/// Drawing helpers on the crate's fixed-seed `SplitMix64`, so every run checks
/// the same inputs.
trait Draw {
    fn coordinate(&mut self) -> f32;
}

impl Draw for SplitMix64 {
    /// One coordinate, drawn from a mix of distributions so that both the
    /// whole `f32` space and the interesting part of it get samples.
    fn coordinate(&mut self) -> f32 {
        let r = self.next_u64();
        let low = r as u32;
        match r >> 61 {
            // Any bit pattern: NaNs, infinities, subnormals, negatives, huge.
            0 => f32::from_bits(low),
            // Any f32 in [0, 1], spread evenly over bit patterns (binades).
            1 | 2 => f32::from_bits(low % 0x3f80_0001),
            // A point of the 2^-24 grid in [0, 1): uniform in value.
            3 | 4 => (low >> 8) as f32 / 16_777_216.0,
            // A coarse dyadic: lands on low-level grid lines and vertices.
            5 => ((low >> 16) & 0x3ff) as f32 / 1024.0,
            // Slightly outside [0, 1].
            _ => (low >> 8) as f32 / 16_777_216.0 * 1.5 - 0.25,
        }
    }
}

/// Compares the port with the C reference and keeps count.
struct Oracle {
    name: &'static str,
    compared: u64,
    mismatches: u64,
    first: Vec<String>,
}

impl Oracle {
    fn new(name: &'static str) -> Self {
        Oracle {
            name,
            compared: 0,
            mismatches: 0,
            first: Vec::new(),
        }
    }

    fn check(&mut self, u: f32, v: f32, level: u32) {
        self.compared += 1;
        let port = reference_bits_f32(u, v, level);
        let mirror = reference_bits_f32_by_integers(u, v, level);
        let reference = spec_index(u, v, level);
        // The kernel's entry points take a validated level.
        let (kernel, one) = match SpecLevel::new(level) {
            Ok(valid) => (
                spec::index_f32(u, v, valid),
                batch::index_f32_one(u, v, valid),
            ),
            Err(_) => (reference, reference),
        };
        if port != reference || mirror != reference || kernel != reference || one != reference {
            self.mismatches += 1;
            if self.first.len() < MAX_REPORTED {
                self.first.push(format!(
                    "u = {:#010x} ({u:e}), v = {:#010x} ({v:e}), level = {level}: \
                     Rust reference_bits_f32 = {port}, reference_bits_f32_by_integers = {mirror}, \
                     index_f32 = {kernel}, index_f32_one = {one}, C reference = {reference}",
                    u.to_bits(),
                    v.to_bits(),
                ));
            }
        }
    }

    /// Prints the count (and any mismatches) and fails on a mismatch.
    fn finish(self, detail: &str) {
        // libtest captures `eprintln!` of passing tests; the count should
        // show in every run's log, so write to the stream directly.
        let _ = writeln!(
            std::io::stderr(),
            "c_oracle {}: compared {} inputs{detail}",
            self.name,
            self.compared
        );
        for line in &self.first {
            let _ = writeln!(std::io::stderr(), "MISMATCH {line}");
        }
        assert_eq!(
            self.mismatches,
            0,
            "{}: {} of {} inputs differ from the C reference; first: {}",
            self.name,
            self.mismatches,
            self.compared,
            self.first.first().map_or("", String::as_str)
        );
    }
}

/// Every ordered pair of edge values at every level.
#[test]
fn edge_value_pairs_at_every_level() {
    let values = edge_values();
    let mut oracle = Oracle::new("edge pairs");
    for &u in &values {
        for &v in &values {
            for level in LEVELS {
                oracle.check(u, v, level);
            }
        }
    }
    oracle.finish(&format!(
        " ({} edge values squared, levels 0..=31)",
        values.len()
    ));
}

/// Levels of 32 and more, where the C `1u << level` would be undefined.
#[test]
fn edge_value_pairs_at_levels_past_31() {
    let values = edge_values();
    let mut oracle = Oracle::new("levels past 31");
    for &u in &values {
        for &v in &values {
            for level in HIGH_LEVELS {
                oracle.check(u, v, level);
            }
        }
    }
    oracle.finish(&format!(" (levels {HIGH_LEVELS:?})"));
}

/// Pairs whose scaled fractions `uf`, `vf` sum to within a few ulps of 1:
/// the binary32 sum in `uf + vf >= 1` rounds `[1 - 2^-25, 1)` up to 1, see
/// `spec::diagonal_decision_f32`. For a given `u`, `v` is aimed at the exact
/// complement of `uf` in a chosen row and moved up to 4 ulps either way.
#[test]
fn pairs_around_the_diagonal_rounding_window() {
    let mut rng = SplitMix64::new(0x0d1a_6011_a1d0_2024);
    let mut us: Vec<f32> = edge_values()
        .into_iter()
        .filter(|x| (0.0..=1.0).contains(x))
        .collect();
    us.extend((0..2000).map(|_| (rng.next_u64() >> 40) as f32 / 16_777_216.0));

    let mut oracle = Oracle::new("diagonal window");
    let mut flipped = 0u64;
    for level in LEVELS {
        let cells = 1u64 << level;
        for &u in &us {
            let (iu, uf) = quantize(u, level);
            let iu = u64::from(iu).min(cells - 1);
            let rows = [
                0,
                1,
                2,
                cells / 2,
                cells - 1 - iu,
                (cells - 1 - iu).saturating_sub(1),
            ];
            for iv in rows.into_iter().filter(|&iv| iv < cells) {
                // Near the complement of `uf` (f64 then f32 may round it):
                // the ulp steps below cover the window either way.
                let aim = window_partner(uf, iv, level);
                for steps in -4..=4 {
                    let v = step_ulps(aim, steps);
                    let (_, vf) = quantize(v, level);
                    if rounding_flips_diagonal(uf, vf) {
                        flipped += 1;
                    }
                    oracle.check(u, v, level);
                    oracle.check(v, u, level);
                }
            }
        }
    }
    assert!(flipped > 0, "no pair landed in the rounding window");
    oracle.finish(&format!(
        " ({flipped} pairs where binary32 rounding decides the diagonal)"
    ));
}

/// Pseudo-random pairs (fixed seed), each at every level.
#[test]
fn pseudo_random_pairs_at_every_level() {
    const PAIRS: u32 = 1_000_000;
    let mut rng = SplitMix64::new(0x5eed_0000_c0de_0001);
    let mut oracle = Oracle::new("pseudo-random");
    for _ in 0..PAIRS {
        let u = rng.coordinate();
        let v = rng.coordinate();
        for level in LEVELS {
            oracle.check(u, v, level);
        }
    }
    oracle.finish(&format!(" ({PAIRS} pairs, levels 0..=31)"));
}
