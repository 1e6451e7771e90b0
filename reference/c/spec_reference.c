/*
 * BarycentricsToSpaceFillingCurveIndex, from the "Reference Code" section of
 * the Vulkan specification (Khronos Vulkan-Docs,
 * appendices/VK_EXT_opacity_micromap.adoc; identical in
 * appendices/VK_KHR_opacity_micromap.adoc), read at Vulkan-Docs commit
 * 090f1b190d60ced4a1d198fd3747d071cc271b1c (Vulkan 1.4.360); the function is
 * unchanged since 2022 but for whitespace.
 *
 * Origin and licence of that text:
 *   Copyright 2022-2023 The Khronos Group Inc.
 *   SPDX-License-Identifier: CC-BY-4.0
 * This copy keeps the attribution above; the comments and the wrapper are
 * micromap-index's own (MIT OR Apache-2.0).
 *
 * The body is the reference token for token, except that the C++
 * functional cast `float(iu)` is written as the C cast `(float)(iu)` and the
 * function is static, so the wrapper at the end is the only way in.
 * Two things the specification leaves to its reader are fixed here:
 *
 *  - `clamp(x, lo, hi)` is min(max(x, lo), hi) where max and min return the
 *    non-NaN operand for *every* NaN, quiet or signalling, as GPU max/min
 *    (SPIR-V NMax/NMin) and IEEE 754-2019 maximumNumber/minimumNumber do: NaN
 *    clamps to 0. It is written with comparisons rather than fmaxf/fminf
 *    because libm's fmaxf follows IEEE 754-2008 maxNum, which returns NaN for
 *    a *signalling* NaN operand (glibc does), and the final fminf then gives 1.
 *  - `1u << level` is undefined behaviour in C for level >= 32; the exported
 *    wrapper passes level % 32 (what x86, ARM and SPIR-V hardware shift by).
 *
 * The arithmetic must be IEEE binary32 with round-to-nearest-even and no
 * contraction into FMA; the build (reference/oracle/build.rs) passes the
 * flags for that, and the checks below reject excess precision and fast math.
 */
#include <float.h>
#include <stdint.h>

#include "spec_reference.h"

/* x87 excess precision would change the rounding of `uf + vf`. */
#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "spec_reference.c needs float expressions evaluated in binary32 (FLT_EVAL_METHOD == 0)"
#endif

/* Fast math may drop the NaN handling of the clamp and reassociate; CFLAGS
   from the environment come after the build script's -fno-fast-math. */
#if defined(__FAST_MATH__) || (defined(__FINITE_MATH_ONLY__) && __FINITE_MATH_ONLY__)
#error "spec_reference.c must not be compiled with fast or finite-only math"
#endif

static float clamp(float x, float lo, float hi)
{
    /* A NaN fails both comparisons and so becomes lo, then stays lo. */
    float at_least_lo = (x > lo) ? x : lo;
    return (at_least_lo < hi) ? at_least_lo : hi;
}

static uint32_t BarycentricsToSpaceFillingCurveIndex(float u, float v, uint32_t level)
{
    u = clamp(u, 0.0f, 1.0f);
    v = clamp(v, 0.0f, 1.0f);
    uint32_t iu, iv, iw;
    // Quantize barycentric coordinates
    float fu = u * (1u << level);
    float fv = v * (1u << level);
    iu = (uint32_t)fu;
    iv = (uint32_t)fv;
    float uf = fu - (float)(iu);
    float vf = fv - (float)(iv);
    if (iu >= (1u << level)) iu = (1u << level) - 1u;
    if (iv >= (1u << level)) iv = (1u << level) - 1u;
    uint32_t iuv = iu + iv;
    if (iuv >= (1u << level))
        iu -= iuv - (1u << level) + 1u;
    iw = ~(iu + iv);
    if (uf + vf >= 1.0f && iuv < (1u << level) - 1u) --iw;
    uint32_t b0 = ~(iu ^ iw);
    b0 &= ((1u << level) - 1u);
    uint32_t t = (iu ^ iv) & b0;
    uint32_t f = t;
    f ^= f >> 1u;
    f ^= f >> 2u;
    f ^= f >> 4u;
    f ^= f >> 8u;
    uint32_t b1 = ((f ^ iu) & ~b0) | t;
    // Interleave bits
    b0 = (b0 | (b0 << 8u)) & 0x00ff00ffu;
    b0 = (b0 | (b0 << 4u)) & 0x0f0f0f0fu;
    b0 = (b0 | (b0 << 2u)) & 0x33333333u;
    b0 = (b0 | (b0 << 1u)) & 0x55555555u;
    b1 = (b1 | (b1 << 8u)) & 0x00ff00ffu;
    b1 = (b1 | (b1 << 4u)) & 0x0f0f0f0fu;
    b1 = (b1 | (b1 << 2u)) & 0x33333333u;
    b1 = (b1 | (b1 << 1u)) & 0x55555555u;
    return b0 | (b1 << 1u);
}

uint32_t micromap_spec_reference_index(float u, float v, uint32_t level)
{
    /* The modulo keeps every shift count in 0..=31 (defined in C). */
    return BarycentricsToSpaceFillingCurveIndex(u, v, level % 32u);
}
