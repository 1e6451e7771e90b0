//! Conformance for `micromap-index` and for other implementations of the
//! opacity-micromap index (GPU drivers, shaders, emulation layers, ports).
//!
//! * [`vectors`]: the vector file format, a streaming reader for vector
//!   files and for another implementation's answer lines, and the check
//!   that compares them (what `micromap-index check` runs).
//! * [`value`]: the value syntax of coordinates (binary32 or binary64 bit
//!   patterns, exact decimals and rationals), with its limits.
//! * [`eval`]: the engine of `micromap-index eval`: one JSON line in, one
//!   answer line out, for each variant of the library's functions.
//!
//! The generator of the committed vectors (`reference/vectors/`) is in the
//! repository's unpublished lab (`micromap-lab vectors --out`).
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod eval;
pub mod value;
pub mod vectors;
