//! Conformance vectors: deterministic test cases for other implementations
//! of the mapping (GPU drivers, shaders, emulation layers, ports), a reader
//! for the files and for another implementation's answers, and the check
//! that compares them.
//!
//! # The sets
//!
//! One [`VectorFile`] per [`VectorSet`] (written by the lab's generator,
//! `micromap-lab vectors --out`, committed in `reference/vectors/`):
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
//! Every set covers every level [`LEVELS`]: all lattice faces up to level 3,
//! sampled cells above. Each case carries tags naming its classes (see
//! [`tag`]); `docs/vectors.md` has the schema.
//!
//! ```
//! use micromap_index_conformance::vectors::{check, parse_answers, parse_vector_file};
//!
//! let file = br#"{"format": "micromap-index-vectors", "version": 1, "function": "spec-f32",
//!   "description": "", "cases": [
//!   {"id": 7, "u": "0x3e800000", "v": "0x3e800000", "level": 2, "index": 5, "tags": ["vertex"]}]}"#;
//! let vectors = parse_vector_file(file).unwrap();
//! assert!(check(&vectors, &parse_answers(b"{\"id\": 7, \"index\": 5}").unwrap()).passed());
//! assert!(!check(&vectors, &parse_answers(b"{\"id\": 7, \"index\": 4}").unwrap()).passed());
//! ```

mod answers;
mod check;
mod classify;
mod format;
mod read;
mod report;
pub mod tag;

pub use answers::{Answer, Answers};
pub use check::{
    check, check_reader, check_selected, is_known_tag, CheckReport, Checker, Mismatch, Selection,
    Tally, MAX_LISTED_IDS,
};
pub use classify::{classify, micro_triangle_contains, place_of, MismatchClass, Place};
pub use format::{exact_of_f32, f32_text, rational_text, Case, VectorFile, VectorSet};
pub use read::{parse_answers, parse_vector_file, read_vector_file, VectorError, VectorHeader};
pub use report::exact_form;

/// The `format` field of every vector file.
pub const FORMAT: &str = "micromap-index-vectors";
/// The `version` field this crate writes and reads.
pub const VERSION: u64 = 1;
/// The levels every set covers.
pub const LEVELS: std::ops::RangeInclusive<u32> = 0..=16;
