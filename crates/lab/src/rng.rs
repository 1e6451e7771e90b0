//! `SplitMix64`, the small deterministic generator behind every sampled set in
//! this crate (conformance vectors, sampled proofs) and its tests. Its one
//! home is `micromap-index-test-support`; this module re-exports it so the
//! lab's code keeps one path to it.
//!
//! ```
//! use micromap_index_test_support::SplitMix64;
//! let mut rng = SplitMix64::new(0);
//! assert_eq!(rng.next_u64(), 0xe220_a839_7b1d_cdaf);
//! assert!(rng.below(10) < 10);
//! ```

pub use micromap_index_test_support::SplitMix64;
