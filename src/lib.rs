//! Barycentric coordinates → opacity-micromap micro-triangle index.
//!
//! A ray hit reports barycentrics `(u, v)` (the weights of vertices 1 and 2;
//! `w = 1 - u - v` weighs vertex 0). An opacity micromap of subdivision level
//! `n` splits the triangle into `4^n` micro-triangles stored in the order of a
//! space-filling curve; this crate maps `(u, v, n)` to the position of the
//! micro-triangle on that curve, exactly as the Vulkan specification's
//! reference code `BarycentricsToSpaceFillingCurveIndex` does.
//!
//! ```
//! use micromap_index::SpecLevel;
//!
//! let level = SpecLevel::new(3)?;
//! // What a GPU's micromap lookup reads for the hit (0.28, 0.4).
//! assert_eq!(micromap_index::index(0.28, 0.4, level), 23);
//! # Ok::<(), micromap_index::Error>(())
//! ```
//!
//! # Implementations
//!
//! Sibling functions compute the same mapping in different ways; the name
//! says the guarantee, and each module states its guarantees in its docs.
//!
//! | function | numbers | levels | guarantee |
//! |---|---|---|---|
//! | [`index`] = [`spec::index_f32`] | binary32 | 0..=16 | bit for bit the Vulkan reference on a GPU, for every pair of `f32` including NaN, ±inf, subnormals and points outside the triangle (checked against the C reference) |
//! | [`spec::index_f32_by_integers`] | integers | 0..=16 | the same bits as [`spec::index_f32`], with integer operations only |
//! | [`spec::reference_bits_f32`] | binary32 | any `u32` | the reference's C code literally, including its wrong answers above 16 and `level % 32` |
//! | `spec::index_real` (`exact`), [`spec::index_dyadic`] | exact | 0..=16 | the reference's steps over the reals; differs from binary32 only where `uf + vf` is in `[1 - 2^-25, 1)` |
//! | [`spec::wide_index_f32`], `spec::wide_index_real` (`exact`), [`spec::wide_index_dyadic`] | binary32 / exact | 0..=32 | the reference widened to 64-bit words (the 32-bit original is wrong above 16) |
//! | [`uv2index::exact_index_f32`], [`uv2index::exact_index_f64`] | integers | 0..=32 | the paper's walk over the reals, for every finite float point; equal to the reference's real reading at every real point of levels 0..=16 (proved face by face) |
//! | `uv2index::index_real` (`exact`) | exact rationals | 0..=32 | the paper's walk (Algorithm 4) over the reals, for rational points |
//! | [`uv2index::index_in_f32_arithmetic`], [`uv2index::index_in_f64_arithmetic`] | binary32 / binary64 | 0..=32 | the walk evaluated in that float type as the talk's Python reads; **not** exact near lattice lines (`docs/float.md`) |
//! | [`uv2index::index`], [`uv2index::index_unchecked`] | any [`num::WalkNumber`] | 0..=32 | the walk written once, generic over the number type |
//! | [`batch::index_f32`], [`batch::wide_index_f32`] | binary32 slices | 0..=16 / 0..=32 | [`spec::index_f32`] / [`spec::wide_index_f32`] bit for bit on every element, branch-free over slices, with AVX2 / AVX-512 picked at run time ([`batch::Backend`]) |
//! | [`inverse::micro_triangle`] | integers | 0..=32 | the inverse: index → the micro-triangle's exact vertices in constant time; the walk maps every point inside it back to the index |
//! | [`inverse::micro_triangles`] | integers | 0..=32 | every micro-triangle of a level in curve order, each equal to [`inverse::micro_triangle`] of its index |
//!
//! # Validation, one convention
//!
//! Levels are validated once, by their type: [`Level`] (`0..=32`) for the
//! walk and the widened reference, [`SpecLevel`] (`0..=16`) for the 32-bit
//! reference. Functions that can reject a point (NaN, infinite, outside the
//! closed triangle) return `Result<_, Error>`; those that accept every input
//! return the index directly and say in their docs what they do with every
//! input; `_unchecked` marks the one that validates nothing.
//!
//! # Crate features
//!
//! * `std` (default): implies `alloc`; run-time CPU feature detection, so
//!   that [`batch`] can pick its AVX2 / AVX-512 backends on x86-64 (without
//!   `std` it runs the portable backend). The error types implement
//!   `core::error::Error` either way.
//! * `alloc`: micromap containers, the succinct trees and the exact baker
//!   (module `bake`) (they own buffers).
//! * `exact`: exact rational inputs (`spec::index_real`,
//!   `uv2index::index_real`, `inverse::MicroTriangle::vertices_rational`, ...)
//!   through `num-bigint` and `num-rational`; implies `std`.
//! * `rayon`: the mesh bake (`bake::mesh`) on several threads
//!   (`MeshOptions::threads`), through `rayon`; the bytes are the serial
//!   bake's. Implies `std`.
//! * `unstable-public-internals`: the test oracles the verification crate
//!   needs (module `internals`: `*_ref` twins, the talk's version 1 walk, the
//!   rounding-window predicate, the kernel's generic steps and, on x86-64,
//!   a probe of the SIMD lanes). Not covered by semver.
//!
//! With `default-features = false` the crate is `no_std`, allocation-free and
//! dependency-free: the reference in binary32, by integers and on dyadics, the
//! generic walk with fixed point, the exact-for-every-float walk, the batch
//! API (portable backend; AVX2 / AVX-512 dispatch needs `std` for CPU
//! feature detection) and the inverse.
#![cfg_attr(not(feature = "std"), no_std)]
// `deny` (also the workspace lint), not `forbid`: `arch::x86_64`
// (runtime-dispatched SIMD and `popcnt`) is the one module allowed
// `unsafe`, to call `#[target_feature]` functions behind CPU feature checks.
#![deny(unsafe_code)]
#![deny(missing_docs)]

#[cfg(feature = "alloc")]
extern crate alloc;

/// Declares a function `pub` with the `unstable-public-internals` feature
/// (so [`internals`] can re-export it) and `pub(crate)` without it: test
/// oracles are never stable API.
macro_rules! unstable_pub_fn {
    ($(#[$meta:meta])* fn $($rest:tt)*) => {
        #[cfg(feature = "unstable-public-internals")]
        $(#[$meta])*
        pub fn $($rest)*
        #[cfg(not(feature = "unstable-public-internals"))]
        $(#[$meta])*
        #[allow(dead_code)]
        pub(crate) fn $($rest)*
    };
}

// The README's Rust example is compiled and run as a doc-test.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
mod readme {}

mod arch;
#[cfg(feature = "alloc")]
pub mod bake;
pub mod batch;
mod error;
pub mod inverse;
mod kernel;
mod level;
pub mod micromap;
pub mod names;
pub mod num;
pub mod spec;
#[cfg(feature = "alloc")]
pub mod succinct;
pub mod uv2index;

pub use error::{Coordinate, Error, Outside};
pub use level::{Level, SpecLevel};

/// The micro-triangle index a GPU reads for the ray hit `(u, v)` at
/// `level`: the Vulkan reference in binary32, bit for bit, for every pair of
/// `f32` ([`spec::index_f32`]; NaN and values outside `[0, 1]` are clamped as
/// the reference does, points past the hypotenuse are folded back).
///
/// ```
/// use micromap_index::SpecLevel;
/// let level = SpecLevel::new(2)?;
/// assert_eq!(micromap_index::index(0.3, 0.3, level), 5);
/// assert_eq!(micromap_index::index(f32::NAN, 1.0, level), 15);
/// # Ok::<(), micromap_index::Error>(())
/// ```
#[inline]
#[must_use]
pub fn index(u: f32, v: f32, level: SpecLevel) -> u32 {
    spec::index_f32(u, v, level)
}

/// Test oracles for the verification crate: slow `*_ref` twins, the talk's
/// version 1 walk and the binary32 rounding-window predicate. Enabled by the
/// `unstable-public-internals` feature; **not** part of the stable API.
#[cfg(feature = "unstable-public-internals")]
pub mod internals {
    pub use crate::inverse::micro_triangle_ref;
    pub use crate::spec::{clamp_unit, rounding_flips_diagonal, truncate_scaled};
    /// The reference's integer half and dyadic diagonal test, generic over
    /// the word, for the lab's symbolic derivation of the reference
    /// transducer (`docs/verification.md`, section 10.3).
    pub use crate::spec::{
        dyadic_cell, fractions_reach_one, reference_cell, reference_digits, CoordinateWord,
        ReferenceWord, NARROW_INTERLEAVE, NARROW_PREFIX_XOR, WIDE_INTERLEAVE, WIDE_PREFIX_XOR,
    };
    pub use crate::uv2index::index_version1_unchecked;
    /// The kernel's integer half and interleave, generic over the lane
    /// word, for the lab's bit-level proof that they equal the reference's
    /// at every level (`docs/verification.md`, section 10.12).
    pub mod kernel {
        pub use crate::kernel::coordinate::{
            binary32_coordinate, binary32_unit_coordinate, clamp_binary32,
        };
        /// The chunked pipeline's buffers, for [`lanes`](super::lanes).
        pub use crate::kernel::pipeline::{Cells, Halves, CHUNK};
        pub use crate::kernel::point::{clamp_flushed, truncate_float, BELOW_ONE};
        pub use crate::kernel::word::{
            interleave_16, interleave_32, narrow_lane, narrow_point, wide_lane, wide_point,
            LaneWord,
        };
    }
    /// The x86-64 SIMD lanes (SSE2, AVX2, AVX-512) run step by step, for
    /// the lab's proof that they compute what the proved kernel computes
    /// (`docs/verification.md`, section 10.12): safe wrappers that exist
    /// only for a backend this CPU runs.
    #[cfg(target_arch = "x86_64")]
    pub mod lanes {
        pub use crate::arch::x86_64::probe::{LaneProbe, Step, BLOCK};
    }
    pub use crate::uv2index::{
        binary64_clamped_coordinate, binary64_coordinate, binary64_diagonal, cell_real_f32,
        cell_real_f64, exact_index_f32_ref, exact_index_f64_ref,
    };

    /// One step of the talk's version 1 walk: fixed digits, the Top child
    /// re-oriented by rotating the coordinates; the flags stay untouched.
    pub fn step_version1<T: crate::num::WalkNumber>(walk: &mut crate::uv2index::Walk<T>) -> u8 {
        walk.step_version1()
    }

    #[cfg(feature = "exact")]
    pub use crate::num::rational::{
        over_common_denominator, BigShared, Numerator, Shared, SmallRational,
    };
    #[cfg(feature = "exact")]
    pub use crate::spec::cell_real_ref;
    #[cfg(feature = "exact")]
    pub use crate::uv2index::index_real_ref;
}
