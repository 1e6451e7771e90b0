//! Conformance vectors: deterministic test cases for other implementations
//! of the mapping (GPU drivers, shaders, emulation layers, ports), a reader
//! for the files and for another implementation's answers, and the check
//! that compares them.
//!
//! # The sets
//!
//! [`generate_sets`] builds one [`VectorFile`] per [`VectorSet`]:
//!
//! * `spec-f32` — the Vulkan reference in binary32 ([`spec::index_f32`](micromap_index::spec::index_f32)):
//!   what a GPU must return. Coordinates are binary32 bit patterns
//!   (`"0x3e000000"`), including NaN, ±inf, -0, subnormals and points outside
//!   the triangle.
//! * `spec-exact` — the reference's steps over the reals
//!   ([`spec::index_real`](micromap_index::spec::index_real)). Coordinates are exact rationals `"p/q"`: the
//!   finite points of `spec-f32` (so the two sets disagree exactly on the
//!   cases tagged `rounding-window`) and the exact centroids.
//! * `uv2index-exact` — the paper's walk over the reals
//!   ([`uv2index::index_real`](micromap_index::uv2index::index_real)), only on points of the closed triangle (the
//!   walk rejects the others, so the clamping classes are left out). Every
//!   coordinate is also exactly a binary32 value, so float implementations of
//!   the walk can be run on it without rounding their input.
//!
//! Every set covers every level `0..=16`: all lattice faces up to level
//! [`ALL_FACES_MAX_LEVEL`], sampled cells above. Each case carries tags
//! naming its classes (see [`tag`]); `docs/vectors.md` has the schema.
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

mod answers;
mod check;
mod classify;
mod format;
mod generate;
mod read;
mod report;
pub mod tag;

pub use answers::{compute_answers, Answer, AnswerSource, Answers};
pub use check::{
    check, check_reader, check_selected, is_known_tag, CheckReport, Checker, Mismatch, Selection,
    Tally, MAX_LISTED_IDS,
};
pub use classify::{classify, micro_triangle_contains, place_of, MismatchClass, Place};
pub use format::{Case, VectorFile, VectorSet};
pub use generate::{generate_sets, sampled_anchors};
pub use read::{parse_answers, parse_vector_file, read_vector_file, VectorError, VectorHeader};
pub use report::exact_form;

/// The `format` field of every vector file.
pub const FORMAT: &str = "micromap-index-vectors";
/// The `version` field this crate writes and reads.
pub const VERSION: u64 = 1;
/// The levels every set covers.
pub const LEVELS: std::ops::RangeInclusive<u32> = 0..=16;
/// Up to this level every face of the lattice is in the sets; above it, the
/// faces of [`sampled_anchors`] cells.
pub const ALL_FACES_MAX_LEVEL: u32 = 3;
/// Pseudo-random anchor cells per sampled level (on top of the fixed ones).
pub const RANDOM_ANCHORS_PER_LEVEL: usize = 6;
/// Uniform random points of the triangle per level.
pub const RANDOM_POINTS_PER_LEVEL: usize = 16;
/// The seed of every pseudo-random choice (mixed with the level and class).
pub const SEED: u64 = 0x6d69_6372_6f6d_6170; // "micromap"
