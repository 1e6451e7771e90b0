//! Where the crate meets the instruction sets: the batch [`Backend`]s, CPU
//! feature detection, and every function compiled with
//! `#[target_feature]`, behind safe dispatch.
//!
//! * This file is safe code: [`Backend`] (re-exported as
//!   `batch::Backend`), the detection (`has_avx2`, `has_avx512`,
//!   `has_popcnt`, each cached by `std`), the table of each batch loop's
//!   compilations per backend ([`NARROW`], [`WIDE`], run by `batch`), and
//!   [`with_popcnt`], the one way to the `popcnt` compilation.
//! * `x86_64.rs` is the crate's only `unsafe` code (its own
//!   `#![allow(unsafe_code)]`): the SSE2, AVX2 and AVX-512 lanes and every
//!   `#[target_feature]` entry point, each called only after detecting
//!   exactly the features it enables. A lane type is built only where its
//!   features are known to be present, so holding one proves them.
//!
//! # Direction of the calls
//!
//! `arch` sits below its callers and calls none of them: it depends on
//! [`crate::kernel`] alone. `batch` and `succinct` call into it; it never
//! names them. What a `#[target_feature]` copy compiles is passed in as a
//! generic: the batch loops instantiate [`kernel::chunked`] with a lane
//! type, and the level-order tree's lookup reaches its `popcnt` copy by
//! handing [`with_popcnt`] a [`PopcntBody`], whose `#[inline(always)]`
//! [`PopcntBody::run`] (the tree's safe lookup) is compiled inside the
//! `popcnt` function. So the tree owns its code and `arch` owns the
//! features, with no circle between them.

mod features;
#[cfg(target_arch = "x86_64")]
pub(crate) mod x86_64;

#[cfg(feature = "alloc")]
pub(crate) use features::PopcntBody;

use crate::kernel;
use core::fmt;
use core::sync::atomic::{AtomicU8, Ordering};

/// One compilation of the batch loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Backend {
    /// The loop compiled for the target's baseline features (SSE2 on
    /// x86-64). Always available.
    Portable,
    /// x86-64 with AVX2 (8 lanes of 32 bits).
    Avx2,
    /// x86-64 with AVX-512 F, BW, VL and DQ (16 lanes of 32 bits). Built only
    /// by compilers that support it (Rust 1.89 and later).
    Avx512,
}

impl Backend {
    /// Every backend, available here or not, fastest last.
    pub const ALL: [Backend; 3] = [Backend::Portable, Backend::Avx2, Backend::Avx512];

    /// Whether this CPU (and this build) can run the backend.
    ///
    /// ```
    /// use micromap_index::batch::Backend;
    /// assert!(Backend::Portable.is_available());
    /// ```
    #[must_use]
    pub fn is_available(self) -> bool {
        match self {
            Backend::Portable => true,
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Backend::Avx2 => features::has_avx2(),
            #[cfg(all(feature = "std", target_arch = "x86_64"))]
            Backend::Avx512 => features::has_avx512(),
            #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
            Backend::Avx2 | Backend::Avx512 => false,
        }
    }

    /// The backends this CPU can run, in the order of [`Backend::ALL`].
    ///
    /// ```
    /// use micromap_index::batch::Backend;
    /// assert_eq!(Backend::available().next(), Some(Backend::Portable));
    /// ```
    pub fn available() -> impl Iterator<Item = Backend> {
        Backend::ALL
            .into_iter()
            .filter(|backend| backend.is_available())
    }

    /// The fastest available backend; detected on the first call and cached.
    ///
    /// ```
    /// use micromap_index::batch::Backend;
    /// assert!(Backend::best().is_available());
    /// ```
    #[must_use]
    pub fn best() -> Backend {
        static BEST: AtomicU8 = AtomicU8::new(u8::MAX);
        let cached = BEST.load(Ordering::Relaxed);
        if let Some(&backend) = Backend::ALL.get(usize::from(cached)) {
            return backend;
        }
        let best = Backend::available().last().unwrap_or(Backend::Portable);
        let position = Backend::ALL.iter().position(|&b| b == best).unwrap_or(0);
        // Racing first calls store the same value.
        BEST.store(position as u8, Ordering::Relaxed);
        best
    }

    /// A short lowercase name (`portable`, `avx2`, `avx512`).
    ///
    /// ```
    /// use micromap_index::batch::Backend;
    /// assert_eq!(Backend::Avx2.name(), "avx2");
    /// ```
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Backend::Portable => "portable",
            Backend::Avx2 => "avx2",
            Backend::Avx512 => "avx512",
        }
    }
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// One slice loop of the kernel (`out` of `O`) compiled for each backend;
/// a compilation returns `false`, writing nothing, where the CPU cannot run
/// it.
pub(crate) struct Loops<O> {
    portable: fn(&[f32], &[f32], &mut [O], &kernel::Params),
    avx2: fn(&[f32], &[f32], &mut [O], &kernel::Params) -> bool,
    avx512: fn(&[f32], &[f32], &mut [O], &kernel::Params) -> bool,
}

impl<O> Loops<O> {
    /// Runs the compilation for `backend` on slices of equal length
    /// (checked by the caller); `false`, writing nothing, where this CPU
    /// cannot run it.
    pub(crate) fn run(
        &self,
        backend: Backend,
        u: &[f32],
        v: &[f32],
        out: &mut [O],
        params: &kernel::Params,
    ) -> bool {
        match backend {
            Backend::Portable => {
                (self.portable)(u, v, out, params);
                true
            }
            Backend::Avx2 => (self.avx2)(u, v, out, params),
            Backend::Avx512 => (self.avx512)(u, v, out, params),
        }
    }
}

/// The reference in 32-bit words; the portable build takes the float cell.
pub(crate) const NARROW: Loops<u32> = Loops {
    #[cfg(target_arch = "x86_64")]
    portable: x86_64::narrow_slice_sse2,
    #[cfg(not(target_arch = "x86_64"))]
    portable: kernel::narrow_slice_portable,
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    avx2: x86_64::narrow_slice_avx2,
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    avx512: x86_64::narrow_slice_avx512,
    #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
    avx2: not_built,
    #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
    avx512: not_built,
};

/// The reference widened to 64-bit words.
pub(crate) const WIDE: Loops<u64> = Loops {
    #[cfg(target_arch = "x86_64")]
    portable: x86_64::wide_slice_sse2,
    #[cfg(not(target_arch = "x86_64"))]
    portable: kernel::wide_slice_portable,
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    avx2: x86_64::wide_slice_avx2,
    #[cfg(all(feature = "std", target_arch = "x86_64"))]
    avx512: x86_64::wide_slice_avx512,
    #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
    avx2: not_built,
    #[cfg(not(all(feature = "std", target_arch = "x86_64")))]
    avx512: not_built,
};

/// A backend this build does not have.
#[cfg(not(all(feature = "std", target_arch = "x86_64")))]
fn not_built<O>(_: &[f32], _: &[f32], _: &mut [O], _: &kernel::Params) -> bool {
    false
}

/// `body.run()`, compiled with hardware `popcnt` where the CPU has it and
/// the target's baseline does not (x86-64 with `std`, detected at run time
/// and cached), else as it is. A software popcount on a rank's critical
/// path doubles a level-order tree lookup.
#[cfg(feature = "alloc")]
#[inline]
pub(crate) fn with_popcnt<B: PopcntBody>(body: B) -> B::Output {
    #[cfg(all(
        feature = "std",
        target_arch = "x86_64",
        not(target_feature = "popcnt")
    ))]
    {
        x86_64::with_popcnt(body)
    }
    #[cfg(not(all(
        feature = "std",
        target_arch = "x86_64",
        not(target_feature = "popcnt")
    )))]
    {
        body.run()
    }
}
