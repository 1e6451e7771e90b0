//! What the CPU can run (detected at run time, with `std`), and the
//! body a `popcnt`-compiled caller runs: the pieces both the dispatch
//! (`mod.rs`) and the backends (`x86_64.rs`) use.

/// Whether this CPU runs the AVX2 backend.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
pub(super) fn has_avx2() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// Whether this CPU runs the AVX-512 backend (and this compiler built it):
/// every feature the AVX-512 functions enable.
#[cfg(all(feature = "std", target_arch = "x86_64"))]
pub(super) fn has_avx512() -> bool {
    #[cfg(micromap_avx512)]
    {
        std::arch::is_x86_feature_detected!("avx512f")
            && std::arch::is_x86_feature_detected!("avx512bw")
            && std::arch::is_x86_feature_detected!("avx512vl")
            && std::arch::is_x86_feature_detected!("avx512dq")
    }
    #[cfg(not(micromap_avx512))]
    {
        false
    }
}

/// Whether this CPU has hardware `popcnt` (not in the x86-64 baseline).
#[cfg(all(
    feature = "std",
    target_arch = "x86_64",
    not(target_feature = "popcnt")
))]
pub(super) fn has_popcnt() -> bool {
    std::arch::is_x86_feature_detected!("popcnt")
}

/// A computation that [`with_popcnt`](super::with_popcnt) runs compiled with hardware
/// `popcnt` where that helps.
///
/// Implementations must mark [`PopcntBody::run`] `#[inline(always)]`, and
/// keep everything it calls `#[inline(always)]` too: only code inlined
/// into the `#[target_feature]` function is compiled with the feature.
/// (Its one user, `succinct`, needs `alloc`.)
#[cfg(feature = "alloc")]
pub(crate) trait PopcntBody {
    /// What the computation returns.
    type Output;
    /// The computation, in safe code.
    fn run(self) -> Self::Output;
}
