//! `SplitMix64`, the small deterministic generator behind every sampled set in
//! this crate (conformance vectors, sampled proofs) and its tests: a
//! well-known algorithm, so the streams depend on no crate's random-number
//! implementation and anyone can regenerate them.
//!
//! ```
//! use micromap_index_lab::rng::SplitMix64;
//! let mut rng = SplitMix64::new(0);
//! assert_eq!(rng.next_u64(), 0xe220_a839_7b1d_cdaf);
//! assert!(rng.below(10) < 10);
//! ```

/// `SplitMix64` (Steele, Lea and Flood, 2014): a 64-bit state advanced by the
/// golden-ratio increment and finished with a mixing function.
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
}
