#version 450
// One invocation per case: cases[i] = (u bits, v bits, level, unused).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Cases { uvec4 cases[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Indices { uint indices[]; };
layout(push_constant) uniform Count { uint case_count; };

// The reference's clamp(x, 0, 1) with NaN (quiet or signalling) -> 0.
// GLSL's clamp() leaves NaN undefined; an ordered compare is false for NaN.
float clamp01(float x) { return x > 0.0 ? min(x, 1.0) : 0.0; }

uint BarycentricsToSpaceFillingCurveIndex(float u, float v, uint level)
{
    u = clamp01(u);
    v = clamp01(v);
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

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= case_count) return;
    uvec4 c = cases[i];
    indices[i] = BarycentricsToSpaceFillingCurveIndex(uintBitsToFloat(c.x), uintBitsToFloat(c.y), c.z);
}
