//! The verification lab of `micromap-index` (not published): everything that
//! checks the library rather than being it.
//!
//! * [`prove`]: the face-by-face proof that the walk equals the reference
//!   on every face of a level's lattice ([`lattice`]).
//! * [`vectors`]: the conformance vectors' generator, and the format,
//!   reader and checker of `micromap-index-conformance` re-exported.
//! * [`eval`] and [`value`]: the engine and value syntax of the CLI's `eval`
//!   (`micromap-index-conformance`'s, re-exported for the lab's users).
//! * [`fuzzing`] (feature `fuzzing`): the bodies of the fuzz targets.
//! * [`rng`]: the deterministic generator every sampled check uses.
//! * [`succinct_maps`]: the micromaps of the succinct-tree tests, size
//!   example and benchmark.
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// The checking functions panic on a disagreement by design: that is how a
// fuzz target or a test reports it.
#![allow(clippy::missing_panics_doc)]

pub use micromap_index_conformance::eval;
pub mod entry_points;
#[cfg(feature = "fuzzing")]
pub mod fuzzing;
pub mod lattice;
pub mod prove;
pub mod prove_all_levels;
pub mod rng;
pub mod succinct_maps;
pub mod uv_transform_oracle;
pub use micromap_index_conformance::value;
pub mod vectors;
