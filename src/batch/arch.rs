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

// `unsafe fn`, not a safe `#[target_feature]` function: the latter needs
// Rust 1.86, above the crate's minimum supported version.
/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
unsafe fn narrow_avx2(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) {
    kernel::narrow_slice::<false>(u, v, out, params);
}

/// # Safety
/// The CPU must support AVX2.
#[target_feature(enable = "avx2")]
unsafe fn wide_avx2(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) {
    kernel::wide_slice(u, v, out, params);
}

#[cfg(micromap_avx512)]
/// # Safety
/// The CPU must support AVX-512 F, BW, VL and DQ.
#[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq")]
unsafe fn narrow_avx512(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) {
    kernel::narrow_slice::<false>(u, v, out, params);
}

#[cfg(micromap_avx512)]
/// # Safety
/// The CPU must support AVX-512 F, BW, VL and DQ.
#[target_feature(enable = "avx512f,avx512bw,avx512vl,avx512dq")]
unsafe fn wide_avx512(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) {
    kernel::wide_slice(u, v, out, params);
}

/// [`kernel::narrow_slice`] with AVX2; `false` (nothing written) if the CPU
/// lacks AVX2.
pub(super) fn narrow_slice_avx2(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) -> bool {
    if !has_avx2() {
        return false;
    }
    // SAFETY: `narrow_avx2`'s only requirement is AVX2, which the CPU has
    // (checked just above); its body is safe code on valid slices.
    unsafe { narrow_avx2(u, v, out, params) };
    true
}

/// [`kernel::wide_slice`] with AVX2; `false` if the CPU lacks AVX2.
pub(super) fn wide_slice_avx2(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) -> bool {
    if !has_avx2() {
        return false;
    }
    // SAFETY: as in `narrow_slice_avx2`: "avx2" was detected just above.
    unsafe { wide_avx2(u, v, out, params) };
    true
}

/// [`kernel::narrow_slice`] with AVX-512; `false` if the CPU lacks one of
/// the features or the compiler could not build the backend.
pub(super) fn narrow_slice_avx512(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) -> bool {
    #[cfg(micromap_avx512)]
    if avx512_detected!() {
        // SAFETY: every feature `narrow_avx512` enables was detected just
        // above; the function itself is safe code on valid slices.
        unsafe { narrow_avx512(u, v, out, params) };
        return true;
    }
    let _ = (u, v, out, params);
    false
}

/// [`kernel::wide_slice`] with AVX-512; `false` if unavailable.
pub(super) fn wide_slice_avx512(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) -> bool {
    #[cfg(micromap_avx512)]
    if avx512_detected!() {
        // SAFETY: every feature `wide_avx512` enables was detected just above.
        unsafe { wide_avx512(u, v, out, params) };
        return true;
    }
    let _ = (u, v, out, params);
    false
}

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
