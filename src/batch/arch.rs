//! The x86-64 backends: the safe loops of [`super::kernel`] compiled again
//! with AVX2 or AVX-512 enabled, so the compiler vectorises them 8 or 16
//! lanes wide, and the level-order tree's lookup compiled again with
//! hardware `popcnt`. This is the only module of the crate allowed `unsafe`: calling
//! a `#[target_feature]` function is `unsafe` because running it on a CPU
//! without the feature is undefined behaviour. Each call below sits behind a
//! runtime check of exactly the features its callee enables; where the check
//! fails the function returns `false` and the caller falls back to the
//! portable loop (which is the same kernel without target features).
#![allow(unsafe_code)]

use super::kernel::{self, Params};

/// The features the AVX-512 functions enable, all checked before a call.
#[cfg(micromap_avx512)]
macro_rules! avx512_detected {
    () => {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512bw")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("avx512dq")
    };
}

/// Whether this CPU runs the AVX2 backend.
pub(super) fn has_avx2() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// Whether this CPU runs the AVX-512 backend (and this compiler built it).
pub(super) fn has_avx512() -> bool {
    #[cfg(micromap_avx512)]
    {
        avx512_detected!()
    }
    #[cfg(not(micromap_avx512))]
    {
        false
    }
}

/// Stamps one kernel loop compiled with target features: an `unsafe fn`
/// with `#[target_feature]` (not a safe `#[target_feature]` function, which
/// needs Rust 1.86, above the crate's minimum supported version) and the
/// safe entry point that calls it only after detecting every feature it
/// enables, returning `false` (nothing written) otherwise.
macro_rules! feature_loop {
    (
        $(#[$cfg:meta])?
        $doc:literal, $entry:ident, $compiled:ident, $features:literal, $detected:expr,
        $out:ty, $kernel:expr
    ) => {
        $(#[$cfg])?
        /// # Safety
        /// The CPU must support every feature in the `target_feature` list.
        #[target_feature(enable = $features)]
        unsafe fn $compiled(u: &[f32], v: &[f32], out: &mut [$out], params: &Params) {
            $kernel(u, v, out, params);
        }

        #[doc = $doc]
        pub(super) fn $entry(u: &[f32], v: &[f32], out: &mut [$out], params: &Params) -> bool {
            $(#[$cfg])?
            if $detected {
                // SAFETY: every feature the compiled loop enables was
                // detected just above; its body is safe code on valid
                // slices.
                unsafe { $compiled(u, v, out, params) };
                return true;
            }
            let _ = (u, v, out, params);
            false
        }
    };
}

feature_loop!(
    "[`kernel::narrow_slice`] with AVX2; `false` if the CPU lacks AVX2.",
    narrow_slice_avx2,
    narrow_avx2,
    "avx2",
    has_avx2(),
    u32,
    kernel::narrow_slice::<{ kernel::CELL_BY_TRUNC }>
);
feature_loop!(
    "[`kernel::wide_slice`] with AVX2; `false` if the CPU lacks AVX2.",
    wide_slice_avx2,
    wide_avx2,
    "avx2",
    has_avx2(),
    u64,
    kernel::wide_slice
);
feature_loop!(
    #[cfg(micromap_avx512)]
    "[`kernel::narrow_slice`] with AVX-512; `false` if the CPU lacks one of \
     the features or the compiler could not build the backend.",
    narrow_slice_avx512,
    narrow_avx512,
    "avx512f,avx512bw,avx512vl,avx512dq",
    avx512_detected!(),
    u32,
    kernel::narrow_slice::<{ kernel::CELL_BY_TRUNC }>
);
feature_loop!(
    #[cfg(micromap_avx512)]
    "[`kernel::wide_slice`] with AVX-512; `false` if unavailable.",
    wide_slice_avx512,
    wide_avx512,
    "avx512f,avx512bw,avx512vl,avx512dq",
    avx512_detected!(),
    u64,
    kernel::wide_slice
);

/// # Safety
/// The CPU must support `popcnt`.
#[cfg(feature = "alloc")]
#[target_feature(enable = "popcnt")]
unsafe fn level_order_get_popcnt(
    tree: &crate::succinct::LevelOrderTree,
    index: u64,
) -> Option<crate::micromap::State> {
    tree.get_portable(index)
}

/// [`crate::succinct::LevelOrderTree::get`] with hardware `popcnt` where the
/// CPU has it (x86-64's baseline does not, and a software popcount on the
/// rank's critical path doubles the lookup), else the same code without.
#[cfg(feature = "alloc")]
#[inline]
pub(crate) fn level_order_get(
    tree: &crate::succinct::LevelOrderTree,
    index: u64,
) -> Option<crate::micromap::State> {
    if std::arch::is_x86_feature_detected!("popcnt") {
        // SAFETY: `level_order_get_popcnt` enables only "popcnt", detected
        // just above.
        unsafe { level_order_get_popcnt(tree, index) }
    } else {
        tree.get_portable(index)
    }
}
