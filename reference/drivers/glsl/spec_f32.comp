#version 450
#extension GL_GOOGLE_include_directive : require
// One invocation per case: cases[i] = (u bits, v bits, level, unused).
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Cases { uvec4 cases[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Indices { uint indices[]; };
layout(push_constant) uniform Count { uint case_count; };

// The Vulkan reference, shared with every shader of the project:
// shaders/glsl/micromap_index.glsl (compile with -Ishaders/glsl).
#include "micromap_index.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= case_count) return;
    uvec4 c = cases[i];
    indices[i] = BarycentricsToSpaceFillingCurveIndex(uintBitsToFloat(c.x), uintBitsToFloat(c.y), c.z);
}
