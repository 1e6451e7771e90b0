//! The test support of `micromap-index` (not published, no dependencies):
//! the one pseudo-random generator and the input generators that the
//! library's tests, the lab, its tests, benches and examples and the CLI's
//! tests share.
//!
//! * [`SplitMix64`]: the deterministic generator behind every sampled set,
//!   the committed conformance vectors included (so its sequence is fixed:
//!   changing it changes `reference/vectors/`).
//! * [`step_ulps`] and [`step_ulps_f64`]: a value moved by a number of ulps.
//! * [`edge_values`]: the structured `f32` inputs of the index functions
//!   (NaN payloads, zeros, infinities, subnormals, lattice lines of every
//!   level and their neighbours).
//! * [`window_fractions`] and [`window_partner`]: scaled fractions whose sum
//!   lies just below 1, where binary32 rounding decides the reference's
//!   diagonal test.
//!
//! ```
//! use micromap_index_test_support::{edge_values, step_ulps, SplitMix64};
//! let mut rng = SplitMix64::new(0);
//! assert_eq!(rng.next_u64(), 0xe220_a839_7b1d_cdaf);
//! assert_eq!(step_ulps(1.0, -1), 1.0 - f32::EPSILON / 2.0);
//! assert!(edge_values().iter().any(|x| x.is_nan()));
//! ```
#![forbid(unsafe_code)]

/// `SplitMix64` (Steele, Lea and Flood, 2014): a 64-bit state advanced by the
/// golden-ratio increment and finished with a mixing function. A well-known
/// algorithm, so the streams depend on no crate's random-number
/// implementation and anyone can regenerate them.
///
/// ```
/// use micromap_index_test_support::SplitMix64;
/// let mut rng = SplitMix64::new(0);
/// assert_eq!(rng.next_u64(), 0xe220_a839_7b1d_cdaf);
/// assert!(rng.below(10) < 10);
/// assert_eq!(rng.pick(&[7, 7]), 7);
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A generator whose state starts at `seed`.
    #[must_use]
    pub const fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A value in `0..n` (by remainder: the bias is below `n / 2^64`); 0 when
    /// `n` is 0.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64().checked_rem(n).unwrap_or(0)
    }

    /// A value in `0..=max`.
    pub fn up_to(&mut self, max: u64) -> u64 {
        match max.checked_add(1) {
            Some(count) => self.next_u64() % count,
            None => self.next_u64(),
        }
    }

    /// One of `items`, uniformly (by [`below`](Self::below)).
    ///
    /// # Panics
    ///
    /// If `items` is empty.
    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len() as u64) as usize]
    }
}

/// `x` moved by `steps` bit patterns: by `steps` ulps for finite `x >= 0`,
/// never below `+0` (a step down from `+0` stays there). Negative values
/// move away from zero for positive `steps`.
///
/// ```
/// use micromap_index_test_support::step_ulps;
/// assert_eq!(step_ulps(0.5, 1), 0.5 + f32::EPSILON / 2.0);
/// assert_eq!(step_ulps(0.0, -3).to_bits(), 0);
/// assert_eq!(step_ulps(0.0, 1), f32::from_bits(1));
/// ```
#[must_use]
pub fn step_ulps(x: f32, steps: i32) -> f32 {
    let bits = i64::from(x.to_bits()) + i64::from(steps);
    f32::from_bits(bits.clamp(0, i64::from(u32::MAX)) as u32)
}

/// [`step_ulps`] for `f64`: `x` moved by `steps` bit patterns, never below
/// `+0`.
///
/// ```
/// use micromap_index_test_support::step_ulps_f64;
/// assert_eq!(step_ulps_f64(1.0, 1), 1.0 + f64::EPSILON);
/// assert_eq!(step_ulps_f64(0.0, -1).to_bits(), 0);
/// ```
#[must_use]
pub fn step_ulps_f64(x: f64, steps: i64) -> f64 {
    let bits = i128::from(x.to_bits()) + i128::from(steps);
    f64::from_bits(bits.clamp(0, i128::from(u64::MAX)) as u64)
}

/// Structured `f32` inputs for the index functions: the values where their
/// clamp, quantisation or truncation changes behaviour, and their
/// neighbours.
///
/// * NaN with several payloads, quiet and signalling, both signs;
/// * ±0, ±inf, the smallest and largest subnormals, `f32::MIN_POSITIVE`,
///   `f32::MAX`, `f32::EPSILON`;
/// * a few non-dyadic fractions, values above 1, huge values, and the
///   negation of each;
/// * for every `m` in `0..=26`, dyadics `k / 2^m` with a spread of `k`
///   (1, 3, 5, 7, around `2^(m-1)`, `2^m - 3`, `2^m - 1`, `2^m`,
///   `2^m + 1` just above 1, one scrambled odd `k`), each with its
///   neighbours 1 and 2 ulps below and above, and its negation: the grid
///   lines of every level up to 26, including 1/2 and 1.
///
/// Sorted by bit pattern, without duplicates.
///
/// ```
/// use micromap_index_test_support::{edge_values, step_ulps};
/// let values = edge_values();
/// let has = |x: f32| values.iter().any(|y| y.to_bits() == x.to_bits());
/// assert!(has(-0.0) && has(f32::from_bits(1)) && has(step_ulps(0.75, -2)));
/// ```
#[must_use]
pub fn edge_values() -> Vec<f32> {
    let mut values: Vec<f32> = [
        0x7fc0_0000u32, // the default quiet NaN
        0xffc0_0000,    // ... negative
        0x7fc0_0001,    // quiet, payload 1
        0xffc0_1234,    // ... negative, another payload
        0x7fff_ffff,    // quiet, all payload bits
        0xffff_ffff,    // ... negative
        0x7f80_0001,    // signalling, payload 1
        0xff80_0001,    // ... negative
        0x7fa5_a5a5,    // signalling, mixed payload
        0x0000_0002,    // the second subnormal
        0x0040_0000,    // a subnormal in the middle
    ]
    .into_iter()
    .map(f32::from_bits)
    .collect();

    let magnitudes = [
        0.0,
        f32::INFINITY,
        f32::from_bits(1),           // smallest subnormal
        f32::from_bits(0x007f_ffff), // largest subnormal
        f32::MIN_POSITIVE,
        f32::MAX,
        f32::EPSILON,
        0.1,
        1.0 / 3.0,
        2.0 / 3.0,
        0.9,
        1.5,
        2.0,
        3.0,
        1e3,
        16_777_216.0,    // 2^24: above it f32 has no fractions
        2_147_483_648.0, // 2^31
        4_294_967_296.0, // 2^32: would not fit the reference's uint32_t
        1e10,
        1e-30,
        1e30,
    ];
    for x in magnitudes {
        values.extend([x, -x]);
    }

    for m in 0..=26u32 {
        let n = 1u64 << m;
        let ks = [
            1,
            3,
            5,
            7,
            (n / 2).saturating_sub(1),
            n / 2 + 1,
            n.saturating_sub(3),
            n - 1,
            n,
            n + 1,
            (0x9e37_79b9 % n) | 1,
        ];
        for k in ks.into_iter().filter(|&k| k > 0 && k <= n + 1) {
            let x = (k as f64 / n as f64) as f32;
            values.extend((-2..=2).map(|steps| step_ulps(x, steps)));
            values.push(-x);
        }
    }

    values.sort_unstable_by_key(|x| x.to_bits());
    values.dedup_by_key(|x| x.to_bits());
    values
}

/// Scaled fractions `(uf, vf)` whose exact sum lies a few ulps below 1, where
/// the reference's binary32 `uf + vf >= 1` may round up (the window
/// `[1 - 2^-25, 1)`): `uf` in `[1/2, 1)` chosen by `bits`, and `vf` the exact
/// complement `1 - uf` (Sterbenz) lowered by `k % 6` ulps, so
/// `uf + vf = 1 - (k % 6) ulp(vf)`. Placed in cells of a level
/// (`(cell + fraction) / 2^level`, exact for small cells) they give points
/// where binary32 rounding decides the diagonal.
///
/// ```
/// use micromap_index_test_support::window_fractions;
/// let (uf, vf) = window_fractions(12345, 1);
/// assert!((0.5..1.0).contains(&uf));
/// let sum = f64::from(uf) + f64::from(vf);
/// assert!(sum < 1.0 && sum >= 1.0 - 2f64.powi(-25));
/// ```
#[must_use]
pub fn window_fractions(bits: u32, k: u32) -> (f32, f32) {
    let uf = f32::from_bits(0x3f00_0000 + bits % 0x80_0000);
    let vf = f32::from_bits((1.0 - uf).to_bits().saturating_sub(k % 6));
    (uf, vf)
}

/// The `v` aimed at the rounding window from a point whose scaled fraction
/// is `uf`: `(row + 1 - uf) / 2^level` (computed in binary64, then rounded to
/// binary32), whose scaled fraction in cell `row` complements `uf` to 1 up
/// to that rounding. A few [`step_ulps`] either way then cover the window
/// `[1 - 2^-25, 1)` of the reference's `uf + vf >= 1`.
///
/// ```
/// use micromap_index_test_support::window_partner;
/// assert_eq!(window_partner(0.25, 1, 2), 0.4375); // (1 + 0.75) / 4
/// ```
#[must_use]
pub fn window_partner(uf: f32, row: u64, level: u32) -> f32 {
    ((row as f64 + 1.0 - f64::from(uf)) / (1u64 << level) as f64) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_mix_64_is_the_published_sequence() {
        // The first outputs for seed 0 (the reference implementation's).
        let mut rng = SplitMix64::new(0);
        assert_eq!(
            [rng.next_u64(), rng.next_u64(), rng.next_u64()],
            [
                0xe220_a839_7b1d_cdaf,
                0x6e78_9e6a_a1b9_65f4,
                0x06c4_5d18_8009_454f
            ]
        );
        assert_eq!(SplitMix64::new(5).below(0), 0);
        assert_eq!(
            SplitMix64::new(5).up_to(u64::MAX),
            SplitMix64::new(5).next_u64()
        );
    }

    #[test]
    fn edge_values_cover_the_listed_cases() {
        let values = edge_values();
        let has = |x: f32| values.iter().any(|y| y.to_bits() == x.to_bits());
        for x in [0.0, 0.5, 1.0, f32::MIN_POSITIVE, f32::INFINITY, f32::MAX] {
            assert!(has(x) && has(-x), "{x:e}");
        }
        for x in [0.5f32, 1.0, 0.25 * 3.0, 1.0 / 16_777_216.0, 2f32.powi(-26)] {
            for steps in [-2, -1, 1, 2] {
                assert!(has(step_ulps(x, steps)), "{x:e} {steps}");
            }
        }
        assert!(has(f32::from_bits(1)) && has(-f32::from_bits(1)));
        assert!(has(f32::from_bits(0x007f_ffff)));
        let nans = values.iter().filter(|x| x.is_nan());
        assert!(nans.clone().count() >= 6 && nans.clone().any(|x| x.is_sign_negative()));
        assert!(values.windows(2).all(|w| w[0].to_bits() < w[1].to_bits()));
    }

    #[test]
    fn window_fractions_sum_to_just_below_one() {
        let mut rng = SplitMix64::new(1);
        for _ in 0..10_000 {
            let r = rng.next_u64();
            let (uf, vf) = window_fractions(r as u32, (r >> 32) as u32);
            let sum = f64::from(uf) + f64::from(vf);
            assert!((0.5..1.0).contains(&uf) && sum <= 1.0 && sum > 1.0 - 2f64.powi(-22));
        }
    }
}
