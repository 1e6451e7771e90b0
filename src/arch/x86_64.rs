//! The x86-64 backends, the crate's only `unsafe` code: the chunked
//! pipeline of [`crate::kernel`] with its float first half and bit
//! interleave written with SSE2, AVX2 and AVX-512 instructions
//! ([`kernel::Lanes`]), both forms' loops compiled with AVX2 or AVX-512
//! enabled so the compiler also vectorises their safe stages for those
//! sets, and [`super::PopcntBody`]s (the level-order tree's lookup)
//! compiled again with hardware `popcnt`. Intrinsics are `unsafe` to call
//! on the crate's minimum Rust version, and calling a `#[target_feature]`
//! function is `unsafe` because running it on a CPU without the feature is
//! undefined behaviour. Each such call below sits behind a runtime check
//! (the detection in [`super`]) of exactly the features its callee
//! enables; where the check fails the function returns `false` and the
//! caller falls back to the portable loop (or runs the body without
//! `popcnt`).
//!
//! What the intrinsics add over the safe kernel: a truncating conversion
//! (`cvttps2dq`, which safe Rust's saturating casts cannot use directly),
//! packing the cells into 16-bit words for the integer half, and, with
//! AVX2 and AVX-512, the interleave by byte shuffles (`pshufb` as a 16-entry
//! table that spreads a nibble to the even bits of a byte) instead of
//! twelve shifts and masks per word.
#![allow(unsafe_code)]

#[cfg(feature = "std")]
use super::features::has_avx2;
#[cfg(all(feature = "std", micromap_avx512))]
use super::features::has_avx512;
#[cfg(all(feature = "std", not(target_feature = "popcnt")))]
use super::features::{has_popcnt, PopcntBody};
use crate::kernel::{self, Cells, Halves, Lanes, Narrow, Params, Wide, CHUNK};

/// # Safety
/// The CPU must support `popcnt`.
#[cfg(all(feature = "std", not(target_feature = "popcnt")))]
#[target_feature(enable = "popcnt")]
unsafe fn run_popcnt<B: PopcntBody>(body: B) -> B::Output {
    // `run` is `#[inline(always)]` (the trait's contract): its body is
    // compiled here, with `popcnt`.
    body.run()
}

/// [`super::with_popcnt`] on x86-64: `body` compiled with hardware
/// `popcnt` where the CPU has it, else the same code without.
#[cfg(all(feature = "std", not(target_feature = "popcnt")))]
#[inline]
pub(super) fn with_popcnt<B: PopcntBody>(body: B) -> B::Output {
    if has_popcnt() {
        // SAFETY: `run_popcnt` enables only "popcnt", detected just above;
        // its body is the safe code of `body`.
        unsafe { run_popcnt(body) }
    } else {
        body.run()
    }
}

/// Stamps a [`Lanes`] for one instruction set from one body: `$ops` names
/// the set's intrinsics under common names, and `interleave` is either
/// `shuffle` (byte shuffles, SSSE3 and up: a nibble table) or `unpack`
/// (SSE2, which has no byte shuffle: the perfect shuffle of each 16-bit
/// word by shifts and masks).
///
/// The cells are packed to 16 bits per 128-bit lane (a pack of two vectors
/// puts lane `l`'s four points of the first before its four of the second),
/// and the shuffle interleave unpacks per 128-bit lane, which restores the
/// order: the low halves of every lane are the first vector's points, the
/// high halves the second's (with 128-bit vectors, SSE2, that is plain
/// order).
///
/// The type's field is private and the type is built only where its
/// features are known to be present: SSE2 is the x86-64 baseline, and the
/// others are built only inside the `#[target_feature]` loop that
/// `feature_loop!` calls after detecting them. Holding one proves the CPU
/// has the features, which is what makes its safe methods sound.
macro_rules! simd_lanes {
    ($(#[$attr:meta])* $name:ident, $ops:ident, interleave: $interleave:ident) => {
        $(#[$attr])*
        pub(crate) struct $name(());

        $(#[$attr])*
        impl Lanes for $name {
            #[inline(always)]
            fn cells(&self, u: &[f32; CHUNK], v: &[f32; CHUNK], params: &Params, cells: &mut Cells<u16>) {
                use $ops::*;
                /// The cells of the `LANES` points from `at` (32-bit lanes)
                /// and their diagonal outcomes as 0 or 1.
                #[inline(always)]
                unsafe fn coordinates(
                    (u, v, at): (&[f32; CHUNK], &[f32; CHUNK], usize),
                    (floor, below_one, scale): (Ps, Ps, Ps),
                ) -> (Si, Si, Si) {
                    // (No closures in these bodies: a closure would not
                    // inherit the target features on every supported
                    // compiler, and its intrinsics would not inline.)
                    let (x, y) = (loadu_ps(u.as_ptr().add(at)), loadu_ps(v.as_ptr().add(at)));
                    let fu = mul_ps(min_ps(max_ps(x, floor), below_one), scale);
                    let fv = mul_ps(min_ps(max_ps(y, floor), below_one), scale);
                    let (iu, iv) = (cvttps_epi32(fu), cvttps_epi32(fv));
                    let sum = add_ps(sub_ps(fu, cvtepi32_ps(iu)), sub_ps(fv, cvtepi32_ps(iv)));
                    // The sum is below 2: its truncation is the diagonal test.
                    (iu, iv, cvttps_epi32(sum))
                }
                // SAFETY: `self` exists only where the CPU has the
                // features (see the type); the loads of LANES f32 and the
                // stores of 2 * LANES u16 stay inside the chunk's arrays
                // (CHUNK is a multiple of 2 * LANES, every offset plus its
                // width at most CHUNK).
                unsafe {
                    let limits = (set1_ps(f32::MIN_POSITIVE), set1_ps(kernel::BELOW_ONE), set1_ps(params.scale));
                    let mut k = 0;
                    while k < CHUNK {
                        let (iu0, iv0, d0) = coordinates((u, v, k), limits);
                        let (iu1, iv1, d1) = coordinates((u, v, k + LANES), limits);
                        storeu_si(cells.iu.as_mut_ptr().add(k).cast(), pack_u16(iu0, iu1));
                        storeu_si(cells.iv.as_mut_ptr().add(k).cast(), pack_u16(iv0, iv1));
                        storeu_si(cells.diagonal.as_mut_ptr().add(k).cast(), pack_u16(d0, d1));
                        k += 2 * LANES;
                    }
                }
            }

            #[inline(always)]
            fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
                use $ops::*;
                simd_lanes!(@pairs $interleave, $ops);
                // SAFETY: as in `cells`; loads of 2 * LANES u16 and stores
                // of LANES u32 at offsets up to CHUNK minus their width.
                unsafe {
                    let mut k = 0;
                    while k < CHUNK {
                        let b0 = loadu_si(halves.b0.as_ptr().add(k).cast());
                        let b1 = loadu_si(halves.b1.as_ptr().add(k).cast());
                        // Per 128-bit lane, the unpacks put each point's
                        // bytes b0 low, b1 low, b0 high, b1 high where its
                        // index goes, and undo `cells`' pack order.
                        storeu_si(out.as_mut_ptr().add(k).cast(), pairs(unpacklo_epi8(b0, b1)));
                        storeu_si(out.as_mut_ptr().add(k + LANES).cast(), pairs(unpackhi_epi8(b0, b1)));
                        k += 2 * LANES;
                    }
                }
            }

            #[inline(always)]
            fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
                use $ops::*;
                simd_lanes!(@pairs $interleave, $ops);
                // SAFETY: as in `cells`; loads of LANES u32 and stores of
                // LANES / 2 u64 at offsets up to CHUNK minus their width.
                unsafe {
                    let mut k = 0;
                    while k < CHUNK {
                        // The points' 64-bit groups reordered so that the
                        // low halves of the 128-bit lanes hold the first
                        // half of the points, in order.
                        let b0 = order_for_unpack(loadu_si(halves.b0.as_ptr().add(k).cast()));
                        let b1 = order_for_unpack(loadu_si(halves.b1.as_ptr().add(k).cast()));
                        // Each point's bytes: b0's and b1's byte 0, then
                        // byte 1, 2, 3: its index's 16-bit words.
                        storeu_si(out.as_mut_ptr().add(k).cast(), pairs(unpacklo_epi8(b0, b1)));
                        storeu_si(out.as_mut_ptr().add(k + LANES / 2).cast(), pairs(unpackhi_epi8(b0, b1)));
                        k += LANES;
                    }
                }
            }
        }

        $(#[$attr])*
        #[cfg(feature = "unstable-public-internals")]
        impl $name {
            /// One step of `cells` lane-wise on every element of a block
            /// (binary32 bits in, the step's bits out), with `cells`'
            /// intrinsics and constant operands: what [`probe`] runs.
            #[inline(always)]
            fn step(&self, step: probe::Step, x: &[u32; probe::BLOCK], out: &mut [u32; probe::BLOCK]) {
                use $ops::*;
                use core::ptr::write_unaligned;
                // SAFETY: as in `cells`; loads and stores of LANES 32-bit
                // elements at offsets up to BLOCK minus LANES (BLOCK is a
                // multiple of every LANES).
                unsafe {
                    let (floor, below_one) = (set1_ps(f32::MIN_POSITIVE), set1_ps(kernel::BELOW_ONE));
                    let level = if let probe::Step::Scale(level) = step { level } else { 0 };
                    let scale = set1_ps(Params::new(level, kernel::BINARY32_THRESHOLD).scale);
                    let (input, output) = (x.as_ptr(), out.as_mut_ptr());
                    // One loop per step (a `match` inside one loop would
                    // be decided again for every vector).
                    let mut k = 0;
                    match step {
                        probe::Step::Clamp => while k < probe::BLOCK {
                            let x = loadu_ps(input.add(k).cast());
                            write_unaligned(output.add(k).cast(), min_ps(max_ps(x, floor), below_one));
                            k += LANES;
                        },
                        probe::Step::Scale(_) => while k < probe::BLOCK {
                            let x = loadu_ps(input.add(k).cast());
                            write_unaligned(output.add(k).cast(), mul_ps(x, scale));
                            k += LANES;
                        },
                        probe::Step::Truncate => while k < probe::BLOCK {
                            let x = loadu_ps(input.add(k).cast());
                            storeu_si(output.add(k).cast(), cvttps_epi32(x));
                            k += LANES;
                        },
                        probe::Step::Fraction => while k < probe::BLOCK {
                            let x = loadu_ps(input.add(k).cast());
                            write_unaligned(output.add(k).cast(), sub_ps(x, cvtepi32_ps(cvttps_epi32(x))));
                            k += LANES;
                        },
                    }
                }
            }

            /// `cells`' `pack_u16` of the first LANES elements of `a` and
            /// of `b` into the first 2 * LANES of `out`.
            #[inline(always)]
            fn pack(&self, a: &[u32; 16], b: &[u32; 16], out: &mut [u16; 32]) {
                use $ops::*;
                // SAFETY: as in `cells`; loads of LANES <= 16 u32 and a
                // store of 2 * LANES <= 32 u16.
                unsafe {
                    let packed = pack_u16(loadu_si(a.as_ptr().cast()), loadu_si(b.as_ptr().cast()));
                    storeu_si(out.as_mut_ptr().cast(), packed);
                }
            }
        }
    };
    // `pairs`: every 16-bit word (b0's byte, b1's byte) of a vector to
    // those bytes' bits interleaved, b0's on the even bits. A function,
    // not a closure, for the target features (see `cells`).
    (@pairs unpack, $ops:ident) => {
        /// The perfect shuffle of each 16-bit word, by three
        /// shift-and-mask steps (the last three of `kernel::word::interleave_16`).
        #[inline(always)]
        unsafe fn pairs(mut x: Si) -> Si {
            use $ops::*;
            let t = and_si(xor_si(x, srli_epi16::<4>(x)), set1_epi16(0x00f0));
            x = xor_si(x, xor_si(t, slli_epi16::<4>(t)));
            let t = and_si(xor_si(x, srli_epi16::<2>(x)), set1_epi16(0x0c0c));
            x = xor_si(x, xor_si(t, slli_epi16::<2>(t)));
            let t = and_si(xor_si(x, srli_epi16::<1>(x)), set1_epi16(0x2222));
            xor_si(x, xor_si(t, slli_epi16::<1>(t)))
        }
    };
    (@pairs shuffle, $ops:ident) => {
        /// Each nibble spread to the even bits of a byte by a 16-entry
        /// byte shuffle, then each word's two spread bytes merged as
        /// b0's | b1's << 1 by a multiply-add of the byte pairs with
        /// (1, 2).
        #[inline(always)]
        unsafe fn pairs(bytes: Si) -> Si {
            use $ops::*;
            let nibble = set1_epi8(0x0f);
            let spread = broadcast_128(core::arch::x86_64::_mm_setr_epi8(
                0, 1, 4, 5, 16, 17, 20, 21, 64, 65, 68, 69, 80, 81, 84, 85,
            ));
            let pair = set1_epi16(0x0201);
            let low = shuffle_epi8(spread, and_si(bytes, nibble));
            let high = shuffle_epi8(spread, and_si(srli_epi16::<4>(bytes), nibble));
            // Each 16-bit word of `low` is one byte of the index, of
            // `high` the byte above it.
            or_si(maddubs_epi16(low, pair), slli_epi16::<8>(maddubs_epi16(high, pair)))
        }
    };
}

/// SSE2's intrinsics under the names [`simd_lanes!`] uses.
mod sse2_ops {
    use core::arch::x86_64 as x86;
    pub(super) use core::arch::x86_64::{
        __m128 as Ps, __m128i as Si, _mm_add_ps as add_ps, _mm_and_si128 as and_si,
        _mm_cvtepi32_ps as cvtepi32_ps, _mm_cvttps_epi32 as cvttps_epi32, _mm_loadu_ps as loadu_ps,
        _mm_loadu_si128 as loadu_si, _mm_max_ps as max_ps, _mm_min_ps as min_ps,
        _mm_mul_ps as mul_ps, _mm_set1_epi16 as set1_epi16, _mm_set1_ps as set1_ps,
        _mm_slli_epi16 as slli_epi16, _mm_srli_epi16 as srli_epi16, _mm_storeu_si128 as storeu_si,
        _mm_sub_ps as sub_ps, _mm_unpackhi_epi8 as unpackhi_epi8,
        _mm_unpacklo_epi8 as unpacklo_epi8, _mm_xor_si128 as xor_si,
    };
    /// f32 lanes of a vector.
    pub(super) const LANES: usize = 4;

    /// One 128-bit lane: already in unpack order.
    #[inline(always)]
    pub(super) fn order_for_unpack(a: Si) -> Si {
        a
    }

    /// Two vectors of values in `0..2^16` as one of 16-bit words, in order.
    /// SSE2's only 32-to-16-bit pack saturates signed, so the values are
    /// moved down by `2^15` first and back after.
    ///
    /// # Safety
    /// None beyond SSE2, the x86-64 baseline.
    #[inline(always)]
    pub(super) unsafe fn pack_u16(a: Si, b: Si) -> Si {
        let bias = x86::_mm_set1_epi32(0x8000);
        let packed = x86::_mm_packs_epi32(x86::_mm_sub_epi32(a, bias), x86::_mm_sub_epi32(b, bias));
        x86::_mm_xor_si128(packed, x86::_mm_set1_epi16(i16::MIN))
    }
}

/// AVX2's intrinsics under the names [`simd_lanes!`] uses.
#[cfg(feature = "std")]
mod avx2_ops {
    pub(super) use core::arch::x86_64::{
        __m256 as Ps, __m256i as Si, _mm256_add_ps as add_ps, _mm256_and_si256 as and_si,
        _mm256_broadcastsi128_si256 as broadcast_128, _mm256_cvtepi32_ps as cvtepi32_ps,
        _mm256_cvttps_epi32 as cvttps_epi32, _mm256_loadu_ps as loadu_ps,
        _mm256_loadu_si256 as loadu_si, _mm256_maddubs_epi16 as maddubs_epi16,
        _mm256_max_ps as max_ps, _mm256_min_ps as min_ps, _mm256_mul_ps as mul_ps,
        _mm256_or_si256 as or_si, _mm256_packus_epi32 as pack_u16, _mm256_set1_epi16 as set1_epi16,
        _mm256_set1_epi8 as set1_epi8, _mm256_set1_ps as set1_ps,
        _mm256_shuffle_epi8 as shuffle_epi8, _mm256_slli_epi16 as slli_epi16,
        _mm256_srli_epi16 as srli_epi16, _mm256_storeu_si256 as storeu_si, _mm256_sub_ps as sub_ps,
        _mm256_unpackhi_epi8 as unpackhi_epi8, _mm256_unpacklo_epi8 as unpacklo_epi8,
    };
    /// f32 lanes of a vector.
    pub(super) const LANES: usize = 8;

    /// 64-bit groups 0, 2, 1, 3: lane 0 gets groups 0 and 1's places.
    ///
    /// # Safety
    /// The CPU must have AVX2.
    #[inline(always)]
    pub(super) unsafe fn order_for_unpack(a: Si) -> Si {
        core::arch::x86_64::_mm256_permute4x64_epi64::<0b11_01_10_00>(a)
    }
}

/// AVX-512's intrinsics (F and BW) under the names [`simd_lanes!`] uses.
#[cfg(all(feature = "std", micromap_avx512))]
mod avx512_ops {
    pub(super) use core::arch::x86_64::{
        __m512 as Ps, __m512i as Si, _mm512_add_ps as add_ps, _mm512_and_si512 as and_si,
        _mm512_broadcast_i32x4 as broadcast_128, _mm512_cvtepi32_ps as cvtepi32_ps,
        _mm512_cvttps_epi32 as cvttps_epi32, _mm512_loadu_ps as loadu_ps,
        _mm512_loadu_si512 as loadu_si, _mm512_maddubs_epi16 as maddubs_epi16,
        _mm512_max_ps as max_ps, _mm512_min_ps as min_ps, _mm512_mul_ps as mul_ps,
        _mm512_or_si512 as or_si, _mm512_packus_epi32 as pack_u16, _mm512_set1_epi16 as set1_epi16,
        _mm512_set1_epi8 as set1_epi8, _mm512_set1_ps as set1_ps,
        _mm512_shuffle_epi8 as shuffle_epi8, _mm512_slli_epi16 as slli_epi16,
        _mm512_srli_epi16 as srli_epi16, _mm512_storeu_si512 as storeu_si, _mm512_sub_ps as sub_ps,
        _mm512_unpackhi_epi8 as unpackhi_epi8, _mm512_unpacklo_epi8 as unpacklo_epi8,
    };
    /// f32 lanes of a vector.
    pub(super) const LANES: usize = 16;

    /// 64-bit groups 0, 4, 1, 5, 2, 6, 3, 7: lane `l` gets groups `l` and
    /// `l + 4`.
    ///
    /// # Safety
    /// The CPU must have AVX-512 F.
    #[inline(always)]
    #[allow(clippy::incompatible_msrv)] // built from Rust 1.89 on (the cfg)
    pub(super) unsafe fn order_for_unpack(a: Si) -> Si {
        use core::arch::x86_64::{_mm512_permutexvar_epi64, _mm512_setr_epi64};
        _mm512_permutexvar_epi64(_mm512_setr_epi64(0, 4, 1, 5, 2, 6, 3, 7), a)
    }
}

simd_lanes!(Sse2Lanes, sse2_ops, interleave: unpack);
simd_lanes!(
    #[cfg(feature = "std")]
    Avx2Lanes,
    avx2_ops,
    interleave: shuffle
);
simd_lanes!(
    #[cfg(all(feature = "std", micromap_avx512))]
    // Built only by compilers from 1.89 on (the cfg), where these are stable.
    #[allow(clippy::incompatible_msrv)]
    Avx512Lanes,
    avx512_ops,
    interleave: shuffle
);

/// [`kernel::chunked`] through [`Sse2Lanes`]: the portable backend on
/// x86-64.
pub(super) fn narrow_slice_sse2(u: &[f32], v: &[f32], out: &mut [u32], params: &Params) {
    // SSE2 is the x86-64 baseline: every CPU this runs on has it.
    kernel::chunked::<Narrow, _>(&Sse2Lanes(()), u, v, out, params);
}

/// The wide form through [`Sse2Lanes`].
pub(super) fn wide_slice_sse2(u: &[f32], v: &[f32], out: &mut [u64], params: &Params) {
    kernel::chunked::<Wide, _>(&Sse2Lanes(()), u, v, out, params);
}

/// Stamps one kernel loop compiled with target features: an `unsafe fn`
/// with `#[target_feature]` (not a safe `#[target_feature]` function, which
/// needs Rust 1.86, above the crate's minimum supported version) whose body
/// is written in place (so that everything it inlines is compiled with the
/// features), and the safe entry point that calls it only after detecting
/// every feature it enables, returning `false` (nothing written) otherwise.
macro_rules! feature_loop {
    (
        $(#[$cfg:meta])?
        $doc:literal, $entry:ident, $compiled:ident, $features:literal, $detected:expr,
        $out:ty, |$u:ident, $v:ident, $o:ident, $params:ident| $body:expr
    ) => {
        #[cfg(feature = "std")]
        $(#[$cfg])?
        /// # Safety
        /// The CPU must support every feature in the `target_feature` list.
        #[target_feature(enable = $features)]
        unsafe fn $compiled($u: &[f32], $v: &[f32], $o: &mut [$out], $params: &Params) {
            $body
        }

        #[cfg(feature = "std")]
        #[doc = $doc]
        pub(super) fn $entry(u: &[f32], v: &[f32], out: &mut [$out], params: &Params) -> bool {
            $(#[$cfg])?
            if $detected {
                // SAFETY: every feature the compiled loop enables was
                // detected just above; its body is safe code on valid
                // slices, or a `Lanes` whose existence asserts exactly
                // these features.
                unsafe { $compiled(u, v, out, params) };
                return true;
            }
            let _ = (u, v, out, params);
            false
        }
    };
}

feature_loop!(
    "[`kernel::chunked`] through [`Avx2Lanes`]; `false` if the CPU lacks \
     AVX2.",
    narrow_slice_avx2,
    narrow_avx2,
    "avx2",
    has_avx2(),
    u32,
    |u, v, out, params| kernel::chunked::<Narrow, _>(&Avx2Lanes(()), u, v, out, params)
);
feature_loop!(
    "The wide form through [`Avx2Lanes`]; `false` if the CPU lacks AVX2.",
    wide_slice_avx2,
    wide_avx2,
    "avx2",
    has_avx2(),
    u64,
    |u, v, out, params| kernel::chunked::<Wide, _>(&Avx2Lanes(()), u, v, out, params)
);
feature_loop!(
    #[cfg(micromap_avx512)]
    "[`kernel::chunked`] through [`Avx512Lanes`]; `false` if the CPU lacks \
     one of the features or the compiler could not build the backend.",
    narrow_slice_avx512,
    narrow_avx512,
    "avx512f,avx512bw,avx512vl,avx512dq",
    has_avx512(),
    u32,
    |u, v, out, params| kernel::chunked::<Narrow, _>(&Avx512Lanes(()), u, v, out, params)
);
feature_loop!(
    #[cfg(micromap_avx512)]
    "The wide form through [`Avx512Lanes`]; `false` if unavailable.",
    wide_slice_avx512,
    wide_avx512,
    "avx512f,avx512bw,avx512vl,avx512dq",
    has_avx512(),
    u64,
    |u, v, out, params| kernel::chunked::<Wide, _>(&Avx512Lanes(()), u, v, out, params)
);

/// Stamps one backend's [`probe`] functions: the lanes' methods compiled
/// with the backend's features (called only where the CPU has them).
#[cfg(feature = "unstable-public-internals")]
macro_rules! probe_backend {
    ($(#[$attr:meta])* $module:ident, $lanes:ident, $features:literal) => {
        $(#[$attr])*
        mod $module {
            use super::super::*;
            use super::{Step, BLOCK};

            /// # Safety
            /// The CPU must support every feature in the list.
            #[target_feature(enable = $features)]
            pub(super) unsafe fn step(step: Step, x: &[u32; BLOCK], out: &mut [u32; BLOCK]) {
                $lanes(()).step(step, x, out);
            }

            /// # Safety
            /// As [`step`].
            #[target_feature(enable = $features)]
            pub(super) unsafe fn pack(a: &[u32; 16], b: &[u32; 16], out: &mut [u16; 32]) {
                $lanes(()).pack(a, b, out);
            }

            /// # Safety
            /// As [`step`].
            #[target_feature(enable = $features)]
            pub(super) unsafe fn cells(u: &[f32; CHUNK], v: &[f32; CHUNK], params: &Params, cells: &mut Cells<u16>) {
                $lanes(()).cells(u, v, params, cells);
            }

            /// # Safety
            /// As [`step`].
            #[target_feature(enable = $features)]
            pub(super) unsafe fn interleave(halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
                $lanes(()).interleave(halves, out);
            }

            /// # Safety
            /// As [`step`].
            #[target_feature(enable = $features)]
            pub(super) unsafe fn wide_interleave(halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
                $lanes(()).wide_interleave(halves, out);
            }
        }
    };
}

/// The SIMD lanes' steps run one at a time, for the lab's proof that the
/// x86-64 backends compute what `docs/verification.md` 10.12 says
/// (`micromap-lab prove --all-levels`). A [`LaneProbe`] exists only for a
/// backend this CPU runs; each method calls the backend's own lane methods
/// (the ones `batch` runs, or a step of them with its intrinsics and
/// constant operands) compiled with the backend's features.
#[cfg(feature = "unstable-public-internals")]
pub mod probe {
    use super::{kernel, Cells, Halves, Params, CHUNK};
    use crate::arch::Backend;

    /// Elements per [`LaneProbe::step`] call.
    pub const BLOCK: usize = 1024;

    /// A step of the lanes' first half (`cells`), lane-wise.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Step {
        /// `min_ps(max_ps(x, set1_ps(f32::MIN_POSITIVE)), set1_ps(BELOW_ONE))`.
        Clamp,
        /// `mul_ps(x, set1_ps(scale))`, `scale` of `Params::new(level, _)`.
        Scale(u32),
        /// `cvttps_epi32(x)`.
        Truncate,
        /// `sub_ps(x, cvtepi32_ps(cvttps_epi32(x)))`.
        Fraction,
    }

    probe_backend!(sse2, Sse2Lanes, "sse2");
    probe_backend!(
        #[cfg(feature = "std")]
        avx2,
        Avx2Lanes,
        "avx2"
    );
    probe_backend!(
        #[cfg(all(feature = "std", micromap_avx512))]
        #[allow(clippy::incompatible_msrv)]
        avx512,
        Avx512Lanes,
        "avx512f,avx512bw,avx512vl,avx512dq"
    );

    /// One backend's lanes, built only where this CPU runs it.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct LaneProbe {
        backend: Backend,
    }

    /// Calls the backend's compilation of `$f`.
    macro_rules! dispatch {
        ($probe:ident, $f:ident($($arg:expr),*)) => {
            match $probe.backend {
                // SAFETY: SSE2 is the x86-64 baseline.
                Backend::Portable => unsafe { sse2::$f($($arg),*) },
                // SAFETY: a probe exists only for a backend whose every
                // feature `Backend::is_available` detected (`new`).
                #[cfg(feature = "std")]
                Backend::Avx2 => unsafe { avx2::$f($($arg),*) },
                // SAFETY: as above.
                #[cfg(all(feature = "std", micromap_avx512))]
                Backend::Avx512 => unsafe { avx512::$f($($arg),*) },
                #[allow(unreachable_patterns)]
                _ => unreachable!("a probe exists only for an available backend"),
            }
        };
    }

    impl LaneProbe {
        /// The probe of `backend`'s lanes (`Portable`: SSE2), or `None`
        /// where this CPU (or this build) cannot run it.
        #[must_use]
        pub fn new(backend: Backend) -> Option<LaneProbe> {
            backend.is_available().then_some(LaneProbe { backend })
        }

        /// The backend.
        #[must_use]
        pub fn backend(&self) -> Backend {
            self.backend
        }

        /// The instruction set's name (`SSE2`, `AVX2`, `AVX-512`).
        #[must_use]
        pub fn name(&self) -> &'static str {
            match self.backend {
                Backend::Portable => "SSE2",
                Backend::Avx2 => "AVX2",
                Backend::Avx512 => "AVX-512",
            }
        }

        /// 32-bit lanes per vector.
        #[must_use]
        pub fn lanes(&self) -> usize {
            match self.backend {
                Backend::Portable => 4,
                Backend::Avx2 => 8,
                Backend::Avx512 => 16,
            }
        }

        /// `step` lane-wise on every element of `x` (binary32 bits); `out`
        /// holds the results' bits (an `i32` for [`Step::Truncate`]).
        pub fn step(&self, step: Step, x: &[u32; BLOCK], out: &mut [u32; BLOCK]) {
            dispatch!(self, step(step, x, out));
        }

        /// `cells`' `pack_u16(a, b)` on the first [`LaneProbe::lanes`]
        /// elements of each; `out`'s first twice as many are written.
        pub fn pack(&self, a: &[u32; 16], b: &[u32; 16], out: &mut [u16; 32]) {
            dispatch!(self, pack(a, b, out));
        }

        /// The lanes' `cells` (what `batch::index_f32` runs) at `level`
        /// (`0..=16`), cells in the lanes' order.
        pub fn cells(
            &self,
            u: &[f32; CHUNK],
            v: &[f32; CHUNK],
            level: u32,
            cells: &mut Cells<u16>,
        ) {
            let params = Params::new(level.min(16), kernel::BINARY32_THRESHOLD);
            dispatch!(self, cells(u, v, &params, cells));
        }

        /// The lanes' `interleave` (`batch::index_f32`'s last stage).
        pub fn interleave(&self, halves: &Halves<u16>, out: &mut [u32; CHUNK]) {
            dispatch!(self, interleave(halves, out));
        }

        /// The lanes' `wide_interleave` (`batch::wide_index_f32`'s last
        /// stage).
        pub fn wide_interleave(&self, halves: &Halves<u32>, out: &mut [u64; CHUNK]) {
            dispatch!(self, wide_interleave(halves, out));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every backend this CPU runs (SSE2, the x86-64 portable one, always)
    /// against the point kernel at several levels, over full chunks, a
    /// padded tail and a short one. Small enough for Miri, which checks the
    /// loads and stores of this module's `unsafe` blocks:
    /// `cargo +nightly miri test -p micromap-index --lib arch::`
    /// (SSE2), with `RUSTFLAGS="-C target-feature=+avx2"` for the AVX2
    /// lanes too.
    #[test]
    fn lanes_equal_the_point_kernel() {
        const POINTS: usize = CHUNK + 40;
        let mut rng = micromap_index_test_support::SplitMix64::new(0x9e37_79b9_7f4a_7c15);
        let (mut u, mut v) = ([0f32; POINTS], [0f32; POINTS]);
        let mut out = [0u32; POINTS];
        for (k, (u, v)) in u.iter_mut().zip(v.iter_mut()).enumerate() {
            let x = rng.next_u64();
            // Every fourth point any bit pattern (NaN, negatives, huge),
            // the others in [0, 1].
            *u = if k % 4 == 0 {
                f32::from_bits(x as u32)
            } else {
                f32::from_bits(x as u32 % 0x3f80_0001)
            };
            *v = f32::from_bits((x >> 32) as u32 % 0x3f80_0001);
        }
        for level in [0, 1, 5, 12, 16] {
            let params = Params::new(level, kernel::BINARY32_THRESHOLD);
            let check = |out: &[u32]| {
                for (k, &got) in out.iter().enumerate() {
                    let expected = kernel::narrow::<{ kernel::CELL_BY_SHIFTS }>(
                        u[k].to_bits(),
                        v[k].to_bits(),
                        &params,
                    );
                    assert_eq!(
                        got,
                        expected,
                        "level {level}, length {}, point {k}",
                        out.len()
                    );
                }
            };
            let wide_params = Params::new(2 * level, kernel::BINARY32_THRESHOLD);
            let check_wide = |out: &[u64]| {
                for (k, &got) in out.iter().enumerate() {
                    let expected = kernel::wide(u[k].to_bits(), v[k].to_bits(), &wide_params);
                    assert_eq!(
                        got,
                        expected,
                        "wide level {}, length {}, point {k}",
                        2 * level,
                        out.len()
                    );
                }
            };
            let mut wide_out = [0u64; POINTS];
            for len in [POINTS, CHUNK + 17, 15] {
                wide_slice_sse2(&u[..len], &v[..len], &mut wide_out[..len], &wide_params);
                check_wide(&wide_out[..len]);
                #[cfg(feature = "std")]
                {
                    if wide_slice_avx2(&u[..len], &v[..len], &mut wide_out[..len], &wide_params) {
                        check_wide(&wide_out[..len]);
                    }
                    #[cfg(micromap_avx512)]
                    if wide_slice_avx512(&u[..len], &v[..len], &mut wide_out[..len], &wide_params) {
                        check_wide(&wide_out[..len]);
                    }
                }
                narrow_slice_sse2(&u[..len], &v[..len], &mut out[..len], &params);
                check(&out[..len]);
                #[cfg(feature = "std")]
                {
                    if narrow_slice_avx2(&u[..len], &v[..len], &mut out[..len], &params) {
                        check(&out[..len]);
                    }
                    #[cfg(micromap_avx512)]
                    if narrow_slice_avx512(&u[..len], &v[..len], &mut out[..len], &params) {
                        check(&out[..len]);
                    }
                }
            }
        }
    }
}
