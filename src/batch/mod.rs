//! The Vulkan reference over slices: many points, one level, bit-identical
//! to [`spec::index_f32`] / [`spec::wide_index_f32`] on every input.
//!
//! Ray tracers and bakers map millions of hits per frame. [`index_f32`]
//! validates the level and the slice lengths once, then runs a branch-free
//! rewrite of the reference's steps (see `src/kernel/` for the
//! derivation) over the whole slice:
//!
//! * the clamp by float comparisons, with two changes that leave the index
//!   alone: everything below the smallest normal (NaN, negatives, zeros,
//!   subnormals) becomes the smallest normal, and everything from 1 up
//!   becomes the float below 1, whose cell is the one the reference clamps
//!   1's to;
//! * the cell `trunc(x * 2^level)` and the fraction by the reference's own
//!   float operations, all exact (the truncating conversion `cvttps2dq` on
//!   x86-64, the `2^23` rounding trick in the safe code of other targets);
//! * the reference's `uf + vf >= 1.0f` as it is, in binary32;
//! * the fold, prefix XOR and interleave: the reference's integer half, in
//!   16-bit words (every value is below `2^16` at levels `0..=16`).
//!
//! The wide form (and [`index_f32_one`]) takes the cell and fraction from
//! the exponent and significand by shifts instead, and decides the rounded
//! `uf + vf >= 1.0f` exactly as `uf + vf >= 1 - 2^-25` on 31-bit
//! fractions. Every way gives the reference's bits.
//!
//! # Backends
//!
//! Both loops run in chunks of 256 points through three stages: the first
//! half, the integer half (16-bit words for levels `0..=16`, 32-bit for the
//! wide form) and the interleave. Each [`Backend`] is one instruction set
//! for the stages that differ: [`Backend::Portable`] is the target's
//! baseline (SSE2 on x86-64: the narrow first half with its truncating
//! conversion, the interleave by byte unpacks; safe code elsewhere), and on
//! x86-64 with `std`, AVX2 and AVX-512 add the interleave by byte shuffles.
//! They are picked at run time by CPU feature detection (done once and
//! cached). The integer half and the wide first half are the same safe
//! code for every backend, compiled for each.
//! [`index_f32_with`] forces a backend, for tests and benchmarks. Every
//! backend gives the same bits (`crates/lab/tests/batch.rs` stamps the
//! same tests on each).
//!
//! ```
//! use micromap_index::{batch, spec, SpecLevel};
//!
//! let level = SpecLevel::new(1)?;
//! let u = [0.1, 0.4, f32::NAN, 0.9];
//! let v = [0.1, 0.4, 2.0, 0.05];
//! let mut out = [0u32; 4];
//! batch::index_f32(&u, &v, level, &mut out)?;
//! assert_eq!(out, [0, 1, 3, 2]);
//! for i in 0..4 {
//!     assert_eq!(out[i], spec::index_f32(u[i], v[i], level));
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! [`spec::index_f32`]: crate::spec::index_f32
//! [`spec::wide_index_f32`]: crate::spec::wide_index_f32

use crate::arch::{self, Loops};
use crate::kernel;
use crate::{Level, SpecLevel};
use core::fmt;

pub use crate::arch::Backend;

/// Why a batch call wrote nothing. (Levels are validated by their types,
/// [`SpecLevel`] and [`Level`], before a call.)
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum BatchError {
    /// `u`, `v` and `out` do not all have the same length.
    LengthMismatch {
        /// `u.len()`.
        u: usize,
        /// `v.len()`.
        v: usize,
        /// `out.len()`.
        out: usize,
    },
    /// The backend asked for cannot run on this CPU (or was not built).
    BackendUnavailable(Backend),
}

impl fmt::Display for BatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BatchError::LengthMismatch { u, v, out } => write!(
                f,
                "slice lengths differ: u has {u}, v has {v}, out has {out} elements"
            ),
            BatchError::BackendUnavailable(backend) => {
                write!(f, "the {backend} backend is not available on this CPU")
            }
        }
    }
}

impl core::error::Error for BatchError {}

/// Checks the lengths, then runs `loops` on `backend`.
fn run_loop<O>(
    backend: Backend,
    u: &[f32],
    v: &[f32],
    out: &mut [O],
    params: &kernel::Params,
    loops: &Loops<O>,
) -> Result<(), BatchError> {
    if u.len() != v.len() || v.len() != out.len() {
        return Err(BatchError::LengthMismatch {
            u: u.len(),
            v: v.len(),
            out: out.len(),
        });
    }
    let ran = loops.run(backend, u, v, out, params);
    if ran {
        Ok(())
    } else {
        Err(BatchError::BackendUnavailable(backend))
    }
}

/// `out[i] = spec::index_f32(u[i], v[i], level)` for every `i`, with the
/// fastest backend this CPU has ([`Backend::best`]).
///
/// The three slices must have the same length
/// ([`BatchError::LengthMismatch`]); on an error nothing is written.
///
/// ```
/// use micromap_index::batch::{self, BatchError};
/// use micromap_index::SpecLevel;
/// let level = SpecLevel::new(2).unwrap();
/// let mut out = [0u32; 2];
/// batch::index_f32(&[0.3, 0.3], &[0.3, 0.6], level, &mut out).unwrap();
/// assert_eq!(out, [5, 12]);
/// assert_eq!(
///     batch::index_f32(&[0.3], &[0.3, 0.6], level, &mut out),
///     Err(BatchError::LengthMismatch { u: 1, v: 2, out: 2 })
/// );
/// ```
#[inline]
pub fn index_f32(
    u: &[f32],
    v: &[f32],
    level: SpecLevel,
    out: &mut [u32],
) -> Result<(), BatchError> {
    index_f32_with(Backend::best(), u, v, level, out)
}

/// [`index_f32`] on a chosen backend ([`BatchError::BackendUnavailable`] if
/// this CPU cannot run it). Every backend writes the same bits.
///
/// ```
/// use micromap_index::batch::{self, Backend};
/// use micromap_index::SpecLevel;
/// let (u, v) = ([0.28f32; 3], [0.4f32; 3]);
/// let level = SpecLevel::new(3).unwrap();
/// let mut expected = [0u32; 3];
/// batch::index_f32_with(Backend::Portable, &u, &v, level, &mut expected).unwrap();
/// for backend in Backend::available() {
///     let mut out = [0u32; 3];
///     batch::index_f32_with(backend, &u, &v, level, &mut out).unwrap();
///     assert_eq!(out, expected);
/// }
/// ```
pub fn index_f32_with(
    backend: Backend,
    u: &[f32],
    v: &[f32],
    level: SpecLevel,
    out: &mut [u32],
) -> Result<(), BatchError> {
    let params = kernel::Params::new(level.get(), kernel::BINARY32_THRESHOLD);
    run_loop(backend, u, v, out, &params, &arch::NARROW)
}

/// `out[i] = spec::wide_index_f32(u[i], v[i], level)` for every `i`: the
/// reference widened to 64-bit words in binary32, levels `0..=32`, with the
/// fastest backend this CPU has.
///
/// ```
/// use micromap_index::{batch, spec, Level};
/// let level = Level::new(24).unwrap();
/// let (u, v) = ([0.1f32, 1.0, -3.0], [0.2f32, 0.0, f32::INFINITY]);
/// let mut out = [0u64; 3];
/// batch::wide_index_f32(&u, &v, level, &mut out).unwrap();
/// for i in 0..3 {
///     assert_eq!(out[i], spec::wide_index_f32(u[i], v[i], level));
/// }
/// ```
#[inline]
pub fn wide_index_f32(
    u: &[f32],
    v: &[f32],
    level: Level,
    out: &mut [u64],
) -> Result<(), BatchError> {
    wide_index_f32_with(Backend::best(), u, v, level, out)
}

/// [`wide_index_f32`] on a chosen backend.
///
/// ```
/// use micromap_index::batch::{self, Backend};
/// use micromap_index::Level;
/// let mut out = [0u64; 1];
/// batch::wide_index_f32_with(Backend::Portable, &[1.0], &[0.0], Level::new(32).unwrap(), &mut out).unwrap();
/// assert_eq!(out[0], 2 * 0x5555_5555_5555_5555); // the Right corner, all digits 2
/// ```
pub fn wide_index_f32_with(
    backend: Backend,
    u: &[f32],
    v: &[f32],
    level: Level,
    out: &mut [u64],
) -> Result<(), BatchError> {
    let params = kernel::Params::new(level.get(), kernel::BINARY32_THRESHOLD);
    run_loop(backend, u, v, out, &params, &arch::WIDE)
}

/// The reference in binary32 for one point: the batch kernel on one lane
/// with the cell and fraction taken by shifts of the float's bits, the same
/// bits as [`spec::index_f32`](crate::spec::index_f32) (the same kernel with
/// the reference's own float steps). Infallible, so a caller's loop carries
/// no `Result`.
///
/// ```
/// use micromap_index::{batch, spec, SpecLevel};
/// let level = SpecLevel::new(2).unwrap();
/// assert_eq!(batch::index_f32_one(0.3, 0.3, level), 5);
/// assert_eq!(batch::index_f32_one(f32::NAN, 2.0, level), spec::index_f32(f32::NAN, 2.0, level));
/// ```
#[inline]
#[must_use]
pub fn index_f32_one(u: f32, v: f32, level: SpecLevel) -> u32 {
    let params = kernel::Params::new(level.get(), kernel::BINARY32_THRESHOLD);
    kernel::narrow::<{ kernel::CELL_BY_SHIFTS }>(u.to_bits(), v.to_bits(), &params)
}
