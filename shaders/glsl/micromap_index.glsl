// micromap_index.glsl: the Vulkan reference BarycentricsToSpaceFillingCurveIndex
// (appendix "Reference Code" of VK_EXT_opacity_micromap / VK_KHR_opacity_micromap),
// in binary32, bit for bit what micromap_index::spec::index_f32 returns.
//
// Contract
//   uint BarycentricsToSpaceFillingCurveIndex(float u, float v, uint level)
//   - u, v: a hit's barycentrics (weights of vertices 1 and 2), any float:
//     NaN clamps to 0 (quiet or signalling), -inf to 0, +inf to 1, values
//     outside [0, 1] are clamped as the reference does.
//   - level 0..=16: the index of the micro-triangle, below 4^level, equal to
//     the library's spec::index_f32 (checked on the committed spec-f32
//     conformance vectors by crates/lab/tests/shaders.rs).
//   - level 17..=31: the reference's 32-bit steps as written (they give wrong
//     indices there, like the C code; spec::reference_bits_f32; not checked
//     by the test). level >= 32: an undefined value (GLSL shifts by 32 or
//     more are undefined); never a memory access.
//   - Reads no memory; no buffer can be malformed.
// The float operations are `precise`: a compiler must neither contract nor
// reassociate them (uf + vf is rounded to binary32 before the compare).
//
// Use: #extension GL_GOOGLE_include_directive : require
//      #include "micromap_index.glsl"     (glslangValidator -I shaders/glsl)
#ifndef MICROMAP_INDEX_GLSL
#define MICROMAP_INDEX_GLSL

// The reference's clamp(x, 0, 1) with NaN (quiet or signalling) -> 0.
// GLSL's clamp() leaves NaN undefined; an ordered compare is false for NaN.
float mmi_clamp01(float x) { return x > 0.0 ? min(x, 1.0) : 0.0; }

uint BarycentricsToSpaceFillingCurveIndex(float u, float v, uint level)
{
    u = mmi_clamp01(u);
    v = mmi_clamp01(v);
    uint iu, iv, iw;
    // `precise`: no contraction or reassociation of these float operations.
    precise float fu = u * float(1u << level);
    precise float fv = v * float(1u << level);
    iu = uint(fu);
    iv = uint(fv);
    precise float uf = fu - float(iu);
    precise float vf = fv - float(iv);
    if (iu >= (1u << level)) iu = (1u << level) - 1u;
    if (iv >= (1u << level)) iv = (1u << level) - 1u;
    uint iuv = iu + iv;
    if (iuv >= (1u << level)) iu -= iuv - (1u << level) + 1u;
    iw = ~(iu + iv);
    precise float sum = uf + vf; // rounded to binary32 before the compare
    if (sum >= 1.0 && iuv < (1u << level) - 1u) --iw;
    uint b0 = ~(iu ^ iw);
    b0 &= ((1u << level) - 1u);
    uint t = (iu ^ iv) & b0;
    uint f = t;
    f ^= f >> 1u;
    f ^= f >> 2u;
    f ^= f >> 4u;
    f ^= f >> 8u;
    uint b1 = ((f ^ iu) & ~b0) | t;
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

#endif // MICROMAP_INDEX_GLSL
