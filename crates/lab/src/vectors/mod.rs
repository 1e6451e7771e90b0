//! The conformance vectors of `micromap-index-conformance` (re-exported
//! here whole), and what only the lab does with them: generate the sets
//! ([`generate_sets`], from the lattice and the lab's PRNG) and answer them
//! with this crate's own functions ([`AnswerSource`], [`compute_answers`]).
//!
//! [`generate_sets`] builds one [`VectorFile`] per [`VectorSet`]: every set
//! covers every level `0..=16`, all lattice faces up to level
//! [`ALL_FACES_MAX_LEVEL`], sampled cells above.
//!
//! ```
//! use micromap_index_lab::vectors::{check, compute_answers, generate_sets, AnswerSource};
//!
//! let sets = generate_sets();
//! let spec_f32 = &sets[0];
//! assert_eq!(spec_f32.function, "spec-f32");
//! // The fixed-point mirror of the GPU passes the binary32 set ...
//! let mirror = AnswerSource::from_name("fixed-mirror").unwrap();
//! assert!(check(spec_f32, &compute_answers(mirror, spec_f32)).passed());
//! // ... the exact reading of the reference does not: binary32 rounding.
//! let exact = AnswerSource::from_name("spec-exact").unwrap();
//! let report = check(spec_f32, &compute_answers(exact, spec_f32));
//! assert!(!report.passed());
//! assert!(report.mismatches.iter().all(|m| m.tags.iter().any(|t| t == "clamp" || t == "rounding-window")));
//! ```

pub use micromap_index_conformance::vectors::*;

mod generate;
mod sources;

pub use generate::{generate_sets, sampled_anchors};
pub use sources::{compute_answers, AnswerSource};

/// Up to this level every face of the lattice is in the sets; above it, the
/// faces of [`sampled_anchors`] cells.
pub const ALL_FACES_MAX_LEVEL: u32 = 3;
/// Pseudo-random anchor cells per sampled level (on top of the fixed ones).
pub const RANDOM_ANCHORS_PER_LEVEL: usize = 6;
/// Uniform random points of the triangle per level.
pub const RANDOM_POINTS_PER_LEVEL: usize = 16;
/// The seed of every pseudo-random choice (mixed with the level and class).
pub const SEED: u64 = 0x6d69_6372_6f6d_6170; // "micromap"
