/* The implementation under test: replace this file with yours (same
   signature). This one is the Vulkan specification's reference
   BarycentricsToSpaceFillingCurveIndex with clamp written as comparisons,
   so every NaN (quiet or signalling) becomes 0. Do NOT write the clamp as
   fminf(fmaxf(x, 0), 1), std::clamp, saturate or min/max: they let NaN
   through (or turn a signalling NaN into 1), and the float-to-integer
   conversion of NaN below is undefined -- it may pass on one instruction
   set and fail on another. Compile without fast math and without FMA
   contraction (see build.sh). */
#include <stdint.h>

static float clamp01(float x) { return x > 0.0f ? (x < 1.0f ? x : 1.0f) : 0.0f; }

uint32_t BarycentricsToSpaceFillingCurveIndex(float u, float v, uint32_t level)
{
    u = clamp01(u);
    v = clamp01(v);
    uint32_t iu, iv, iw;
    float fu = u * (1u << level);
    float fv = v * (1u << level);
    iu = (uint32_t)fu;
    iv = (uint32_t)fv;
    float uf = fu - (float)iu;
    float vf = fv - (float)iv;
    if (iu >= (1u << level)) iu = (1u << level) - 1u;
    if (iv >= (1u << level)) iv = (1u << level) - 1u;
    uint32_t iuv = iu + iv;
    if (iuv >= (1u << level)) iu -= iuv - (1u << level) + 1u;
    iw = ~(iu + iv);
    if (uf + vf >= 1.0f && iuv < (1u << level) - 1u) --iw;
    uint32_t b0 = ~(iu ^ iw);
    b0 &= ((1u << level) - 1u);
    uint32_t t = (iu ^ iv) & b0;
    uint32_t f = t;
    f ^= f >> 1u; f ^= f >> 2u; f ^= f >> 4u; f ^= f >> 8u;
    uint32_t b1 = ((f ^ iu) & ~b0) | t;
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
